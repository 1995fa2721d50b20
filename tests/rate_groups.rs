//! Scenario: a directory of recordings sampled at two rates (issue 51 item 4). Thermal free–free
//! beams of one κ from the independent continuum generator (tests/common/continuum.rs: each
//! continuum mode an exactly sampled oscillator, tracking noise, 5 % of the frames lost in
//! bursts), two animals at 10 frames per period of the first mode and two at 25, each a file:
//! `fit` pools each rate group, lists both, and combines κ across the rates in the one time
//! unit. Over 10 seeds the combined interval covers the true κ in at least 8, the rates are
//! found to agree in at least 8, and every animal is listed with its group.

mod common;

use common::beam::model;
use common::continuum::{record, Beam};
use theory_search::fit::{fit_inputs, FitSettings, Input};
use theory_search::modal::Params;
use theory_search::recording::InputKind;

const SEEDS: u64 = 10;

/// The four recordings of seed `seed` written into `dir`: two animals at each rate.
fn recordings(dir: &std::path::Path, seed: u64) -> Vec<Input<'static>> {
    let mut inputs = Vec::new();
    for (i, fpp) in [10.0, 10.0, 25.0, 25.0].into_iter().enumerate() {
        let beam = Beam {
            frames: 6000,
            fpp,
            ..Beam::passive(false)
        };
        let path = dir.join(format!("s{seed}_{i}_{fpp}fpp.csv"));
        std::fs::write(&path, record(&beam, 100 * seed + i as u64)).unwrap();
        inputs.push(Input::File(path));
    }
    inputs
}

#[test]
fn each_rate_is_its_own_pool_and_kappa_is_combined_across_rates() {
    let dir = std::env::temp_dir().join(format!("ts-rate-groups-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let truth = Beam::passive(false).kappa();
    let (mut covered, mut agree) = (0, 0);
    for seed in 0..SEEDS {
        let inputs = recordings(&dir, seed);
        let settings = FitSettings::new(InputKind::Midline);
        let r = fit_inputs(inputs, &model(false), &Params::default(), &settings, None).unwrap();
        assert_eq!(r.rate_groups.len(), 2, "seed {seed}");
        for (g, fpp) in r.rate_groups.iter().zip([10.0, 25.0]) {
            assert_eq!(g.animals.len(), 2, "seed {seed}: {:?}", g.animals);
            assert!(g.animals.iter().all(|a| a.contains(&format!("_{fpp}fpp"))));
            let dt = Beam {
                fpp,
                ..Beam::passive(false)
            }
            .dt();
            assert!(
                (g.interval / dt - 1.0).abs() < 1e-6,
                "{} against {dt}",
                g.interval
            );
            assert!(g.fit.continuum.is_some(), "seed {seed}: {:?}", g.fit.note);
        }
        // The pool above is the first group's; every animal is listed, the second group's
        // with its group named.
        assert_eq!(r.animals.len(), 4);
        let noted = r
            .animals
            .iter()
            .filter(|a| {
                a.note
                    .as_deref()
                    .is_some_and(|n| n.starts_with("rate group 2"))
            })
            .count();
        assert_eq!(noted, 2);
        let a = r
            .across_rates
            .as_ref()
            .expect("a constant across the rates");
        let [lo, hi] = a.interval.unwrap();
        println!(
            "seed {seed}: κ {} [{lo}, {hi}] truth {truth}, Q p {}",
            a.constant, a.p
        );
        covered += usize::from(lo <= truth && truth <= hi);
        agree += usize::from(!a.differ);
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(covered >= 8, "covered in {covered} of {SEEDS}");
    assert!(agree >= 8, "the rates agree in {agree} of {SEEDS}");
}

#[test]
fn the_report_prints_the_rate_groups() {
    let dir = std::env::temp_dir().join(format!("ts-rate-text-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let inputs = recordings(&dir, 99);
    let settings = FitSettings::new(InputKind::Midline);
    let r = fit_inputs(inputs, &model(false), &Params::default(), &settings, None).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let text = theory_search::report::Report::text(&r);
    assert!(
        text.contains("rate groups: the animals were sampled at 2 rates"),
        "{text}"
    );
    assert!(
        text.contains("    1. every ") && text.contains("    2. every "),
        "{text}"
    );
    assert!(text.contains("across the 2 rates: κ = "), "{text}");
    let json = theory_search::report::Report::json(&r);
    assert_eq!(json["rate_groups"].as_array().unwrap().len(), 2);
    assert!(json["across_rates"]["constant"].as_f64().unwrap() > 0.0);
}
