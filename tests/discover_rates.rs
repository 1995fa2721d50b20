//! Scenario: `discover` on recordings it did not make: the independent continuum beam of
//! tests/common/continuum.rs (an exact linear SDE on the body's own modes, sampled exactly at a
//! tracker's rate, tracked at K points with noise and lost frames). The passive library is
//! estimated by the exact likelihood on the continuum modes, so its coefficients are the
//! continuum's whatever `--points`, at 8, 14 and 30 frames per period, with 5 % of the frames
//! lost and not bridged.

mod common;

use common::continuum::{record, Beam};
use theory_search::discover::{discover, DiscoverReport, DiscoverSettings, Source};
use theory_search::model::Model;
use theory_search::recording::{InputKind, Setting};

fn model(clamped: bool) -> Model {
    if clamped {
        Model::from_toml(include_str!("../tables/models/zebrafish.toml")).expect("shipped model")
    } else {
        Model::from_toml(include_str!("../tables/models/crawler.toml")).expect("shipped model")
    }
}

/// `discover` on `beam`'s recording (seed `seed`) at `points` model points, no bridging.
fn discovered(beam: &Beam, seed: u64, points: usize, bootstrap: usize) -> DiscoverReport {
    let text = record(beam, seed);
    let mut settings = DiscoverSettings::new(InputKind::Midline);
    settings.recording.points = points;
    settings.bootstrap = bootstrap;
    settings
        .recording
        .set("fill_gaps", &Setting::Int(0))
        .expect("a setting");
    let source = Source::Reader("continuum".into(), Box::new(std::io::Cursor::new(text)));
    discover(vec![source], &model(beam.clamped), &settings).expect("discovers")
}

#[test]
fn probe() {
    for fpp in [14.0, 30.0] {
        for points in [12] {
            let lost: f64 = std::env::var("LOST").map_or(0.05, |v| v.parse().unwrap());
            let modes: usize = std::env::var("MODES").map_or(12, |v| v.parse().unwrap());
            let beam = Beam {
                fpp,
                lost,
                modes,
                ..Beam::passive(false)
            };
            let r = discovered(&beam, 1, points, 200);
            eprintln!("fpp {fpp} points {points}: {}", r.equation);
            for t in &r.library {
                eprintln!("  {} {:.5e} {:?} {:?} sel {}", t.name, t.coefficient, t.interval, t.inclusion, t.selected);
            }
            for n in 1..=3 { eprintln!("  truth mode {n}: omega {:.5} zeta {:.5}", beam.omega(n), beam.zeta(n)); }
            eprintln!("  truth c {:.5e} c' {:.5e}; modes {:?} {}", beam.c, beam.cp / 2.0, r.modes, r.estimator);
        }
    }
}
