//! The projection on a body's continuum modes keeps tracking noise bounded: white noise on the
//! tracked coordinates reaches no modal coordinate with more than twice the standard deviation
//! the N-point projector gives it, on every end and at 8 to 60 points (a clamped end once gave
//! 9.8·10³), and a clamped thermal beam with tracking noise, simulated independently of the
//! engine (`tests/common/beam.rs`), is fitted with κ covered.

mod common;

use common::beam::{fitted, record, Body};
use theory_search::fit::FitSettings;
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::{InputKind, Projector};

/// The larva with its bending field's ends replaced (the head is point 1 of a recording).
fn body(head: &str, tail: &str) -> Model {
    let text = include_str!("../tables/models/zebrafish.toml").replace(
        "boundary = { head = \"clamped\", tail = \"free\" }",
        &format!("boundary = {{ head = \"{head}\", tail = \"{tail}\" }}"),
    );
    Model::from_toml(&text).expect("the zebrafish with other ends")
}

fn gains(model: &Model, points: usize) -> (Vec<f64>, usize, usize) {
    let mut s = FitSettings::new(InputKind::Midline);
    s.recording.points = points;
    let p =
        Projector::new(model, &Params::default(), &s.recording, 2 * points).expect("a projector");
    let g = p.noise_gains().expect("midline gains");
    (g, p.continuum_modes, p.eigenvalues.len())
}

#[test]
fn tracking_noise_reaches_no_coordinate_with_a_gain_above_two() {
    let ends = [
        ("free", "free"),
        ("clamped", "free"),
        ("pinned", "free"),
        ("clamped", "clamped"),
        ("pinned", "pinned"),
    ];
    for (head, tail) in ends {
        let model = body(head, tail);
        for n in [8, 12, 19, 41, 60] {
            let (g, continuum, m) = gains(&model, n);
            let worst = g.iter().copied().fold(0.0, f64::max);
            let low = g
                .iter()
                .take(4)
                .map(|v| format!("{v:.2}"))
                .collect::<Vec<_>>();
            println!(
                "{head}–{tail} N = {n}: {continuum} of {m} coordinates continuum, \
                 largest gain {worst:.3}, first four {low:?}"
            );
            assert!(
                worst <= 2.0 + 1e-9,
                "{head}–{tail} at {n} points: gain {worst}"
            );
            // The continuum is kept wherever it is safe: at least the lowest modes.
            assert!(continuum >= m.min(3), "{head}–{tail} at {n}: {continuum}");
        }
    }
}

/// A clamped–free thermal beam (κ = 0.01, ζ₁ = 0.05, eight modes, 20 000 frames) tracked at
/// `points` points with position noise `share` of its first mode's rms.
fn clamped(points: usize, share: f64) -> Body {
    Body {
        clamped: true,
        kappa: 0.01,
        zeta1: 0.05,
        amplitude: 0.01,
        points,
        noise: share * 0.01,
        frames: 20_000,
        modes: 8,
    }
}

/// κ covered in at least 18 of 20 seeds for a clamped–free thermal beam at `points` tracked
/// and model points, with tracking noise `share` of the first mode's rms.
fn clamped_coverage(points: usize, share: f64) -> usize {
    let body = clamped(points, share);
    let fits = common::beam::on_two_cores(20, |seed| {
        fitted(&record(&body, 31_000 + seed), true, points, None)
    });
    let covered = fits
        .iter()
        .filter(|r| {
            r.continuum
                .as_ref()
                .and_then(|c| c.interval)
                .is_some_and(|[lo, hi]| lo <= body.kappa && body.kappa <= hi)
        })
        .count();
    let kappas: Vec<String> = fits
        .iter()
        .map(|r| {
            r.continuum
                .as_ref()
                .map_or("none".into(), |c| format!("{:.5}", c.constant))
        })
        .collect();
    println!("clamped–free N = {points}, noise {share}: κ covered {covered} of 20: {kappas:?}");
    covered
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn a_clamped_beam_with_tracking_noise_keeps_its_kappa() {
    for (points, share) in [(12, 0.01), (12, 0.05), (19, 0.05), (41, 0.01), (41, 0.05)] {
        let covered = clamped_coverage(points, share);
        assert!(
            covered >= 18,
            "N = {points}, noise {share}: {covered} of 20"
        );
    }
}

/// `discover` answers a clamped–free thermal beam with tracking noise (the projection no longer
/// drowns its low modes): its stiffness selected, positive, at 12 and 19 points, 1 % and 5 %.
#[test]
fn discover_answers_a_clamped_beam_with_tracking_noise_or_says_why_not() {
    use theory_search::discover::{discover, DiscoverSettings, Source};
    // At 41 points discover answers "∂t² y = 0" in 1 of 4 seeds at 1 % noise: its selection,
    // not the projection (fit covers κ there in 20 of 20); issue 50's.
    for (points, share) in [(12, 0.01), (12, 0.05), (19, 0.01), (19, 0.05)] {
        let body = clamped(points, share);
        let answers = common::beam::on_two_cores(4, |seed| {
            let mut fit = FitSettings::new(InputKind::Midline);
            fit.recording.points = points;
            let settings = DiscoverSettings {
                recording: fit.recording,
                active: false,
                bootstrap: 0,
                seed: 1,
                replay: false,
                estimator: theory_search::discover::Estimator::Auto,
            };
            let text = record(&body, 41_000 + seed);
            let source = Source::Reader("beam".into(), Box::new(std::io::Cursor::new(text)));
            discover(vec![source], &common::beam::model(true), &settings)
                .map(|r| r.equation.clone())
                .map_err(|e| e.to_string())
        });
        println!("clamped–free N = {points}, noise {share}: {answers:?}");
        // The clamped head's coordinate (gain 33 at 12 points): its exact likelihood puts the
        // first mode on an over-damped ridge (Ω 0.7–2.4 per frame, ζ 11–38, se of ln Ω ≈ 10)
        // where fit's spectrum has a sharp line at 0.035; such a fit is not used, so discover
        // refuses in words rather than answer from it (it used to: c_y from that Ω).
        for a in &answers {
            match a {
                Ok(equation) => assert!(equation.contains("c_y"), "no stiffness: {equation}"),
                Err(why) => assert!(why.contains("time scales resolved"), "{why}"),
            }
        }
    }
}

/// Fewer tracked points than the default N (issue 56, item 4): 9 and 11 tracked points of the
/// free and the clamped thermal beam, with six or twelve modes and tracking noise 2e-5 or 1e-3,
/// fitted with `--points` the tracked count (the default 12 is refused, tests/recordings.rs): κ
/// lies within its interval of the truth and within 1 % of it.
#[test]
fn fewer_tracked_points_are_fitted_at_their_own_count() {
    for (clamped, modes, noise, tracked) in [
        (false, 6, 2e-5, 9),
        (false, 12, 1e-3, 11),
        (true, 6, 2e-5, 9),
        (true, 12, 1e-3, 11),
    ] {
        let base = if clamped {
            common::beam::CLAMPED_BEAM
        } else {
            common::beam::FREE_BEAM
        };
        let beam = Body {
            points: tracked,
            modes,
            noise,
            ..base
        };
        let r = fitted(&record(&beam, 56 + tracked as u64), clamped, tracked, None);
        let c = r.continuum.as_ref().expect("a continuum constant");
        let what = format!(
            "clamped {clamped}, {modes} modes, noise {noise}, {tracked} points: κ = {} {:?}, floor {:?}, tests {:?}, warnings {:?}",
            c.constant, c.interval, r.noise_floor, r.tests, r.warnings
        );
        let [lo, hi] = c.interval.expect("an interval");
        assert!(lo <= beam.kappa && beam.kappa <= hi, "{what}");
        assert!((c.constant / beam.kappa - 1.0).abs() < 0.01, "{what}");
        assert!(!r.tests.dispersion.modes.is_empty(), "{what}");
    }
}

/// The grid rule spares the continuum coordinates (issue 56, item 4): at 9 tracked points the
/// grid's fourth mode is 17 % off the continuum's, which once took its vote and left every law
/// undetermined in 20 of 20. A coordinate votes unless neighbouring continuum modes the tracked
/// points cannot separate put over 2 % of its variance in it. Thermal beams with three modes
/// under Nyquist, `--points` the tracked count, 40 seeds each: the free beam at 9 points and
/// the clamped one at 19 decide every law in ≥ 36 of 40; the clamped beam at 12 points, whose
/// third coordinate takes 10 % from the fifth mode (which rejected the three laws in 9, 11 and
/// 6 of 40 without this rule; at 9 points it takes 33 %, a +9 % bias of its Ω), keeps two
/// voting modes and decides nothing. No true law is rejected in more than 4 of 40 and κ is
/// covered in ≥ 36 of 40 at every setting.
#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn continuum_coordinates_vote_unless_their_neighbours_mix_in() {
    use theory_search::fit::{ModeNote, Verdict};
    for (clamped, points, decides) in [(false, 9, true), (true, 19, true), (true, 12, false)] {
        // The clamped beam slower than the shared one, whose third mode reaches past Nyquist.
        let beam = if clamped {
            Body {
                points,
                kappa: 0.015,
                zeta1: 0.02,
                ..common::beam::CLAMPED_BEAM
            }
        } else {
            Body {
                points,
                ..common::beam::FREE_BEAM
            }
        };
        let runs = common::beam::on_two_cores(40, |seed| {
            let r = fitted(&record(&beam, 900 + seed), clamped, points, None);
            let c = r.continuum.as_ref().expect("a continuum constant");
            let [lo, hi] = c.interval.expect("an interval");
            let verdicts = [
                &r.tests.equipartition,
                &r.tests.dispersion,
                &r.tests.damping,
            ]
            .map(|t| t.verdict);
            let mixed = r
                .modes_fit
                .iter()
                .any(|m| matches!(m.note, Some(ModeNote::Mixed { .. })));
            (lo <= beam.kappa && beam.kappa <= hi, verdicts, mixed)
        });
        let covered = runs.iter().filter(|r| r.0).count();
        let count = |law: usize, v: Verdict| runs.iter().filter(|r| r.1[law] == v).count();
        let table: Vec<(usize, usize)> = (0..3)
            .map(|law| {
                (
                    40 - count(law, Verdict::Undetermined),
                    count(law, Verdict::Rejected),
                )
            })
            .collect();
        let mixed = runs.iter().filter(|r| r.2).count();
        let what = format!(
            "clamped {clamped}, {points} points: κ covered {covered}/40, (decided, rejected) per law {table:?}, a mode mixed in {mixed}/40"
        );
        eprintln!("{what}");
        assert!(covered >= 36, "{what}");
        for &(decided, rejected) in &table {
            assert!(rejected <= 4, "{what}");
            assert!(if decides { decided >= 36 } else { decided == 0 }, "{what}");
        }
        assert!(decides || mixed == 40, "{what}");
    }
}
