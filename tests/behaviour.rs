//! Scenario: the seed's forward/backward asymmetry (App. C) and axial–transverse resonance
//! (App. D), against their analytic results.

use theory_search::behaviour::{asymmetry, floquet, stability_chart};

#[test]
fn the_larva_ratio_from_the_seeds_coupling() {
    // c = −√2/2, A = ω = 1: frequencies √2 and −√2/2, ratio 1:2.
    let a = asymmetry(-std::f64::consts::FRAC_1_SQRT_2, 1.0, 1.0).unwrap();
    assert!((a.forward - 2f64.sqrt()).abs() < 1e-14);
    assert!((a.backward + std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-14);
    assert!((a.ratio - 0.5).abs() < 1e-14);
    assert!(
        (a.simulated_forward - a.forward).abs() < 1e-6,
        "{}",
        a.simulated_forward
    );
    assert!(
        (a.simulated_backward - a.backward).abs() < 1e-6,
        "{}",
        a.simulated_backward
    );
}

#[test]
fn the_amplitude_enters_squared_not_linearly() {
    // With A = 2 the simulated pair follows ω_s² + cA²ω_s − ω² = 0 (roots 1 ± √2 for c = −½),
    // not the seed's printed ω_s² + cAω_s − ω² = 0 (roots (1 ± √5)/2).
    let a = asymmetry(-0.5, 2.0, 1.0).unwrap();
    assert!((a.forward - (1.0 + 2f64.sqrt())).abs() < 1e-12);
    assert!((a.backward - (1.0 - 2f64.sqrt())).abs() < 1e-12);
    assert!(
        (a.simulated_forward - a.forward).abs() < 1e-5,
        "{}",
        a.simulated_forward
    );
    assert!(
        (a.simulated_backward - a.backward).abs() < 1e-5,
        "{}",
        a.simulated_backward
    );
    assert!((a.simulated_forward - (1.0 + 5f64.sqrt()) / 2.0).abs() > 0.5);
}

#[test]
fn no_coupling_no_asymmetry_and_bad_input_is_refused() {
    let a = asymmetry(0.0, 0.7, 1.3).unwrap();
    assert!((a.forward - 1.3).abs() < 1e-14 && (a.backward + 1.3).abs() < 1e-14);
    assert!(asymmetry(f64::NAN, 1.0, 1.0).is_err());
    assert!(asymmetry(0.1, -1.0, 1.0).is_err());
    assert!(asymmetry(0.1, 1.0, 0.0).is_err());
}

#[test]
fn without_forcing_the_monodromy_is_a_rotation() {
    for ratio in [0.7, 1.3, 2.0, 3.1] {
        let p = floquet(1.0, 0.0, ratio).unwrap();
        let want = 2.0 * (2.0 * std::f64::consts::PI / ratio).cos();
        assert!(
            (p.trace - want).abs() < 1e-8,
            "ω/λ = {ratio}: {} vs {want}",
            p.trace
        );
        assert!(p.stable);
    }
}

#[test]
fn the_first_tongue_sits_at_twice_the_natural_frequency() {
    let eps = 0.05;
    let stable = |r: f64| floquet(1.0, eps, r).unwrap().stable;
    assert!(!stable(2.0));
    assert!(stable(1.9) && stable(2.1));
    // Edges at 2√(1 ∓ ε) + O(ε²): bisect each.
    let edge = |mut inside: f64, mut outside: f64| {
        for _ in 0..50 {
            let mid = 0.5 * (inside + outside);
            if stable(mid) {
                outside = mid
            } else {
                inside = mid
            }
        }
        0.5 * (inside + outside)
    };
    let (lo, hi) = (edge(2.0, 1.9), edge(2.0, 2.1));
    assert!(
        (lo - 2.0 * (1.0 - eps).sqrt()).abs() < 2.0 * eps * eps,
        "{lo}"
    );
    assert!(
        (hi - 2.0 * (1.0 + eps).sqrt()).abs() < 2.0 * eps * eps,
        "{hi}"
    );
    // The chart has the tongue: unstable near 2, stable far from it, at every ε > 0 row.
    let chart = stability_chart(1.0, (1.5, 2.5), 0.2, (41, 5)).unwrap();
    for row in chart.chunks(41).skip(1) {
        assert!(!row[20].stable, "ε = {}", row[20].epsilon);
        assert!(row[0].stable && row[40].stable);
    }
}
