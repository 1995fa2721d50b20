//! `operators` of a nonlinear body: the operators of its linearisation, against the linear
//! operators the engine prints for the same squares and against hand-built matrices.

mod common;

use common::{cli, matrix};

fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&cli(args).unwrap()).unwrap()
}

#[test]
fn the_linearised_larva_has_the_linear_operators() {
    // The larva at the next order with its new terms off, linearised at rest: K = ω²D and
    // C = 2ζωD for each field's operator D of the linear command (ω = 1.5, ζ = 0.2 on s).
    let linear = json(&["operators", "-p", "7", "--format", "json"]);
    let next = json(&[
        "operators",
        "--beyond-leading",
        "1",
        "-p",
        "7",
        "--param",
        "omega_s=1.5",
        "--param",
        "zeta_s=0.2",
        "--format",
        "json",
    ]);
    assert_eq!(next["linearised"], true);
    for f in next["fields"].as_array().unwrap() {
        let id = f["field"].as_str().unwrap();
        let scale = if id == "x" {
            (2.25, 2.0 * 0.2 * 1.5)
        } else {
            (1.0, 0.2)
        };
        let ops = linear["operators"].as_array().unwrap();
        for (density, key, factor) in [
            ("lagrangian", "stiffness", scale.0),
            ("rayleigh", "damping", scale.1),
        ] {
            let d = ops
                .iter()
                .find(|o| o["field"] == id && o["density"] == density)
                .unwrap();
            let (want, got) = (matrix(&d["matrix"]), matrix(&f[key]));
            assert_eq!(want.len(), got.len(), "{id} {key}");
            for (a, b) in want.iter().flatten().zip(got.iter().flatten()) {
                assert!(
                    (factor * a - b).abs() < 1e-12,
                    "{id} {key}: {b} against {}",
                    factor * a
                );
            }
        }
    }
}

#[test]
fn the_linearised_tethered_filament_has_its_curvature_and_friction() {
    // ∇V = ½c1 + c2u + 2c4u³ = 0 at each point: K = (c2 + 6c4u*²)·I; R = c'(∂ts u)² gives
    // C = 2c'·ΔᵀΔ with Δ the free first difference.
    let model = format!("{}/tables/models/tethered.toml", env!("CARGO_MANIFEST_DIR"));
    let v = json(&[
        "operators",
        "--model",
        &model,
        "-p",
        "5",
        "--param",
        "c1_u=1",
        "--param",
        "c2_u=1",
        "--param",
        "c4_u=0.5",
        "--param",
        "cp_u=0.3",
        "--format",
        "json",
    ]);
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
    let k = 1.0 + 3.0 * lo * lo;
    for (i, row) in matrix(&f["stiffness"]).iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            let want = if i == j { k } else { 0.0 };
            assert!((x - want).abs() < 1e-12, "K[{i}][{j}] = {x}, want {want}");
        }
    }
    for (i, row) in matrix(&f["damping"]).iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            // ΔᵀΔ of the free first difference on 5 points.
            let dtd = match (i, j) {
                _ if i == j && (i == 0 || i == 4) => 1.0,
                _ if i == j => 2.0,
                _ if i.abs_diff(j) == 1 => -1.0,
                _ => 0.0,
            };
            assert!((x - 0.6 * dtd).abs() < 1e-12, "C[{i}][{j}] = {x}");
        }
    }
    // The text and CSV say the same.
    let text = cli(&["operators", "--model", &model, "-p", "3"]).unwrap();
    assert!(text.contains("stiffness K = ∇²V(u*) · 3×3"), "{text}");
    let csv = cli(&["operators", "--model", &model, "-p", "3", "--format", "csv"]).unwrap();
    assert!(
        csv.starts_with("field,matrix,row,column,value\nu,stiffness,0,0,"),
        "{csv}"
    );
    // A linear body's operators take no coefficient.
    let err = cli(&["operators", "-p", "4", "--param", "c_y=1"]).unwrap_err();
    assert!(err.contains("no coefficients"), "{err}");
}

#[test]
fn every_shipped_model_runs_through_every_numerical_command() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models");
    let out = common::scratch("emit");
    let out = out.path().to_str().unwrap();
    let mut seen = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let path = path.to_str().unwrap();
        for command in [
            &["operators", "-p", "12"][..],
            &["modes", "-p", "12"],
            &["simulate", "-p", "12", "--steps", "20"],
            &["emit", "--out", out],
        ] {
            let mut args = command.to_vec();
            args.extend(["--model", path]);
            cli(&args).unwrap_or_else(|e| panic!("{path}: {command:?}: {e}"));
        }
        // The emitted forces are the engine's, for this model.
        let forces = std::fs::read_to_string(format!("{out}/src/generated/forces.rs")).unwrap();
        let model = theory_search::model::Model::from_toml(&std::fs::read_to_string(path).unwrap())
            .unwrap();
        assert_eq!(
            forces,
            theory_search::codegen::forces_source(&model, 4).unwrap()
        );
        seen += 1;
    }
    assert!(seen >= 6, "{seen} models");
}

#[test]
fn a_linear_body_takes_its_printed_coefficients_as_scales() {
    // c = ω², c′ = ζω of the field's scale: the same run as with the scales themselves.
    let by_names = cli(&[
        "simulate",
        "-p",
        "9",
        "--param",
        "c_y=4",
        "--param",
        "cp_y=0.6",
        "--param",
        "c_z=4",
        "--initial",
        "y:3=0.5",
        "--steps",
        "300",
        "--every",
        "100",
    ])
    .unwrap();
    let by_scales = cli(&[
        "simulate",
        "-p",
        "9",
        "--param",
        "omega_b=2",
        "--param",
        "zeta_b=0.3",
        "--initial",
        "y:3=0.5",
        "--steps",
        "300",
        "--every",
        "100",
    ])
    .unwrap();
    assert_eq!(by_names, by_scales);
    let err = cli(&["modes", "-p", "9", "--param", "c_y=4", "--param", "c_z=2"]).unwrap_err();
    assert!(
        err.contains("omega_b") && err.contains("share this scale"),
        "{err}"
    );
    let err = cli(&["modes", "-p", "9", "--param", "c_y=-1"]).unwrap_err();
    assert!(err.contains("ω² > 0"), "{err}");
}
