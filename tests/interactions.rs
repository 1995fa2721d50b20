//! Scenario: the interaction densities of the larva reproduce the seed's argument that the
//! long-wavelength theory is free (Appendix A, seed lines 1160–1230).

use theory_search::interaction::interactions;
use theory_search::model::{Density, Model};
use theory_search::term::Term;

fn t(s: &str) -> Term {
    s.parse().unwrap()
}

#[test]
fn only_the_axial_torsional_potential_coupling_is_admitted_and_it_is_dominated() {
    let i = interactions(&Model::larva(), Density::Lagrangian, 4).unwrap();
    // 6 pairs, 4 triples and the quadruple.
    assert_eq!(i.couplings.len(), 11);
    for p in &i.couplings {
        // The seed's three classes are among the lowest candidates of every pair that shares
        // only TRAN and REF.
        if p.shared == ["TRAN", "REF"] && p.fields.len() == 2 {
            let rows: Vec<&Term> = p.rows.iter().map(|r| &r.term).collect();
            for class in [
                "(∂s φ₁)²·(∂s φ₂)²",
                "(∂t φ₁)²·(∂t φ₂)²",
                "(∂s φ₁)²·(∂t φ₂)²",
            ] {
                assert!(rows.contains(&&t(class)), "{:?} lacks {class}", p.fields);
            }
        }
        let is_x_theta = p.fields == ["x", "theta"];
        if is_x_theta {
            assert_eq!(p.admitted, [t("(∂s φ₁)²·(∂s φ₂)²")]);
            assert_eq!(p.admitted[0].orders().sigma, 4);
        } else {
            assert!(
                p.admitted.is_empty(),
                "{:?} admits {:?}",
                p.fields,
                p.admitted
            );
        }
        assert!(p.kept.is_empty(), "{:?}", p.fields);
    }
    assert!(i.is_free());
    // The kinetic and mixed couplings fail KIN; a potential coupling with y fails ROT on y.
    let xy = &i.couplings[1];
    assert_eq!(xy.fields, ["x", "y"]);
    let row = xy
        .rows
        .iter()
        .find(|r| r.term == t("(∂s φ₁)²·(∂s φ₂)²"))
        .unwrap();
    let failed: Vec<(&str, Option<&str>)> = row
        .verdicts
        .iter()
        .filter(|v| !v.verdict.passed())
        .map(|v| (v.rule, v.field.as_deref()))
        .collect();
    assert_eq!(failed, [("ROT", Some("y"))]);
}

#[test]
fn rayleigh_interactions_are_also_negligible() {
    let i = interactions(&Model::larva(), Density::Rayleigh, 4).unwrap();
    assert!(i.is_free());
}

#[test]
fn without_kin_a_mixed_coupling_would_survive() {
    // Drop KIN from the interaction rules: couplings with time derivatives, such as the mixed
    // (∂s x)²·(∂t θ)² at (τ, σ) = (2, 2), are then admitted, but the free (∂t x)² at (2, 0)
    // dominates them, so the long-wavelength theory stays free.
    let text = Model::larva_toml().replacen(
        "interaction = [\"OST\", \"KIN\"]",
        "interaction = [\"OST\"]",
        1,
    );
    let model = Model::from_toml(&text).unwrap();
    let i = interactions(&model, Density::Lagrangian, 4).unwrap();
    let xt = &i.couplings[0];
    assert!(
        xt.admitted.iter().any(|a| a.orders().tau > 0),
        "{:?}",
        xt.admitted
    );
    // Every admitted coupling is still dominated by a free term: the theory stays free.
    assert!(i.is_free());
}

#[test]
fn couplings_of_three_fields_need_higher_orders() {
    // Under REF every field needs an even power, so a three-field term has ε ≥ 6: at order 4
    // there is no three-field candidate at all, at order 6 there are some, all at ε = 6.
    let i4 = interactions(&Model::larva(), Density::Lagrangian, 4).unwrap();
    let triples4: Vec<_> = i4
        .couplings
        .iter()
        .filter(|c| c.fields.len() == 3)
        .collect();
    assert_eq!(
        triples4.len(),
        4,
        "every triple of the four fields is listed"
    );
    assert!(triples4
        .iter()
        .all(|c| c.rows.is_empty() && c.admitted.is_empty()));
    let i = interactions(&Model::larva(), Density::Lagrangian, 6).unwrap();
    let triple = i
        .couplings
        .iter()
        .find(|c| c.fields == ["x", "theta", "y"])
        .unwrap();
    // Real candidates, not an empty list: (∂tφ, ∂sφ)-pairs of each field, 3³ of them.
    assert_eq!(triple.rows.len(), 27);
    assert!(triple.rows.iter().all(|r| r.term.orders().epsilon == 6));
    // None survives: y's rotation symmetry strikes every (∂s y)² and the standard kinetic
    // term every other product carrying (∂t y)² or ∂t y·∂s y; each rejection names its rule.
    for r in &triple.rows {
        assert!(!r.admitted(), "{} admitted", r.term);
        let failed: Vec<&str> = r
            .verdicts
            .iter()
            .filter(|v| !v.verdict.passed())
            .map(|v| v.rule)
            .collect();
        assert!(
            failed.iter().any(|c| ["ROT", "KIN", "REF"].contains(c)),
            "{}: {failed:?}",
            r.term
        );
    }
    assert!(triple.admitted.is_empty());
    assert!(i.is_free());
}

#[test]
fn a_coupling_none_admits_says_which_order_would() {
    let m = Model::larva();
    let l = interactions(&m, Density::Lagrangian, 4).unwrap();
    let xy = l.couplings.iter().find(|c| c.fields == ["x", "y"]).unwrap();
    assert!(xy.admitted.is_empty());
    // The paper's argument: (∂s x)²(∂ss y)² at σ = 6, outranked by the free terms.
    match &xy.later {
        Some(Ok((6, terms))) => assert_eq!(terms, &vec![t("(∂s φ₁)²·(∂ss φ₂)²")]),
        other => panic!("{other:?}"),
    }
    assert!(l
        .text(&m)
        .contains("the first at order 6 (--order 6): (∂s x)²·(∂ss y)² (0, 6)"));
}

#[test]
fn refusals_advise_only_what_the_command_takes() {
    let mut out = Vec::new();
    let e = theory_search::cli::run(["theory-search", "interactions", "--order", "9"], &mut out)
        .unwrap_err();
    assert!(!e.to_string().contains("--basis"), "{e}");
    let e = theory_search::cli::run(
        ["theory-search", "--basis", "monomials", "--order", "20"],
        &mut out,
    )
    .unwrap_err();
    assert!(e.to_string().contains("--basis powers"), "{e}");
}
