//! Coverage studies of `fit` at its defaults (12 model points, the window chosen from the data),
//! on thermal beams simulated independently of the engine (tests/common/beam.rs), 20 fixed
//! seeds each: a true law is rejected by each of the three tests in at most 2 of 20
//! recordings, κ's 95 % interval covers the truth in at least 18, a mode near 0.8 × Nyquist is
//! fitted at its own frequency (not an alias above Nyquist), an over-damped mode never votes,
//! a driven travelling wave is never called a passive beam, and the tracking noise printed is
//! the position noise put in.

mod common;

use common::beam::{fitted, on_two_cores, record, Body, CLAMPED_BEAM, FREE_BEAM};
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
fn a_free_free_thermal_beam_keeps_its_true_laws() {
    check_true_laws("free–free", FREE, &study(FREE, 7000));
}

#[test]
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
