//! A driven travelling wave is not a passive body (issue 56, item 2): recordings of
//! y = A sin(k s − Ω t), alone or over a thermal beam, simulated here independently of the fit
//! (tests/common/beam.rs), 40 seeds a setting. A pure wave puts every mode at one frequency,
//! phase-locked and partly in quadrature (r² ≈ 0, so "modes move together" cannot see it): the
//! dispersion must be `rejected` with the driven-wave warning in at least 38 of 40, a weak wave
//! over thermal modes likewise, and a thermal beam with no wave must draw the warning in at
//! most 2 of 40 and keep its verdicts.

mod common;

use common::beam::{fitted, on_two_cores, record, record_with, Body, Wave, FREE_BEAM};
use theory_search::fit::{FitReport, Verdict};

const RUNS: u64 = 40;

/// The free–free thermal beam at a few thousand frames.
const THERMAL: Body = Body {
    frames: 6000,
    ..FREE_BEAM
};

/// No thermal part: the wave alone, with tracking noise.
const STILL: Body = Body {
    modes: 0,
    ..THERMAL
};

/// A wave of 0.7 body lengths at 18 frames a period (between the beam's first two modes).
const WAVE: Wave = Wave {
    amplitude: 0.02,
    k: 2.0 * std::f64::consts::PI / 0.7,
    omega: 0.35,
};

/// The same wave at a fifth of the first thermal mode's rms amplitude (4 % of its variance).
const WEAK: Wave = Wave {
    amplitude: 0.002,
    ..WAVE
};

fn warned(r: &FitReport) -> bool {
    r.warnings
        .iter()
        .any(|w| w.contains("driven travelling wave"))
}

fn rejected(r: &FitReport) -> bool {
    r.tests.dispersion.verdict == Verdict::Rejected
}

fn study(body: Body, wave: Option<Wave>, seed0: u64) -> Vec<FitReport> {
    on_two_cores(RUNS, |r| {
        fitted(&record_with(&body, wave, seed0 + r), false, 12, None)
    })
}

fn caught(name: &str, fits: &[FitReport]) {
    let n = fits.iter().filter(|r| rejected(r) && warned(r)).count();
    eprintln!("{name}: dispersion rejected with the warning in {n} of {RUNS}");
    let missed: Vec<String> = (fits.iter())
        .filter(|r| !(rejected(r) && warned(r)))
        .map(|r| format!("{:?} {:?}", r.tests.dispersion, r.warnings))
        .collect();
    assert!(n as u64 >= RUNS - 2, "{name}: {n} of {RUNS}: {missed:#?}");
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_pure_travelling_wave_is_rejected_on_the_dispersion() {
    caught("pure wave", &study(STILL, Some(WAVE), 5600));
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_weak_wave_over_thermal_modes_is_rejected_on_the_dispersion() {
    caught("weak wave", &study(THERMAL, Some(WEAK), 5700));
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_thermal_beam_draws_no_driven_wave_warning() {
    // At the coverage studies' 20 000 frames, and at the waves' 6000.
    for (body, seed0) in [(FREE_BEAM, 5800), (THERMAL, 5900)] {
        let fits = on_two_cores(RUNS, |r| fitted(&record(&body, seed0 + r), false, 12, None));
        let alarms = fits.iter().filter(|r| warned(r)).count();
        let rejected = fits.iter().filter(|r| rejected(r)).count();
        eprintln!(
            "thermal beam, {} frames: warning in {alarms} of {RUNS}, dispersion rejected in {rejected}",
            body.frames
        );
        assert!(alarms <= 2, "{alarms} of {RUNS}");
        if body.frames == FREE_BEAM.frames {
            assert!(rejected <= 4, "{rejected} of {RUNS}");
        }
    }
}
