//! Coverage studies of `fit` at its defaults (12 model points, the window chosen from the data),
//! on thermal beams simulated independently of the engine (tests/common/beam.rs), 20 fixed
//! seeds each: a true law is rejected by each of the three tests in at most 2 of 20
//! recordings, κ's 95 % interval covers the truth in at least 18, a mode near 0.8 × Nyquist is
//! fitted at its own frequency (not an alias above Nyquist), an over-damped mode never votes,
//! a driven travelling wave is never called a passive beam, and the tracking noise printed is
//! the position noise put in.

mod common;

use common::beam::{fitted, fitted_with, on_two_cores, record, Body, CLAMPED_BEAM, FREE_BEAM};
use theory_search::fit::{FitReport, Verdict};

const RUNS: u64 = 20;

/// The free–free beam of tests/verdicts.rs, with two over-damped modes more.
const FREE: Body = Body {
    modes: 8,
    ..FREE_BEAM
};

/// The clamped–free beam, with its over-damped modes, as the referee's audit.
const CLAMPED: Body = Body {
    modes: 8,
    ..CLAMPED_BEAM
};

/// The study: every fit of `body` at the defaults, seeds `seed0 + r`.
fn study(body: Body, seed0: u64) -> Vec<FitReport> {
    on_two_cores(RUNS, |r| {
        fitted(&record(&body, seed0 + r), body.clamped, 12, None)
    })
}

fn check_true_laws(name: &str, body: Body, fits: &[FitReport]) {
    let count = |pick: &dyn Fn(&FitReport) -> bool| fits.iter().filter(|r| pick(r)).count();
    let rejected = [
        (
            "equipartition",
            count(&|r| r.tests.equipartition.verdict == Verdict::Rejected),
        ),
        (
            "dispersion",
            count(&|r| r.tests.dispersion.verdict == Verdict::Rejected),
        ),
        (
            "damping",
            count(&|r| r.tests.damping.verdict == Verdict::Rejected),
        ),
    ];
    let covered = count(&|r| {
        r.continuum
            .as_ref()
            .and_then(|c| c.interval)
            .is_some_and(|[lo, hi]| lo <= body.kappa && body.kappa <= hi)
    });
    let exponents: Vec<Option<f64>> = fits
        .iter()
        .map(|r| r.tests.equipartition.exponent)
        .collect();
    println!("{name}: rejected {rejected:?}, κ covered {covered} of {RUNS}; equipartition exponents {exponents:?}");
    for r in fits {
        for (test, t) in [
            ("equipartition", &r.tests.equipartition),
            ("dispersion", &r.tests.dispersion),
            ("damping", &r.tests.damping),
        ] {
            if t.verdict == Verdict::Rejected {
                let modes: Vec<String> = r
                    .modes_fit
                    .iter()
                    .filter(|m| t.modes.contains(&m.mode))
                    .map(|m| {
                        format!(
                            "{}: Ω {:.4}±{:.4} ζ {:.4}±{:.4} σ² {:.3e}±{:.1e} bins {:.1}",
                            m.mode,
                            m.omega,
                            m.omega_error.unwrap_or(f64::NAN),
                            m.zeta,
                            m.zeta_error.unwrap_or(f64::NAN),
                            m.variance,
                            m.variance_error.unwrap_or(f64::NAN),
                            m.bins
                        )
                    })
                    .collect();
                println!(
                    "  {name} {test} rejected: {:?} {:?} {:?}; {modes:?}",
                    t.exponent, t.interval, t.note
                );
            }
        }
    }
    // The tests' false-rejection rate is about 5–8 % (tests/verdicts.rs measures the
    // intervals' coverage over 100 recordings): with these fixed seeds 2, 1 and 0 of 20.
    for (test, n) in rejected {
        assert!(
            n <= 2,
            "{name}: {test} rejected a true law in {n} of {RUNS}"
        );
    }
    assert!(covered >= 18, "{name}: κ covered in {covered} of {RUNS}");
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_free_free_thermal_beam_keeps_its_true_laws() {
    check_true_laws("free–free", FREE, &study(FREE, 7000));
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_clamped_free_thermal_beam_keeps_its_true_laws() {
    check_true_laws("clamped–free", CLAMPED, &study(CLAMPED, 8000));
}

/// A free beam whose third mode sits at 0.77 × Nyquist (Ω₃ = 2.418, ζ₃ = 0.27, interval 1),
/// with the fourth above Nyquist.
const NEAR_NYQUIST: Body = Body {
    kappa: 0.02,
    zeta1: 0.05,
    ..FREE
};

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_mode_near_nyquist_is_fitted_at_its_own_frequency() {
    let fits = study(NEAR_NYQUIST, 9000);
    let truth = NEAR_NYQUIST.kappa * common::beam::root(false, 3).powi(2);
    let third: Vec<(f64, bool)> = fits
        .iter()
        .map(|r| {
            let m = r.modes_fit.iter().find(|m| m.mode == 4).expect("mode 3");
            (m.omega, m.resolved)
        })
        .collect();
    let right = third
        .iter()
        .filter(|(omega, _)| (omega / truth - 1.0).abs() < 0.1)
        .count();
    println!("Ω₃ = {truth}: fitted {third:?}");
    assert!(
        right >= 19,
        "Ω₃ fitted near {truth} in {right} of {RUNS}: {third:?}"
    );
    check_true_laws("near Nyquist", NEAR_NYQUIST, &fits);
}

/// A free beam whose fourth mode (Ω₄ = 4.0, above Nyquist) is over-damped (ζ₄ = 1.14).
const OVERDAMPED: Body = Body {
    kappa: 0.02,
    zeta1: 0.1276,
    ..FREE
};

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn an_over_damped_mode_never_votes() {
    let fits = study(OVERDAMPED, 9500);
    for r in &fits {
        // Modes 0 and 1 are the free beam's zero modes; the fourth elastic mode is index 5.
        let m = r.modes_fit.iter().find(|m| m.mode == 5).expect("mode 4");
        assert!(
            !m.votes,
            "the over-damped mode 4 voted: Ω = {}, ζ = {}, {:?}",
            m.omega, m.zeta, m.note
        );
    }
}

/// The free beam with 1 % of its frames lost at random: κ's interval within 1.5× of the
/// complete recording's, and the report says how the gaps were handled.
#[test]
fn one_percent_lost_frames_cost_little_precision() {
    use rand::{RngExt, SeedableRng};
    let widths: Vec<(f64, f64, usize)> = on_two_cores(4, |r| {
        let text = record(&FREE, 9900 + r);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(r);
        let lossy: String = text
            .lines()
            .enumerate()
            .filter(|(i, _)| *i == 0 || rng.random::<f64>() >= 0.01)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        let width = |report: &FitReport| {
            let [lo, hi] = report
                .continuum
                .as_ref()
                .and_then(|c| c.interval)
                .expect("κ's interval");
            hi - lo
        };
        let lost = fitted(&lossy, false, 12, None);
        (
            width(&fitted(&text, false, 12, None)),
            width(&lost),
            lost.recording.frames_filled,
        )
    });
    println!("κ interval widths (complete, 1 % lost, bridged): {widths:?}");
    for (complete, lost, bridged) in widths {
        assert!(lost <= 1.5 * complete, "{lost} against {complete}");
        assert!(bridged > 100, "{bridged} frames bridged");
    }
}

/// `text` with `share` of its frames lost in bursts of 3 to 30 frames (a tracker losing the
/// animal for a while), the lines of the lost frames removed: the time steps skip them.
fn lost_in_bursts(text: &str, share: f64, seed: u64) -> String {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let lines: Vec<&str> = text.lines().collect();
    let frames = lines.len() - 1;
    let mut lost = vec![false; frames];
    let mut count = 0;
    while (count as f64) < share * frames as f64 {
        let (start, len) = (rng.random_range(1..frames), rng.random_range(3..=30));
        for l in lost.iter_mut().skip(start).take(len) {
            count += usize::from(!*l);
            *l = true;
        }
    }
    std::iter::once(lines[0])
        .chain(
            lines[1..]
                .iter()
                .zip(&lost)
                .filter(|(_, l)| !**l)
                .map(|(t, _)| *t),
        )
        .map(|l| format!("{l}\n"))
        .collect()
}

/// Lost frames in bursts (2 % and 10 %, bursts of 3–30 frames, left as gaps at the default
/// `--fill-gaps`, and 10 % bridged by `--fill-gaps 10`): κ covered in ≥ 18 of 20 each, and its
/// interval within 1.25× (2 %) and 1.5× (10 %) of the complete recording's at the median, where
/// the Welch fit of runs alone widened it 1.51× and 3.2× (issue 56's audit). Measured: ×0.89
/// and ×0.91 (the exact likelihood over the runs is sharper than the complete recording's
/// Welch fit), covered 19 and 19 of 20.
#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn lost_frames_in_bursts_keep_kappa_covered() {
    let fits: Vec<(f64, f64, f64, bool, bool, bool)> = on_two_cores(RUNS, |r| {
        let text = record(&FREE, 5600 + r);
        let width_and_cover = |report: &FitReport| {
            let [lo, hi] = report
                .continuum
                .as_ref()
                .and_then(|c| c.interval)
                .expect("κ's interval");
            (hi - lo, lo <= FREE.kappa && FREE.kappa <= hi)
        };
        let (complete, _) = width_and_cover(&fitted(&text, false, 12, None));
        let (two, two_in) =
            width_and_cover(&fitted(&lost_in_bursts(&text, 0.02, r), false, 12, None));
        let ten_lost = lost_in_bursts(&text, 0.10, r);
        let (ten, ten_in) = width_and_cover(&fitted(&ten_lost, false, 12, None));
        let mut bridging =
            theory_search::fit::FitSettings::new(theory_search::recording::InputKind::Midline);
        bridging.recording.fill_gaps = 10;
        let (_, bridged_in) = width_and_cover(&fitted_with(&ten_lost, false, &bridging));
        (
            complete,
            two / complete,
            ten / complete,
            two_in,
            ten_in,
            bridged_in,
        )
    });
    type Row = (f64, f64, f64, bool, bool, bool);
    let median = |pick: fn(&Row) -> f64| {
        let mut v: Vec<f64> = fits.iter().map(pick).collect();
        v.sort_by(f64::total_cmp);
        0.5 * (v[v.len() / 2 - 1] + v[v.len() / 2])
    };
    let (two, ten) = (median(|f| f.1), median(|f| f.2));
    let covered = |pick: fn(&Row) -> bool| fits.iter().filter(|f| pick(f)).count();
    let (two_in, ten_in, bridged_in) = (covered(|f| f.3), covered(|f| f.4), covered(|f| f.5));
    println!("bursts: κ width ×{two:.3} (2 %), ×{ten:.3} (10 %); covered {two_in}, {ten_in} and {bridged_in} (bridged) of {RUNS}");
    assert!(
        two_in >= 18 && ten_in >= 18 && bridged_in >= 18,
        "κ covered {two_in}, {ten_in} and {bridged_in} of {RUNS}"
    );
    assert!(
        two <= 1.25 && ten <= 1.5,
        "κ's interval widened ×{two:.3} and ×{ten:.3}"
    );
}

/// The tracking noise printed is the position noise put in, within 1.5×, from 1e-6 to 1e-3
/// body lengths, on both beams (25 and 41 tracked points, 8 modes; 20 thermal modes at 41
/// points), and called measured, not a bound. (20 modes at 25 points leave three directions
/// that the body's nonlinear terms still reach: 1e-6 reads 2.5e-6 there, docs/fit.md.)
#[test]
fn tracking_noise_is_measured_from_1e_6_to_1e_3() {
    let cases: Vec<(Body, f64)> = [
        FREE,
        CLAMPED,
        Body {
            modes: 20,
            points: 41,
            ..FREE
        },
    ]
    .into_iter()
    .flat_map(|b| [1e-6, 1e-5, 1e-4, 1e-3].map(|noise| (Body { noise, ..b }, noise)))
    .collect();
    let fits = on_two_cores(cases.len() as u64, |r| {
        let (body, _) = cases[r as usize];
        fitted(&record(&body, 40 + r), body.clamped, 12, None)
    });
    for ((body, noise), fit) in cases.iter().zip(&fits) {
        let measured = fit
            .tracking_noise
            .as_ref()
            .expect("midlines give a tracking noise");
        let ratio = measured.sigma / noise;
        eprintln!(
            "{} points, {} modes, noise {noise:e}: σ = {:.3e} ({ratio:.3}×), bound {}",
            body.points, body.modes, measured.sigma, measured.bound
        );
        assert!(
            (1.0 / 1.5..=1.5).contains(&ratio) && !measured.bound,
            "noise {noise:e} read {:e} (bound {})",
            measured.sigma,
            measured.bound
        );
        assert_eq!(measured.points, body.points);
    }
}

/// On 12 tracked points of a 20-mode body the noise cannot be told from the body: the report
/// says σ is an upper bound, and it is one.
#[test]
fn tracking_noise_under_a_busy_body_is_a_bound() {
    let body = Body {
        modes: 20,
        points: 12,
        noise: 1e-6,
        ..FREE
    };
    let measured = tracking_noise(body, 7);
    assert!(
        measured.bound && measured.sigma >= body.noise,
        "{measured:?}"
    );
}

/// Of more than `MAX_POINTS` tracked points every k-th is used (a budget), and σ still reads
/// the noise put in.
#[test]
fn tracking_noise_of_many_points_uses_every_kth() {
    let body = Body {
        points: 301,
        frames: 3000,
        noise: 1e-4,
        ..FREE
    };
    let measured = tracking_noise(body, 11);
    assert_eq!((measured.points, measured.tracked), (101, 301));
    let ratio = measured.sigma / body.noise;
    assert!(
        (1.0 / 1.5..=1.5).contains(&ratio) && !measured.bound,
        "{measured:?}"
    );
}

/// The tracking noise `fit` reads, at its defaults, on a recording of `body`.
fn tracking_noise(body: Body, seed: u64) -> theory_search::recording::TrackingNoise {
    let fit = fitted(&record(&body, seed), body.clamped, 12, None);
    fit.tracking_noise.expect("midlines give a tracking noise")
}

/// Issue 56's grid, `runs` seeds a setting (a multiple of 40): each true law rejected in at
/// most 4 of 40 and κ covered in at least 36 of 40, the bounds scaled to `runs` (seeds
/// 56 000 + 100 i + r for the i-th setting of [`GRID`]).
fn grid_study(which: &[usize], runs: u64) {
    let mut failed = Vec::new();
    let scale = (runs / 40) as usize;
    for &i in which {
        let (name, body, points) = GRID[i];
        let fits = on_two_cores(runs, |r| {
            let seed = 56_000 + 100 * i as u64 + r;
            fitted(&record(&body, seed), body.clamped, points, None)
        });
        let count = |pick: &dyn Fn(&FitReport) -> bool| fits.iter().filter(|r| pick(r)).count();
        let tests = |r: &FitReport| {
            let t = &r.tests;
            [&t.equipartition, &t.dispersion, &t.damping].map(|t| t.verdict)
        };
        let rejected = [0, 1, 2].map(|k| count(&|r| tests(r)[k] == Verdict::Rejected));
        let undetermined = [0, 1, 2].map(|k| count(&|r| tests(r)[k] == Verdict::Undetermined));
        let covered = count(&|r| {
            r.continuum
                .as_ref()
                .and_then(|c| c.interval)
                .is_some_and(|[lo, hi]| lo <= body.kappa && body.kappa <= hi)
        });
        let line = format!(
            "{name}: rejected {rejected:?}, undetermined {undetermined:?}, κ covered {covered} of {runs}"
        );
        println!("{line}");
        if rejected.iter().any(|&n| n > 4 * scale) || covered < 36 * scale {
            failed.push(line);
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}

/// The settings: (name, body, `--points`).
const GRID: [(&str, Body, usize); 6] = [
    (
        "ζ₁ = 0.005",
        Body {
            zeta1: 0.005,
            ..FREE
        },
        12,
    ),
    (
        "ζ₁ = 0.12",
        Body {
            zeta1: 0.12,
            ..FREE
        },
        12,
    ),
    ("9 tracked points", Body { points: 9, ..FREE }, 9),
    (
        "clamped, ζ₁ = 0.01",
        Body {
            zeta1: 0.01,
            ..CLAMPED
        },
        12,
    ),
    (
        "third mode at 0.9 × Nyquist",
        Body {
            kappa: 0.0234,
            ..NEAR_NYQUIST
        },
        12,
    ),
    ("33 tracked points", Body { points: 33, ..FREE }, 12),
];

/// A sharp first line (ζ₁ = 0.005: rejected 3, 1, 4 of 40; 2, 18 and 20 before a mode
/// unfolded above an alias marked it, once the continuum coordinates' modes 5–7 vote), broad
/// lines (ζ₁ = 0.12: undetermined, κ covered 40), 9 tracked points at `--points 9` (rejected
/// 1, 4, 2; κ covered 38), the clamped beam at ζ₁ = 0.01 (rejected 4, 4, 4, κ covered 37;
/// every test undetermined until the lab's frame, κ covered 33 of 40 when the setting was
/// opened) and a third mode at 0.9 × Nyquist (rejected 4, 2, 4; κ covered 38).
#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn issue_56_grid_forty_seeds_a_setting() {
    grid_study(&[0, 1, 2, 3, 4], 40);
}

/// 33 tracked points at N = 12, over 120 seeds: rejected 4, 5, 6 of 120, κ covered 116. At
/// the first 40 seeds the damping law was rejected in 5 (the bound is 4), at seeds 90 000 +
/// r in 5 of 120, and its exponent's z-scores over those 120 have mean −0.16 and spread 0.83:
/// a calibrated test exceeds 4 of 40 in 4.8 % of studies, so this setting is judged on three
/// times the seeds, with the bounds scaled.
#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn thirty_three_tracked_points_at_n_12_over_120_seeds() {
    grid_study(&[5], 120);
}
