//! Text from a model file never becomes code: hostile names, symbols and meanings are refused
//! when they could end a line, and otherwise reach the generated source only as escaped string
//! literals or comments. The generated code is compiled with rustc against a stub of
//! `src/generated/mod.rs` and its items are counted.

mod common;

use std::process::Command;

use theory_search::codegen::operators_source;
use theory_search::discretise::plan;
use theory_search::model::Model;

const PLANAR: &str = include_str!("../tables/models/planar.toml");

/// The planar model with field x's symbol and meaning and the model's name replaced.
fn hostile(symbol: &str, meaning: &str, name: &str) -> String {
    let quote = |s: &str| toml::Value::String(s.into()).to_string();
    PLANAR
        .replacen("symbol = \"x\"", &format!("symbol = {}", quote(symbol)), 1)
        .replacen(
            "meaning = \"axial displacement\"",
            &format!("meaning = {}", quote(meaning)),
            1,
        )
        .replacen("name = \"planar\"", &format!("name = {}", quote(name)), 1)
}

const STUB: &str = r#"
pub mod boundary {
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum End { Free, Pinned, Clamped }
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Boundary { Periodic, Ends { tail: End, head: End } }
    impl Boundary {
        pub const fn both(end: End) -> Boundary { Boundary::Ends { tail: end, head: end } }
    }
}
pub mod generated {
    #[derive(Debug)]
    pub enum OperatorError { TooFewPoints { points: usize, min: usize } }
    pub struct Banded;
    pub type ApplyFn = fn(usize, &[f64], &mut [f64]) -> Result<(), OperatorError>;
    pub struct GeneratedOperator {
        pub field: &'static str,
        pub density: &'static str,
        pub term: &'static str,
        pub boundary: crate::boundary::Boundary,
        pub k: u32,
        pub size: fn(usize) -> Result<usize, OperatorError>,
        pub apply: ApplyFn,
        pub dense: fn(usize) -> Result<Vec<Vec<f64>>, OperatorError>,
        pub banded: Option<fn(usize) -> Result<Banded, OperatorError>>,
    }
    pub struct Stencil {
        pub weights: &'static [f64],
        pub positions: fn(usize) -> usize,
        pub index: fn(usize, usize, usize) -> Option<usize>,
    }
    impl Stencil {
        pub fn apply(&self, _: usize, _: &[f64], _: &mut [f64]) -> Result<(), OperatorError> { Ok(()) }
        pub fn dense(&self, _: usize) -> Vec<Vec<f64>> { Vec::new() }
        pub fn banded(&self, _: usize) -> Banded { Banded }
    }
    pub mod operators;
}
pub fn entries() -> Vec<(&'static str, &'static str)> {
    generated::operators::OPERATORS.iter().map(|o| (o.field, o.term)).collect()
}
"#;

/// Compile `source` as `generated/operators.rs` under the stub; panics with rustc's errors.
fn compile(source: &str, _tag: &str) {
    let dir_held = common::scratch("hostile");
    let dir = dir_held.path();
    std::fs::create_dir_all(dir.join("generated")).unwrap();
    std::fs::write(dir.join("lib.rs"), STUB).unwrap();
    // The stub's `pub mod operators;` inside `mod generated` looks in generated/.
    std::fs::write(dir.join("generated/operators.rs"), source).unwrap();
    let out = Command::new("rustc")
        .args([
            "--edition",
            "2021",
            "--crate-type",
            "lib",
            "--emit",
            "metadata",
            "-o",
        ])
        .arg(dir.join("out.rmeta"))
        .arg(dir.join("lib.rs"))
        .output()
        .expect("rustc runs");
    assert!(
        out.status.success(),
        "generated code does not compile:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn hostile_text_stays_inside_literals_and_comments() {
    let cases = [
        (
            "x\"};//",
            "\"); } fn pwned() { // */ {{ op.field }} {% raw %}",
            "p\"w\\ned */",
        ),
        (
            "φ'\\",
            "GeneratedOperator { field: \"pwned\" }, //",
            "{{ model }}",
        ),
    ];
    for (i, (symbol, meaning, name)) in cases.iter().enumerate() {
        let model = Model::from_toml(&hostile(symbol, meaning, name))
            .unwrap_or_else(|e| panic!("case {i}: {e}"));
        let source = operators_source(&model, 4).unwrap();
        compile(&source, &i.to_string());
        // Exactly the planned entries, and no item but the generated ones.
        let planned = plan(&model, 4).unwrap().len();
        let entries = source
            .lines()
            .filter(|l| l.trim_start().starts_with("GeneratedOperator {"))
            .count();
        assert_eq!(entries, planned, "case {i}");
        for line in source.lines().map(str::trim_start) {
            if let Some(rest) = line.strip_prefix("pub fn ").or(line.strip_prefix("fn ")) {
                assert!(
                    ["size_", "apply_", "dense_", "banded_"]
                        .iter()
                        .any(|p| rest.starts_with(p)),
                    "case {i}: unexpected item {line}"
                );
            }
        }
        // The hostile words appear only in comments and inside string literals.
        for line in source.lines().filter(|l| l.contains("pwned")) {
            let t = line.trim_start();
            let quoted = t.find('"').is_some_and(|q| q < t.find("pwned").unwrap());
            assert!(t.starts_with("//") || quoted, "case {i}: {line}");
        }
    }
}

#[test]
fn text_that_could_end_a_line_is_refused_naming_the_key() {
    let newline = hostile(
        "x",
        "a\n GeneratedOperator { field: \"pwned\" },\n//",
        "planar",
    );
    let err = Model::from_toml(&newline).unwrap_err().to_string();
    assert!(
        err.contains("field \"x\" meaning contains the control character U+000A"),
        "{err}"
    );
    let symbol = hostile("x\ny", "axial", "planar");
    let err = Model::from_toml(&symbol).unwrap_err().to_string();
    assert!(err.contains("field \"x\" symbol"), "{err}");
    let long = hostile(&"x".repeat(17), "axial", "planar");
    let err = Model::from_toml(&long).unwrap_err().to_string();
    assert!(err.contains("at most 16"), "{err}");
    let id = PLANAR.replacen("id = \"x\"", "id = \"1x\"", 1);
    let err = Model::from_toml(&id).unwrap_err().to_string();
    assert!(err.contains("field id \"1x\""), "{err}");
    // The CLI says it in one line, exit 1.
    let dir_held = common::scratch("hostile-cli");
    let dir = dir_held.path();
    let path = dir.join("m.toml");
    std::fs::write(&path, &newline).unwrap();
    let mut out = Vec::new();
    let e = theory_search::cli::run(
        [
            "theory-search",
            "emit",
            "--out",
            dir.to_str().unwrap(),
            "--model",
            path.to_str().unwrap(),
        ],
        &mut out,
    )
    .unwrap_err();
    assert_eq!(e.exit_code(), 1);
    assert!(!e.to_string().contains('\n'));
    assert!(!dir.join("src").exists(), "nothing is written");
}

#[test]
fn invisible_formatting_characters_are_refused_and_markup_is_escaped() {
    // Bidirectional overrides and isolates, zero-width characters: rustc refuses them in a doc
    // comment, and a reader cannot see them.
    for c in ['\u{202E}', '\u{2066}', '\u{200B}', '\u{FEFF}', '\u{2028}'] {
        for (symbol, meaning, name) in [
            (format!("x{c}"), "axial".to_string(), "planar".to_string()),
            ("x".into(), format!("axial {c}"), "planar".into()),
            ("x".into(), "axial".into(), format!("plan{c}ar")),
        ] {
            let err = Model::from_toml(&hostile(&symbol, &meaning, &name))
                .unwrap_err()
                .to_string();
            assert!(
                err.contains(&format!(
                    "invisible formatting character U+{:04X}",
                    c as u32
                )),
                "{err}"
            );
        }
    }
    // Markup in a symbol stays inside its cell and math: the generated code still compiles.
    let model = Model::from_toml(&hostile("a|b_{}$", "axial", "pipes")).unwrap();
    compile(&operators_source(&model, 4).unwrap(), "markup");
    let md = theory_search::table::render(
        &model,
        &[
            theory_search::reduce::analyse(&model, theory_search::model::Density::Lagrangian, 4)
                .unwrap(),
        ],
        theory_search::table::Format::Markdown,
    );
    let header = md.lines().find(|l| l.starts_with("| term")).unwrap();
    let row = md.lines().find(|l| l.starts_with("| φ ")).unwrap();
    let cells = |l: &str| l.replace("\\|", "").matches('|').count();
    assert_eq!(cells(header), cells(row), "{header}\n{row}");
    assert!(header.contains("a\\|b_{}$"), "{header}");
    let latex = theory_search::table::render(
        &model,
        &[
            theory_search::reduce::analyse(&model, theory_search::model::Density::Lagrangian, 4)
                .unwrap(),
        ],
        theory_search::table::Format::Latex,
    );
    assert!(latex.contains("a|b\\_\\{\\}\\$"), "{latex}");
}

/// `theory-search args…`: (exit code, stdout, the error line).
fn cli(args: &[&str]) -> (u8, String, String) {
    let mut all = vec!["theory-search"];
    all.extend(args);
    let mut out = Vec::new();
    match theory_search::cli::run(all, &mut out) {
        Ok(()) => (0, String::from_utf8(out).unwrap(), String::new()),
        Err(e) => (
            e.exit_code(),
            String::from_utf8(out).unwrap(),
            e.to_string(),
        ),
    }
}

#[test]
fn hostile_input_ii_exits_cleanly_with_bounded_lines() {
    let dir_held = common::scratch("hostile-ii");
    let dir = dir_held.path();
    // Coordinates whose squares overflow: no panic, a finite report or one clean line.
    let header: Vec<String> = (0..12).map(|i| format!("x{i},y{i}")).collect();
    let mut text = format!("t,{}\n", header.join(","));
    for f in 0..120 {
        let cells: Vec<String> = (0..12)
            .map(|i| {
                format!(
                    "{:e},{:e}",
                    1e155 * i as f64,
                    1e154 * (0.3 * f as f64 + i as f64).sin()
                )
            })
            .collect();
        text += &format!("{f},{}\n", cells.join(","));
    }
    let big = dir.join("big.csv");
    std::fs::write(&big, &text).unwrap();
    let (code, out, err) = cli(&["fit", big.to_str().unwrap(), "--window", "16"]);
    assert!(code == 0 || !err.contains('\n'), "{err}");
    assert!(!out.contains("NaN") && !out.contains("inf"), "{out}");
    // A sampling interval that underflows is refused up front.
    let (code, _, err) = cli(&["fit", big.to_str().unwrap(), "--fps", "1e300"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--fps"), "{err}");
    // Unused scales are refused, as modes refuses them.
    for args in [
        &["stats", "pair", "--param", "bogus=1"][..],
        &["asymmetry", "--coupling", "0.5", "--param", "bogus=1"][..],
        &["stats", "pair", "--omega", "2", "--param", "omega_s=3"][..],
    ] {
        let (code, _, err) = cli(args);
        assert_eq!(code, 2, "{args:?}: {err}");
    }
    let (code, _, _) = cli(&["stats", "pair", "--params", "/nonexistent/p.toml"]);
    assert_eq!(code, 1);
    let (_, with, _) = cli(&["stats", "pair", "--param", "omega_s=50"]);
    let (_, without, _) = cli(&["stats", "pair"]);
    assert_ne!(with, without, "--param omega_s must change ω");
    // Error lines quote at most a bounded part of their input.
    let long = "9".repeat(100_000);
    let (code, _, err) = cli(&["--order", &long]);
    assert_eq!(code, 2);
    assert!(
        err.len() < 1200 && err.contains("whole number"),
        "{}",
        err.len()
    );
    let path = dir.join("x".repeat(200));
    let (code, _, err) = cli(&["fit", path.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.chars().count() < 400, "{err}");
    let model = dir.join("long.toml");
    std::fs::write(&model, format!("name = \"{}\"\n", "x".repeat(1 << 20))).unwrap();
    let (code, _, err) = cli(&["--model", model.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.len() < 1200, "{}", err.len());
    // Negative values reach the range check as values.
    let (code, _, err) = cli(&["fit", big.to_str().unwrap(), "--omega", "-1"]);
    assert_eq!(code, 2);
    assert!(err.contains("positive"), "{err}");
    // A sweep is bounded.
    let sweep = vec!["1"; 51].join(",");
    let (code, _, err) = cli(&["behave", "self-righting", "--sweep", &sweep]);
    assert_eq!(code, 2);
    assert!(err.contains("at most 50"), "{err}");
}

#[test]
fn fitted_scales_written_by_params_out_read_back() {
    let dir_held = common::scratch("params-out");
    let dir = dir_held.path();
    let example = format!(
        "{}/tables/examples/midlines.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    // At the highest frame rate ω is of order 10⁸ or more: still written as a float.
    for fps in ["1e9", "30"] {
        let params = dir.join(format!("p{fps}.toml"));
        let (code, report, err) = cli(&[
            "fit",
            &example,
            "--fps",
            fps,
            "--params-out",
            params.to_str().unwrap(),
            "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{err}");
        let omega = serde_json::from_str::<serde_json::Value>(&report).unwrap()["omega"]
            .as_f64()
            .unwrap();
        let (code, modes, err) = cli(&[
            "modes",
            "-p",
            "12",
            "--params",
            params.to_str().unwrap(),
            "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{fps}: {err}");
        assert!(modes.contains("omega"), "{modes}");
        let written = std::fs::read_to_string(&params).unwrap();
        let value: f64 = written
            .lines()
            .find_map(|l| l.strip_prefix("omega_b = "))
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(value, omega, "{written}");
    }
}
