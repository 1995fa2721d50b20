//! The nonlinear integrator (`dynamics::nonlinear`) against independent oracles: the Duffing
//! oscillator's exact period (an elliptic integral), energy held without dissipation, the
//! discrete energy balance with it, and a linear beam against RK4 on hand-built stencils.

mod common;
use common::cli;

use std::collections::BTreeMap;

use theory_search::dynamics::nonlinear::{coefficient_names, NonlinearBody};
use theory_search::model::Model;

fn tethered() -> Model {
    Model::from_toml(include_str!("../tables/models/tethered.toml")).unwrap()
}

fn values(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// K(k) by the arithmetic–geometric mean: π / (2 AGM(1, √(1 − k²))).
fn elliptic_k(k2: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k2).sqrt());
    // Quadratic convergence: a few rounds reach the last digit (a fixed count, since a and b
    // may then differ by an ulp for ever).
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn the_tethered_filament_is_a_duffing_oscillator_of_exact_period() {
    // ü = −c2 u − 2c4 u³ at every point: ü + u + u³ = 0 for c2 = 1, c4 = ½.
    let v = values(&[
        ("c1_u", 0.0),
        ("c2_u", 1.0),
        ("c3_u", 0.0),
        ("c4_u", 0.5),
        ("c'_u", 0.0),
    ]);
    let body = NonlinearBody::new(&tethered(), 4, 8, &v).unwrap();
    let amplitude = 0.7;
    let (alpha, beta) = (1.0, 1.0);
    let omega2 = alpha + beta * amplitude * amplitude;
    let k2 = beta * amplitude * amplitude / (2.0 * omega2);
    let period = 4.0 * elliptic_k(k2) / omega2.sqrt();
    let h = 1e-3;
    let mut state = vec![(vec![amplitude; 8], vec![0.0; 8])];
    let e0 = body.energy(&state);
    // Downward zero crossings of point 3, interpolated linearly.
    let mut crossings = Vec::new();
    let mut t = 0.0;
    let mut integrator = body.integrator(h);
    while crossings.len() < 4 {
        let before = state[0].0[3];
        integrator.step(&mut state, t).unwrap();
        t += h;
        let after = state[0].0[3];
        if before > 0.0 && after <= 0.0 {
            crossings.push(t - h + h * before / (before - after));
        }
        assert!(t < 10.0 * period, "no swing");
    }
    for w in crossings.windows(2) {
        let measured = w[1] - w[0];
        assert!(
            (measured / period - 1.0).abs() < 1e-5,
            "period {measured} against {period}"
        );
    }
    // Every point swings alike, and the energy is the Duffing energy, held.
    assert!(state[0].0.iter().all(|u| (u - state[0].0[0]).abs() < 1e-12));
    let duffing = 8.0 * (0.5 * amplitude.powi(2) + 0.25 * amplitude.powi(4));
    assert!(
        (e0 - duffing).abs() < 1e-12 * duffing,
        "{e0} against {duffing}"
    );
    assert!((body.energy(&state) - e0).abs() < 1e-10 * e0);
}

#[test]
fn energy_is_held_over_a_hundred_thousand_steps_without_dissipation() {
    let v = values(&[
        ("c1_u", 0.2),
        ("c2_u", 1.0),
        ("c3_u", 0.3),
        ("c4_u", 0.5),
        ("c'_u", 0.0),
    ]);
    let body = NonlinearBody::new(&tethered(), 4, 8, &v).unwrap();
    let u0: Vec<f64> = (0..8).map(|j| 0.3 * (j as f64).sin()).collect();
    let v0: Vec<f64> = (0..8).map(|j| 0.2 * (0.7 * j as f64).cos()).collect();
    let mut state = vec![(u0, v0)];
    let e0 = body.energy(&state);
    let mut t = 0.0;
    let mut integrator = body.integrator(0.05);
    for _ in 0..100_000 {
        integrator.step(&mut state, t).unwrap();
        t += 0.05;
    }
    let drift = (body.energy(&state) - e0).abs() / e0.abs();
    assert!(drift < 1e-8, "relative energy drift {drift}");
}

#[test]
fn the_larva_at_the_next_order_keeps_its_energy_balance() {
    // Every coefficient the next-order equations name; the cubic stress c2 included.
    let mut model = Model::larva();
    model.lagrangian.beyond_leading = 1;
    model.rayleigh.beyond_leading = 1;
    let names = coefficient_names(&model, 4).unwrap();
    assert!(names.iter().any(|n| n == "c2_x"), "{names:?}");
    let v: BTreeMap<String, f64> = names
        .iter()
        .map(|n| (n.clone(), if n.starts_with("c'") { 0.05 } else { 1.0 }))
        .collect();
    let body = NonlinearBody::new(&model, 4, 12, &v).unwrap();
    assert_eq!(body.fields.len(), 4);
    let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
        .fields
        .iter()
        .map(|f| {
            let u = (0..f.unknowns)
                .map(|j| 0.2 * (0.9 * j as f64).sin())
                .collect();
            (u, vec![0.0; f.unknowns])
        })
        .collect();
    let h = 0.01;
    let (mut t, e0) = (0.0, body.energy(&state));
    let mut dissipated = 0.0;
    let mut integrator = body.integrator(h);
    for _ in 0..2000 {
        let before = state.clone();
        integrator.step(&mut state, t).unwrap();
        t += h;
        // Discrete balance: E₁ − E₀ = −h v̄·∇R(v̄), field by field.
        for (f, ((_, v0), (_, v1))) in body.fields.iter().zip(before.iter().zip(&state)) {
            let mean: Vec<f64> = v0.iter().zip(v1).map(|(a, b)| 0.5 * (a + b)).collect();
            let g = f.dissipation_gradient(&mean);
            dissipated += h * mean.iter().zip(&g).map(|(a, b)| a * b).sum::<f64>();
        }
    }
    let e1 = body.energy(&state);
    assert!(e1 < 0.5 * e0, "the damping acts: {e0} → {e1}");
    assert!(
        (e1 - e0 + dissipated).abs() < 1e-10 * e0,
        "E₁ − E₀ = {} against −{dissipated}",
        e1 - e0
    );
}

#[test]
fn a_linear_beam_agrees_with_rk4_on_hand_built_stencils() {
    // The larva's y: ÿ = −c DY − 2c' DẎ, D = SᵀS with S the second differences that fit.
    let (c, damping, n) = (1.0, 0.03, 10);
    let larva = Model::larva();
    let v: BTreeMap<String, f64> = coefficient_names(&larva, 4)
        .unwrap()
        .into_iter()
        .map(|name| {
            let value = match name.as_str() {
                "c_y" => c,
                "c'_y" => damping,
                other if other.starts_with("c'") => 0.0,
                _ => 1.0,
            };
            (name, value)
        })
        .collect();
    assert!(v.contains_key("c_y") && v.contains_key("c'_y"), "{v:?}");
    let body = NonlinearBody::new(&larva, 4, n, &v).unwrap();
    let y = body.fields.iter().position(|f| f.id == "y").unwrap();
    let mut d = vec![vec![0.0; n]; n];
    for r in 0..n - 2 {
        let row = [(r, 1.0), (r + 1, -2.0), (r + 2, 1.0)];
        for &(i, a) in &row {
            for &(j, b) in &row {
                d[i][j] += a * b;
            }
        }
    }
    let apply = |x: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| d[i][j] * x[j]).sum())
            .collect()
    };
    let force = |q: &[f64], p: &[f64]| -> Vec<f64> {
        let (dq, dp) = (apply(q), apply(p));
        (0..n).map(|i| -c * dq[i] - 2.0 * damping * dp[i]).collect()
    };
    let q0: Vec<f64> = (0..n).map(|j| 0.1 * (0.5 * j as f64).cos()).collect();
    let (mut q, mut p) = (q0.clone(), vec![0.0; n]);
    let k = 1e-4;
    for _ in 0..20_000 {
        let a1 = force(&q, &p);
        let (q2, p2): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| (q[i] + 0.5 * k * p[i], p[i] + 0.5 * k * a1[i]))
            .unzip();
        let a2 = force(&q2, &p2);
        let (q3, p3): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| (q[i] + 0.5 * k * p2[i], p[i] + 0.5 * k * a2[i]))
            .unzip();
        let a3 = force(&q3, &p3);
        let (q4, p4): (Vec<f64>, Vec<f64>) =
            (0..n).map(|i| (q[i] + k * p3[i], p[i] + k * a3[i])).unzip();
        let a4 = force(&q4, &p4);
        for i in 0..n {
            q[i] += k / 6.0 * (p[i] + 2.0 * p2[i] + 2.0 * p3[i] + p4[i]);
            p[i] += k / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
        }
    }
    let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
        .fields
        .iter()
        .map(|f| (vec![0.0; f.unknowns], vec![0.0; f.unknowns]))
        .collect();
    state[y].0 = q0;
    let h = 5e-4;
    let mut t = 0.0;
    let mut integrator = body.integrator(h);
    for _ in 0..4000 {
        integrator.step(&mut state, t).unwrap();
        t += h;
    }
    let error = state[y]
        .0
        .iter()
        .zip(&q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(error < 1e-6, "max |y − y_RK4| = {error}");
    assert!(q.iter().any(|x| x.abs() > 1e-3), "the beam moved");
}

#[test]
fn missing_and_unsupported_say_so() {
    let err = NonlinearBody::new(&tethered(), 4, 8, &values(&[("c1_u", 1.0)]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("c2_u has no value"), "{err}");
    assert!(err.contains("c1_u, c2_u, c3_u, c4_u, c'_u"), "{err}");
    let v = values(&[
        ("c1_u", 0.0),
        ("c2_u", f64::NAN),
        ("c3_u", 0.0),
        ("c4_u", 0.0),
        ("c'_u", 0.0),
    ]);
    let err = NonlinearBody::new(&tethered(), 4, 8, &v)
        .unwrap_err()
        .to_string();
    assert!(err.contains("not a finite number"), "{err}");
}

#[test]
fn simulate_swings_the_tethered_filament_with_the_duffing_period() {
    let model = format!("{}/tables/models/tethered.toml", env!("CARGO_MANIFEST_DIR"));
    // The command, with the prime spelled in ASCII too (`cp_u`).
    let csv = cli(&[
        "simulate",
        "--model",
        &model,
        "--points",
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
        "cp_u=0.2",
        "--initial",
        "u=0.7",
        "--dt",
        "0.001",
        "--steps",
        "20000",
        "--every",
        "1",
    ])
    .unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(
        csv.lines().next().unwrap(),
        "t,energy,u_0,u_1,u_2,u_3,u_4,u_5,u_6,u_7"
    );
    let e0 = rows[0][1];
    assert!(
        rows.iter().all(|r| (r[1] - e0).abs() < 1e-10 * e0),
        "energy held"
    );
    let up: Vec<f64> = rows
        .windows(2)
        .filter(|w| w[0][2] < 0.0 && w[1][2] >= 0.0)
        .map(|w| w[0][0] + (w[1][0] - w[0][0]) * w[0][2] / (w[0][2] - w[1][2]))
        .collect();
    let omega2: f64 = 1.0 + 0.49;
    let period = 4.0 * elliptic_k(0.49 / (2.0 * omega2)) / omega2.sqrt();
    assert!(up.len() >= 2, "{up:?}");
    assert!(
        ((up[1] - up[0]) / period - 1.0).abs() < 1e-5,
        "{up:?} against {period}"
    );
}

#[test]
fn simulate_runs_the_larva_at_the_next_order_and_refuses_what_it_cannot() {
    let csv = cli(&[
        "simulate",
        "--beyond-leading",
        "1",
        "-p",
        "12",
        "--param",
        "c2_x=5",
        "--initial",
        "x:1=0.3",
        "--steps",
        "500",
        "--every",
        "100",
    ])
    .unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    let energies: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(
        energies.windows(2).all(|w| w[1] < w[0]),
        "damped: {energies:?}"
    );
    for (args, says) in [
        (
            vec!["--temperature", "0.1", "--param", "c'2_x=-1"],
            "Langevin noise needs",
        ),
        (vec!["--param", "c9_x=1"], "coefficients: c1_x"),
        (vec!["--initial", "w=1"], "unknown field \"w\""),
        (vec!["--initial", "x:40=1"], "has modes 0…10"),
        (vec!["--steps", "100000000"], "a run may take"),
    ] {
        let mut all = vec!["simulate", "--beyond-leading", "1", "-p", "12"];
        all.extend(args);
        let err = cli(&all).unwrap_err();
        assert!(err.contains(says), "{err}");
    }
    // A linear body keeps its modal path, and says what a uniform state is for.
    let err = cli(&["simulate", "-p", "12", "--initial", "y=1"]).unwrap_err();
    assert!(err.contains("for a nonlinear body"), "{err}");
}

#[test]
fn modes_of_a_nonlinear_body_are_those_of_its_linearisation() {
    let model = format!("{}/tables/models/tethered.toml", env!("CARGO_MANIFEST_DIR"));
    // ∇V = ½c1 + c2 u + 2c4 u³ = 0 at every point: the real root, by bisection.
    let json = cli(&[
        "modes", "--model", &model, "-p", "5", "--param", "c1_u=1", "--param", "c2_u=1", "--param",
        "c4_u=0.5", "--format", "json",
    ])
    .unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let f = &v["fields"][0];
    let (mut lo, mut hi) = (-2.0f64, 2.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 0.5 + mid + mid.powi(3) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    for u in f["equilibrium"].as_array().unwrap() {
        assert!((u.as_f64().unwrap() - lo).abs() < 1e-12, "{u} against {lo}");
    }
    let stiffness = 1.0 + 3.0 * lo * lo;
    for l in f["eigenvalues"].as_array().unwrap() {
        assert!((l.as_f64().unwrap() - stiffness).abs() < 1e-12, "{l}");
    }
    // The larva at the next order with only its leading squares: the linear modes, by another
    // solver (the modal one) at ω = 1.
    let lin: serde_json::Value =
        serde_json::from_str(&cli(&["modes", "-p", "9", "--format", "json"]).unwrap()).unwrap();
    let next: serde_json::Value = serde_json::from_str(
        &cli(&[
            "modes",
            "--beyond-leading",
            "1",
            "-p",
            "9",
            "--format",
            "json",
        ])
        .unwrap(),
    )
    .unwrap();
    assert_eq!(next["linearised"], true);
    let fields = lin["fields"].as_array().unwrap();
    for (k, f) in next["fields"].as_array().unwrap().iter().enumerate() {
        let want: Vec<f64> = fields[k]["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_f64().unwrap())
            .collect();
        let got: Vec<f64> = f["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(got.len(), want.len(), "field {k}");
        for (a, b) in got.iter().zip(&want) {
            assert!(
                (a - b).abs() < 1e-9 * (1.0 + b.abs()),
                "field {k}: {a} against {b}"
            );
        }
    }
}

#[test]
fn the_tethered_filament_agrees_with_rk4_on_its_printed_equation() {
    // `equations --model tethered.toml` prints ∂t²u = −½c1 − c2 u + 2c' ∂t∂s²u − 3/2 c3 u²
    // − 2c4 u³. RK4 on that equation, discretised by hand (∂t∂s² of the velocity: the second
    // difference, one-sided at the free ends, the natural condition), against the implicit
    // integrator with every coefficient on.
    let printed = cli(&[
        "equations",
        "--model",
        concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml"),
    ])
    .unwrap();
    assert!(
        printed.contains("∂t² u = −1/2 c1_u − c2_u u + 2 c'_u ∂t∂s² u − 3/2 c3_u u² − 2 c4_u u³"),
        "{printed}"
    );
    let (c1, c2, c3, c4, cp) = (0.4, 1.3, 0.2, 0.5, 0.15);
    let v = values(&[
        ("c1_u", c1),
        ("c2_u", c2),
        ("c3_u", c3),
        ("c4_u", c4),
        ("c'_u", cp),
    ]);
    let n = 7;
    let body = NonlinearBody::new(&tethered(), 4, n, &v).unwrap();
    let accel = |u: &[f64], w: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| {
                // Σ of the differences to the neighbours there are: w_{i−1} − 2w_i + w_{i+1}
                // inside, w_{i±1} − w_i at an end.
                let mut lap = 0.0;
                if i > 0 {
                    lap += w[i - 1] - w[i];
                }
                if i + 1 < n {
                    lap += w[i + 1] - w[i];
                }
                -0.5 * c1 - c2 * u[i] + 2.0 * cp * lap
                    - 1.5 * c3 * u[i] * u[i]
                    - 2.0 * c4 * u[i].powi(3)
            })
            .collect()
    };
    let u0: Vec<f64> = (0..n).map(|j| 0.5 * (0.9 * j as f64).cos()).collect();
    let w0: Vec<f64> = (0..n).map(|j| 0.3 * (1.3 * j as f64).sin()).collect();
    let (mut q, mut p) = (u0.clone(), w0.clone());
    let k = 1e-3;
    let steps = 5000;
    for _ in 0..steps {
        let a1 = accel(&q, &p);
        let (q2, p2): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| (q[i] + 0.5 * k * p[i], p[i] + 0.5 * k * a1[i]))
            .unzip();
        let a2 = accel(&q2, &p2);
        let (q3, p3): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| (q[i] + 0.5 * k * p2[i], p[i] + 0.5 * k * a2[i]))
            .unzip();
        let a3 = accel(&q3, &p3);
        let (q4, p4): (Vec<f64>, Vec<f64>) =
            (0..n).map(|i| (q[i] + k * p3[i], p[i] + k * a3[i])).unzip();
        let a4 = accel(&q4, &p4);
        for i in 0..n {
            q[i] += k / 6.0 * (p[i] + 2.0 * p2[i] + 2.0 * p3[i] + p4[i]);
            p[i] += k / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
        }
    }
    let mut state = vec![(u0, w0)];
    let mut integrator = body.integrator(k);
    for step in 0..steps {
        integrator.step(&mut state, step as f64 * k).unwrap();
    }
    for i in 0..n {
        // The midpoint scheme is second order: 5 time units at h = 10⁻³.
        assert!(
            (state[0].0[i] - q[i]).abs() < 1e-6 && (state[0].1[i] - p[i]).abs() < 1e-6,
            "point {i}: ({}, {}) against RK4 ({}, {})",
            state[0].0[i],
            state[0].1[i],
            q[i],
            p[i]
        );
    }
}
