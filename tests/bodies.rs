//! Every example body through every command: the model file is the only place an animal
//! exists, so each command must run on each body or refuse it in one line that says why (a
//! missing role, a field without the structure a behaviour needs).

use theory_search::dynamics::{simulate, Config};
use theory_search::modal::Params;
use theory_search::model::Model;

const BODIES: [&str; 6] = [
    "larva",
    "worm",
    "planar",
    "zebrafish",
    "channel_worm",
    "crawler",
];

fn model_path(name: &str) -> String {
    format!("{}/tables/models/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

mod common;

use common::in_process as run;

/// Which (body, command) pairs are refused, and a phrase the refusal must contain. Everything
/// else must succeed.
fn expected_refusal(body: &str, command: &str) -> Option<&'static str> {
    let no_axial_pair = "has no degenerate pair";
    match (body, command) {
        // Only the larva's axial field is periodic (the visceral piston).
        (b, "behave peristalsis" | "stats pair" | "asymmetry") if b != "larva" => {
            Some(no_axial_pair)
        }
        ("zebrafish", "behave self-righting") => Some("free at both ends"),
        ("planar", "behave rolling" | "behave rearing") => {
            Some("needs a dorsoventral field, and model \"planar\" has none")
        }
        ("planar", "behave self-righting") => {
            Some("needs a torsion field, and model \"planar\" has none")
        }
        ("crawler", "behave rolling" | "behave rearing") => {
            Some("needs a dorsoventral field, and model \"crawler\" has none")
        }
        ("crawler", "behave self-righting") => {
            Some("needs a torsion field, and model \"crawler\" has none")
        }
        _ => None,
    }
}

/// Lateral midlines of `body` at ω_b = 1, ζ_b = 0.05, as CSV text `t,x1,y1,…` (head last).
fn midlines(body: &str, points: usize) -> String {
    let model = Model::from_toml(&std::fs::read_to_string(model_path(body)).unwrap()).unwrap();
    let lateral = model
        .fields
        .iter()
        .position(|f| f.role == Some(theory_search::model::Role::Lateral))
        .unwrap();
    let mut params = Params::default();
    for f in &model.fields {
        params.set(&format!("zeta_{}", f.scale()), 0.05).unwrap();
    }
    let config = Config {
        points,
        order: 4,
        dt: 0.5,
        steps: 40_000,
        every: 1,
        temperature: 1e-4,
        seed: 5,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    let mut text = String::new();
    simulate(&model, &params, &config, |s| {
        let y = &s.positions[lateral];
        text += &s.t.to_string();
        for (j, v) in y.iter().enumerate() {
            text += &format!(",{j},{v}");
        }
        text.push('\n');
        Ok(())
    })
    .unwrap();
    text
}

#[test]
fn every_body_runs_every_command() {
    for body in BODIES {
        let m = model_path(body);
        let dir_held = common::scratch(&format!("bodies-{body}"));
        let dir = dir_held.path();
        let data = dir.join("midlines.csv");
        std::fs::write(&data, midlines(body, 12)).unwrap();
        let (figs, gen) = (dir.join("figures"), dir.join("emit"));
        let commands: Vec<(&str, Vec<&str>)> = vec![
            ("table", vec!["--model", &m]),
            ("equations", vec!["equations", "--model", &m]),
            ("operators", vec!["operators", "-p", "8", "--model", &m]),
            (
                "modes",
                vec!["modes", "-p", "12", "--model", &m, "--shapes"],
            ),
            (
                "modes csv",
                vec!["modes", "-p", "12", "--model", &m, "--format", "csv"],
            ),
            (
                "simulate",
                vec!["simulate", "-p", "8", "--steps", "3", "--model", &m],
            ),
            (
                "interactions",
                vec!["interactions", "--order", "3", "--model", &m],
            ),
            ("parts", vec!["parts", "--model", &m]),
            (
                "asymmetry",
                vec!["asymmetry", "--coupling", "0.1", "--model", &m],
            ),
            (
                "asymmetry ω",
                vec![
                    "asymmetry",
                    "--coupling",
                    "0.1",
                    "--omega",
                    "1",
                    "--model",
                    &m,
                ],
            ),
            (
                "behave peristalsis",
                vec!["behave", "peristalsis", "--periods", "3", "--model", &m],
            ),
            (
                "behave rolling",
                vec!["behave", "rolling", "--periods", "3", "--model", &m],
            ),
            ("behave rearing", vec!["behave", "rearing", "--model", &m]),
            ("behave hunching", vec!["behave", "hunching", "--model", &m]),
            (
                "behave self-righting",
                vec!["behave", "self-righting", "--model", &m],
            ),
            (
                "stats explore",
                vec!["stats", "explore", "--samples", "2000", "--model", &m],
            ),
            (
                "stats equipartition",
                vec!["stats", "equipartition", "--steps", "3000", "--model", &m],
            ),
            (
                "stats pair",
                vec!["stats", "pair", "--beta", "2", "--model", &m],
            ),
            (
                "figures",
                vec![
                    "figures",
                    "--out",
                    figs.to_str().unwrap(),
                    "--samples",
                    "2000",
                    "--model",
                    &m,
                ],
            ),
            (
                "fit",
                vec![
                    "fit",
                    data.to_str().unwrap(),
                    "--model",
                    &m,
                    "--format",
                    "json",
                ],
            ),
            ("count", vec!["count", "--max-order", "3", "--model", &m]),
            ("rules", vec!["rules", "--model", &m]),
            (
                "emit",
                vec!["emit", "--out", gen.to_str().unwrap(), "--model", &m],
            ),
        ];
        for (name, args) in &commands {
            let got = run(args);
            match (expected_refusal(body, name), got) {
                (None, Ok(out)) => assert!(!out.is_empty(), "{body} {name}: no output"),
                (None, Err((code, msg))) => panic!("{body} {name}: refused ({code}): {msg}"),
                (Some(why), Ok(_)) => panic!("{body} {name}: ran, but should refuse ({why})"),
                (Some(why), Err((code, msg))) => {
                    assert_eq!(code, 2, "{body} {name}: {msg}");
                    assert!(!msg.contains('\n'), "{body} {name}: {msg}");
                    assert!(msg.contains(why), "{body} {name}: {msg:?} lacks {why:?}");
                }
            }
        }
        // The figures a body cannot make are skipped and named; the others are written.
        let listed = run(&commands[18].1).unwrap();
        let written = listed.lines().filter(|l| l.starts_with("wrote")).count();
        assert!(written >= 6, "{body}: {listed}");
    }
}

#[test]
fn fit_recovers_the_scale_of_a_held_body() {
    // ω_b = 1 in the simulation: the fit must find it through the body's own boundary.
    for body in ["zebrafish", "channel_worm", "larva"] {
        let dir_held = common::scratch(&format!("bodies-fit-{body}"));
        let dir = dir_held.path();
        let data = dir.join("m.csv");
        std::fs::write(&data, midlines(body, 12)).unwrap();
        let out = run(&[
            "fit",
            data.to_str().unwrap(),
            "--model",
            &model_path(body),
            "--format",
            "json",
            "--window",
            "2048",
            // Written in the model's order, tail first.
            "--head",
            "last",
        ])
        .unwrap();
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let omega = v["omega"].as_f64().unwrap();
        assert!((omega - 1.0).abs() < 0.05, "{body}: ω = {omega}");
    }
}

#[test]
fn a_missing_role_is_one_line_naming_role_and_command() {
    let dir_held = common::scratch("bodies-norole");
    let dir = dir_held.path();
    let path = dir.join("m.toml");
    let text = std::fs::read_to_string(model_path("zebrafish"))
        .unwrap()
        .replace("role = \"torsion\"\n", "");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap();
    let (code, msg) = run(&["behave", "self-righting", "--model", p]).unwrap_err();
    assert_eq!(code, 2);
    assert_eq!(
        msg,
        "behave self-righting needs a torsion field, and model \"zebrafish\" has none (give one field role = \"torsion\")"
    );
    // Two fields may not claim one role.
    let twice = std::fs::read_to_string(model_path("zebrafish"))
        .unwrap()
        .replace("role = \"torsion\"", "role = \"axial\"");
    std::fs::write(&path, twice).unwrap();
    let (code, msg) = run(&["modes", "-p", "8", "--model", p]).unwrap_err();
    assert_eq!(code, 1);
    assert!(msg.contains("both have role axial"), "{msg}");
}
