//! Scenario: every failure is one bounded line whose exit code follows its kind (usage 2,
//! input and output 1, numerical 3: docs/commands.md), hostile numbers end at once without
//! printing a non-finite number, and a body at rest stays at rest. Hostile input IV: a body
//! moved by a gyroscopic force alone runs, words and numbers quoted in any error are bounded,
//! `[active]` keys that forces cannot use are refused, invisible characters in a quoted TOML
//! line are escaped, emitted operators import only what they use, and a recording too short
//! for the spectra exits 1 whatever its length.

use std::time::{Duration, Instant};

mod common;
use common::binary as run;

const TETHERED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml");
const WORM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/worm.toml");
const PERISTALSIS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tables/models/peristalsis.toml"
);
const MIDLINES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");

/// `args` fails with `code`, one line on stderr containing `needle`, nothing on stdout that
/// is not a finite number, within a few seconds; the line.
fn fails(args: &[&str], code: i32, needle: &str) -> String {
    let started = Instant::now();
    let (got, out, err) = run(args);
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "{args:?} took {:?}",
        started.elapsed()
    );
    assert_eq!(got, code, "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.len() < 600, "{args:?}: unbounded: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
    no_non_finite(&out, args);
    err
}

fn no_non_finite(out: &str, args: &[&str]) {
    for cell in out.split([',', '\n', ' ', '[', ']']) {
        let cell = cell.trim().to_ascii_lowercase();
        assert!(
            !matches!(cell.as_str(), "inf" | "-inf" | "nan" | "null"),
            "{args:?} printed {cell}"
        );
    }
}

/// The rows of a simulated series (its header skipped).
fn rows(out: &str) -> Vec<Vec<f64>> {
    out.lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect()
}

#[test]
fn the_exit_code_follows_the_kind_of_failure() {
    // Usage: a name that is no scale or coefficient (and the list it gives is clipped).
    fails(
        &["modes", "-p", "12", "--param", "nope=1"],
        2,
        "no field of the larva model uses it",
    );
    // Usage: a command group without its subcommand.
    fails(&["behave"], 2, "commands: peristalsis, rolling");
    fails(&["stats"], 2, "a subcommand is needed");
    // Input: a model file that does not exist.
    fails(
        &["modes", "-p", "12", "--model", "/no/such.toml"],
        1,
        "cannot read",
    );
    // Numerical: valid input on which the linearisation overflows.
    fails(
        &[
            "operators",
            "-p",
            "4",
            "--model",
            TETHERED,
            "--param",
            "c4_u=1e308",
        ],
        3,
        "overflows f64",
    );
    // Output: a file that cannot be created.
    fails(
        &[
            "simulate",
            "-p",
            "6",
            "--initial",
            "y:2=1",
            "--out",
            "/no/dir/run.csv",
        ],
        1,
        "cannot create",
    );
}

#[test]
fn huge_coefficients_and_states_end_at_once_with_finite_output() {
    let t = format!("-p 4 --model {TETHERED}");
    for (line, needle) in [
        (format!("modes {t} --param c3_u=1.7976931348623157e308"), "overflows f64"),
        (format!("simulate {t} --param c4_u=1e308 --initial u:1=1 --steps 1"), "overflows f64"),
        (format!("simulate {t} --initial u=1e155 --steps 1"), "overflowed f64 at t = 0"),
        (format!("simulate {t} --param c3_u=1e308 --initial u=1 --steps 1"), "overflowed f64 at t = 0"),
        (format!("simulate {t} --drive u:1=1e308,1e300 --steps 3"), "overflowed f64"),
        (
            format!("simulate --points 5 --model {WORM} --beyond-leading 3 --param c1_x=-1e6 --param=c'3_θ=100 --temperature 1e300 --steps 100 --every 100"),
            "overflowed f64",
        ),
    ] {
        let args: Vec<&str> = line.split(' ').collect();
        fails(&args, 3, needle);
    }
}

#[test]
fn numbers_are_printed_in_exponent_form_where_plain_would_be_dozens_of_digits() {
    let (code, out, err) = run(&[
        "simulate",
        "-p",
        "4",
        "--dt",
        "1e300",
        "--steps",
        "1",
        "--initial",
        "y:1=1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.lines().nth(2).unwrap().starts_with("1e300,"), "{out}");
    assert!(out.split(',').all(|c| c.trim().len() < 30), "{out}");
}

/// The three at-rest repros of the audit: the implicit step once stopped with "did not
/// converge" after the motion had damped out. They run to their end and stay put.
#[test]
fn a_body_at_rest_stays_at_rest() {
    for (extra, steps) in [
        (vec!["--initial", "x:0=0.3"], "2000"),
        (
            vec![
                "--param",
                "cp1_x=0.5",
                "--initial",
                "x:1=0.3",
                "--initial",
                "x:0=0.1",
            ],
            "30000",
        ),
        (
            vec!["--param", "cp1_x=0.5", "--initial", "x:0=0.2"],
            "30000",
        ),
    ] {
        let mut args = vec![
            "simulate",
            "--beyond-leading",
            "1",
            "--points",
            "8",
            "--dt",
            "0.01",
            "--param",
            "c2_x=1",
            "--param",
            "c3_x=0.3",
            "--every",
            "500",
            "--steps",
            steps,
        ];
        args.extend(extra);
        let (code, out, err) = run(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        let rows = rows(&out);
        let last = rows.last().unwrap();
        assert_eq!(
            last[0],
            steps.parse::<f64>().unwrap() * 0.01,
            "ran to its end"
        );
        // The last two reports, 500 steps apart, agree to rounding: at rest.
        let before = &rows[rows.len() - 2];
        for (a, b) in last[2..10].iter().zip(&before[2..10]) {
            assert!((a - b).abs() <= 1e-11 * a.abs().max(1e-3), "{a} vs {b}");
        }
    }
}

/// A ring whose only force is gyroscopic has a Newton matrix without wrapped corners; its
/// empty Woodbury correction once panicked in nalgebra ("Matrix slicing out of bounds"). It
/// runs, and the gyroscopic force does no work: the kinetic energy stays put.
#[test]
fn a_body_moved_by_a_gyroscopic_force_alone_runs_and_keeps_its_energy() {
    for points in ["3", "12", "105"] {
        let gyroscopic = [
            "simulate",
            "--model",
            PERISTALSIS,
            "--points",
            points,
            "--param",
            "c_x=0",
            "--param",
            "c'_x=0",
            "--param",
            "g_x=1",
        ];
        for extra in [
            &["--steps", "20"][..],
            &[
                "--steps",
                "2000",
                "--every",
                "500",
                "--initial",
                "x:1=0,0.5",
            ],
        ] {
            let args = [&gyroscopic[..], extra].concat();
            let (code, out, err) = run(&args);
            assert_eq!(code, 0, "{args:?}: {err}");
            no_non_finite(&out, &args);
            let rows = rows(&out);
            assert!(rows.len() >= 5, "{args:?}: {out}");
            for row in &rows {
                assert!(
                    (row[1] - rows[0][1]).abs() <= 1e-12,
                    "{args:?}: energy {row:?}"
                );
                assert!(row[2].abs() <= 1e-12, "{args:?}: injected {row:?}");
            }
        }
    }
}

/// Hostile input IV: a 100 000-character `--field` or recording path is quoted cut to 80
/// characters with its length said, and a number of 301 digits in short form.
#[test]
fn long_words_and_long_numbers_in_errors_are_cut_or_shortened() {
    let long = "x".repeat(100_000);
    let path = format!("/no/such/{long}.csv");
    for command in ["fit", "discover"] {
        let err = fails(
            &[command, MIDLINES, "--field", &long],
            2,
            "(100002 characters)",
        );
        // The word (its opening quote and 79 characters) cut to 80.
        assert!(err.contains(&format!("\"{}…", "x".repeat(79))), "{err}");
        fails(&[command, &path], 1, "characters)");
    }
    let err = fails(
        &["modes", "--points", "12", "--param", "zeta_b=-1e300"],
        2,
        "(-1e300)",
    );
    assert!(!err.contains("000000"), "{err}");
    let err = fails(
        &["mathieu", "--ratio-max", "1e-300"],
        2,
        "0.5…1e-300 is empty",
    );
    assert!(!err.contains("000000"), "{err}");
    // A typed count or index is never rewritten, and digits past f64's range are cut, not ∞.
    let words = theory_search::markup::bound_line(&format!(
        "18446744073709551615 x{0} /{0}/ 1{0}. {1}",
        "0".repeat(30),
        "9".repeat(400)
    ));
    assert!(
        words.starts_with(&format!(
            "18446744073709551615 x{0} /{0}/ 1e30. ",
            "0".repeat(30)
        )),
        "{words}"
    );
    assert!(words.ends_with("(400 characters)"), "{words}");
    // Library errors folded onto one line (Python's exceptions) are bounded the same way.
    let folded =
        theory_search::markup::one_line(&format!("no field {long:?}\n\n-1{}", "0".repeat(300)));
    assert!(folded.ends_with("(100002 characters); -1e300"), "{folded}");
}

/// A model file: the peristalsis body with `from` replaced by `to`.
fn peristalsis_with(from: &str, to: &str) -> tempfile::NamedTempFile {
    let text = std::fs::read_to_string(PERISTALSIS).unwrap();
    assert!(text.contains(from), "{from}");
    let file = common::scratch_file("hostile-iv", ".toml");
    std::fs::write(file.path(), text.replacen(from, to, 1)).unwrap();
    file
}

/// `[active]` keys that forces cannot use are refused naming the key, as `[rayleigh]`
/// refuses `dominance`, even at the value that would change nothing (a reader would think
/// it was read).
#[test]
fn active_keys_forces_cannot_use_are_refused_naming_the_key() {
    for (section, key, line) in [
        (
            "[active]",
            "[active] dominance",
            "dominance = \"by-part\"\n",
        ),
        ("[active]", "[active] dominance", "dominance = \"joint\"\n"),
        (
            "[active]",
            "[active] interaction",
            "interaction = [\"OST\"]\n",
        ),
        ("[active]", "[active] interaction", "interaction = []\n"),
        (
            "[rayleigh]",
            "[rayleigh] dominance",
            "dominance = \"joint\"\n",
        ),
    ] {
        let model = peristalsis_with(&format!("{section}\n"), &format!("{section}\n{line}"));
        fails(
            &[
                "modes",
                "-p",
                "12",
                "--model",
                model.path().to_str().unwrap(),
            ],
            1,
            key,
        );
    }
}

/// A TOML error quoting a line with a bidirectional override shows it escaped, as a quoted
/// model name does.
#[test]
fn a_quoted_toml_line_shows_invisible_characters_escaped() {
    let model = peristalsis_with(
        "name = \"peristalsis\"",
        "name = \"peri\u{202e}stalsis\" = 3",
    );
    let args = [
        "modes",
        "-p",
        "12",
        "--model",
        model.path().to_str().unwrap(),
    ];
    let err = fails(&args, 1, "peri\\u{202e}stalsis");
    assert!(!err.contains('\u{202e}'), "{err}");
}

/// The emitted operators of every shipped model import only names they use (a ring's file
/// has no `banded_*` and once imported `Banded` all the same: an unused-import warning).
#[test]
fn emitted_operators_import_only_what_they_use() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/models");
    let mut checked = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let text = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        let model = theory_search::model::Model::from_toml(&text).unwrap();
        for order in [2, 4, 6] {
            let Ok(source) = theory_search::codegen::operators_source(&model, order) else {
                continue;
            };
            checked += 1;
            let (imports, body): (Vec<&str>, Vec<&str>) =
                source.lines().partition(|l| l.starts_with("use "));
            let body = body.join("\n");
            for name in imports.iter().flat_map(|l| {
                l.rsplit("::")
                    .next()
                    .unwrap()
                    .split(|c: char| !c.is_alphanumeric() && c != '_')
            }) {
                let used = body
                    .split(|c: char| !c.is_alphanumeric() && c != '_')
                    .any(|w| w == name);
                assert!(
                    name.is_empty() || used,
                    "{} at order {order}: {name} unused",
                    model.name
                );
            }
        }
    }
    assert!(checked >= 8, "{checked}");
}

/// A recording too short for the spectra is a problem of the recording: one frame and nine
/// exit alike (1), through `fit` and `discover`; a field the midlines cannot observe is named
/// with its boundary in words, not Rust's debug text.
#[test]
fn a_short_recording_exits_as_input_whatever_its_length() {
    let text = std::fs::read_to_string(MIDLINES).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    for frames in [1, 2, 7, 9] {
        let mut f = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
        let body = lines[..2 + frames].join("\n") + "\n";
        std::io::Write::write_all(&mut f, body.as_bytes()).unwrap();
        let path = f.path().to_str().unwrap();
        for command in ["fit", "discover"] {
            let (code, _, err) = run(&[command, path]);
            if command == "fit" && frames >= 8 {
                continue;
            }
            assert_eq!(code, 1, "{command} on {frames} frame(s): {err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        }
    }
    for model in ["worm", "zebrafish", "channel_worm"] {
        let path = format!("{}/tables/models/{model}.toml", env!("CARGO_MANIFEST_DIR"));
        let err = fails(
            &["discover", MIDLINES, "--field", "x", "--model", &path],
            2,
            "field x (",
        );
        assert!(
            !err.contains("Ends {") && !err.contains("tail:"),
            "{model}: {err}"
        );
    }
}

const CRAWLER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/crawler.toml");

/// The bending field's damped roots with `a_y`, against the trace of the companion matrix
/// [[0, I], [−M⁻¹K, −M⁻¹C]] read from `operators`: Σ Re λ (a conjugate pair twice) and
/// −tr(M⁻¹(C − ∂f/∂v)). `None` when `modes` refuses, with its exit code and line.
fn roots_against_trace(a: &str) -> Result<(f64, f64, f64), (i32, String, String)> {
    let args = [
        "-p", "12", "--model", CRAWLER, "--param", a, "--format", "json",
    ];
    let (code, out, err) = run(&[&["modes"], &args[..]].concat());
    if code != 0 {
        return Err((code, out, err));
    }
    let modes: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (code, ops, err) = run(&[&["operators"], &args[..]].concat());
    assert_eq!(code, 0, "{err}");
    let ops: serde_json::Value = serde_json::from_str(&ops).unwrap();
    let y = &ops["fields"][1];
    assert_eq!(y["field"], "y");
    let m = |name: &str, i: usize, j: usize| y[name][i][j].as_f64().unwrap();
    let dv = |i: usize| y["active"][1][i][i].as_f64().unwrap();
    let n = y["size"].as_u64().unwrap() as usize;
    let mut trace = 0.0;
    for i in 0..n {
        for j in 0..n {
            // A diagonal mass: tr(M⁻¹C) is Σ C_ii / M_ii.
            assert!(i == j || m("mass", i, j) == 0.0);
        }
        trace -= (m("damping", i, i) - dv(i)) / m("mass", i, i);
    }
    let (mut sum, mut size) = (0.0, 0.0f64);
    for r in modes["fields"][1]["damped"].as_array().unwrap() {
        let (sigma, omega) = (
            r["decay_rate"].as_f64().unwrap(),
            r["frequency"].as_f64().unwrap(),
        );
        sum -= sigma * if omega > 0.0 { 2.0 } else { 1.0 };
        size = size.max(sigma.hypot(omega));
    }
    Ok((sum, trace, size))
}

/// Huge coefficients (issue 52 item 8): the damped roots' real parts add up to the trace where
/// they are printed (the companion matrix scaled to the roots' size before its QR iteration);
/// where the coefficients would lose the decay rates to rounding, `modes` refuses in one line
/// with exit 3 (numerical), nothing non-finite printed.
#[test]
fn huge_coefficients_give_roots_that_match_the_trace_or_exit_3() {
    for a in ["a_y=1", "a_y=1e8", "a_y=1e12"] {
        let (sum, trace, size) = roots_against_trace(a).unwrap_or_else(|e| panic!("{a}: {e:?}"));
        assert!(trace < -1.0, "{a}: damped: {trace}");
        assert!(
            (sum - trace).abs() < 1e-6 * trace.abs(),
            "{a}: Σ Re λ {sum} against {trace}"
        );
        // The roots do grow with the coefficient (√a for a stiffness term).
        if a == "a_y=1e12" {
            assert!(size > 1e5, "{a}: {size}");
        }
    }
    // At 1e16 the slowest roots sit within rounding of the zero modes' double roots.
    match roots_against_trace("a_y=1e16") {
        Ok((sum, trace, _)) => assert!((sum - trace).abs() < 1e-3 * trace.abs(), "{sum} {trace}"),
        Err((code, _, err)) => {
            assert_eq!(code, 3, "{err}");
            assert!(err.contains("cannot be trusted"), "{err}");
        }
    }
    for a in ["a_y=1e16", "a_y=1e100", "a_y=1e308", "a_y=-1e308"] {
        for format in ["text", "json"] {
            let args = [
                "modes", "-p", "12", "--model", CRAWLER, "--param", a, "--format", format,
            ];
            if a == "a_y=1e16" {
                // Either (checked above); here only: never a non-finite number.
                no_non_finite(&run(&args).1, &args);
                continue;
            }
            fails(&args, 3, "field y");
        }
    }
}

/// A time column that leaps to 1e300 and back (found by tests/fuzz.rs): the leap counted its
/// lost frames as usize::MAX, and adding them overflowed into a capacity panic. Now the leap is
/// one long gap and the step back a one-line input error, for `fit` and `discover` alike.
#[test]
fn a_time_column_leaping_to_1e300_is_refused_in_one_line() {
    let text = std::fs::read_to_string(MIDLINES).unwrap();
    let mut data = 0;
    let leaped: Vec<String> = (text.lines())
        .map(|l| {
            let numeric = l
                .split(',')
                .next()
                .is_some_and(|t| t.parse::<f64>().is_ok());
            data += usize::from(numeric);
            match (numeric && data == 5, l.split_once(',')) {
                (true, Some((_, rest))) => format!("1e300,{rest}"),
                _ => l.to_string(),
            }
        })
        .collect();
    let file = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(file.path(), leaped.join("\n")).unwrap();
    let path = file.path().to_str().unwrap();
    for command in ["fit", "discover"] {
        fails(&[command, path], 1, "does not increase");
    }
}
