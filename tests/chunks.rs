//! A file fitted alone is parsed in chunks on every core; a stream is read line by line. The
//! two must agree to the last bit on every report and word every error the same, wherever in
//! the file the odd line sits (the chunks are 64 KiB: these files hold dozens of them).

use std::fmt::Write as _;

use theory_search::fit::{fit_inputs, foretold_windows, FitSettings, Input};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::InputKind;

mod common;

const POINTS: usize = 12;
/// The frame the odd line replaces: dozens of chunks into the file.
const FAR: usize = 25_000;

/// A midline file of `frames` frames, head first, plain 6-decimal cells; `odd(i)` may replace
/// frame i's line (or add lines before it).
fn midlines(frames: usize, odd: impl Fn(usize, &str) -> Option<String>) -> String {
    let mut text = String::from("t");
    for j in 0..POINTS {
        write!(text, ",x{j},y{j}").unwrap();
    }
    text.push('\n');
    for i in 0..frames {
        let line = frame(i, 0.04 * i as f64);
        match odd(i, &line) {
            Some(other) => text.push_str(&other),
            None => text.push_str(&line),
        }
        text.push('\n');
    }
    text
}

/// Frame i's line (time 0.04 i), the body in its posture at time `phase`.
fn frame(i: usize, phase: f64) -> String {
    let mut line = format!("{:.2}", i as f64 * 0.04);
    for j in 0..POINTS {
        let s = j as f64 / (POINTS - 1) as f64;
        let t = phase;
        let y = 0.02 * (0.7 * t + 3.0 * s).sin() + 0.01 * (0.23 * t * (1.0 + s)).cos();
        write!(line, ",{:.6},{y:.6}", j as f64 + 0.001 * (1.3 * t).sin()).unwrap();
    }
    line
}

/// The fit of `text` as a file (chunked) and as a stream of the same name (line by line): the
/// JSON of each report, or each error's message.
fn both(text: &[u8], settings: &FitSettings, tag: &str) -> (String, String) {
    let (file, stream, _) = both_foretold(text, settings, tag);
    (file, stream)
}

/// [`both`], and the windows a pilot foretold for the file.
fn both_foretold(
    text: &[u8],
    settings: &FitSettings,
    tag: &str,
) -> (String, String, Option<Vec<usize>>) {
    let held = common::scratch_file(&format!("chunks-{tag}"), ".csv");
    let path = held.path().to_path_buf();
    std::fs::write(&path, text).unwrap();
    let (model, params) = (Model::larva(), Params::default());
    let foretold = foretold_windows(&path, &model, &params, settings);
    let show = |r: Result<theory_search::fit::FitReport, theory_search::fit::FitError>| match r {
        Ok(report) => serde_json::to_string(&report).unwrap(),
        Err(e) => format!("error: {e}"),
    };
    let file = show(fit_inputs(
        vec![Input::File(path.clone())],
        &model,
        &params,
        settings,
        None,
    ));
    let stream = show(fit_inputs(
        vec![Input::Reader {
            name: path.display().to_string(),
            reader: Box::new(std::io::Cursor::new(text.to_vec())),
        }],
        &model,
        &params,
        settings,
        None,
    ));
    (file, stream, foretold)
}

/// A file of `frames` frames of 10 segment lengths, sampled every time unit.
fn lengths(frames: usize) -> String {
    (0..frames)
        .map(|i| {
            let t = i as f64;
            let cells: Vec<String> = (0..10)
                .map(|j| format!("{:.6}", 1.0 + 0.01 * (0.3 * t + j as f64).sin()))
                .collect();
            format!("{t},{}\n", cells.join(","))
        })
        .collect()
}

/// What replaces frame i's line (given the line), if anything.
type Odd = dyn Fn(usize, &str) -> Option<String>;

/// `line` with cell `k` replaced.
fn with_cell(line: &str, k: usize, cell: &str) -> String {
    let mut cells: Vec<&str> = line.split(',').collect();
    cells[k] = cell;
    cells.join(",")
}

fn settings(window: Option<usize>) -> FitSettings {
    FitSettings {
        window,
        ..FitSettings::new(InputKind::Midline)
    }
}

#[test]
fn reports_agree_to_the_bit() {
    // Comments, blank lines, white space and CRLF, lost frames, exponents and long mantissas
    // (left to the general parser), skipped time steps: in later chunks.
    let text = midlines(40_000, |i, line| match i % 4999 {
        17 => Some(format!("# a comment\n\n  {line}\r")),
        1001 => Some(with_cell(line, 2, "NaN")),
        1501 => Some(with_cell(line, 3, "")),
        2002 => Some(line.replace(',', " \t")),
        3003 => {
            let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
            let line = with_cell(line, 2, &format!("{:e}", cells[2]));
            Some(with_cell(&line, 3, &format!("{:.19}", cells[3])))
        }
        4004 => Some(String::new()),
        _ => None,
    });
    for (tag, s) in [
        ("w128", settings(Some(128))),
        ("auto", settings(None)),
        ("filled", {
            let mut s = settings(Some(64));
            s.recording.fill_gaps = 3;
            s
        }),
        ("tail", {
            let mut s = settings(Some(64));
            s.recording.head_first = false;
            s.bootstrap = 20;
            s
        }),
    ] {
        let (file, stream) = both(text.as_bytes(), &s, tag);
        assert!(!file.starts_with("error"), "{tag}: {file}");
        assert_eq!(file, stream, "{tag}");
    }
}

/// A file eight times the text of its first 10 240 frames: a pilot over those foretells the
/// window, and the pass keeps every mode only there. The numbers stay the whole ladder's (the
/// stream keeps every window): when the recording chooses the window foretold, and when its
/// first frames move four times faster than the rest, so the pilot foretells shorter windows
/// than the recording chooses and the file is read again; an error past the pilot's frames
/// is worded the same. A pilot whose frames are too broken by losses for its longest window
/// (the only one its ladder keeps the lead modes at) foretells nothing.
#[test]
fn a_pilot_changes_no_number() {
    let steady = midlines(90_000, |_, _| None);
    let hasty = midlines(90_000, |i, _| {
        (i < 12_000).then(|| frame(i, 0.16 * i as f64))
    });
    let resampled = FitSettings {
        bootstrap: 20,
        ..settings(None)
    };
    for (tag, text, s, kept) in [
        ("steady", &steady, settings(None), true),
        ("hasty", &hasty, settings(None), false),
        ("steady-bootstrap", &steady, resampled.clone(), true),
        ("hasty-bootstrap", &hasty, resampled, false),
    ] {
        let (file, stream, foretold) = both_foretold(text.as_bytes(), &s, tag);
        assert!(!file.starts_with("error"), "{tag}: {file}");
        assert_eq!(file, stream, "{tag}");
        let report: serde_json::Value = serde_json::from_str(&file).unwrap();
        let chosen = report["window"]["frames"].as_u64().unwrap() as usize;
        let foretold = foretold.unwrap_or_else(|| panic!("{tag}: no pilot"));
        assert_eq!(
            foretold.contains(&chosen),
            kept,
            "{tag}: {foretold:?}, {chosen}"
        );
    }
    // Segment lengths are foretold as midlines are.
    let mut s = settings(None);
    s.recording.kind = InputKind::Lengths;
    let (file, stream, foretold) = both_foretold(lengths(120_000).as_bytes(), &s, "lengths");
    assert!(foretold.is_some() && !file.starts_with("error"), "{file}");
    assert_eq!(file, stream);
    let late = midlines(90_000, |i, l| (i == 80_000).then(|| with_cell(l, 5, "x1")));
    let (file, stream, foretold) = both_foretold(late.as_bytes(), &settings(None), "late");
    assert!(foretold.is_some() && file.starts_with("error"), "{file}");
    assert_eq!(file, stream);
    // Three frames lost every 2000 in the pilot's: no forecast, the same numbers.
    let gappy = midlines(90_000, |i, _| (i % 2000 < 3).then(String::new));
    let (file, stream, foretold) = both_foretold(gappy.as_bytes(), &settings(None), "gappy");
    assert!(foretold.is_none() && !file.starts_with("error"), "{file}");
    assert_eq!(file, stream);
    // A shorter file keeps the whole ladder.
    let short = midlines(40_000, |_, _| None);
    assert_eq!(
        both_foretold(short.as_bytes(), &settings(None), "short").2,
        None
    );
}

#[test]
fn lengths_and_resampled_midlines_agree() {
    let lengths = lengths(30_000);
    let mut s = settings(Some(64));
    s.recording.kind = InputKind::Lengths;
    let (file, stream) = both(lengths.as_bytes(), &s, "lengths");
    assert!(!file.starts_with("error"), "{file}");
    assert_eq!(file, stream);
    let mut s = settings(Some(64));
    s.recording.points = 9;
    let (file, stream) = both(midlines(30_000, |_, _| None).as_bytes(), &s, "resampled");
    assert!(!file.starts_with("error"), "{file}");
    assert_eq!(file, stream);
}

#[test]
fn errors_agree_wherever_they_sit() {
    let cases: Vec<(&str, Box<Odd>)> = vec![
        (
            "number",
            Box::new(|i, l| (i == FAR).then(|| with_cell(l, 5, "x1"))),
        ),
        (
            "width",
            Box::new(|i, l| (i == FAR).then(|| format!("{l},1"))),
        ),
        (
            "time",
            Box::new(|i, l| (i == FAR).then(|| with_cell(l, 0, "later"))),
        ),
        (
            "backwards",
            Box::new(|i, _| (i == FAR).then(|| "0.5".to_string() + &",1".repeat(24))),
        ),
        (
            "uneven",
            Box::new(|i, l| (i == FAR).then(|| l.replacen(".", ".01", 1))),
        ),
        (
            "long",
            Box::new(|i, _| (i == FAR).then(|| "1,".repeat(700_000))),
        ),
        (
            "coincident",
            Box::new(|i, _| {
                (i == FAR).then(|| format!("{:.2}", i as f64 * 0.04) + &",1,1".repeat(12))
            }),
        ),
    ];
    for (tag, odd) in cases {
        let text = midlines(FAR + 100, odd);
        let (file, stream) = both(text.as_bytes(), &settings(Some(64)), tag);
        assert!(file.starts_with("error"), "{tag}: no error");
        assert_eq!(file, stream, "{tag}");
    }
    // Not UTF-8, far in.
    let mut bytes = midlines(FAR + 100, |_, _| None).into_bytes();
    let at = bytes.len() - 3000;
    bytes[at] = 0xFF;
    let (file, stream) = both(&bytes, &settings(Some(64)), "utf8");
    assert!(file.contains("UTF-8"), "{file}");
    assert_eq!(file, stream);
}
