//! Kinetic terms beyond ½(∂tφ)² (the next order of a body without Galilean invariance, e.g. the
//! worm: ½k2(∂ts x)² and k1(∂t x)⁴): the energy balance of the integrator, its order where T is
//! not quadratic, the linearisation's generalised eigenproblem K x = λ M x.

mod common;
use common::matrix;

use std::collections::BTreeMap;

use theory_search::dynamics::nonlinear::{coefficient_names, NonlinearBody};
use theory_search::model::Model;

fn worm() -> Model {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/worm.toml");
    let mut m = Model::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    m.lagrangian.beyond_leading = 1;
    m.rayleigh.beyond_leading = 1;
    m
}

fn body(set: &[(&str, f64)], points: usize) -> NonlinearBody {
    let model = worm();
    let mut values: BTreeMap<String, f64> = coefficient_names(&model, 4)
        .unwrap()
        .into_iter()
        .map(|n| (n, 0.0))
        .collect();
    for (k, v) in set {
        assert!(values.contains_key(*k), "{k}");
        values.insert(k.to_string(), *v);
    }
    NonlinearBody::new(&model, 4, points, &values).unwrap()
}

fn start(body: &NonlinearBody) -> Vec<(Vec<f64>, Vec<f64>)> {
    body.fields
        .iter()
        .map(|f| {
            let u = (0..f.unknowns)
                .map(|j| 0.3 * (0.8 * j as f64).sin())
                .collect();
            let v = (0..f.unknowns)
                .map(|j| 0.2 * (0.5 * j as f64).cos())
                .collect();
            (u, v)
        })
        .collect()
}

#[test]
fn a_quadratic_kinetic_energy_keeps_the_exact_energy_balance() {
    // T = ½|v|² + ½k2 Σ(Δv)²: with the cubic stress on and the dissipation of each field,
    // E₁ − E₀ = −h v̄·∇R(v̄) to rounding, step by step.
    let body = body(
        &[
            ("c1_x", 1.0),
            ("c2_x", 0.7),
            ("k2_x", 0.5),
            ("c'1_x", 0.05),
            ("c1_θ", 1.0),
            ("k2_θ", 0.3),
            ("c_y", 1.0),
            ("c_z", 1.0),
        ],
        10,
    );
    let h = 0.02;
    let mut state = start(&body);
    let mut integrator = body.integrator(h);
    for step in 0..2000 {
        let before = state.clone();
        let e0 = body.energy(&state);
        integrator.step(&mut state, step as f64 * h).unwrap();
        let mut lost = 0.0;
        for (f, ((_, v0), (_, v1))) in body.fields.iter().zip(before.iter().zip(&state)) {
            let mean: Vec<f64> = v0.iter().zip(v1).map(|(a, b)| 0.5 * (a + b)).collect();
            let g = f.dissipation_gradient(&mean);
            lost += h * mean.iter().zip(&g).map(|(a, b)| a * b).sum::<f64>();
        }
        let e1 = body.energy(&state);
        assert!(
            (e1 - e0 + lost).abs() < 1e-12 * e0.abs().max(1.0),
            "step {step}: ΔE = {} against −{lost}",
            e1 - e0
        );
    }
}

#[test]
fn a_quartic_kinetic_energy_holds_energy_to_second_order() {
    // T ⊃ k1 v⁴: the scheme is second order, not exactly conservative: the energy error after
    // a fixed time falls fourfold when h halves.
    let drift = |h: f64| {
        let body = body(&[("c1_x", 1.0), ("k1_x", 0.4), ("c_y", 1.0)], 8);
        let mut state = start(&body);
        let e0 = body.energy(&state);
        let mut integrator = body.integrator(h);
        let steps = (4.0 / h).round() as usize;
        for step in 0..steps {
            integrator.step(&mut state, step as f64 * h).unwrap();
        }
        (body.energy(&state) - e0).abs()
    };
    let (coarse, fine) = (drift(0.04), drift(0.02));
    assert!(coarse > 1e-9, "the quartic term acts: {coarse}");
    let ratio = coarse / fine;
    assert!((3.0..5.5).contains(&ratio), "{coarse} / {fine} = {ratio}");
}

fn cli(args: &[&str]) -> String {
    common::cli(args).unwrap()
}

#[test]
fn the_linearised_modes_solve_the_generalised_eigenproblem() {
    // K x = λ M x with K, M from `operators`, x and λ from `modes`: two commands, one identity.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/worm.toml");
    let common = [
        "--model",
        path,
        "--beyond-leading",
        "1",
        "-p",
        "9",
        "--param",
        "k2_x=0.5",
    ];
    let mut ops = vec!["operators", "--format", "json"];
    ops.extend(common);
    let mut modes = vec!["modes", "--shapes", "--format", "json"];
    modes.extend(common);
    let ops: serde_json::Value = serde_json::from_str(&cli(&ops)).unwrap();
    let modes: serde_json::Value = serde_json::from_str(&cli(&modes)).unwrap();
    let x = &ops["fields"][0];
    assert_eq!(x["field"], "x");
    let (k, m) = (matrix(&x["stiffness"]), matrix(&x["mass"]));
    assert!(m[0][0] > 1.0, "a mass beyond the identity: {}", m[0][0]);
    let f = &modes["fields"][0];
    let shapes = matrix(&f["shapes"]);
    for (lambda, s) in f["eigenvalues"].as_array().unwrap().iter().zip(&shapes) {
        let lambda = lambda.as_f64().unwrap();
        let norm: f64 = (0..9)
            .map(|i| (0..9).map(|j| s[i] * m[i][j] * s[j]).sum::<f64>())
            .sum();
        assert!((norm - 1.0).abs() < 1e-12, "xᵀMx = {norm}");
        for i in 0..9 {
            let kx: f64 = (0..9).map(|j| k[i][j] * s[j]).sum();
            let mx: f64 = (0..9).map(|j| m[i][j] * s[j]).sum();
            assert!(
                (kx - lambda * mx).abs() < 1e-12,
                "row {i}: {kx} against λ·{mx}"
            );
        }
    }
}

#[test]
fn noise_is_refused_with_a_kinetic_energy_that_is_not_quadratic() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/worm.toml");
    let mut out = Vec::new();
    let err = theory_search::cli::run(
        [
            "theory-search",
            "simulate",
            "--model",
            path,
            "--beyond-leading",
            "1",
            "-p",
            "8",
            "--param",
            "k1_x=0.1",
            "--temperature",
            "0.1",
        ],
        &mut out,
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("Langevin noise needs a kinetic energy quadratic"),
        "{err}"
    );
}
