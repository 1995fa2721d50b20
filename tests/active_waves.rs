//! Active forces moved (`simulate`, `modes`): a bending field around a ring with the active
//! force a∂s³y (a body with a head) against the continuum dispersion relation ω² = ck⁴ + iak³
//! (docs/derivation.md), its direction of travel from the sign of a, the discrete energy
//! balance E₁ − E₀ = −dissipated + injected at every step (linear and nonlinear active forces),
//! and the linearisation's complex roots against the discrete dispersion relation; on a
//! free-ended body, growth that is the grid's (past the grid Péclet number, or moving with N)
//! is said to be.

mod common;

use std::collections::BTreeMap;

use nalgebra::Complex;

type Complex64 = Complex<f64>;
use theory_search::dynamics::nonlinear::NonlinearBody;
use theory_search::model::Model;

/// A bending field around a ring, without PAR: the active section allows a∂s³y.
const RING: &str = include_str!("common/ring.toml");

fn values(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

fn ring(points: usize, c: f64, damping: f64, a: f64) -> NonlinearBody {
    let model = Model::from_toml(RING).unwrap();
    let v = values(&[("c_y", c), ("c'_y", damping), ("a_y", a), ("g_y", 0.0)]);
    NonlinearBody::new(&model, 4, points, &v).unwrap()
}

/// The Fourier coefficient Σⱼ yⱼ e^{−ikj} of the field at wavenumber k (lattice units).
fn amplitude(y: &[f64], k: f64) -> Complex64 {
    y.iter()
        .enumerate()
        .map(|(j, &x)| x * Complex64::from_polar(1.0, -k * j as f64))
        .sum()
}

/// Runs `steps` steps of `h` from (y, v) and returns the amplitude at k every `every` steps.
fn run(
    body: &NonlinearBody,
    state: (Vec<f64>, Vec<f64>),
    h: f64,
    steps: usize,
    k: f64,
) -> Vec<Complex64> {
    let mut state = vec![state];
    let mut integrator = body.integrator(h);
    let mut out = vec![amplitude(&state[0].0, k)];
    for step in 0..steps {
        integrator.step(&mut state, step as f64 * h).unwrap();
        out.push(amplitude(&state[0].0, k));
    }
    out
}

/// ω from A(t) ∝ e^{−iωt}: the unwrapped phase and the log modulus, fitted by least squares
/// over the samples (one per step of `h`).
fn measured_omega(series: &[Complex64], h: f64) -> Complex64 {
    let mut phase = 0.0;
    let mut points = vec![(0.0, series[0].norm().ln(), 0.0)];
    for (i, w) in series.windows(2).enumerate() {
        phase += (w[1] / w[0]).arg();
        points.push(((i + 1) as f64 * h, w[1].norm().ln(), phase));
    }
    let slope = |pick: &dyn Fn(&(f64, f64, f64)) -> f64| {
        let n = points.len() as f64;
        let (mt, my) = points
            .iter()
            .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + pick(p) / n));
        let num: f64 = points.iter().map(|p| (p.0 - mt) * (pick(p) - my)).sum();
        let den: f64 = points.iter().map(|p| (p.0 - mt).powi(2)).sum();
        num / den
    };
    // A ∝ e^{−iωt} = e^{Im ω t} e^{−i Re ω t}.
    Complex64::new(-slope(&|p| p.2), slope(&|p| p.1))
}

#[test]
fn an_active_bending_force_drives_a_wave_at_the_speed_and_growth_of_the_dispersion_relation() {
    let (points, m) = (257, 2);
    let n = points - 1;
    let k = 2.0 * std::f64::consts::PI * m as f64 / n as f64;
    let c = 1.0;
    let a = 0.2 * c * k;
    // The continuum root of ω² = ck⁴ + iak³ that travels towards +s (Re ω > 0).
    let omega = Complex64::new(c * k.powi(4), a * k.powi(3)).sqrt();
    assert!(
        omega.re > 0.0 && omega.im > 0.0,
        "forward and growing: {omega}"
    );
    let body = ring(points, c, 0.0, a);
    // Start on the forward wave: y = Re e^{i(kj)}, v = Re(−iω e^{ikj}).
    let y: Vec<f64> = (0..n).map(|j| (k * j as f64).cos()).collect();
    let v: Vec<f64> = (0..n)
        .map(|j| (Complex64::new(0.0, -1.0) * omega * Complex64::from_polar(1.0, k * j as f64)).re)
        .collect();
    let period = 2.0 * std::f64::consts::PI / omega.re;
    let h = period / 1000.0;
    let series = run(&body, (y, v), h, 2000, k);
    let got = measured_omega(&series, h);
    // Phase speed Re ω / k (its sign the direction) and growth rate Im ω, each within 1 %.
    let (speed, want_speed) = (got.re / k, omega.re / k);
    assert!(
        (speed / want_speed - 1.0).abs() < 0.01,
        "phase speed {speed} against {want_speed} (towards +s)"
    );
    assert!(
        (got.im / omega.im - 1.0).abs() < 0.01,
        "growth rate {} against {}",
        got.im,
        omega.im
    );
}

#[test]
fn a_standing_wave_becomes_a_wave_running_the_way_the_sign_of_a_says() {
    let (points, m) = (129, 2);
    let n = points - 1;
    let k = 2.0 * std::f64::consts::PI * m as f64 / n as f64;
    for sign in [1.0, -1.0] {
        let a = sign * 0.3 * k;
        let omega = Complex64::new(k.powi(4), a.abs() * k.powi(3)).sqrt();
        let body = ring(points, 1.0, 0.0, a);
        let y: Vec<f64> = (0..n).map(|j| (k * j as f64).cos()).collect();
        let h = 2.0 * std::f64::consts::PI / omega.re / 500.0;
        let series = run(&body, (y, vec![0.0; n]), h, 3000, k);
        // Over the last period the growing wave dominates: its phase runs at ∓Re ω.
        let tail = &series[series.len() - 500..];
        let got = measured_omega(tail, h);
        assert!(
            (got.re / (sign * omega.re) - 1.0).abs() < 0.02,
            "a = {a}: phase rate {} against {} (a > 0 runs towards +s)",
            got.re,
            sign * omega.re
        );
        assert!(series.last().unwrap().norm() > 3.0 * series[0].norm());
    }
}

#[test]
fn the_energy_balance_with_active_power_holds_at_every_step() {
    // The ring, linear, with Kelvin damping; and the free crawler with its nonlinear active
    // forces on x at the next orders ((∂s x)²·∂ts x among them).
    let crawler = {
        let mut model = Model::from_toml(include_str!("../tables/models/crawler.toml")).unwrap();
        model.set_beyond_leading(3);
        let names = theory_search::dynamics::nonlinear::coefficient_names(&model, 4).unwrap();
        let active: Vec<&String> = names.iter().filter(|n| n.starts_with('a')).collect();
        assert!(active.len() > 2, "the crawler's active forces: {names:?}");
        let mut v = theory_search::dynamics::default_coefficients(
            &model,
            4,
            &theory_search::params::Params::default(),
        )
        .unwrap();
        for (i, n) in active.iter().enumerate() {
            v.insert((*n).clone(), 0.3 * if i % 2 == 0 { 1.0 } else { -1.0 });
        }
        NonlinearBody::new(&model, 4, 30, &v).unwrap()
    };
    for body in [ring(65, 1.0, 0.05, 0.2), crawler] {
        let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
            .fields
            .iter()
            .map(|f| {
                let u: Vec<f64> = (0..f.unknowns)
                    .map(|j| 0.3 * (0.4 * j as f64).sin())
                    .collect();
                let v: Vec<f64> = (0..f.unknowns)
                    .map(|j| 0.2 * (0.25 * j as f64).cos())
                    .collect();
                (u, v)
            })
            .collect();
        let mut integrator = body.integrator(0.05);
        let (mut worst, mut injected) = (0.0f64, 0.0f64);
        for step in 0..400 {
            let e0 = body.energy(&state);
            let (d0, i0) = integrator.work();
            integrator.step(&mut state, step as f64 * 0.05).unwrap();
            let (d1, i1) = integrator.work();
            let e1 = body.energy(&state);
            let gap = (e1 - e0) - (-(d1 - d0) + (i1 - i0));
            worst = worst.max(gap.abs() / e0.abs().max(1e-300));
            injected += (i1 - i0).abs();
        }
        assert!(injected > 0.0, "the active forces did work");
        assert!(
            worst < 1e-8,
            "energy balance off by {worst:e} of E in a step"
        );
    }
}

#[test]
fn the_linearisation_gives_the_discrete_dispersion_relation_as_complex_roots() {
    let (points, c, a) = (21, 1.0, 0.05);
    let fields = ring(points, c, 0.0, a).linearise(false).unwrap();
    let roots = &fields[0].damped;
    assert!(fields[0].active);
    let n = points - 1;
    for m in 1..n / 2 {
        let k = 2.0 * std::f64::consts::PI * m as f64 / n as f64;
        let s2 = (2.0 * (k / 2.0).sin()).powi(2);
        // ∂s⁴ → (2 sin k/2)⁴, ∂s³ → −i sin k (2 sin k/2)² on e^{ikj}.
        let w = Complex64::new(c * s2 * s2, a * k.sin() * s2).sqrt();
        for growth in [w.im, -w.im] {
            assert!(
                roots
                    .iter()
                    .any(|r| (r.frequency - w.re).abs() < 1e-9 * w.re
                        && (r.decay_rate + growth).abs() < 1e-9 * w.re),
                "m = {m}: no root ω = {}, σ = {} among {roots:?}",
                w.re,
                -growth
            );
        }
    }
}

#[test]
fn the_linearised_operators_carry_the_active_forces_matrices() {
    // `operators` of a driven body: A = ∂f/∂u is a·(the centred ∂s³ stencil) around the ring,
    // B = ∂f/∂v is g·(the centred ∂s stencil); neither symmetric.
    let (points, a, g) = (9, 0.3, -0.2);
    let model = Model::from_toml(RING).unwrap();
    let v = values(&[("c_y", 1.0), ("c'_y", 0.1), ("a_y", a), ("g_y", g)]);
    let body = NonlinearBody::new(&model, 4, points, &v).unwrap();
    let ops = body.linearised_operators().unwrap();
    let [da, db] = ops[0].active.as_ref().expect("active matrices");
    let n = points - 1;
    let third = [-0.5, 1.0, 0.0, -1.0, 0.5];
    for i in 0..n {
        for j in 0..n {
            let offset = (j + n - i + 2) % n;
            let want_a = if offset < 5 { a * third[offset] } else { 0.0 };
            assert!(
                (da[i][j] - want_a).abs() < 1e-15,
                "A[{i}][{j}] = {}",
                da[i][j]
            );
            let want_b = match (j + n - i) % n {
                1 => 0.5 * g,
                k if k == n - 1 => -0.5 * g,
                _ => 0.0,
            };
            assert!(
                (db[i][j] - want_b).abs() < 1e-15,
                "B[{i}][{j}] = {}",
                db[i][j]
            );
        }
    }
}

#[test]
fn a_section_without_ost_keeps_inertia_out_of_every_numerical_command() {
    // Without OST the section admits ∂t³y: `equations` prints it (the model asked), but no
    // command integrates, linearises or emits it; each says why in one line, exit code 2.
    let text = RING.replace(
        "y = [\"OST\", \"TRAN\", \"REF\", \"ROT\", \"GAL\"]",
        "y = [\"TRAN\", \"REF\", \"ROT\", \"GAL\"]",
    );
    let dir_held = common::scratch("noost");
    let dir = dir_held.path();
    let path = dir.join("noost.toml");
    std::fs::write(&path, text).unwrap();
    let m = path.to_str().unwrap();
    let out = dir.join("emit");
    for args in [
        vec![
            "simulate", "-p", "10", "--steps", "2", "--model", m, "--param", "a1_y=1",
        ],
        vec!["modes", "-p", "10", "--model", m, "--param", "a1_y=1"],
        vec!["emit", "--model", m, "--out", out.to_str().unwrap()],
    ] {
        let (code, _, err) = common::binary(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.starts_with("error: field y: ∂ttt y") && err.contains("inertia"),
            "{err}"
        );
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    }
}

/// `modes` of the crawler's axial field with a∂s x against c∂s²x and no damping, as JSON.
fn crawler_axial(a: &str, points: &str) -> (String, serde_json::Value) {
    let mut args = vec![
        "modes",
        "-p",
        points,
        "--model",
        "tables/models/crawler.toml",
        "--param",
        a,
        "--param",
        "c_x=1",
        "--param",
        "cp_x=0",
    ];
    let (code, text, err) = common::binary(&args);
    assert_eq!(code, 0, "{err}");
    args.extend(["--format", "json"]);
    let (code, json, err) = common::binary(&args);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["fields"][0]["field"], "x");
    (text, v["fields"][0].clone())
}

/// Issue 52 item 7: on a free-ended body a∂s x + c∂s²x has a real spectrum (weight e^{as/c}),
/// and so does its centred stencil while |a| < 2c (lattice units). Past that, the roots grow at
/// every N, and `modes` says the growth is the grid's; below it nothing grows at 12 points and
/// nothing is said. A growth that moves by more than 20 % from N to 2N, or vanishes, is said to
/// be unconverged.
#[test]
fn growth_that_is_the_grids_is_said_to_be() {
    let (text, x) = crawler_axial("a_x=2.1", "12");
    let growth = &x["growth"];
    assert_eq!(growth["points"], 24, "{x}");
    assert_eq!(growth["grid_peclet"], true, "{x}");
    let g = growth["growth"].as_f64().unwrap();
    assert!(g > 0.1, "{x}");
    // σ < 0 is growth: the fastest growing root is the one reported.
    let fastest = x["damped"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| -r["decay_rate"].as_f64().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(fastest, g);
    assert!(text.contains("past its grid Péclet number"), "{text}");
    assert!(text.contains("the growth is the grid's"), "{text}");
    let (text, x) = crawler_axial("a_x=1.9", "12");
    assert!(x.get("growth").is_none(), "{x}");
    assert!(
        !text.contains("growth −σ") && !text.contains("Péclet"),
        "{text}"
    );
    // The comparison itself: within 20 % of the larger, or not (a vanishing growth included).
    use theory_search::dynamics::{check_growth, DampedMode, LinearisedField};
    let field = |rates: &[f64]| LinearisedField {
        field: "x".into(),
        equilibrium: vec![0.0],
        residual: 0.0,
        eigenvalues: vec![1.0],
        frequencies: vec![Some(1.0)],
        shapes: None,
        damped: rates
            .iter()
            .map(|&r| DampedMode {
                decay_rate: r,
                frequency: 1.0,
            })
            .collect(),
        active: true,
        growth: None,
        peclet: false,
    };
    for (at_n, at_2n, converged) in [
        (-0.2, -0.22, true),
        (-0.2, -0.26, false),
        (-0.2, 0.1, false),
        (-0.2, -0.1, false),
    ] {
        let mut fields = vec![field(&[0.5, at_n])];
        check_growth(&mut fields, 24, Some(&[field(&[at_2n, 0.3])]));
        let check = fields[0].growth.unwrap();
        assert_eq!(check.growth, -at_n);
        assert_eq!(check.doubled, Some((-at_2n).max(0.0)));
        assert_eq!(check.converged, converged, "{at_n} against {at_2n}");
    }
    // No growth, no check; 2N not solved, not converged.
    let mut fields = vec![field(&[0.5])];
    check_growth(&mut fields, 24, None);
    assert!(fields[0].growth.is_none());
    let mut fields = vec![field(&[-0.2])];
    check_growth(&mut fields, 24, None);
    assert!(!fields[0].growth.unwrap().converged);
}
