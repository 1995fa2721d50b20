//! The projection on a body's continuum modes keeps tracking noise bounded: white noise on the
//! tracked coordinates reaches no modal coordinate with more than twice the standard deviation
//! the N-point projector gives it, on every end and at 8 to 60 points (a clamped end once gave
//! 9.8·10³), and a clamped thermal beam with tracking noise, simulated independently of the
//! engine (`tests/common/beam.rs`), is fitted with κ covered.

mod common;

use common::beam::{fitted, record, Body};
use theory_search::discover::{discover, Conclusion, DiscoverSettings, Finding, Source, Verdict};
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
/// drowns its low modes): the exact set, stiffness and Kelvin damping, at 12, 19 and 41
/// points, 1 % and 5 %, four seeds each.
#[test]
fn discover_answers_a_clamped_beam_with_tracking_noise() {
    use theory_search::discover::{discover, DiscoverSettings, Source};
    // At 41 points discover once answered "∂t² y = 0" in 1 of 4 seeds at 1 % noise.
    for (points, share) in [(12, 0.01), (12, 0.05), (19, 0.05), (41, 0.01), (41, 0.05)] {
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
        // Each frame once set its own frame by the clamped head's first segment, whose noise
        // put the lowest mode on an over-damped ridge, and discover refused in words; in the
        // lab's frame (the held points of the first frame) every seed gets the exact set.
        for a in &answers {
            assert_eq!(
                a.as_deref(),
                Ok("∂t² y = −c_y ∂s⁴ y − 2 c'_y ∂t∂s⁴ y"),
                "N = {points}, noise {share}"
            );
        }
    }
}

/// Fewer tracked points than the default N (issue 56, item 4): 9 and 11 tracked points of the
/// free and the clamped thermal beam, with six or twelve modes and tracking noise 2e-5 or 1e-3,
/// fitted with `--points` the tracked count (the default 12 is refused, tests/recordings.rs), at
/// four seeds each: κ within 1 % of the truth in every fit and its interval covering it in at
/// least 3 of 4 (one seed alone misses a 95 % interval one time in twenty).
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
        let fits = common::beam::on_two_cores(4, |s| {
            fitted(
                &record(&beam, 56 + tracked as u64 + 100 * s),
                clamped,
                tracked,
                None,
            )
        });
        let mut covered = 0;
        for r in &fits {
            let c = r.continuum.as_ref().expect("a continuum constant");
            let what = format!(
                "clamped {clamped}, {modes} modes, noise {noise}, {tracked} points: κ = {} {:?}, floor {:?}, tests {:?}, warnings {:?}",
                c.constant, c.interval, r.noise_floor, r.tests, r.warnings
            );
            let [lo, hi] = c.interval.expect("an interval");
            covered += usize::from(lo <= beam.kappa && beam.kappa <= hi);
            assert!((c.constant / beam.kappa - 1.0).abs() < 0.01, "{what}");
            assert!(!r.tests.dispersion.modes.is_empty(), "{what}");
        }
        assert!(
            covered >= 3,
            "clamped {clamped}, {tracked} points: κ covered in {covered} of 4"
        );
    }
}

/// The grid rule spares the continuum coordinates (issue 56, item 4): at 9 tracked points the
/// grid's fourth mode is 17 % off the continuum's, which once took its vote and left every law
/// undetermined in 20 of 20. A coordinate votes unless neighbouring continuum modes the tracked
/// points cannot separate put over 2 % of its variance in it. Thermal beams with three modes
/// under Nyquist, `--points` the tracked count, 40 seeds each: the free beam at 9 points and
/// the clamped one at 19 and 12 decide every law in ≥ 36 of 40. The clamped beam at 12 points
/// once kept two voting modes and decided nothing: its third coordinate took 10 % from the
/// fifth mode (which rejected the three laws in 9, 11 and 6 of 40 without this rule) while the
/// noise of each frame's own head frame kept its projector to three continuum columns; in the
/// lab's frame it keeps all ten, the fifth mode is projected out, no mode is mixed and the
/// laws are decided in 40 of 40 (rejected 2, 1, 1). No true law is rejected in more than 4 of
/// 40 and κ is covered in ≥ 36 of 40 at every setting.
#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn continuum_coordinates_vote_unless_their_neighbours_mix_in() {
    use theory_search::fit::{ModeNote, Verdict};
    for (clamped, points) in [(false, 9), (true, 19), (true, 12)] {
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
            assert!(decided >= 36, "{what}");
        }
    }
}

/// A body held in place is observed in the lab's frame: white tracking noise on a straight
/// clamped–free body reaches each modal coordinate with about its own variance (in point
/// spacings): 1.27, 1.07, 1.11, 1.20 on the first four of a clamped–free body at 25 points.
/// Each frame observed in its own frame instead (its held points its own, as before) put
/// 9.5·10³ times that into the clamped–free body's lowest coordinate (clamped–clamped 4·10²,
/// pinned–pinned 11): the clamped head's first segment turned the whole body.
#[test]
fn a_held_body_keeps_tracking_noise_off_its_lowest_coordinates() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let (k, sigma, frames) = (25usize, 0.05, 4000);
    let h = 100.0 / (k - 1) as f64;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let noisy: Vec<Vec<f64>> = (0..frames)
        .map(|_| {
            (0..k)
                .flat_map(|p| [100.0 * p as f64 / (k - 1) as f64, 0.0])
                .map(|v| {
                    let z: f64 = StandardNormal.sample(&mut rng);
                    v + sigma * z
                })
                .collect()
        })
        .collect();
    for (head, tail) in [
        ("clamped", "free"),
        ("pinned", "pinned"),
        ("clamped", "clamped"),
    ] {
        let mut s = FitSettings::new(InputKind::Midline);
        s.recording.points = k;
        let model = body(head, tail);
        let mut p =
            Projector::new(&model, &Params::default(), &s.recording, 2 * k).expect("a projector");
        assert!(p.holds());
        let variances = |p: &mut Projector, own: bool| -> Vec<f64> {
            if !own {
                p.hold(&noisy[0], false);
            }
            let q: Vec<Vec<f64>> = (noisy.iter())
                .map(|f| {
                    if own {
                        p.hold(f, false);
                    }
                    p.modal(f).expect("a frame")
                })
                .collect();
            (0..4)
                .map(|j| {
                    let mean = q.iter().map(|v| v[j]).sum::<f64>() / frames as f64;
                    let var = q.iter().map(|v| (v[j] - mean).powi(2)).sum::<f64>();
                    var / (frames - 1) as f64 / (sigma / h).powi(2)
                })
                .collect()
        };
        let held = variances(&mut p, false);
        let own = variances(&mut p, true);
        println!("{head}–{tail}: lab frame {held:.2?}, each frame's own {own:.2?} (σ² per point spacing²)");
        assert!(held.iter().all(|&v| v < 3.0), "{head}–{tail}: {held:?}");
        if head == "clamped" {
            assert!(own[0] > 100.0, "{head}–{tail}: {own:?}");
        }
    }
}

/// The model's claim that an end is held is checked: a clamped–free beam whose whole midline
/// also drifts in the images (a slow sway of three times the first mode's rms, as a fish that
/// is not restrained) is fitted with a warning that its held end moves; the same beam held
/// draws none.
#[test]
fn a_held_end_that_moves_is_named() {
    let body = clamped(19, 0.01);
    let text = record(&body, 77);
    let swayed = each_row(&text, |line| {
        let cells: Vec<f64> = line
            .split(',')
            .map(|c| c.parse().expect("a number"))
            .collect();
        let t = cells[0];
        let (dx, dy) = (
            300.0 * body.amplitude * (0.013 * t).sin(),
            300.0 * body.amplitude * (0.007 * t).cos(),
        );
        let moved: Vec<String> = std::iter::once(t)
            .chain(cells[1..].chunks(2).flat_map(|p| [p[0] + dx, p[1] + dy]))
            .map(|v| v.to_string())
            .collect();
        moved.join(",")
    });
    let moves =
        |r: &theory_search::fit::FitReport| r.warnings.iter().any(|w| w.contains("held end moves"));
    let held = fitted(&text, true, 19, None);
    assert!(!moves(&held), "{:?}", held.warnings);
    let swaying = fitted(&swayed, true, 19, None);
    assert!(moves(&swaying), "{:?}", swaying.warnings);
    println!("{:?}", swaying.warnings);
    // discover reads the same claim into its verdict: the theory does not hold here.
    let zebrafish = self::body("clamped", "free");
    let verdict = |text: &str| {
        let mut s = DiscoverSettings::new(InputKind::Midline);
        s.recording.points = 19;
        s.bootstrap = 0;
        let source = Source::Reader(
            "beam".into(),
            Box::new(std::io::Cursor::new(text.to_owned())),
        );
        let r = discover(vec![source], &zebrafish, &s).expect("discovers");
        r.verdict.expect("a verdict")
    };
    let held_end = |v: &Verdict| {
        (v.findings.iter()).any(|f| matches!(f, Finding::HeldEndMoves { share } if *share > 0.25))
    };
    let still = verdict(&text);
    assert!(!held_end(&still), "{still:?}");
    let moving = verdict(&swayed);
    assert!(held_end(&moving), "{moving:?}");
    assert_eq!(moving.conclusion, Conclusion::DoesNotHold);
}

/// The held points are the model's, whichever end a recording lists first: a clamped–free
/// beam's recording with its points in the other order, read with `head_first` off, gives the
/// same κ and modes as read head first.
#[test]
fn a_held_body_read_tail_first_is_the_same_body() {
    let body = clamped(19, 0.05);
    let text = record(&body, 78);
    let reversed = each_row(&text, |line| {
        let cells: Vec<&str> = line.split(',').collect();
        let points: Vec<&[&str]> = cells[1..].chunks(2).rev().collect();
        let row: Vec<&str> = std::iter::once(cells[0])
            .chain(points.into_iter().flatten().copied())
            .collect();
        row.join(",")
    });
    let head_first = fitted(&text, true, 19, None);
    let mut s = FitSettings::new(InputKind::Midline);
    s.recording.points = 19;
    s.recording.head_first = false;
    let tail_first = common::beam::fitted_with(&reversed, true, &s);
    let kappa = |r: &theory_search::fit::FitReport| r.continuum.as_ref().map(|c| c.constant);
    assert_eq!(kappa(&head_first), kappa(&tail_first));
    assert!(kappa(&head_first).is_some_and(|k| (k / body.kappa - 1.0).abs() < 0.01));
    assert!(tail_first
        .warnings
        .iter()
        .all(|w| !w.contains("held end moves")));
}

/// A recording's CSV with each row after the header rewritten by `row`.
fn each_row(text: &str, row: impl Fn(&str) -> String) -> String {
    let mut lines = text.lines();
    let mut out = lines.next().map_or(String::new(), |h| format!("{h}\n"));
    for line in lines {
        out += &row(line);
        out.push('\n');
    }
    out
}
