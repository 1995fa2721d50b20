//! Noise and forces on the nonlinear path (`simulate` of a body with a non-square term):
//! fluctuation–dissipation against the Gibbs distribution, computed independently (a count of
//! the linear modes; a Boltzmann integral by quadrature), and modal forces against the modal
//! path's exact propagators.

mod common;
use common::cli;

/// The rows of a `simulate` CSV after the header, as numbers, without the first `skip` rows.
fn rows(csv: &str, skip: usize) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1 + skip)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn a_linear_body_on_the_nonlinear_path_holds_kt_per_damped_mode() {
    // The larva at the next order with its new terms off is linear, but goes the nonlinear
    // way (its terms are not all squares). The midpoint rule with this noise keeps the Gibbs
    // distribution exactly: ⟨E⟩ = kT per mode that feels friction (the zero modes, a rigid
    // translation or rotation, feel none and stay at rest).
    let kt = 0.1;
    let modes: serde_json::Value =
        serde_json::from_str(&cli(&["modes", "-p", "12", "--format", "json"]).unwrap()).unwrap();
    let damped = modes["fields"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|f| f["eigenvalues"].as_array().unwrap().clone())
        .filter(|l| l.as_f64().unwrap().abs() > 1e-9)
        .count();
    let csv = cli(&[
        "simulate",
        "--beyond-leading",
        "1",
        "-p",
        "12",
        "--temperature",
        "0.1",
        "--steps",
        "400000",
        "--every",
        "10",
        "--dt",
        "0.05",
        "--param",
        "zeta_s=1",
        "--param",
        "zeta_t=1",
        "--param",
        "zeta_b=1",
    ])
    .unwrap();
    let rows = rows(&csv, 4000);
    let mean = rows.iter().map(|r| r[1]).sum::<f64>() / rows.len() as f64;
    let want = kt * damped as f64;
    assert!(
        (mean / want - 1.0).abs() < 0.03,
        "⟨E⟩ = {mean} against {want} ({damped} damped modes)"
    );
}

#[test]
fn a_nonlinear_body_at_a_temperature_samples_the_boltzmann_distribution() {
    // The tethered filament with u̇̇ = −u − u³ at each point, coupled only by its friction:
    // ⟨u²⟩ = ∫u² e^{−V/kT} / ∫e^{−V/kT}, V = u²/2 + u⁴/4, by the trapezoid rule.
    let kt = 0.5f64;
    let model = format!("{}/tables/models/tethered.toml", env!("CARGO_MANIFEST_DIR"));
    let csv = cli(&[
        "simulate",
        "--model",
        &model,
        "-p",
        "8",
        "--param",
        "c1_u=0",
        "--param",
        "c2_u=1",
        "--param",
        "c3_u=0",
        "--param",
        "c4_u=0.5",
        "--param",
        "cp_u=1",
        "--temperature",
        "0.5",
        "--steps",
        "400000",
        "--every",
        "10",
        "--dt",
        "0.05",
    ])
    .unwrap();
    let rows = rows(&csv, 4000);
    let sampled = rows
        .iter()
        .flat_map(|r| r[2..].iter().map(|u| u * u))
        .sum::<f64>()
        / (rows.len() * 8) as f64;
    let weight = |u: f64| (-(0.5 * u * u + 0.25 * u.powi(4)) / kt).exp();
    let grid = (0..=12000).map(|i| -6.0 + 1e-3 * i as f64);
    let (num, den) = grid.fold((0.0, 0.0), |(n, d), u| {
        (n + u * u * weight(u), d + weight(u))
    });
    let want = num / den;
    assert!(
        (sampled / want - 1.0).abs() < 0.04,
        "⟨u²⟩ = {sampled} against {want}"
    );
}

#[test]
fn a_modal_force_moves_the_nonlinear_path_as_the_exact_propagators() {
    // A constant force on the beam's fourth mode, the larva at the next order (new terms off,
    // the nonlinear path) against the leading order (exact modal propagators): the same state.
    let run = |beyond: &str| {
        let csv = cli(&[
            "simulate",
            "--beyond-leading",
            beyond,
            "-p",
            "12",
            "--param",
            "zeta_b=1",
            "--force",
            "y:3=0.2",
            "--drive",
            "z:2=0.1,0.7",
            "--steps",
            "4000",
            "--dt",
            "0.02",
            "--every",
            "4000",
        ])
        .unwrap();
        let header: Vec<String> = csv
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(String::from)
            .collect();
        let last = rows(&csv, 0).pop().unwrap();
        header
            .into_iter()
            .zip(last)
            .filter(|(h, _)| !h.starts_with("q_"))
            .collect::<Vec<_>>()
    };
    let (exact, implicit) = (run("0"), run("1"));
    assert_eq!(exact.len(), implicit.len());
    let moved = exact.iter().map(|(_, v)| v.abs()).fold(0.0, f64::max);
    assert!(moved > 0.1, "the force moved the body: {moved}");
    for ((name, a), (other, b)) in exact.iter().zip(&implicit) {
        assert_eq!(name, other);
        // Second order in h = 0.02 for the drive; the constant force's steady state is exact.
        assert!((a - b).abs() < 1e-4, "{name}: {a} against {b}");
    }
}

#[test]
fn held_ends_on_the_nonlinear_path_move_as_the_exact_propagators() {
    // The clamped-head zebrafish and the pinned channel worm are linear: the library's implicit
    // integrator (held points dropped from the unknowns) against `simulate`'s exact modal
    // propagators, from the same modal initial state.
    use theory_search::dynamics::default_coefficients;
    use theory_search::dynamics::nonlinear::NonlinearBody;
    use theory_search::model::Model;
    for (file, field) in [
        ("zebrafish", "y"),
        ("channel_worm", "y"),
        ("channel_worm", "x"),
    ] {
        let path = format!("{}/tables/models/{file}.toml", env!("CARGO_MANIFEST_DIR"));
        let model = Model::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let (points, h, steps) = (10usize, 2e-3, 5000u64);
        let initial = format!("{field}:1=0.5");
        let csv = cli(&[
            "simulate",
            "--model",
            &path,
            "-p",
            "10",
            "--initial",
            &initial,
            "--dt",
            "0.002",
            "--steps",
            "5000",
            "--every",
            "5000",
        ])
        .unwrap();
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let exact = rows(&csv, 0).pop().unwrap();
        let modes: serde_json::Value = serde_json::from_str(
            &cli(&[
                "modes", "--model", &path, "-p", "10", "--shapes", "--format", "json",
            ])
            .unwrap(),
        )
        .unwrap();
        let values = default_coefficients(&model, 4, &Default::default()).unwrap();
        let body = NonlinearBody::new(&model, 4, points, &values).unwrap();
        let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
            .fields
            .iter()
            .map(|f| (vec![0.0; f.unknowns], vec![0.0; f.unknowns]))
            .collect();
        let k = body.fields.iter().position(|f| f.id == field).unwrap();
        let shape: Vec<f64> = modes["fields"][k]["shapes"][1]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| 0.5 * x.as_f64().unwrap())
            .collect();
        state[k].0 = body.fields[k].strip(&shape);
        let mut integrator = body.integrator(h);
        for step in 0..steps {
            integrator.step(&mut state, step as f64 * h).unwrap();
        }
        for (f, (u, _)) in body.fields.iter().zip(&state) {
            for (j, x) in f.embed(u).iter().enumerate() {
                let name = format!("{}_{j}", f.id);
                let at = header.iter().position(|h| *h == name).unwrap();
                assert!(
                    (x - exact[at]).abs() < 1e-4,
                    "{file} {name}: {x} against {}",
                    exact[at]
                );
            }
        }
    }
}
