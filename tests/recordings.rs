//! Real recordings (`../shared/data`, never copied here): lost frames split the runs, the
//! counts match the data's README, and the fits agree with what a plain PCA of the gap-free
//! frames shows there.

mod common;

/// The path of a recording in `../shared/data`.
fn data(file: &str) -> String {
    format!("{}/../shared/data/{file}", env!("CARGO_MANIFEST_DIR"))
}

fn fit(file: &str, extra: &[&str]) -> serde_json::Value {
    let path = data(file);
    assert!(
        std::path::Path::new(&path).exists(),
        "{path} is missing: the recording tests need ../shared beside the repository"
    );
    let mut args = vec![
        "theory-search",
        "fit",
        &path,
        "--head",
        "first",
        "--format",
        "json",
    ];
    args.extend_from_slice(extra);
    let mut out = Vec::new();
    theory_search::cli::run(args, &mut out).unwrap_or_else(|e| panic!("{file}: {e}"));
    serde_json::from_slice(&out).unwrap()
}

#[test]
fn lost_frames_are_counted_and_split_the_runs() {
    for (file, read, lost) in [
        ("celegans_wt2_crawling_30fps_49pts.csv", 499, 99),
        ("celegans_wormpose_15fps_52pts.csv", 1000, 280),
    ] {
        let v = fit(file, &["--window", "64"]);
        let rec = &v["recording"];
        assert_eq!(rec["frames_read"], read, "{file}");
        assert_eq!(rec["frames_lost"], lost, "{file}");
        // Frames used: the usable ones and the lost ones bridged (gaps of ≤ 2 by default).
        let filled = rec["frames_filled"].as_u64().unwrap();
        assert_eq!(v["frames"], read - lost + filled, "{file}");
        assert_eq!(rec["fill_gaps"], 2, "{file}");
        let none = fit(file, &["--window", "64", "--fill-gaps", "0"]);
        assert_eq!(none["frames"], read - lost, "{file}");
        assert!(rec["runs"].as_u64().unwrap() > 1, "{file}");
        assert!(v["omega"].as_f64().unwrap().is_finite());
    }
}

#[test]
fn the_fits_see_what_the_data_show() {
    // WormPose: the first components lie close to the free–free beam modes.
    let v = fit("celegans_wormpose_15fps_52pts.csv", &["--window", "64"]);
    let overlap = v["mode_overlap"].as_array().unwrap();
    for k in 0..3 {
        assert!(overlap[k].as_f64().unwrap() > 0.95, "mode {k}: {overlap:?}");
    }
    // WT2 forward crawling: a driven travelling wave, its first two components a
    // near-degenerate pair of about 53 % and 42 % of the variance (in the coordinates of the
    // continuum modes; the N-point modes' read 54 % and 38 %).
    let v = fit("celegans_wt2_crawling_30fps_49pts.csv", &["--window", "64"]);
    let shares = v["pca_variance_share"].as_array().unwrap();
    let (a, b) = (shares[0].as_f64().unwrap(), shares[1].as_f64().unwrap());
    assert!(
        (a - 0.53).abs() < 0.03 && (b - 0.42).abs() < 0.03,
        "{a} {b}"
    );
    // Bridging the short stage-move gaps gives longer runs and more frames, never fewer.
    let bridged = fit(
        "celegans_wt2_crawling_30fps_49pts.csv",
        &["--window", "64", "--fill-gaps", "5"],
    );
    assert!(bridged["recording"]["longest_run"].as_u64() > v["recording"]["longest_run"].as_u64());
    assert!(bridged["frames"].as_u64() > v["frames"].as_u64());
}

#[test]
fn several_recordings_pool_into_one_fit_beside_each_own() {
    // The same animal twice: the pooled statistics are those of one copy, with twice the frames.
    let path = data("celegans_wormpose_15fps_52pts.csv");
    let one = fit("celegans_wormpose_15fps_52pts.csv", &["--window", "64"]);
    let mut out = Vec::new();
    theory_search::cli::run(
        [
            "theory-search",
            "fit",
            &path,
            &path,
            "--head",
            "first",
            "--window",
            "64",
            "--format",
            "json",
        ],
        &mut out,
    )
    .unwrap();
    let two: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(two["frames"], 2 * one["frames"].as_u64().unwrap());
    assert_eq!(two["recording"]["recordings"], 2);
    let (a, b) = (&one["pca_variance_share"], &two["pca_variance_share"]);
    for k in 0..3 {
        assert!(
            (a[k].as_f64().unwrap() - b[k].as_f64().unwrap()).abs() < 1e-6,
            "{a} {b}"
        );
    }
    assert_eq!(two["animals"].as_array().unwrap().len(), 2);
    // The animal alone against the same file fitted alone: one iterative fit, to its tolerance.
    let (alone, whole) = (
        two["animals"][0]["omega"].as_f64().unwrap(),
        one["omega"].as_f64().unwrap(),
    );
    assert!((alone / whole - 1.0).abs() < 1e-6, "{alone} {whole}");
    // Recordings of different rates cannot share spectra: the pool keeps the first's rate, the
    // other is its own rate group (here one animal), listed with its group.
    let wt2 = data("celegans_wt2_crawling_30fps_49pts.csv");
    let mixed = fit("celegans_wormpose_15fps_52pts.csv", &[&wt2]);
    assert_eq!(mixed["frames"], one["frames"], "only the first rate pooled");
    assert_eq!(mixed["recording"]["recordings"], 1);
    let animals = mixed["animals"].as_array().unwrap();
    assert_eq!(animals.len(), 2);
    assert!(animals[0].get("note").is_none(), "{}", animals[0]);
    let note = animals[1]["note"].as_str().unwrap();
    assert!(
        note.contains("rate group 2, sampled every 0.0333"),
        "{note}"
    );
    assert_eq!(mixed["rate_groups"].as_array().unwrap().len(), 2);
    assert!(mixed["across_rates"]["constant"].as_f64().unwrap() > 0.0);
    // Its own fit, in its own time unit: the same ω as the file fitted alone.
    let alone = fit("celegans_wt2_crawling_30fps_49pts.csv", &[]);
    let (a, b) = (
        animals[1]["omega"].as_f64().unwrap(),
        alone["omega"].as_f64().unwrap(),
    );
    assert!((a / b - 1.0).abs() < 1e-6, "{a} {b}");
}

#[test]
fn a_fit_feeds_the_other_commands_through_a_parameter_file() {
    let dir_held = common::scratch("params-out");
    let dir = dir_held.path();
    let params = dir.join("fitted.toml");
    let path = data("celegans_wormpose_15fps_52pts.csv");
    let mut out = Vec::new();
    let p = params.to_str().unwrap();
    theory_search::cli::run(
        [
            "theory-search",
            "fit",
            &path,
            "--head",
            "first",
            "--window",
            "64",
            "--format",
            "json",
            "--params-out",
            p,
        ],
        &mut out,
    )
    .unwrap();
    let fitted: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_modes_take_omega(&["--params", p], &fitted);
}

#[test]
fn deeplabcut_files_are_read_with_their_likelihoods() {
    // A DeepLabCut export of the shipped example: three header rows, frame index, then x, y,
    // likelihood per body part (head first, as DLC users label), some points uncertain.
    let example = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tables/examples/midlines.csv"
    ))
    .unwrap();
    let rows: Vec<Vec<f64>> = example
        .lines()
        .filter_map(|l| {
            let v: Result<Vec<f64>, _> = l.split(',').map(|c| c.trim().parse()).collect();
            v.ok()
        })
        .collect();
    let k = (rows[0].len() - 1) / 2;
    let dt = rows[1][0] - rows[0][0];
    let mut dlc = String::new();
    dlc += &format!("scorer{}\n", ",DLC_resnet50".repeat(3 * k));
    let parts: Vec<String> = (0..k).flat_map(|j| vec![format!("p{j}"); 3]).collect();
    dlc += &format!("bodyparts,{}\n", parts.join(","));
    dlc += &format!("coords{}\n", ",x,y,likelihood".repeat(k));
    for (i, r) in rows.iter().enumerate() {
        let mut cells = vec![i.to_string()];
        for j in (0..k).rev() {
            let likely = if i % 97 == 5 && j == 3 { 0.2 } else { 0.99 };
            cells.extend([
                r[1 + 2 * j].to_string(),
                r[2 + 2 * j].to_string(),
                likely.to_string(),
            ]);
        }
        dlc += &(cells.join(",") + "\n");
    }
    let dir_held = common::scratch("dlc");
    let dir = dir_held.path();
    let path = dir.join("dlc.csv");
    std::fs::write(&path, &dlc).unwrap();
    let fps = (1.0 / dt).to_string();
    let p = path.to_str().unwrap();
    let mut out = Vec::new();
    theory_search::cli::run(
        // Single uncertain frames are bridged, so the Welch windows stay long.
        [
            "theory-search",
            "fit",
            p,
            "--head",
            "first",
            "--fps",
            &fps,
            "--fill-gaps",
            "1",
            "--format",
            "json",
        ],
        &mut out,
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let lost = rows.iter().enumerate().filter(|(i, _)| i % 97 == 5).count();
    assert_eq!(v["recording"]["frames_lost"], lost);
    assert_eq!(v["recording"]["frames_filled"], lost);
    // The same physics as the plain file: κ = 0.01 in the generator.
    let kappa = v["continuum"]["constant"].as_f64().unwrap();
    assert!((kappa / 0.01 - 1.0).abs() < 0.03, "{kappa}");
    // --fps took: the frame indices over it are the clock. A file with a time column refuses it.
    assert!((v["sample_interval"].as_f64().unwrap() - dt).abs() < 1e-9 * dt);
    let example = format!(
        "{}/tables/examples/midlines.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let args = ["theory-search", "fit", &example, "--fps", "15"];
    let e = theory_search::cli::run(args, &mut Vec::new()).unwrap_err();
    assert_eq!(e.exit_code(), 2, "{e}");
    assert!(
        e.to_string()
            .contains("--fps applies to files without a time column"),
        "{e}"
    );
}

#[test]
fn the_report_ends_with_arguments_the_other_commands_take() {
    let v = fit(
        "celegans_wormpose_15fps_52pts.csv",
        &["--window", "64", "--time-unit", "s", "--length-unit", "px"],
    );
    assert_eq!(v["units"]["time"], "s");
    assert_eq!(v["units"]["length"], "px");
    assert!(v["spacing"].as_f64().unwrap() > 0.0);
    let onward: Vec<String> = v["onward"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap().to_string())
        .collect();
    assert_eq!(onward[0], "--param");
    assert!(onward[1].starts_with("omega_b="), "{onward:?}");
    // simulate takes them all; modes and behave take the scale.
    let mut args = vec![
        "theory-search",
        "simulate",
        "--steps",
        "20",
        "--points",
        "12",
    ];
    args.extend(onward.iter().map(String::as_str));
    let mut out = Vec::new();
    theory_search::cli::run(args, &mut out).unwrap();
    assert!(String::from_utf8(out).unwrap().lines().count() > 20);
    assert_modes_take_omega(&onward[..2], &v);
    let mut out = Vec::new();
    theory_search::cli::run(
        ["theory-search", "behave", "rolling", &onward[0], &onward[1]],
        &mut out,
    )
    .unwrap();
}

#[test]
fn one_recording_bootstraps_over_moving_blocks_of_time() {
    let v = fit(
        "celegans_wormpose_15fps_52pts.csv",
        &["--window", "64", "--bootstrap", "200", "--seed", "3"],
    );
    let i = &v["intervals"];
    assert_eq!(i["resampled"], "blocks");
    // Blocks of at most 64 frames over the 720 usable frames in 6 runs, drawn several
    // consecutive at a time.
    let units = i["units"].as_u64().unwrap();
    assert!((10..=16).contains(&units), "{units}");
    assert!(i["moving"][0].as_u64().unwrap() > 1, "{}", i["moving"]);
    let omega = v["omega"].as_f64().unwrap();
    let w: Vec<f64> = i["omega"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(w[0] < omega && omega < w[1], "{w:?} around {omega}");
    // Same seed, same intervals.
    let again = fit(
        "celegans_wormpose_15fps_52pts.csv",
        &["--window", "64", "--bootstrap", "200", "--seed", "3"],
    );
    assert_eq!(again["intervals"], v["intervals"]);
    let s = v["subspace"].as_array().unwrap();
    assert!(s[2]["cosine"].as_f64().unwrap() > 0.95, "{s:?}");
}

/// `modes` with `args` gives field y the fitted ω of `fitted`.
fn assert_modes_take_omega<S: AsRef<str>>(args: &[S], fitted: &serde_json::Value) {
    let mut all = vec!["theory-search", "modes", "-p", "12", "--format", "json"];
    all.extend(args.iter().map(|a| a.as_ref()));
    let mut out = Vec::new();
    theory_search::cli::run(all, &mut out).unwrap();
    let m: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let y = m["fields"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["field"] == "y")
        .unwrap();
    let omega = fitted["omega"].as_f64().unwrap();
    assert!(
        (y["omega"].as_f64().unwrap() - omega).abs() < 1e-12 * omega,
        "{y}"
    );
}

/// A window too short to resolve the fitted modes says so (at 15 frames per second a 16-frame
/// window has bins of 0.94 Hz, above the worm's 0.35 Hz), and the continuum constant is the
/// same at 12 and 24 model points.
#[test]
fn a_window_that_cannot_resolve_the_modes_says_so() {
    let worm = data("celegans_wormpose_15fps_52pts.csv");
    let fit = |args: &[&str]| -> serde_json::Value {
        let mut all = vec!["theory-search", "fit", worm.as_str(), "--format", "json"];
        all.extend(args);
        let mut out = Vec::new();
        theory_search::cli::run(all, &mut out).unwrap();
        serde_json::from_slice(&out).unwrap()
    };
    let short = fit(&["--window", "16"]);
    let warnings: Vec<&str> = short["warnings"]
        .as_array()
        .map(|w| w.iter().filter_map(|s| s.as_str()).collect())
        .unwrap_or_default();
    assert!(
        warnings.iter().any(|w| w.contains("cannot resolve")),
        "{warnings:?}"
    );
    // The constant agrees between windows 64 and 128 (their intervals overlap), and the worm is
    // not a passive beam: its modes share one frequency, so the dispersion is rejected.
    let interval = |v: &serde_json::Value| -> [f64; 2] {
        let i = v["continuum"]["interval"].as_array().expect("an interval");
        [i[0].as_f64().unwrap(), i[1].as_f64().unwrap()]
    };
    let (w64, w128) = (fit(&["--window", "64"]), fit(&["--window", "128"]));
    let (a, b) = (interval(&w64), interval(&w128));
    assert!(a[0] < b[1] && b[0] < a[1], "{a:?} {b:?}");
    for v in [&w64, &w128] {
        assert_eq!(
            v["tests"]["dispersion"]["verdict"], "rejected",
            "{}",
            v["tests"]
        );
        assert_eq!(v["continuum"]["interval_from"], "mode errors");
    }
    // With a bootstrap κ has a resampled interval too, around it.
    let boot = fit(&["--window", "128", "--bootstrap", "100"]);
    let iv = boot["intervals"]["continuum"]
        .as_array()
        .expect("an interval");
    let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
    let k = boot["continuum"]["constant"].as_f64().unwrap();
    assert!(lo.is_finite() && lo < k && k < hi, "{lo} {k} {hi}");
    // WT2's short runs: its modes fitted across the runs are sharp (ζ ≈ 0.03), so a draw of
    // moving blocks must span five correlation times, far more than a run holds: the report
    // says there is no bootstrap and why, with the numbers.
    let v = crate::fit(
        "celegans_wt2_crawling_30fps_49pts.csv",
        &["--window", "32", "--bootstrap", "200", "--seed", "1"],
    );
    let said = v["warnings"].to_string();
    assert!(
        said.contains("no bootstrap: a draw must span") && said.contains("record longer"),
        "{said}"
    );
    assert!(v.get("intervals").is_none(), "{}", v["intervals"]);
    // The shipped example, at a window that resolves its modes 2–4 (its fifth reaches past
    // Nyquist), has no such warning.
    let example = format!(
        "{}/tables/examples/midlines.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut out = Vec::new();
    theory_search::cli::run(
        [
            "theory-search",
            "fit",
            example.as_str(),
            "--window",
            "512",
            "--fit-modes",
            "3",
        ],
        &mut out,
    )
    .unwrap();
    assert!(!String::from_utf8(out).unwrap().contains("cannot resolve"));
}

/// WT2 at the defaults: its runs of 12–25 frames between stage moves hold Welch's window to 32
/// frames, under a bin for its low modes; the exact likelihood fits them across all runs
/// (`fit/timedomain.rs`), so modes 2–4 vote and every test is decided: the driven crawl is no
/// passive beam (Ω nearly flat across modes 2–4, 2.73/2.98/3.14 rad/s).
#[test]
fn wt2_at_the_defaults_gets_decided_tests() {
    let v = fit("celegans_wt2_crawling_30fps_49pts.csv", &[]);
    let voting: Vec<u64> = (v["modes_fit"].as_array().unwrap().iter())
        .filter(|m| m["votes"] == true)
        .map(|m| m["mode"].as_u64().unwrap())
        .collect();
    assert_eq!(voting, [2, 3, 4], "{}", v["modes_fit"]);
    for m in v["modes_fit"].as_array().unwrap().iter().take(3) {
        assert_eq!(m["exact"], "window limited by short runs", "{m}");
        let omega = m["omega"].as_f64().unwrap();
        assert!((2.5..3.4).contains(&omega), "{m}");
    }
    for t in ["equipartition", "dispersion", "damping"] {
        assert_eq!(
            v["tests"][t]["verdict"], "rejected",
            "{t}: {}",
            v["tests"][t]
        );
    }
    let k = v["continuum"]["constant"].as_f64().unwrap();
    let iv = v["continuum"]["interval"].as_array().expect("κ's interval");
    let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
    assert!(
        lo < k && k < hi && (0.03..0.045).contains(&k),
        "{lo} {k} {hi}"
    );
    assert!(v.get("advice").is_none(), "{}", v["advice"]);
}

/// WT2's first 150 rows (runs of at most 16 frames): no mode votes, and the advice names the
/// least --fill-gaps that joins runs a period long, with the share it would synthesise; taking
/// it brings modes into the vote.
#[test]
fn a_short_piece_of_wt2_is_told_what_would_decide_it() {
    let dir = common::scratch("wt2-piece");
    let text = std::fs::read_to_string(data("celegans_wt2_crawling_30fps_49pts.csv")).unwrap();
    let piece: String = text.lines().take(150).map(|l| format!("{l}\n")).collect();
    let path = dir.path().join("wt2_150.csv");
    std::fs::write(&path, piece).unwrap();
    let run = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "theory-search",
            "fit",
            path.to_str().unwrap(),
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        let mut out = Vec::new();
        theory_search::cli::run(args, &mut out).unwrap();
        serde_json::from_slice(&out).unwrap()
    };
    let v = run(&[]);
    let advice = &v["advice"];
    assert_eq!(advice["voting"], 0, "{advice}");
    let step = &advice["steps"][0];
    assert_eq!(step["change"], "fill_gaps", "{advice}");
    let k = step["fill_gaps"].as_u64().unwrap();
    assert!(
        step["longest"].as_u64() >= step["needed"].as_u64(),
        "{step}"
    );
    let share = step["share"].as_f64().unwrap();
    assert!(share > 0.05 && share < 0.3, "{step}");
    let bridged = run(&["--fill-gaps", &k.to_string()]);
    let votes = (bridged["modes_fit"].as_array().unwrap().iter())
        .filter(|m| m["votes"] == true)
        .count();
    assert!(votes >= 2, "{}", bridged["modes_fit"]);
    let filled = bridged["recording"]["frames_filled"].as_f64().unwrap();
    let used = bridged["frames"].as_f64().unwrap();
    assert!(
        (filled / used - share).abs() < 1e-9,
        "{filled} {used} {share}"
    );
}

/// Bridging is said whenever it synthesises more than 5 % of the frames used: WT2 (runs of
/// 12–25 frames between stage moves) with `--fill-gaps 10` has a fifth of its frames drawn as
/// straight lines; at the default (gaps of ≤ 2 frames) it has less, and no warning.
#[test]
fn a_fit_says_what_share_of_its_frames_bridging_synthesised() {
    let file = "celegans_wt2_crawling_30fps_49pts.csv";
    let warned = |v: &serde_json::Value| {
        v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|w| w.as_str())
            .find(|w| w.contains("were synthesised by bridging"))
            .map(str::to_string)
    };
    let wide = fit(file, &["--fill-gaps", "10"]);
    let filled = wide["recording"]["frames_filled"].as_u64().unwrap();
    let frames = wide["frames"].as_u64().unwrap();
    assert!(filled * 20 > frames, "{filled} of {frames}");
    let w = warned(&wide).expect("a warning at a fifth of the frames bridged");
    assert!(
        w.contains(&format!("{filled} of the {frames} frames used")),
        "{w}"
    );
    // The recording line says the share whenever bridging ran.
    let mut out = Vec::new();
    let path = data(file);
    theory_search::cli::run(
        ["theory-search", "fit", &path, "--fill-gaps", "10"],
        &mut out,
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    let share = 100.0 * filled as f64 / frames as f64;
    let said = format!("({filled} bridged, {share:.1} % of the frames used: gaps of ≤ 10 frames");
    assert!(text.contains(&said), "{said}\n{text}");
    let default = fit(file, &[]);
    let filled = default["recording"]["frames_filled"].as_u64().unwrap();
    let frames = default["frames"].as_u64().unwrap();
    assert_eq!(
        warned(&default).is_some(),
        filled * 20 > frames,
        "{filled} of {frames}"
    );
}

/// Frames lost right after the first (frames 1–3 of a 30 fps clock): the first step spans four
/// intervals, and the reader takes the interval from the rows ahead instead of refusing every
/// later step as uneven; a plain CSV in seconds and a DeepLabCut CSV of frame indices with
/// `--fps` alike.
#[test]
fn a_first_step_over_lost_frames_is_read_as_a_gap() {
    let dir = common::scratch("first-gap");
    let frames: Vec<usize> = std::iter::once(0).chain(4..300).collect();
    let value = |f: usize, j: usize| ((f * 7 + j * 3) % 11) as f64 * 0.01;
    let mut plain = String::from("t");
    for j in 1..=8 {
        plain += &format!(",x{j},y{j}");
    }
    plain.push('\n');
    let parts: Vec<String> = (0..8).map(|j| format!("p{j}")).collect();
    let mut dlc = format!(
        "scorer{}\nbodyparts{}\ncoords{}\n",
        ",DLC".repeat(24),
        parts
            .iter()
            .map(|p| format!(",{p},{p},{p}"))
            .collect::<String>(),
        ",x,y,likelihood".repeat(8)
    );
    for &f in &frames {
        plain += &format!("{}", f as f64 / 30.0);
        dlc += &format!("{f}");
        for j in 0..8 {
            plain += &format!(",{},{}", 10.0 * j as f64, value(f, j));
            dlc += &format!(",{},{},0.99", 10.0 * j as f64, value(f, j));
        }
        plain.push('\n');
        dlc.push('\n');
    }
    for (name, text, extra) in [
        ("plain.csv", plain, vec![]),
        ("dlc.csv", dlc, vec!["--fps", "30"]),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let path = path.display().to_string();
        let mut args = vec![
            "theory-search",
            "fit",
            &path,
            "--points",
            "8",
            "--format",
            "json",
        ];
        args.extend(extra);
        let mut out = Vec::new();
        theory_search::cli::run(args, &mut out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let r: serde_json::Value = serde_json::from_slice(&out).unwrap();
        assert_eq!(
            r["recording"]["frames_lost"], 3,
            "{name}: {}",
            r["recording"]
        );
        assert!(
            (r["sample_interval"].as_f64().unwrap() - 1.0 / 30.0).abs() < 1e-9,
            "{name}"
        );
    }
}

/// Fewer tracked points than the model's N (issue 56 item 4): resampled past its points, a
/// midline is straight between them and the extra angles a white floor no fit sees through,
/// so the fit refuses in one line naming the `--points` that works; with it, the body fits.
#[test]
fn fewer_tracked_points_than_the_model_are_refused_with_the_points_that_work() {
    let body = common::beam::Body {
        points: 9,
        frames: 4000,
        ..common::beam::FREE_BEAM
    };
    let file = common::scratch_file("nine-points", ".csv");
    std::fs::write(file.path(), common::beam::record(&body, 3)).unwrap();
    let p = file.path().to_str().unwrap();
    let refused = common::cli(&["fit", p]).unwrap_err();
    assert_eq!(refused.lines().count(), 1, "{refused}");
    assert!(
        refused.contains(
            "9 tracked points per frame cannot resolve N = 12 model points: give --points 9"
        ),
        "{refused}"
    );
    let fitted = common::cli(&["fit", p, "--points", "9"]).unwrap();
    assert!(
        fitted.contains("4000 frames of 9-point midlines"),
        "{fitted}"
    );
}
