//! Scenario: work that used to run for seconds or minutes (hostile input IV) is either fast or
//! refused up front in one line, exit 2 (docs/budgets.md): the damped roots of an active body
//! at 400 points, one `simulate` step of a gyroscopic body at 400 points, `discover --active`
//! with eight layers beyond leading, `discover` on hundreds of animals, a weak form over its
//! budget, and the classification of a loose `[active]` section's forces.

use std::time::{Duration, Instant};

mod common;
use common::binary as run;

const CRAWLER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/crawler.toml");
const CHANNEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tables/models/channel_worm.toml"
);
const PERISTALSIS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tables/models/peristalsis.toml"
);
const MIDLINES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");

/// `args` with its exit code, stderr and wall time.
fn timed(args: &[&str]) -> (i32, String, Duration) {
    let started = Instant::now();
    let (code, _, err) = run(args);
    (code, err, started.elapsed())
}

/// A model file of `text`.
fn model(text: &str) -> tempfile::NamedTempFile {
    let mut f = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
    std::io::Write::write_all(&mut f, text.as_bytes()).unwrap();
    f
}

/// The channel worm with an `[active]` section on every field, and `extra` more fields.
fn active_channel(extra: usize) -> tempfile::NamedTempFile {
    let base = std::fs::read_to_string(CHANNEL).unwrap();
    let (fields, rest) = base.split_once("[lagrangian]").unwrap();
    let mut text = fields.to_string();
    let mut ids = vec!["x", "theta", "y", "z"];
    let more: Vec<String> = (0..extra).map(|k| format!("w{k}")).collect();
    for id in &more {
        text += &format!(
            "[[fields]]\nid = \"{id}\"\nsymbol = \"{id}\"\nmeaning = \"extra bending\"\nboundary = \"pinned\"\nscale = \"b\"\n\n"
        );
        ids.push(id);
    }
    text += "[lagrangian]";
    // Every requirements table names the extra fields as it names y.
    for line in rest.lines() {
        text += line;
        text += "\n";
        if let Some(reqs) = line.strip_prefix("y = ") {
            for id in &more {
                text += &format!("{id} = {reqs}\n");
            }
        }
    }
    text += "\n[active]\nbound = \"tau-and-sigma\"\ncolumns = [\"OST\", \"TRAN\", \"REF\", \"ROT\", \"GAL\", \"PAR\", \"TREV\"]\n\n[active.requirements]\n";
    for id in ids {
        text += &format!("{id} = [\"OST\", \"TRAN\", \"REF\", \"ROT\", \"GAL\"]\n");
    }
    model(&text)
}

#[test]
fn the_damped_roots_of_an_active_body_at_400_points_are_fast_or_refused_up_front() {
    let four = active_channel(0);
    let path = four.path().to_str().unwrap();
    // Four fields of 400 unknowns: within the budget (8 s with nalgebra's Schur form).
    let (code, err, took) = timed(&[
        "modes", "-p", "400", "--model", path, "--param", "a_y=1e6", "--modes", "100",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(took < Duration::from_secs(6), "took {took:?}");
    // Five: over it, refused before any eigen-solve.
    let five = active_channel(1);
    let (code, err, took) = timed(&[
        "modes",
        "-p",
        "400",
        "--model",
        five.path().to_str().unwrap(),
        "--param",
        "a_y=1e6",
        "--modes",
        "100",
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("over the budget"), "{err}");
    assert!(took < Duration::from_secs(2), "took {took:?}");
}

#[test]
fn one_step_of_a_gyroscopic_body_at_400_points_does_not_solve_its_damped_roots() {
    // The modal initial state needs the modes, not the quadratic eigenproblem (1.8 s before).
    let started = Instant::now();
    let (code, out, err) = run(&[
        "simulate",
        "--model",
        PERISTALSIS,
        "-p",
        "400",
        "--param",
        "g_x=1",
        "--steps",
        "1",
        "--initial",
        "x:1=0.1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 3, "{out}");
    assert!(
        started.elapsed() < Duration::from_millis(1000),
        "took {:?}",
        started.elapsed()
    );
}

#[test]
fn discover_on_hundreds_of_animals_is_refused_up_front() {
    let mut args = vec!["discover"];
    args.extend(std::iter::repeat_n(MIDLINES, 300));
    let (code, err, took) = timed(&args);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("300 recordings"), "{err}");
    assert!(err.contains("at most 100"), "{err}");
    assert!(took < Duration::from_secs(2), "took {took:?}");
    // Within the limit it runs.
    let (code, err, _) = timed(&["discover", MIDLINES, MIDLINES, "--bootstrap", "0"]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn discover_with_eight_layers_beyond_leading_builds_its_library_once() {
    // Each coefficient's body re-derived the model and its [active] forces: 13 s of CPU.
    let text = std::fs::read_to_string(CRAWLER)
        .unwrap()
        .replace("[lagrangian]\n", "[lagrangian]\nbeyond_leading = 8\n")
        .replace("[rayleigh]\n", "[rayleigh]\nbeyond_leading = 8\n");
    let m = model(&text);
    let (code, err, took) = timed(&[
        "discover",
        MIDLINES,
        "--model",
        m.path().to_str().unwrap(),
        "--active",
        "--order",
        "8",
        "--bootstrap",
        "0",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(took < Duration::from_secs(8), "took {took:?}");
}

/// `base` (a shipped model) with an `[active]` section of `bound` requiring `rules` of every
/// field in `fields` (its own section, if any, dropped).
fn with_active(base: &str, bound: &str, rules: &str, fields: &[&str]) -> tempfile::NamedTempFile {
    let text = std::fs::read_to_string(format!(
        "{}/tables/models/{base}.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let mut text = match text.find("\n[active]\n") {
        Some(at) => text[..at].to_string(),
        None => text,
    };
    text +=
        &format!("\n[active]\nbound = \"{bound}\"\ncolumns = [\"OST\"]\n\n[active.requirements]\n");
    for f in fields {
        text += &format!("{f} = [{rules}]\n");
    }
    model(&text)
}

/// One line, exit 2, naming the classification budget.
fn refused_by_the_classification_budget(args: &[&str]) {
    let (code, err, _) = timed(args);
    assert_eq!(code, 2, "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("covariant candidate forces"), "{err}");
    assert!(err.contains("over the budget of 3e6"), "{err}");
}

#[test]
fn classifying_the_forces_of_a_loose_active_section_is_refused_up_front() {
    // Issue 53 item 2: an [active] section requiring only OST (or nothing) leaves tens of
    // thousands of candidates to classify, each an Euler–Lagrange expansion: 16 s of CPU for
    // `equations --order 12` on the worm, over a minute for the other two.
    let all = ["x", "theta", "y", "z"];
    let worm = with_active("worm", "tau-plus-sigma", "\"OST\"", &all);
    let w = worm.path().to_str().unwrap();
    refused_by_the_classification_budget(&["equations", "--model", w, "--order", "12"]);
    refused_by_the_classification_budget(&["active", "--model", w, "--order", "12"]);
    let fish = with_active("zebrafish", "tau-plus-sigma", "\"OST\"", &all);
    let f = fish.path().to_str().unwrap();
    refused_by_the_classification_budget(&["modes", "--model", f, "-p", "12", "--order", "12"]);
    let ring = with_active("peristalsis", "tau-and-sigma", "", &["x"]);
    let r = ring.path().to_str().unwrap();
    refused_by_the_classification_budget(&["active", "--model", r, "--order", "8"]);
    // Within the budget they run: lower orders of the same sections, and the shipped models'
    // own sections at order 8 (a few hundred covariant candidates of 141,381).
    for (m, order) in [(w, "8"), (r, "6")] {
        let (code, err, _) = timed(&["active", "--model", m, "--order", order]);
        assert_eq!(code, 0, "{m} at {order}: {err}");
    }
    for m in [CRAWLER, PERISTALSIS] {
        let (code, err, _) = timed(&["active", "--model", m, "--order", "8"]);
        assert_eq!(code, 0, "{m}: {err}");
    }
}

#[test]
fn discover_refuses_a_weak_form_over_its_budget_before_its_sums() {
    // 30 copies of the example end to end (90,000 frames), each midline interpolated to 50
    // points (a recording must track at least the model's points), against the crawler's
    // 71-term library at order 8 with eight layers beyond leading (a basis: six active monomials
    // that add no direction are not candidates): 90,000 × 50 × 1 mode × 71 = 3.2e8 units, over
    // the weak form's 3e8.
    let text = std::fs::read_to_string(MIDLINES).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let at = |row: &[f64], u: f64, c: usize| {
        let k = (row.len() - 1) / 2;
        let (j, f) = (
            (u.floor() as usize).min(k - 2),
            u - (u.floor()).min((k - 2) as f64),
        );
        (1.0 - f) * row[1 + 2 * j + c] + f * row[1 + 2 * (j + 1) + c]
    };
    let mut long = String::new();
    for copy in 0..30 {
        for row in &rows {
            let k = (row.len() - 1) / 2;
            long += &(row[0] + (copy * rows.len()) as f64).to_string();
            for i in 0..50 {
                let u = i as f64 * (k - 1) as f64 / 49.0;
                long += &format!(",{},{}", at(row, u, 0), at(row, u, 1));
            }
            long.push('\n');
        }
    }
    let data = common::scratch_file("weak-budget", ".csv");
    std::fs::write(data.path(), long).unwrap();
    let crawler = std::fs::read_to_string(CRAWLER)
        .unwrap()
        .replace("[active]\n", "[active]\nbeyond_leading = 8\n");
    let m = model(&crawler);
    let (code, err, _) = timed(&[
        "discover",
        data.path().to_str().unwrap(),
        "--model",
        m.path().to_str().unwrap(),
        "--active",
        "--order",
        "8",
        "--bootstrap",
        "0",
        "-p",
        "50",
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("the weak form's sums are 3.2e8 units"),
        "{err}"
    );
    assert!(err.contains("71 library terms"), "{err}");
    assert!(err.contains("over the budget of 3e8"), "{err}");
}
