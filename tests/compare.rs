//! Scenario: `compare` on two groups of animals simulated independently of the engine
//! (`tests/common/beam.rs`: thermal Euler–Bernoulli beams, each animal its own κ drawn about its
//! group's): a group 20 % stiffer is found (the difference's interval excludes 0 and covers the
//! truth); two groups from one population cover 0 in ≥ 18 of 20 seeds; the command line's
//! forms and refusals.

mod common;

use common::beam::{model, on_two_cores, record, Body, FREE_BEAM};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use theory_search::compare::{compare, CompareReport, CompareSettings, Group};
use theory_search::fit::{FitSettings, Input};
use theory_search::modal::Params;
use theory_search::recording::InputKind;

/// Ten animals a group, 8 000 frames each.
const ANIMALS: usize = 10;

fn animal(kappa: f64) -> Body {
    Body {
        kappa,
        frames: 8_000,
        ..FREE_BEAM
    }
}

/// Each group's animals' κ: the group's κ times 1 + 5 % × a standard normal.
fn kappas(group: f64, seed: u64) -> Vec<f64> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..ANIMALS)
        .map(|_| {
            let z: f64 = StandardNormal.sample(&mut rng);
            group * (1.0 + 0.05 * z)
        })
        .collect()
}

fn compared(first: f64, second: f64, seed: u64) -> (CompareReport, f64) {
    let [a, b] = [kappas(first, 1000 + seed), kappas(second, 2000 + seed)];
    let truth = b.iter().sum::<f64>() / b.len() as f64 - a.iter().sum::<f64>() / a.len() as f64;
    let group = |name: &str, ks: &[f64], base: u64| Group {
        name: name.into(),
        inputs: ks
            .iter()
            .enumerate()
            .map(|(i, &k)| Input::Reader {
                name: format!("{name}{i}"),
                reader: Box::new(std::io::Cursor::new(record(&animal(k), base + i as u64))),
            })
            .collect(),
    };
    let settings = CompareSettings {
        fit: FitSettings::new(InputKind::Midline),
        permutations: 1999,
        seed,
        discover: false,
    };
    let groups = vec![
        group("wild", &a, 10 * seed),
        group("mutant", &b, 10 * seed + 500),
    ];
    let report = compare(groups, &model(false), &Params::default(), &settings).expect("compares");
    (report, truth)
}

#[test]
fn a_stiffer_group_is_found_with_an_interval_excluding_zero() {
    let (report, truth) = compared(0.01, 0.012, 1);
    let d = &report.differences[0];
    assert_eq!(d.quantity, "kappa");
    assert!(
        d.interval[0] > 0.0 && d.p < 0.01,
        "{d:?}\n{}",
        text(&report)
    );
    assert!(
        d.interval[0] <= truth && truth <= d.interval[1],
        "the animals' own mean difference {truth} outside {:?}",
        d.interval
    );
    assert!((d.ratio - 1.2).abs() < 0.05, "{d:?}");
    // Both groups are thermal beams: no animal rejects a law it obeys in most of them.
    for g in &report.groups {
        assert_eq!(g.animals, ANIMALS);
    }
    assert_eq!(
        report.animals.len(),
        2 * ANIMALS * (1 + 2 * report.modes.len())
    );
    assert!(!report.modes.is_empty(), "{}", text(&report));
}

#[test]
#[ignore = "a coverage study, run by .ci/run: cargo test --release -- --ignored --skip by_hand_"]
fn two_groups_of_one_population_cover_zero() {
    let covered: Vec<bool> = on_two_cores(20, |s| {
        let (report, _) = compared(0.01, 0.01, 100 + s);
        let d = &report.differences[0];
        d.interval[0] <= 0.0 && 0.0 <= d.interval[1]
    });
    let n = covered.iter().filter(|&&c| c).count();
    eprintln!("one population: the κ difference's interval covers 0 in {n} of 20");
    assert!(n >= 18, "{n} of 20");
}

fn text(r: &CompareReport) -> String {
    use theory_search::report::Report;
    r.text()
}

#[test]
fn the_command_line_compares_directories_and_refuses_bad_groups() {
    let dir = common::scratch("compare");
    for (g, k) in [("wild", 0.01), ("mutant", 0.012)] {
        let path = dir.path().join(g);
        std::fs::create_dir(&path).unwrap();
        for (i, &k) in kappas(k, 7).iter().take(4).enumerate() {
            let body = Body {
                frames: 4_000,
                ..animal(k)
            };
            std::fs::write(path.join(format!("a{i}.csv")), record(&body, 40 + i as u64)).unwrap();
        }
    }
    let wild = dir.path().join("wild");
    let mutant = dir.path().join("mutant");
    let (w, m) = (wild.to_str().unwrap(), mutant.to_str().unwrap());
    let text = common::cli(&["compare", w, m, "--permutations", "499"]).expect("compares");
    assert!(text.starts_with("Compared: "), "{text}");
    assert!(text.contains("  kappa "), "{text}");
    assert!(
        text.contains("Laws, animals consistent / rejected / undetermined:"),
        "{text}"
    );
    let csv = common::cli(&["compare", w, m, "--format", "csv"]).unwrap();
    assert!(csv.starts_with("group,animal,quantity,value\n"), "{csv}");
    let json = common::cli(&["compare", w, m, "--format", "json"]).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(doc["differences"][0]["quantity"], "kappa", "{doc}");
    // Refusals: no permutations, a group of one animal, a group that does not exist.
    let (code, _) = common::in_process(&["compare", w, m, "--permutations", "0"]).unwrap_err();
    assert_eq!(code, 2);
    let one = dir.path().join("wild").join("a0.csv");
    let (code, message) = common::in_process(&["compare", one.to_str().unwrap(), m]).unwrap_err();
    assert_eq!(code, 1, "{message}");
    assert!(
        message.contains("a comparison needs 2 a group"),
        "{message}"
    );
    let missing = dir.path().join("none");
    let (code, _) = common::in_process(&["compare", missing.to_str().unwrap(), m]).unwrap_err();
    assert_eq!(code, 1);
}

/// `--discover`: two groups of four continuum beams (the independent generator of
/// `tests/common/continuum.rs`, 5 % of frames lost), the second 44 % stiffer in c (κ +20 %):
/// each animal's discovered c_y compared, the difference found with an interval excluding 0
/// and near the truth.
#[test]
fn discovered_coefficients_are_compared_across_groups() {
    use common::continuum::{record as continuum, Beam, C};
    let dir = common::scratch("compare-discover");
    let group = |name: &str, c: f64, base: u64| Group {
        name: name.into(),
        inputs: (0..4)
            .map(|i| {
                let beam = Beam {
                    frames: 6000,
                    ..Beam::passive(false)
                };
                // The same beam's T/(cλ) amplitudes at the new c.
                let beam = Beam {
                    c,
                    cp: beam.cp * (c / C).sqrt(),
                    temperature: beam.temperature * c / C,
                    ..beam
                };
                let path = dir.path().join(format!("{name}{i}.csv"));
                std::fs::write(&path, continuum(&beam, base + i)).unwrap();
                Input::File(path)
            })
            .collect(),
    };
    let settings = CompareSettings {
        fit: FitSettings::new(InputKind::Midline),
        permutations: 999,
        seed: 1,
        discover: true,
    };
    let groups = vec![group("wild", C, 10), group("stiff", 1.44 * C, 20)];
    let r = compare(groups, &model(false), &Params::default(), &settings).expect("compares");
    let c = r
        .differences
        .iter()
        .find(|d| d.quantity == "c_y")
        .unwrap_or_else(|| {
            panic!(
                "no c_y among {:?}",
                r.differences
                    .iter()
                    .map(|d| &d.quantity)
                    .collect::<Vec<_>>()
            )
        });
    let truth = 0.44 * C;
    println!("c_y: {:?} truth {truth}", c);
    assert!(c.interval[0] > 0.0, "{c:?}");
    assert!((c.estimate / truth - 1.0).abs() < 0.25, "{c:?}");
    assert!(r.animals.iter().any(|a| a.quantity == "c_y"));
    assert!(r.excluded.is_empty(), "{:?}", r.excluded);
    // Each group's mean holds within its own interval, and the figure draws them.
    for d in &r.differences {
        for g in 0..2 {
            let [lo, hi] = d.group_intervals[g];
            assert!(lo <= d.means[g] && d.means[g] <= hi, "{d:?}");
        }
    }
    let page = theory_search::figures::Page::default();
    let path = theory_search::figures::write_compare(dir.path(), &r, &page).unwrap();
    let svg = std::fs::read_to_string(path).unwrap();
    assert!(svg.contains("stiff against wild") && svg.contains("c_y (discovered)"));
}
