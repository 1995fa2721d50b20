//! A linear body whose damping is not modal: a free beam on a substrate, L_y = ½(∂t y)² −
//! ½c(∂ss y)² with viscous drag R_y = c′(∂t y)² (the planar body without Galilean invariance
//! in its Rayleigh density). The drag operator (the identity) is not the stiffness operator, so
//! the modal theory does not apply: `modes` solves the quadratic eigenproblem and `simulate`
//! takes the general path. Because C = 2c′·I commutes with K, the answer is known in closed
//! form and checks both: every root is λ = −c′ ± i√(κ − c′²) for each eigenvalue κ of K, and a
//! mode q(t) = e^{−c′t}(cos ω_d t + c′/ω_d sin ω_d t).

use serde_json::Value;

mod common;

use common::in_process;

/// The planar model with drag on its bending field, written to a temporary file.
fn drag_model() -> tempfile::NamedTempFile {
    let planar = include_str!("../tables/models/planar.toml");
    let drag = planar
        .replace("name = \"planar\"", "name = \"drag\"")
        .replace(
            "y = [\"DIS\", \"TRAN\", \"GAL\", \"REF\", \"SPIN\"]",
            "y = [\"DIS\", \"TRAN\", \"REF\"]",
        );
    assert_ne!(drag, planar.replace("name = \"planar\"", "name = \"drag\""));
    // One file per call, removed when dropped: tests run at once, and a file rewritten while
    // another test reads it reads empty.
    let file = common::scratch_file("drag", ".toml");
    std::fs::write(file.path(), drag).unwrap();
    file
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&in_process(args).unwrap()).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn the_drag_body_is_linear_but_not_modal() {
    let file = drag_model();
    let model = file.path().to_str().unwrap();
    let eq = in_process(&["--model", model]).unwrap();
    assert!(eq.contains("R_y = c'_y (∂t y)²"), "{eq}");
    // Behaviours need the modal theory and say so.
    let (code, err) = in_process(&["behave", "rolling", "--model", model]).unwrap_err();
    assert_eq!(code, 2);
    assert!(err.contains("needs the exact modal theory"), "{err}");
}

#[test]
fn every_root_is_minus_c_prime_plus_i_root_of_kappa_minus_c_prime_squared() {
    let file = drag_model();
    let model = file.path().to_str().unwrap();
    for (cp, args) in [(0.1, vec![]), (0.3, vec!["--param", "cp_y=0.3"])] {
        let mut all = vec!["modes", "-p", "10", "--model", model, "--format", "json"];
        all.extend(args);
        let v = json(&all);
        assert_eq!(v["nonlinear"], false);
        let y = &v["fields"][1];
        assert_eq!(y["field"], "y");
        let kappa = numbers(&y["eigenvalues"]);
        // Each κ gives a pair −c′ ± i√(κ − c′²), or two real roots −c′ ± √(c′² − κ).
        let mut want: Vec<(f64, f64)> = Vec::new();
        for k in &kappa {
            let d = k - cp * cp;
            if d > 0.0 {
                want.push((cp, d.sqrt()));
            } else {
                want.push((cp - (-d).sqrt(), 0.0));
                want.push((cp + (-d).sqrt(), 0.0));
            }
        }
        let got: Vec<(f64, f64)> = y["damped"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r["decay_rate"].as_f64().unwrap(),
                    r["frequency"].as_f64().unwrap(),
                )
            })
            .collect();
        assert_eq!(got.len(), want.len(), "{got:?} against {want:?}");
        for w in &want {
            assert!(
                got.iter()
                    .any(|g| (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9),
                "c′ = {cp}: no root near {w:?} in {got:?}"
            );
        }
    }
}

#[test]
fn a_mode_rings_down_as_the_closed_form_says() {
    let file = drag_model();
    let model = file.path().to_str().unwrap();
    let v = json(&[
        "modes", "-p", "10", "--model", model, "--format", "json", "--shapes",
    ]);
    let y = &v["fields"][1];
    let kappa = numbers(&y["eigenvalues"])[3];
    let shape = numbers(&y["shapes"][3]);
    let cp = 0.1;
    let wd = (kappa - cp * cp).sqrt();
    let (dt, steps) = (0.002, 2500);
    let out = in_process(&[
        "simulate",
        "-p",
        "10",
        "--model",
        model,
        "--initial",
        "y:3=1",
        "--dt",
        "0.002",
        "--steps",
        "2500",
        "--every",
        "500",
    ])
    .unwrap();
    let header: Vec<&str> = out.lines().next().unwrap().split(',').collect();
    let y0 = header.iter().position(|c| *c == "y_0").unwrap();
    for line in out.lines().skip(1) {
        let row: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        let t = row[0];
        let q = (-cp * t).exp() * ((wd * t).cos() + cp / wd * (wd * t).sin());
        for (j, s) in shape.iter().enumerate() {
            let got = row[y0 + j];
            assert!(
                (got - q * s).abs() < 2e-5,
                "t = {t}, point {j}: {got} against the closed form {}",
                q * s
            );
        }
    }
    assert!(out.lines().count() == 2 + steps / 500, "{dt}: {out}");
}
