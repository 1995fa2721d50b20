//! Scenario: which terms each larva field keeps, in both densities, and why the others fail.

use theory_search::model::{Density, Model};
use theory_search::reduce::analyse;
use theory_search::rules::{rule, Verdict};

fn survivors(density: Density, order: u32) -> Vec<Vec<String>> {
    let a = analyse(&Model::larva(), density, order).unwrap();
    a.fields
        .iter()
        .map(|f| f.survivors.iter().map(|t| t.to_string()).collect())
        .collect()
}

#[test]
fn lagrangian_survivors_are_wave_and_beam_at_every_order_from_4_to_10() {
    for order in 4..=10 {
        assert_eq!(
            survivors(Density::Lagrangian, order),
            [
                ["(∂t φ)²", "(∂s φ)²"],
                ["(∂t φ)²", "(∂s φ)²"],
                ["(∂t φ)²", "(∂ss φ)²"],
                ["(∂t φ)²", "(∂ss φ)²"],
            ],
            "order {order}"
        );
    }
}

#[test]
fn rayleigh_survivors_are_kelvin_damping_at_every_order_from_4_to_10() {
    for order in 4..=10 {
        assert_eq!(
            survivors(Density::Rayleigh, order),
            [["(∂ts φ)²"], ["(∂ts φ)²"], ["(∂tss φ)²"], ["(∂tss φ)²"]],
            "order {order}"
        );
    }
}

#[test]
fn low_orders_say_what_is_missing() {
    let l3 = analyse(&Model::larva(), Density::Lagrangian, 3).unwrap();
    assert!(l3.fields[2].missing[0].contains("no potential term survives at order 3"));
    assert!(l3.fields[3].missing[0].contains("needs --order 4"));
    assert_eq!(survivors(Density::Lagrangian, 3)[2], ["(∂t φ)²"]);

    let l1 = analyse(&Model::larva(), Density::Lagrangian, 1).unwrap();
    assert_eq!(l1.fields[0].missing.len(), 2, "{:?}", l1.fields[0].missing);
    assert!(l1.fields[0].missing[0].contains("kinetic"));

    let r2 = analyse(&Model::larva(), Density::Rayleigh, 2).unwrap();
    assert!(r2.fields[0].missing.is_empty());
    assert!(r2.fields[2].missing[0].contains("(∂tss y)², needs --order 4"));
}

fn verdict(code: &str, term: &str) -> Verdict {
    rule(code).unwrap().verdict(&term.parse().unwrap())
}

#[test]
fn each_rule_gives_its_verdict_and_reason() {
    let reject = |code: &str, term: &str, because: &str| match verdict(code, term) {
        Verdict::Reject { rule, why } => {
            assert_eq!(rule, code);
            assert!(why.contains(because), "{code} on {term}: {why}");
        }
        Verdict::Pass => panic!("{code} passed {term}"),
    };
    reject("KIN", "(∂ts φ)²", "not the standard kinetic term");
    reject("KIN", "(∂t φ)⁴", "not the standard kinetic term");
    reject("OST", "(∂tt φ)²", "order 2 > 1");
    reject("TRAN", "φ⁴", "φ → φ + Δ changes φ⁴ by 4Δ·φ³");
    reject("REF", "(∂s φ)³", "φ → −φ");
    reject("ROT", "(∂s φ)²", "2Δ·∂s φ");
    reject("ROT", "φ²", "Δ·s");
    reject("DIS", "(∂s φ)²", "no time derivative");
    reject("DIS", "(∂tts φ)²", "order 2 > 1");
    reject("GAL", "(∂t φ)²", "φ → φ + v·t");
    reject("SPIN", "(∂ts φ)²", "Ω");
    for (code, term) in [
        ("ROT", "∂t φ"),
        ("ROT", "(∂ss φ)²"),
        ("KIN", "(∂t φ)²"),
        ("KIN", "(∂ss φ)²"),
        ("TRAN", "∂s φ"),
        ("OST", "∂tsss φ"),
        ("GAL", "(∂ts φ)²"),
        ("SPIN", "(∂tss φ)²"),
        ("DIS", "(∂ts φ)⁴"),
    ] {
        assert_eq!(verdict(code, term), Verdict::Pass, "{code} on {term}");
    }
}

#[test]
fn factor_kind_verdicts_agree_with_expanding_the_product() {
    use theory_search::enumerate::{interaction_monomials, monomials, Bounds};
    use theory_search::model::BoundShape;
    use theory_search::rules::REGISTRY;
    let mut decided = 0;
    for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
        let single = monomials(&Bounds::for_order(shape, 5));
        let pairs = interaction_monomials(&Bounds::for_order(shape, 4), 2);
        // Prepared for a lower order than some factors have: those are derived on the spot.
        let prepared: Vec<_> = REGISTRY.iter().map(|r| r.prepare(3)).collect();
        for term in single.iter().chain(&pairs) {
            for (rule, ready) in REGISTRY.iter().zip(&prepared) {
                assert_eq!(
                    ready.passes(term),
                    rule.passes(term),
                    "{} on {term}",
                    rule.code
                );
                // One field at a time (interaction terms), against expanding the product.
                if let theory_search::rules::Check::Symmetry(tr) = rule.check {
                    for field in term.fields() {
                        assert_eq!(
                            ready.passes_field(term, field),
                            tr.is_invariant_field(term, field),
                            "{} on field {field} of {term}",
                            rule.code
                        );
                    }
                }
                assert_eq!(
                    rule.passes(term),
                    rule.passes_by_expansion(term),
                    "{} on {term}",
                    rule.code
                );
                assert_eq!(
                    rule.passes(term),
                    rule.verdict(term).passed(),
                    "{} on {term}",
                    rule.code
                );
                decided += 1;
            }
        }
    }
    assert!(decided > 10_000, "{decided}");
}
