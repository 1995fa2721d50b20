//! Scenario: reduction by parts. The canonical basis per block against the Hilbert-series count,
//! every relation checked by an independent Euler–Lagrange operator, and the larva's reduced
//! bases.

use num_rational::Rational64;
use theory_search::model::{Density, Model};
use theory_search::parts::{
    block_monomials, euler_lagrange, hilbert_count, reduce_model, reduce_terms, term_of, JetPoly,
};
use theory_search::term::Term;

#[test]
fn independent_counts_match_the_hilbert_series() {
    for epsilon in 2..=4u32 {
        for tau in 0..=4u32 {
            for sigma in 0..=4u32 {
                if tau + sigma > 6 {
                    continue;
                }
                let terms: Vec<Term> = block_monomials(epsilon, tau, sigma, true)
                    .iter()
                    .filter_map(term_of)
                    .collect();
                if terms.is_empty() {
                    continue;
                }
                let blocks = reduce_terms(&terms);
                assert_eq!(blocks.len(), 1);
                let kept = blocks[0].kept.len() as i64;
                assert_eq!(
                    kept,
                    hilbert_count(epsilon, tau, sigma),
                    "(ε, τ, σ) = ({epsilon}, {tau}, {sigma})"
                );
            }
        }
    }
}

#[test]
fn shift_symmetric_generators_give_the_same_reduction() {
    use theory_search::parts::reduce_terms_full;
    for epsilon in 1..=4u32 {
        for tau in 0..=3u32 {
            for sigma in 0..=4u32 {
                let terms: Vec<Term> = block_monomials(epsilon, tau, sigma, true)
                    .iter()
                    .filter_map(term_of)
                    .collect();
                if terms.is_empty() {
                    continue;
                }
                let (a, b) = (reduce_terms(&terms), reduce_terms_full(&terms));
                assert_eq!(a[0].kept, b[0].kept, "({epsilon}, {tau}, {sigma})");
            }
        }
    }
}

#[test]
fn every_relation_leaves_the_equations_of_motion_unchanged() {
    let mut checked = 0;
    for density in [Density::Lagrangian, Density::Rayleigh] {
        for f in reduce_model(&Model::larva(), density, 5).unwrap() {
            for b in &f.blocks {
                assert_eq!(b.kept.len() + b.relations.len(), b.admitted.len());
                for r in &b.relations {
                    assert!(
                        euler_lagrange(&r.difference()).is_empty(),
                        "{}: {}",
                        f.field,
                        r.text("φ")
                    );
                    checked += 1;
                }
                // And the kept terms are really independent: no non-trivial combination of two
                // kept terms of a block has a vanishing Euler–Lagrange expression (spot check).
                for (i, a) in b.kept.iter().enumerate() {
                    let e = euler_lagrange(&JetPoly::from([(
                        theory_search::parts::mono_of(a),
                        Rational64::from_integer(1),
                    )]));
                    assert!(
                        !e.is_empty() || b.orders.epsilon == 1,
                        "kept {a} is a total derivative ({i})"
                    );
                }
            }
        }
    }
    assert!(checked > 20, "{checked}");
}

#[test]
fn the_seeds_terms_are_independent_and_mixed_forms_reduce() {
    let t = |s: &str| -> Term { s.parse().unwrap() };
    // φ·∂ssφ ≡ −(∂sφ)², ∂sφ·∂sssφ ≡ −(∂ssφ)², and ∂tφ·∂tssφ ≡ −(∂tsφ)².
    let blocks = reduce_terms(&[t("(∂s φ)²"), t("φ·∂ss φ")]);
    assert_eq!(blocks[0].kept, [t("(∂s φ)²")]);
    assert_eq!(blocks[0].relations[0].text("φ"), "φ·∂ss φ ≡ −(∂s φ)²");
    let blocks = reduce_terms(&[t("(∂ss φ)²"), t("∂s φ·∂sss φ")]);
    assert_eq!(blocks[0].kept, [t("(∂ss φ)²")]);
    assert_eq!(blocks[0].relations[0].text("φ"), "∂s φ·∂sss φ ≡ −(∂ss φ)²");
    // The gyroscopic term is not a total derivative; ∂tφ alone is.
    assert_eq!(reduce_terms(&[t("∂t φ·∂s φ")])[0].kept.len(), 1);
    assert!(reduce_terms(&[t("∂t φ")])[0].kept.is_empty());
}

#[test]
fn larva_reduced_lowest_terms_are_the_seeds() {
    let reduced = reduce_model(&Model::larva(), Density::Lagrangian, 4).unwrap();
    let y = &reduced[2];
    let mut kept: Vec<Term> = y.blocks.iter().flat_map(|b| b.kept.clone()).collect();
    kept.sort();
    let front = theory_search::reduce::lowest_order(&kept);
    let names: Vec<String> = front.iter().map(|t| t.to_string()).collect();
    assert_eq!(names, ["(∂t φ)²", "(∂ss φ)²"]);
}
