//! Text from a model file never becomes code: hostile names, symbols and meanings are refused
//! when they could end a line, and otherwise reach the generated source only as escaped string
//! literals or comments. The generated code is compiled with rustc against a stub of
//! `src/generated/mod.rs` and its items are counted.

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
fn compile(source: &str, tag: &str) {
    let dir = std::env::temp_dir().join(format!("ts-hostile-{}-{tag}", std::process::id()));
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
    std::fs::remove_dir_all(&dir).ok();
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
    let dir = std::env::temp_dir().join(format!("ts-hostile-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
    std::fs::remove_dir_all(&dir).ok();
}
