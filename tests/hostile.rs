//! Text from a model file never becomes code: hostile names, symbols and meanings are refused
//! when they could end a line, and otherwise reach the generated source only as escaped string
//! literals or comments. The generated code is compiled with rustc against a stub of
//! `src/generated/mod.rs` and its items are counted.

mod common;

use std::process::Command;

use theory_search::codegen::operators_source;
use theory_search::discretise::plan;
use theory_search::failure::Failure;
use theory_search::fit::{fit_inputs, FitError, FitSettings, Input};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::{Frame, InputKind, Track};

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

/// The shipped example (`tables/examples/midlines.csv`: a comment, the header on line 2, 12
/// points from line 3 on), each data row's cells (time first) rewritten by `row`.
fn example_with(row: impl Fn(Vec<f64>) -> Vec<f64>) -> String {
    let example = include_str!("../tables/examples/midlines.csv");
    let mut text = String::new();
    for line in example.lines() {
        match line
            .split(',')
            .map(str::parse)
            .collect::<Result<Vec<f64>, _>>()
        {
            Ok(cells) => {
                let cells: Vec<String> = row(cells).iter().map(f64::to_string).collect();
                text += &cells.join(",");
            }
            Err(_) => text += line,
        }
        text.push('\n');
    }
    text
}

/// The binary reading `text` on its standard input: (exit code, stderr).
fn binary_reading(args: &[&str], text: &str) -> (i32, String) {
    use std::io::Write as _;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // The binary may stop reading at the refused line: a broken pipe is its answer, not ours.
    let _ = child.stdin.take().map(|mut i| i.write_all(text.as_bytes()));
    let out = child.wait_with_output().expect("the binary ends");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), err)
}

/// `fit_inputs` on one input: its error.
fn fit_error(input: Input<'_>, settings: &FitSettings) -> FitError {
    let (model, params) = (Model::larva(), Params::default());
    match fit_inputs(vec![input], &model, &params, settings, None) {
        Ok(report) => panic!("fitted {} frames", report.frames),
        Err(e) => e,
    }
}

/// `text` as a file (read in chunks on every core), alone and beside the example (read line by
/// line), as standard input, and through the library both ways: every one refused with `want`
/// in one line, with the exit code and failure kind given.
fn refused_everywhere(text: &str, extra: &[&str], settings: &FitSettings, want: &str, code: u8) {
    let held = common::scratch_file("refused", ".csv");
    let path = held.path().to_str().unwrap();
    std::fs::write(path, text).unwrap();
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let mut runs = vec![
        [&["fit", path][..], extra].concat(),
        [&["fit", path, example][..], extra].concat(),
    ];
    if extra.is_empty() {
        runs.push(vec!["fit", example, path]);
    }
    for args in runs {
        let (got, _, err) = cli(&args);
        assert_eq!(got, code, "{args:?}: {err}");
        assert!(err.contains(want) && !err.contains('\n'), "{args:?}: {err}");
    }
    let (got, _, err) = common::binary(&[&["fit", path][..], extra].concat());
    assert_eq!(got, i32::from(code), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(want), "{err}");
    let (got, err) = binary_reading(&[&["fit", "-"][..], extra].concat(), text);
    assert_eq!(got, i32::from(code), "{err}");
    assert!(err.contains(want) && err.contains("-: "), "{err}");
    let kind = if code == 2 {
        Failure::Usage
    } else {
        Failure::Input
    };
    let reader = Box::new(std::io::Cursor::new(text.as_bytes().to_vec()));
    for e in [
        fit_error(Input::File(path.into()), settings),
        fit_error(
            Input::Reader {
                name: "r".into(),
                reader,
            },
            settings,
        ),
    ] {
        assert_eq!(e.failure(), kind, "{e}");
        assert!(e.to_string().contains(want), "{e}");
    }
}

#[test]
fn rows_wider_or_narrower_than_their_header_are_refused_naming_the_line() {
    // Issue 49: a header naming 12 points over rows of 13 was read as 13-point midlines.
    let settings = FitSettings::new(InputKind::Midline);
    let wide = example_with(|mut cells| {
        let (x, y) = (cells[cells.len() - 2], cells[cells.len() - 1]);
        cells.extend([x + 1.0, y]);
        cells
    });
    let want = "line 3: 27 columns where the header (line 2) names 25: 13 points where it names 12";
    refused_everywhere(&wide, &[], &settings, want, 1);
    let narrow = example_with(|cells| cells[..cells.len() - 2].to_vec());
    let want = "line 3: 23 columns where the header (line 2) names 25: 11 points where it names 12";
    refused_everywhere(&narrow, &[], &settings, want, 1);
    // A header ending in an ellipsis names the first columns only; one cell is a title.
    let example = example_with(|cells| cells);
    for header in ["t,x1,y1,...", "t,x1,y1,x2,y2…", "frames"] {
        let text = example.replacen(example.lines().nth(1).unwrap(), header, 1);
        let (model, params) = (Model::larva(), Params::default());
        let read = theory_search::fit::fit(text.as_bytes(), &model, &params, &settings);
        assert_eq!(read.map(|r| r.frames).map_err(|e| e.to_string()), Ok(3000));
    }
    // A track column counts in both; lengths are counted as columns.
    let tracked = "id,t,x1,y1\nA,0,1,2,3\n";
    let mut settings = FitSettings::new(InputKind::Lengths);
    settings.recording.track_column = true;
    let reader = Box::new(std::io::Cursor::new(tracked.as_bytes().to_vec()));
    let e = fit_error(
        Input::Reader {
            name: "r".into(),
            reader,
        },
        &settings,
    );
    assert!(
        e.to_string()
            .ends_with("line 2: 5 columns where the header (line 1) names 4"),
        "{e}"
    );
    // A row wider than the rest deep in a file, in a chunk a worker parses, is refused too.
    let mut late = example;
    late += "3000,0,0,1,0,2,0,3,0,4,0,5,0,6,0,7,0,8,0,9,0,10,0,11,0,12,0\n";
    assert!(late.len() > 1 << 18, "past the first chunk");
    let want = "line 3003: 27 columns where the first frame had 25";
    refused_everywhere(&late, &[], &FitSettings::new(InputKind::Midline), want, 1);
}

#[test]
fn fps_beside_a_time_column_is_refused_by_fit_and_discover() {
    // Issue 53: `fit tables/examples/midlines.csv --fps 15` fitted the file's own clock.
    let mut settings = FitSettings::new(InputKind::Midline);
    settings.recording.fps = Some(15.0);
    let example = example_with(|cells| cells);
    let want = "--fps applies to files without a time column; this file has one: column 1, headed \"t\" (line 2)";
    refused_everywhere(&example, &["--fps", "15"], &settings, want, 2);
    let bare: String = example.lines().skip(2).map(|l| format!("{l}\n")).collect();
    let want = "this file has one: column 1, time \"0\" on line 1";
    refused_everywhere(&bare, &["--fps", "15"], &settings, want, 2);
    let held = common::scratch_file("fps-discover", ".csv");
    let path = held.path().to_str().unwrap();
    std::fs::write(path, &example).unwrap();
    let (code, _, err) = cli(&["discover", path, "--fps", "15", "--bootstrap", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--fps applies to files without a time column"),
        "{err}"
    );
    // WCON records and tracks in memory carry their times as well.
    let wcon = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/two_worms.wcon");
    let e = fit_error(Input::File(wcon.into()), &settings);
    assert_eq!(e.failure(), Failure::Usage, "{e}");
    assert!(
        e.to_string()
            .ends_with("this file has one: its records' \"t\" (WCON)"),
        "{e}"
    );
    let frames = (0..64)
        .map(|i| Frame {
            t: f64::from(i),
            values: Some((0..12).flat_map(|j| [f64::from(j), 0.0]).collect()),
        })
        .collect();
    let tracks = vec![Track {
        name: "a".into(),
        frames,
    }];
    let e = fit_error(Input::Tracks(tracks), &settings);
    assert!(e.to_string().contains("--fps applies"), "{e}");
}

#[test]
fn fitted_scales_written_by_params_out_read_back() {
    let dir_held = common::scratch("params-out");
    let dir = dir_held.path();
    // At the highest frame rate ω is of order 10⁸ or more: still written as a float. The
    // example's time column is rescaled (--fps applies only to DeepLabCut's frame indices).
    for fps in [1e9, 30.0] {
        let params = dir.join(format!("p{fps}.toml"));
        let recording = dir.join(format!("r{fps}.csv"));
        std::fs::write(
            &recording,
            example_with(|mut cells| {
                cells[0] /= fps;
                cells
            }),
        )
        .unwrap();
        let (code, report, err) = cli(&[
            "fit",
            recording.to_str().unwrap(),
            "--params-out",
            params.to_str().unwrap(),
            "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{err}");
        let omega = serde_json::from_str::<serde_json::Value>(&report).unwrap()["omega"]
            .as_f64()
            .unwrap();
        assert!(omega > 1e8 || fps < 1e9, "{omega}");
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
