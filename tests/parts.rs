//! Scenario: reduction by parts. The canonical basis per block against the Hilbert-series count,
//! every relation checked by an independent Euler–Lagrange operator, and the larva's reduced
//! bases.

mod common;

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

/// One field whose Rayleigh density only needs DIS: ∂t u itself survives.
const DIS_ONLY: &str = r#"
name = "dis-only"
description = "one field, dissipation only required"
[[fields]]
id = "u"
symbol = "u"
meaning = "a test field"
boundary = "free"
zero_modes = []
[lagrangian]
bound = "tau-plus-sigma"
columns = ["OST", "TRAN"]
[lagrangian.requirements]
u = ["OST", "TRAN"]
[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS"]
[rayleigh.requirements]
u = ["DIS"]
"#;

fn dissipative_only() -> Model {
    Model::from_toml(DIS_ONLY).unwrap()
}

/// The rank of the velocity-jet Euler operators over `terms`: how many independent classes
/// modulo total s-derivatives (Gaussian elimination over exact rationals, written here apart
/// from the reduction's own echelon form).
fn space_rank(terms: &[Term]) -> usize {
    use theory_search::parts::{mono_of, space_euler};
    type Key = (u32, Vec<(theory_search::term::Deriv, u32)>);
    let mut rows: Vec<std::collections::BTreeMap<Key, Rational64>> = terms
        .iter()
        .map(|t| {
            let p = JetPoly::from([(mono_of(t), Rational64::from_integer(1))]);
            space_euler(&p)
                .into_iter()
                .flat_map(|(a, q)| q.into_iter().map(move |(m, c)| ((a, m), c)))
                .collect()
        })
        .collect();
    let mut rank = 0;
    while let Some(i) = rows.iter().position(|r| !r.is_empty()) {
        let pivot = rows.swap_remove(i);
        let (key, c) = pivot.iter().next().map(|(k, c)| (k.clone(), *c)).unwrap();
        for r in rows.iter_mut() {
            if let Some(&f) = r.get(&key) {
                for (k, v) in &pivot {
                    let e = r.entry(k.clone()).or_insert(Rational64::from_integer(0));
                    *e -= f / c * v;
                }
                r.retain(|_, v| *v != Rational64::from_integer(0));
            }
        }
        rank += 1;
    }
    rank
}

#[test]
fn rayleigh_terms_reduce_modulo_space_derivatives_only() {
    let model = dissipative_only();
    for (order, expected) in [(2, 3), (4, 13), (6, 42)] {
        let f = &reduce_model(&model, Density::Rayleigh, order).unwrap()[0];
        let kept: usize = f.blocks.iter().map(|b| b.kept.len()).sum();
        let admitted: Vec<Term> = f.blocks.iter().flat_map(|b| b.admitted.clone()).collect();
        assert_eq!(kept, space_rank(&admitted), "order {order}");
        assert_eq!(kept, expected, "order {order}");
        // ∂t u is a constant force, not a total derivative.
        assert!(
            f.blocks[0].kept.contains(&"∂t φ".parse().unwrap()),
            "{:?}",
            f.blocks[0]
        );
    }
    // `parts` and `table` agree: the table's survivor ∂t u is kept.
    let mut out = Vec::new();
    let dir_held = common::scratch("dis");
    let dir = dir_held.path();
    let path = dir.join("m.toml");
    std::fs::write(&path, DIS_ONLY).unwrap();
    theory_search::cli::run(
        [
            "theory-search",
            "parts",
            "--density",
            "rayleigh",
            "--order",
            "2",
            "--model",
            path.to_str().unwrap(),
        ],
        &mut out,
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(!text.contains("∂t u ≡ 0"), "{text}");
}
