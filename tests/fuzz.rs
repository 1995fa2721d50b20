//! Hostile-input fuzzing of the command line, the model parser and the recording reader.
//!
//! Each case runs the real binary with a time limit and asserts the one rule: exit 0 with
//! finite output, or exit 1, 2 or 3 with one line on stderr, within the time budget; never a
//! panic, an abort, a hang, NaN or ∞. Hostile III adds the nonlinear family (extreme
//! coefficients, states, drives, temperatures and steps on the tethered filament and the worm
//! at the next orders: every row's energy is checked with the rest) and the figure family
//! (widths, resolutions, formats). Hostile IV adds the `discover` family (pieces of a
//! recording with a scaled clock and replaced cells, hostile options) and the `[active]`
//! family (garbage, extreme and unicode sections through `active`, `equations`, `simulate`,
//! `modes`, `operators` and `emit`), and every refusal is at most 1000 characters; the Python
//! family is `python/tests/test_hostile.py`. The case count is `PROPTEST_CASES` (default 32 here, as
//! `.ci/run` runs it); `PROPTEST_CASES=2000 cargo test --release --test fuzz` is the longer
//! campaign for developers (docs/budgets.md).

mod common;

use std::io::Write;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

/// Each run's limit (the budgets aim at ten seconds; a slow CI machine gets twice that).
const LIMIT: Duration = Duration::from_secs(20);

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_theory-search")
}

/// Run with a time limit; returns (code, stdout, stderr) or panics on a hang or a signal.
fn run(args: &[String], stdin: Option<&str>) -> (i32, String, String) {
    let mut child = Command::new(bin())
        .args(args)
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    if let (Some(text), Some(mut pipe)) = (stdin, child.stdin.take()) {
        let _ = pipe.write_all(text.as_bytes());
    }
    let start = Instant::now();
    // Drain the pipes on threads so a large output cannot block the child.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let o = std::thread::spawn(move || {
        let mut s = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut s).ok();
        s
    });
    let e = std::thread::spawn(move || {
        let mut s = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut s).ok();
        s
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > LIMIT {
            child.kill().ok();
            panic!("{args:?}: still running after {LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let out = String::from_utf8_lossy(&o.join().unwrap()).into_owned();
    let err = String::from_utf8_lossy(&e.join().unwrap()).into_owned();
    let code = status
        .code()
        .unwrap_or_else(|| panic!("{args:?}: killed by a signal (abort?): {err}"));
    (code, out, err)
}

/// The one rule every run obeys.
fn obeys_the_rule(args: &[String], stdin: Option<&str>) {
    let (code, out, err) = run(args, stdin);
    match code {
        0 => {
            let bad = out
                .split(|c: char| !(c.is_alphanumeric() || c == '-'))
                .find(|w| matches!(*w, "NaN" | "inf" | "-inf" | "nan"));
            assert!(bad.is_none(), "{args:?}: printed {bad:?} with exit 0");
        }
        1..=3 => {
            assert!(err.starts_with("error: "), "{args:?}: {err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
            assert!(!err.contains("panicked"), "{args:?}: {err}");
            assert!(
                err.chars().count() <= 1000,
                "{args:?}: a message of {} characters",
                err.chars().count()
            );
        }
        other => panic!("{args:?}: exit {other}: {err}"),
    }
}

/// Values users type, good and bad.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_string()),
        Just("1".to_string()),
        Just("-1".to_string()),
        Just("2".to_string()),
        Just("12".to_string()),
        Just("0.5".to_string()),
        Just("-2.5e-1".to_string()),
        Just("1e300".to_string()),
        Just("-1e300".to_string()),
        Just("1e-320".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("abc".to_string()),
        Just("18446744073709551615".to_string()),
        Just("4294967296".to_string()),
        // Hostile II: underflowing intervals, huge quoted values, negative numbers as values.
        Just("1e-300".to_string()),
        Just("1e19".to_string()),
        Just("9".repeat(400)),
        Just("bogus=1".to_string()),
        Just("omega_s=50".to_string()),
        (1u32..5000).prop_map(|v| v.to_string()),
        (-1e4f64..1e4).prop_map(|v| v.to_string()),
    ]
}

/// Numbers at the edge of f64, for coefficients, states and drives.
fn extreme() -> impl Strategy<Value = String> {
    prop_oneof![
        value(),
        Just("1e308".to_string()),
        Just("1.7976931348623157e308".to_string()),
        Just("1e155".to_string()),
        Just("-1e6".to_string()),
        Just("5e-324".to_string()),
        Just("1e100".to_string()),
    ]
}

/// A run of a nonlinear body with extreme coefficients, states, drives and settings.
fn nonlinear_line() -> impl Strategy<Value = Vec<String>> {
    let bodies: Vec<(Vec<&str>, &[&str], &str)> = vec![
        (
            vec![
                "--model",
                concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml"),
            ],
            &["c1_u", "c2_u", "c3_u", "c4_u", "cp_u"],
            "u",
        ),
        (
            vec![
                "--model",
                concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/worm.toml"),
                "--beyond-leading",
                "3",
            ],
            &["c1_x", "c'3_θ", "c2_x", "c_y"],
            "x",
        ),
        (
            vec!["--beyond-leading", "1"],
            &["c2_x", "c3_x", "cp1_x", "c_y"],
            "x",
        ),
    ];
    let commands = ["simulate", "modes", "operators"];
    (
        0..bodies.len(),
        0..commands.len(),
        prop::collection::vec((0usize..8, extreme()), 0..4),
        prop::collection::vec((0usize..6, extreme()), 0..3),
    )
        .prop_map(move |(b, c, params, settings)| {
            let (model, names, field) = &bodies[b];
            let mut args = vec![commands[c].to_string(), "-p".into(), "5".into()];
            args.extend(model.iter().map(|s| s.to_string()));
            for (i, v) in params {
                args.push(format!("--param={}={v}", names[i % names.len()]));
            }
            if c == 0 {
                args.extend(["--steps".into(), "50".into(), "--every".into(), "10".into()]);
                for (i, v) in settings {
                    let (flag, value) = match i {
                        0 => ("--initial", format!("{field}={v}")),
                        1 => ("--initial", format!("{field}:1={v}")),
                        2 => ("--drive", format!("{field}:1={v},{v}")),
                        3 => ("--force", format!("{field}:1={v}")),
                        4 => ("--temperature", v),
                        _ => ("--dt", v),
                    };
                    args.push(format!("{flag}={value}"));
                }
            }
            args
        })
}

/// A subcommand with a few of its options set to arbitrary values.
fn command_line() -> impl Strategy<Value = Vec<String>> {
    let commands: Vec<(&str, &[&str])> = vec![
        ("table", &["--order", "--density", "--basis", "--format"]),
        ("equations", &["--order", "--basis"]),
        ("operators", &["--points", "--order"]),
        ("modes", &["--points", "--modes", "--order", "--param"]),
        (
            "simulate",
            &[
                "--points",
                "--dt",
                "--steps",
                "--every",
                "--temperature",
                "--initial",
            ],
        ),
        (
            "asymmetry",
            &["--coupling", "--amplitude", "--omega", "--points"],
        ),
        (
            "mathieu",
            &[
                "--lambda",
                "--ratio-min",
                "--ratio-max",
                "--epsilon-max",
                "--columns",
                "--rows",
            ],
        ),
        (
            "behave peristalsis",
            &["--momentum", "--periods", "--points", "--param"],
        ),
        ("behave rolling", &["--momentum", "--periods", "--points"]),
        ("behave rearing", &["--force", "--duration", "--points"]),
        (
            "behave self-righting",
            &[
                "--theta0",
                "--tolerance",
                "--mode-damping",
                "--points",
                "--sweep",
            ],
        ),
        (
            "stats pair",
            &["--omega", "--beta", "--momentum", "--samples", "--param"],
        ),
        ("stats explore", &["--beta", "--samples", "--points"]),
        (
            "stats equipartition",
            &["--steps", "--temperature", "--points"],
        ),
        ("count", &["--max-order", "--format"]),
        ("interactions", &["--order", "--format"]),
        ("parts", &["--order", "--format"]),
        ("rules", &["--order", "--format"]),
        ("equations", &["--order", "--format"]),
    ];
    (
        0..commands.len(),
        prop::collection::vec((0usize..8, value()), 0..4),
    )
        .prop_map(move |(c, opts)| {
            let (name, flags) = commands[c];
            let mut args: Vec<String> = name.split(' ').map(String::from).collect();
            for (f, v) in opts {
                let flag = flags[f % flags.len()];
                args.push(flag.to_string());
                args.push(match flag {
                    "--param" => format!("omega_b={v}"),
                    "--initial" => format!("y:2={v}"),
                    "--density" => "rayleigh".into(),
                    "--basis" => "monomials".into(),
                    "--format" => "json".into(),
                    _ => v,
                });
            }
            // Commands that need a required option get one.
            match name {
                "operators" | "modes" | "simulate" if !args.contains(&"--points".into()) => {
                    args.extend(["--points".into(), "8".into()])
                }
                "asymmetry" if !args.contains(&"--coupling".into()) => {
                    args.extend(["--coupling".into(), "0.1".into()])
                }
                _ => {}
            }
            args
        })
}

/// A `discover` run on a hostile recording (a piece of the example, its clock scaled, a
/// column cut, a cell replaced) with hostile options; the recording on standard input.
fn discover_line() -> impl Strategy<Value = (Vec<String>, String)> {
    let flags = [
        "--points",
        "--bootstrap",
        "--seed",
        "--fill-gaps",
        "--fps",
        "--field",
        "--kind",
        "--order",
        "--active",
        "--model",
    ];
    let scale = prop_oneof![
        Just(1.0),
        Just(1e-200),
        Just(1e100),
        Just(1e300),
        Just(-1.0),
        Just(0.0),
        Just(1e-6),
    ];
    (
        8usize..3000,
        scale,
        prop::collection::vec((0usize..4000, value()), 0..3),
        prop::collection::vec((0usize..flags.len(), value()), 0..4),
    )
        .prop_map(move |(frames, scale, cells, opts)| {
            let example = include_str!("../tables/examples/midlines.csv");
            let mut lines: Vec<String> =
                example.lines().take(2 + frames).map(String::from).collect();
            for line in lines.iter_mut().skip(2) {
                if let Some((t, rest)) = line.split_once(',') {
                    let t: f64 = t.parse().unwrap_or(0.0);
                    *line = format!("{},{rest}", t * scale);
                }
            }
            for (at, v) in cells {
                let row = 2 + at % (lines.len() - 2).max(1);
                if let Some(line) = lines.get_mut(row) {
                    let mut c: Vec<String> = line.split(',').map(String::from).collect();
                    let k = at % c.len();
                    c[k] = v;
                    *line = c.join(",");
                }
            }
            let mut args = vec!["discover".to_string(), "-".to_string()];
            for (f, v) in opts {
                let flag = flags[f];
                match flag {
                    "--active" => args.push(flag.into()),
                    "--model" => args.extend([
                        flag.into(),
                        concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/crawler.toml").into(),
                    ]),
                    "--kind" => args.extend([flag.into(), "lengths".into()]),
                    "--field" => {
                        args.extend([flag.into(), ["x", "y", "θ", "\u{202e}"][v.len() % 4].into()])
                    }
                    // Bootstrap draws and orders within what a case can afford.
                    "--bootstrap" => args.extend([flag.into(), (v.len() % 60).to_string()]),
                    // Points: mostly what a run takes, sometimes the hostile value.
                    "--points" if v.len() % 3 > 0 => {
                        args.extend([flag.into(), (3 + v.len() % 40).to_string()])
                    }
                    "--order" => {
                        args.extend([flag.into(), ["2", "4", "6", v.as_str()][v.len() % 4].into()])
                    }
                    _ => args.extend([flag.into(), v]),
                }
            }
            if !args.contains(&"--bootstrap".to_string()) {
                args.extend(["--bootstrap".into(), "20".into()]);
            }
            (args, lines.join("\n") + "\n")
        })
}

/// An `[active]` section: garbage, extreme and unicode bounds, columns, requirements and keys.
fn active_section() -> impl Strategy<Value = String> {
    // Mostly rule names (a section the model takes), sometimes garbage or unicode.
    let words = prop_oneof![
        12 => prop::sample::select(vec![
            "OST", "TRAN", "REF", "GAL", "PAR", "ROT", "TREV", "KIN", "DIS", "SPIN",
        ]),
        1 => prop::sample::select(vec!["", "ost", "O\u{202e}ST", "\u{200b}", "ÖST"]),
    ];
    let bound = prop_oneof![
        6 => Just("\"tau-and-sigma\"".to_string()),
        2 => Just("\"tau-plus-sigma\"".to_string()),
        1 => Just("\"\u{202e}\"".to_string()),
        1 => Just("12".to_string()),
        1 => Just("\"x\"".to_string()),
    ];
    let extra = prop_oneof![
        10 => Just(""),
        1 => Just("dominance = [\"x\"]\n"),
        1 => Just("interaction = [\"OST\"]\n"),
        1 => Just("beyond_leading = 8\n"),
        1 => Just("nonsense = 1\n"),
        1 => Just("[active.requirements.y]\n"),
    ];
    (
        bound,
        prop::collection::vec(words.clone(), 0..8),
        prop::collection::vec(words, 0..6),
        extra,
        0u8..8,
    )
        .prop_map(|(bound, columns, reqs, extra, field)| {
            let list = |w: &[&str]| {
                w.iter()
                    .map(|x| format!("\"{x}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            // Mostly the model's field; sometimes a quoted key with an override in it.
            let field = if field > 0 { "x" } else { "\"\u{202e}x\"" };
            format!(
                "\n[active]\nbound = {bound}\ncolumns = [{}]\n{extra}\n[active.requirements]\n{field} = [{}]\n",
                list(&columns),
                list(&reqs)
            )
        })
}

/// A SLEAP analysis file (SLEAP's own axis order, `dims` named) of a wiggling 8-point body, as
/// the crate writes it: the seed of the HDF5 mutations.
fn sleap_analysis_file() -> Vec<u8> {
    use hdf5_pure::{AttrValue, FileBuilder};
    let (frames, nodes) = (400usize, 8usize);
    // (track, xy, node, frame): x along the body, y a travelling bend.
    let mut v = Vec::with_capacity(2 * nodes * frames);
    for xy in 0..2 {
        for j in 0..nodes {
            for f in 0..frames {
                let s = j as f64;
                v.push(if xy == 0 {
                    s
                } else {
                    0.3 * (0.7 * s - 0.4 * f as f64).sin()
                });
            }
        }
    }
    let mut b = FileBuilder::new();
    b.create_dataset("tracks")
        .with_f64_data(&v)
        .with_shape(&[1, 2, nodes as u64, frames as u64])
        .set_attr(
            "dims",
            AttrValue::String(r#"["track", "xy", "node", "frame"]"#.into()),
        );
    b.finish().unwrap()
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(32)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn any_command_line_obeys_the_rule(args in command_line()) {
        obeys_the_rule(&args, None);
    }

    #[test]
    fn any_nonlinear_run_obeys_the_rule(args in nonlinear_line()) {
        obeys_the_rule(&args, None);
    }

    #[test]
    fn any_figure_page_obeys_the_rule(
        width in extreme(),
        dpi in extreme(),
        format in prop_oneof![Just("svg"), Just("png"), Just("pdf")],
    ) {
        let dir_held = common::scratch("fuzz-page");
        let dir = dir_held.path();
        let args: Vec<String> = [
            "figures", "--only", "spectrum", "--format", format, "--figures",
            dir.to_str().unwrap(),
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("--width={width}"), format!("--dpi={dpi}")])
        .collect();
        obeys_the_rule(&args, None);
    }

    #[test]
    fn any_mutated_model_file_obeys_the_rule(
        edits in prop::collection::vec((0usize..4000, any::<u8>()), 1..6),
        cut in 0usize..4000,
    ) {
        let mut text = include_str!("../tables/models/larva.toml").as_bytes().to_vec();
        for (at, byte) in edits {
            let at = at % text.len();
            text[at] = byte;
        }
        text.truncate(text.len() - cut % (text.len() / 4).max(1));
        let dir_held = common::scratch("fuzz-model");
        let dir = dir_held.path();
        let path = dir.join(format!("m{}.toml", text.len()));
        std::fs::write(&path, &text).unwrap();
        let p = path.to_str().unwrap().to_string();
        for cmd in [vec!["modes", "-p", "8"], vec!["behave", "rolling", "--periods", "2"], vec!["equations"]] {
            let mut args: Vec<String> = cmd.iter().map(|s| s.to_string()).collect();
            args.extend(["--model".into(), p.clone()]);
            obeys_the_rule(&args, None);
        }
    }

    #[test]
    fn any_discover_run_obeys_the_rule((args, text) in discover_line()) {
        obeys_the_rule(&args, Some(&text));
    }

    #[test]
    fn any_active_section_obeys_the_rule(
        section in active_section(),
        // Orders 2 and 4: the [active] enumeration's cost at higher orders is budgeted in src/active.rs.
        order in prop_oneof![Just("2"), Just("4")],
        value in extreme(),
    ) {
        // The peristalsis ring without its own section, then the hostile one.
        let base = include_str!("../tables/models/peristalsis.toml");
        let base = &base[..base.find("\n[active]\n").unwrap()];
        let dir_held = common::scratch("fuzz-active");
        let dir = dir_held.path();
        let path = dir.join("m.toml");
        std::fs::write(&path, format!("{base}{section}")).unwrap();
        let m = path.to_str().unwrap().to_string();
        let out = dir.join("emit");
        let lines: Vec<Vec<String>> = vec![
            vec!["active".into(), "--order".into(), order.into()],
            vec!["equations".into(), "--order".into(), order.into()],
            vec!["simulate".into(), "-p".into(), "6".into(), "--steps".into(), "5".into(),
                 format!("--param=a_x={value}"), format!("--param=g_x={value}"),
                 "--initial".into(), "x:1=0.1".into()],
            vec!["modes".into(), "-p".into(), "6".into(), format!("--param=g_x={value}")],
            vec!["operators".into(), "-p".into(), "6".into(), format!("--param=a_x={value}")],
            vec!["emit".into(), "--order".into(), order.into(), "--out".into(),
                 out.to_str().unwrap().into()],
        ];
        for mut args in lines {
            args.extend(["--model".into(), m.clone()]);
            obeys_the_rule(&args, None);
        }
    }

    #[test]
    fn any_mutated_hdf5_file_obeys_the_rule(
        edits in prop::collection::vec((0usize..1 << 16, any::<u8>()), 0..8),
        cut in 0usize..1 << 16,
    ) {
        let mut bytes = sleap_analysis_file();
        let n = bytes.len();
        for (at, byte) in edits {
            bytes[at % n] = byte;
        }
        bytes.truncate(n - cut % (n / 2));
        let dir_held = common::scratch("fuzz-hdf5");
        let path = dir_held.path().join("larva.analysis.h5");
        std::fs::write(&path, &bytes).unwrap();
        let p = path.to_str().unwrap().to_string();
        let fit = ["fit", &p, "--fps", "15", "--points", "8"].map(String::from);
        obeys_the_rule(&fit, None);
        obeys_the_rule(&["discover".into(), p, "--bootstrap".into(), "0".into()], None);
    }

    #[test]
    fn any_recording_obeys_the_rule(
        rows in prop::collection::vec(prop::collection::vec(value(), 0..16), 0..40),
        sep in prop_oneof![Just(","), Just(" "), Just("\t")],
    ) {
        let text: String = rows.iter().map(|r| r.join(sep) + "\n").collect();
        obeys_the_rule(&["fit".into(), "-".into()], Some(&text));
        obeys_the_rule(&["fit".into(), "-".into(), "--kind".into(), "lengths".into()], Some(&text));
    }
}

/// The seed of the HDF5 mutations is a recording: read, and fitted.
#[test]
fn the_hdf5_seed_is_a_recording() {
    let dir_held = common::scratch("fuzz-hdf5-seed");
    let path = dir_held.path().join("larva.analysis.h5");
    std::fs::write(&path, sleap_analysis_file()).unwrap();
    let p = path.to_str().unwrap().to_string();
    let args: Vec<String> = ["fit", &p, "--fps", "15", "--points", "8"]
        .map(String::from)
        .into();
    let (code, out, err) = run(&args, None);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("400 frames of 8-point midlines"), "{out}");
}

/// The command lines of the hostile-input campaign that hung, aborted or printed NaN: each now
/// answers (finite) or refuses in one line, in time.
#[test]
fn the_reported_command_lines_answer_in_time() {
    let dir_held = common::scratch("fuzz-reported");
    let dir = dir_held.path();
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let figs = dir.join("figs");
    let figs = figs.to_str().unwrap();
    let tethered = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml");
    let zebrafish = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/zebrafish.toml");
    let lines: Vec<String> = vec![
        "stats pair --omega 5 --momentum 3 --beta 100".into(),
        format!("figures --out {figs} --param omega_s=50 --samples 2000"),
        format!("fit {example} --points 1000"),
        format!("fit {example} --points 2000"),
        "interactions --order 5 --density lagrangian".into(),
        "interactions --order 7".into(),
        "operators --points 2000 --format json".into(),
        "modes --points 10000000".into(),
        // Hostile III: huge coefficients before the SVD, tiny steps, costs up front.
        format!("operators -p 4 --model {tethered} --param c4_u=1e308"),
        format!("modes -p 4 --model {tethered} --param c3_u=1.7976931348623157e308"),
        format!("simulate -p 5 --model {tethered} --param c4_u=1e308 --initial u:1=1 --steps 1"),
        format!("simulate -p 4 --model {tethered} --initial u=1e155 --steps 1"),
        format!("simulate -p 2000 --model {tethered} --initial u:1=1 --steps 1"),
        "figures -p 2000 --figures /tmp/ts-never".into(),
        "stats equipartition --steps 20000000".into(),
        "modes --points 1000000".into(),
        format!("modes --points 3000 --model {zebrafish}"),
        "modes --points 10000000 --modes 3".into(),
        "count --basis monomials --max-order 16".into(),
        "behave rolling --periods 1e6".into(),
        "behave peristalsis --periods 4294967296".into(),
        "stats pair --omega 1e300".into(),
        "stats pair --omega 1e-320".into(),
        "stats pair --momentum 2000".into(),
        "mathieu --ratio-min 1e-9".into(),
        "mathieu --lambda 1e308".into(),
        "simulate --points 12 --steps 10000000".into(),
        "behave self-righting --theta0 1.8e19".into(),
        "asymmetry --coupling 2000".into(),
        "asymmetry --coupling 1e300".into(),
        "asymmetry --coupling 1 --omega 1e-300".into(),
        "asymmetry --coupling -1e-3".into(),
        "stats pair --momentum 1e6".into(),
        "stats pair --momentum -2.5e-1".into(),
        "stats pair --samples 3".into(),
        "stats pair --beta 1e300".into(),
        "stats pair --beta 1e-300".into(),
        "stats equipartition --steps 0".into(),
        "stats equipartition --temperature 1e-320 --steps 2000".into(),
        format!("fit {example} --omega 1e308"),
        format!("fit --kind lengths {example} --ring 18446744073709551615"),
        "modes --points 12 --model /dev/zero".into(),
        "modes --points 12 --params /dev/zero".into(),
        "fit /dev/zero".into(),
        "simulate --points 8 --steps 3 --out /dev/full".into(),
    ];
    for line in &lines {
        let args: Vec<String> = line.split(' ').map(String::from).collect();
        let start = Instant::now();
        obeys_the_rule(&args, None);
        assert!(start.elapsed() < LIMIT, "{line}: {:?}", start.elapsed());
    }
}

/// Exit codes follow one rule: 2 for bad usage or values, 1 for files that cannot be read or
/// written (or are not what they claim), 3 for a computation that failed on valid input.
#[test]
fn exit_codes_follow_one_rule() {
    let dir_held = common::scratch("fuzz-codes");
    let dir = dir_held.path();
    let bad_params = dir.join("p.toml");
    std::fs::write(&bad_params, "omega_b = \"x\"").unwrap();
    let p = bad_params.to_str().unwrap().to_string();
    for (line, want) in [
        ("modes --points 0", 2),
        ("modes --points 8 --param omega_b=-1", 2),
        ("asymmetry --coupling abc", 2),
        ("modes --points 8 --model /nonexistent.toml", 1),
        ("fit /nonexistent.csv", 1),
        ("modes --points 12 --model /dev/zero", 1),
        ("simulate --points 8 --steps 3 --out /dev/full", 1),
    ] {
        let args: Vec<String> = line.split(' ').map(String::from).collect();
        let (code, _, err) = run(&args, None);
        assert_eq!(code, want, "{line}: {err}");
    }
    let (code, _, err) = run(
        &[
            "modes".into(),
            "-p".into(),
            "8".into(),
            "--params".into(),
            p,
        ],
        None,
    );
    assert_eq!(code, 1, "{err}");
}
