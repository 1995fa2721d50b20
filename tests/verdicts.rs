//! The fit against recordings of known physics, simulated here independently of the engine: a
//! continuous Euler–Bernoulli beam (free–free or clamped–free, its modes from the beam's own
//! characteristic equation) whose modes are thermally driven damped oscillators, sampled
//! exactly, tracked at K points with position noise. The fit must give back κ within its
//! interval whatever the model points and the window, call all three predictions consistent,
//! and reject the dispersion of a driven travelling wave.

mod common;

use common::beam::{fitted, on_two_cores, record, Body, CLAMPED_BEAM, FREE_BEAM};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use theory_search::fit::{fit, FitReport, FitSettings, Verdict};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::InputKind;

const BODY: Body = FREE_BEAM;

const CLAMPED: Body = CLAMPED_BEAM;

/// κ recovered within its interval; every test `consistent` when `determined`, else never
/// `rejected`.
fn check_recovered(body: Body, seed: u64, window: usize, determined: bool) {
    let text = record(&body, seed);
    // Up to the tracked points: more are refused (tests/recordings.rs).
    for points in [12, 24, body.points] {
        for window in [None, Some(window)] {
            let r = fitted(&text, body.clamped, points, window);
            let c = r.continuum.as_ref().expect("a continuum constant");
            let [lo, hi] = c.interval.expect("an interval");
            let what = format!(
                "clamped {} N = {points} window {window:?}: κ = {} [{lo}, {hi}], tests {:?}",
                body.clamped, c.constant, r.tests
            );
            assert!(lo <= body.kappa && body.kappa <= hi, "{what}");
            assert!((c.constant / body.kappa - 1.0).abs() < 0.05, "{what}");
            for t in [
                &r.tests.equipartition,
                &r.tests.dispersion,
                &r.tests.damping,
            ] {
                if determined {
                    assert_eq!(t.verdict, Verdict::Consistent, "{what}");
                } else {
                    assert_ne!(t.verdict, Verdict::Rejected, "{what}");
                }
            }
        }
    }
}

#[test]
fn a_free_beam_of_known_kappa_is_recovered_at_every_grid_and_window() {
    check_recovered(BODY, 1, 1024, true);
}

#[test]
fn a_clamped_beam_of_known_kappa_is_recovered_at_every_grid_and_window() {
    // Its third mode (Ω = 2.47, ζ = 0.53) has a line reaching past Nyquist: it does not vote,
    // and two modes leave the tests undetermined.
    check_recovered(CLAMPED, 2, 2048, false);
}

#[test]
fn a_driven_travelling_wave_is_not_a_passive_beam() {
    // Every mode at the one frequency of the wave, with a little thermal noise on top.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let (k, w) = (2.0 * std::f64::consts::PI / 0.7, 0.35f64);
    let mut text = String::from("t");
    let points = 33;
    for j in 1..=points {
        text += &format!(",x{j},y{j}");
    }
    text.push('\n');
    let mut phase = 0.0;
    for t in 0..12_000 {
        text += &t.to_string();
        // A diffusing phase: a rhythm with a finite bandwidth, as a crawling animal's.
        let kick: f64 = StandardNormal.sample(&mut rng);
        phase += w + 0.05 * kick;
        for j in 0..points {
            let s = j as f64 / (points - 1) as f64;
            let e: f64 = StandardNormal.sample(&mut rng);
            let y = 0.02 * (k * s - phase).sin() + 1e-4 * e;
            text += &format!(",{},{}", 100.0 * s, 100.0 * y);
        }
        text.push('\n');
    }
    let r = fitted(&text, false, 12, None);
    for t in [&r.tests.dispersion, &r.tests.equipartition] {
        assert_eq!(t.verdict, Verdict::Rejected, "{:?}", r.tests);
    }
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("not constants of the body")),
        "{:?}",
        r.warnings
    );
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn nominal_95_percent_intervals_cover_the_truth() {
    // 100 recordings of the free beam, shorter than above; every interval the fit gives for κ
    // and for the three exponents is counted.
    let body = Body {
        frames: 6000,
        ..BODY
    };
    let runs = 100u64;
    let results = on_two_cores(runs, |r| fitted(&record(&body, 1000 + r), false, 12, None));
    let covers = |pick: &dyn Fn(&FitReport) -> Option<[f64; 2]>, truth: f64| -> (usize, usize) {
        let intervals: Vec<[f64; 2]> = results.iter().filter_map(pick).collect();
        let n = intervals.len();
        (
            intervals
                .iter()
                .filter(|[lo, hi]| *lo <= truth && truth <= *hi)
                .count(),
            n,
        )
    };
    let kappa = covers(
        &|r| r.continuum.as_ref().and_then(|c| c.interval),
        body.kappa,
    );
    let equi = covers(&|r| r.tests.equipartition.interval, -1.0);
    let disp = covers(&|r| r.tests.dispersion.interval, 0.5);
    let damp = covers(&|r| r.tests.damping.interval, 0.5);
    println!("covered: κ {kappa:?}, equipartition {equi:?}, dispersion {disp:?}, damping {damp:?}");
    for (name, (hit, n)) in [
        ("κ", kappa),
        ("equipartition", equi),
        ("dispersion", disp),
        ("damping", damp),
    ] {
        assert!(n >= 90, "{name}: only {n} of {runs} fits gave an interval");
        assert!(
            hit * 100 >= 90 * n,
            "{name}: {hit} of {n} intervals cover the truth"
        );
    }
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn moving_block_bootstrap_intervals_of_kappa_cover_the_truth() {
    // One animal each: its κ interval from 100 moving-block resamples over time.
    let body = Body {
        frames: 6000,
        ..BODY
    };
    let hits = on_two_cores(100, |r| {
        let mut s = FitSettings::new(InputKind::Midline);
        s.bootstrap = 100;
        s.seed = r;
        let text = record(&body, 5000 + r);
        let fit = fit(
            std::io::Cursor::new(text.as_bytes()),
            &Model::larva(),
            &Params::default(),
            &s,
        )
        .expect("fits");
        fit.intervals
            .and_then(|i| i.continuum)
            .map(|[lo, hi]| lo <= body.kappa && body.kappa <= hi)
    });
    let drawn: Vec<bool> = hits.iter().flatten().copied().collect();
    let covered = drawn.iter().filter(|&&h| h).count();
    println!("moving blocks: κ covered {covered} of {}", drawn.len());
    assert!(drawn.len() >= 95, "only {} bootstraps drawn", drawn.len());
    // Percentile intervals of a moving-block bootstrap run a little short (87–89 of 100 here,
    // seeds fixed); κ's own interval is the modes' errors' (95 of 100 above), and
    // docs/fit.md says so. This guards against worse.
    assert!(
        covered * 100 >= 85 * drawn.len(),
        "{covered} of {}",
        drawn.len()
    );
}

#[test]
fn the_json_contract_of_a_fit() {
    let example = format!(
        "{}/tables/examples/midlines.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut out = Vec::new();
    theory_search::cli::run(
        ["theory-search", "fit", example.as_str(), "--format", "json"],
        &mut out,
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    // The contract's keys first, in order.
    assert_eq!(
        keys[..12],
        [
            "frames",
            "points",
            "pca_variance_share",
            "theory_variance_share",
            "overlap",
            "omega",
            "beta",
            "continuum",
            "modes_fit",
            "tests",
            "noise_floor",
            "window"
        ]
    );
    let c = &v["continuum"];
    assert_eq!(c["name"], "kappa");
    assert!(c["constant"].as_f64().unwrap() > 0.0 && c["unit"].is_string());
    assert_eq!(c["interval"].as_array().unwrap().len(), 2);
    let modes = v["modes_fit"].as_array().unwrap();
    assert_eq!(modes.len(), 10);
    for m in modes {
        for key in ["mode", "lambda", "omega", "zeta", "variance"] {
            assert!(m[key].is_number(), "{key} in {m}");
        }
        for key in ["omega_error", "zeta_error"] {
            assert!(m[key].is_number() || m[key].is_null(), "{key} in {m}");
        }
        assert!(m["resolved"].is_boolean());
    }
    for name in ["equipartition", "dispersion", "damping"] {
        let t = &v["tests"][name];
        assert!(t["expected"].is_number());
        assert!(
            ["consistent", "rejected", "undetermined"].contains(&t["verdict"].as_str().unwrap())
        );
        assert!(t["exponent"].is_number() || t["exponent"].is_null());
        assert!(t["interval"].is_array() || t["interval"].is_null());
    }
    assert!(v["noise_floor"].is_number());
    assert_eq!(v["window"]["frames"], 512);
    assert_eq!(v["window"]["how"], "chosen");
    assert!(v["window"]["why"].as_str().unwrap().contains("16 bins"));
}
