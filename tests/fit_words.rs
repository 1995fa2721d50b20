//! `fit`'s words a biologist acts on (issue 55): the ω line names the modes that vote, the
//! spectral columns say their units, no report line runs past 160 characters (a command to
//! copy aside), a rejected dispersion points to `discover --active`, and a DeepLabCut file read
//! without `--fps` is said to be in frames, and undetermined tests come with what would decide
//! them.

mod common;

const EXAMPLE: &str = "tables/examples/midlines.csv";
const WORMPOSE: &str = "../shared/data/celegans_wormpose_15fps_52pts.csv";

/// The example's voting modes, from its JSON, as the text should name them.
fn voting(args: &[&str]) -> Vec<u64> {
    let json = common::cli(&[args, &["--format", "json"]].concat()).expect("fit runs");
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    doc["modes_fit"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["votes"].as_bool() == Some(true))
        .map(|m| m["mode"].as_u64().unwrap())
        .collect()
}

fn long_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.chars().count() > 160 && !l.contains("theory-search "))
        .map(String::from)
        .collect()
}

#[test]
fn the_omega_line_names_the_voting_modes_and_the_columns_their_units() {
    let args = ["fit", EXAMPLE];
    let text = common::cli(&args).expect("fit runs");
    let modes = voting(&args);
    let (first, last) = (modes[0], modes[modes.len() - 1]);
    assert_eq!(modes.len() as u64, last - first + 1, "{modes:?}");
    let said = format!("least squares over the voting modes {first}–{last})");
    assert!(text.contains(&said), "{said} not in\n{text}");
    assert!(
        text.contains("f in cycles/time unit, ω in rad/time unit"),
        "{text}"
    );
    let seconds = common::cli(&["fit", EXAMPLE, "--time-unit", "s"]).unwrap();
    assert!(seconds.contains("f in cycles/s, ω in rad/s"), "{seconds}");
    assert!(long_lines(&text).is_empty(), "{:#?}", long_lines(&text));
    let given = common::cli(&["fit", EXAMPLE, "--omega", "1"]).unwrap();
    assert!(
        given.contains("rad/time unit (given by --omega)"),
        "{given}"
    );
}

#[test]
fn a_rejected_dispersion_points_to_discover_and_lines_stay_short() {
    let Ok(text) = common::cli(&["fit", WORMPOSE, "--time-unit", "s"]) else {
        panic!("fit runs on {WORMPOSE}")
    };
    assert!(text.contains("rejected (modes"), "{text}");
    // Wrapped lines read as one.
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat.contains("`discover FILE --model M --active` says which terms"),
        "{text}"
    );
    assert!(long_lines(&text).is_empty(), "{:#?}", long_lines(&text));
}

/// The example as a DeepLabCut export (frame indices, x, y, likelihood per body part).
fn deeplabcut() -> String {
    let example = std::fs::read_to_string(EXAMPLE).unwrap();
    let rows: Vec<Vec<f64>> = example
        .lines()
        .filter_map(|l| l.split(',').map(|c| c.trim().parse().ok()).collect())
        .collect();
    let k = (rows[0].len() - 1) / 2;
    let mut dlc = format!("scorer{}\n", ",DLC_resnet50".repeat(3 * k));
    let parts: Vec<String> = (0..k).flat_map(|j| vec![format!("p{j}"); 3]).collect();
    dlc += &format!("bodyparts,{}\n", parts.join(","));
    dlc += &format!("coords{}\n", ",x,y,likelihood".repeat(k));
    for (i, r) in rows.iter().enumerate() {
        let mut cells = vec![i.to_string()];
        for j in 0..k {
            cells.extend([
                r[1 + 2 * j].to_string(),
                r[2 + 2 * j].to_string(),
                "0.99".into(),
            ]);
        }
        dlc += &(cells.join(",") + "\n");
    }
    dlc
}

#[test]
fn a_deeplabcut_file_without_fps_is_said_to_be_in_frames() {
    let dir_held = common::scratch("dlc-words");
    let path = dir_held.path().join("dlc.csv");
    std::fs::write(&path, deeplabcut()).unwrap();
    let p = path.to_str().unwrap();
    let frames = common::cli(&["fit", p]).expect("fit runs");
    assert!(frames.contains("rad/frame"), "{frames}");
    assert!(
        frames.contains("warning: a DeepLabCut export without --fps: times are in frames"),
        "{frames}"
    );
    let seconds = common::cli(&["fit", p, "--fps", "15", "--time-unit", "s"]).unwrap();
    assert!(!seconds.contains("in frames"), "{seconds}");
    assert!(seconds.contains("rad/s"), "{seconds}");
}

/// The shipped example at a 16-frame window: mode 2 lies under a bin, and the advice names the
/// window that resolves it, which then brings it into the vote and decides the tests; the other changes the advice
/// names (points, rate) are said once each, with numbers.
#[test]
fn undetermined_tests_say_what_would_decide_them() {
    let text = common::cli(&["fit", EXAMPLE, "--window", "16"]).expect("fit runs");
    let line = (text.lines())
        .find(|l| l.contains("to decide the tests"))
        .unwrap_or_else(|| panic!("no advice in\n{text}"));
    assert!(line.contains("mode 2: --window 29"), "{line}");
    assert!(long_lines(&text).is_empty(), "{:?}", long_lines(&text));
    let json = common::cli(&["fit", EXAMPLE, "--window", "16", "--format", "json"]).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    let steps = doc["advice"]["steps"].as_array().expect("steps");
    assert_eq!(steps[0]["change"], "window", "{steps:?}");
    for kind in ["points", "rate"] {
        let n = steps.iter().filter(|s| s["change"] == kind).count();
        assert!(n <= 1, "{kind} said {n} times: {steps:?}");
    }
    assert!(voting(&["fit", EXAMPLE, "--window", "29"]).contains(&2));
    // Decided tests carry no advice.
    let decided = common::cli(&["fit", EXAMPLE, "--window", "512"]).unwrap();
    assert!(!decided.contains("to decide the tests") || decided.contains("undetermined"));
}

/// The words before the numbers: whether the theory holds, the constant, and the next command
/// with this recording's names and numbers; every `next:` line that is a command runs.
#[test]
fn the_report_opens_with_the_verdict_and_the_next_command() {
    let first_lines = |args: &[&str]| -> Vec<String> {
        let text = common::cli(args).expect("fit runs");
        text.lines().take(3).map(String::from).collect()
    };
    // Consistent: the fitted body, simulated.
    let holds = first_lines(&["fit", EXAMPLE]);
    assert!(
        holds[0].starts_with("In short: the theory holds here"),
        "{holds:?}"
    );
    assert!(holds[1].starts_with("  κ = 0.00992"), "{holds:?}");
    assert!(
        holds[2].starts_with("  next: theory-search simulate --points 12 --param omega_b="),
        "{holds:?}"
    );
    // Rejected on a model with an [active] section: discover --active, with the same
    // recording, model and reading options.
    let crawler = "tables/models/crawler.toml";
    let rejected = first_lines(&["fit", WORMPOSE, "--model", crawler, "--time-unit", "s"]);
    assert!(
        rejected[0].starts_with("In short: the theory does not hold here: "),
        "{rejected:?}"
    );
    assert!(
        rejected[1].contains("not a constant of this body"),
        "{rejected:?}"
    );
    let next = format!(
        "  next: theory-search discover {WORMPOSE} --time-unit s --model {crawler} --active ("
    );
    assert!(rejected[2].starts_with(&next), "{rejected:?}");
    // Without an [active] section, plain discover (which names the next layer itself).
    let worm = first_lines(&["fit", WORMPOSE, "--model", "tables/models/worm.toml"]);
    assert!(!worm[2].contains("--active"), "{worm:?}");
    // Undetermined: the advice's option, with its number.
    let few = first_lines(&["fit", EXAMPLE, "--points", "5"]);
    assert_eq!(
        few[0],
        "In short: undetermined: 2 voting mode(s), a test needs 3."
    );
    assert!(
        few[2].starts_with("  next: this command again with --points 10 "),
        "{few:?}"
    );
    // Each command printed runs as printed.
    for lines in [&holds, &rejected, &worm] {
        let command = lines[2]
            .trim()
            .strip_prefix("next: theory-search ")
            .unwrap();
        let command = command.split(" (").next().unwrap();
        let args: Vec<&str> = command.split_whitespace().collect();
        common::cli(&args).unwrap_or_else(|e| panic!("{command}: {e}"));
    }
}
