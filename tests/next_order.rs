//! The next order: a model keeps its lowest-order terms and `beyond_leading` layers more. The
//! layers are checked against their definition (a term's layer is one more than the longest
//! chain of admitted terms of strictly lower order below it), the larva's next-order terms
//! and their exact nonlinear forces against a hand derivation, and the leading order against
//! Table 1.

use theory_search::enumerate::Basis;
use theory_search::equations::derive_nonlinear;
use theory_search::model::{Density, Model};
use theory_search::reduce::{analyse, dominates, layers, lowest_order};
use theory_search::term::Term;

/// The layer of each term by its definition: 1 + the longest chain of dominating terms.
fn layer_by_definition(terms: &[Term]) -> Vec<u32> {
    let orders: Vec<_> = terms.iter().map(Term::orders).collect();
    let mut memo = vec![0u32; terms.len()];
    // Lower τ + σ first: every dominator of a term comes before it.
    let mut by_total: Vec<usize> = (0..terms.len()).collect();
    by_total.sort_by_key(|&i| orders[i].tau + orders[i].sigma);
    for &i in &by_total {
        memo[i] = 1
            + (0..terms.len())
                .filter(|&j| dominates(&orders[j], &orders[i]))
                .map(|j| memo[j])
                .max()
                .unwrap_or(0);
    }
    memo
}

#[test]
fn layers_are_the_longest_chains_of_lower_order_terms() {
    // Every pure power (∂tᵃ∂sᵇφ)ⁿ with a, b ≤ 3 and n ≤ 3, in pseudo-random subsets.
    let pool: Vec<Term> = (0..=3)
        .flat_map(|a| (0..=3).flat_map(move |b| (1..=3).map(move |n| (a, b, n))))
        .filter(|&(a, b, _)| a + b > 0)
        .map(|(a, b, n)| Term::power(a, b, n))
        .collect();
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    for _ in 0..300 {
        let subset: Vec<Term> = pool
            .iter()
            .filter(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state % 3 == 0
            })
            .cloned()
            .collect();
        let layer = layer_by_definition(&subset);
        for beyond in 0..4 {
            let want: Vec<Term> = subset
                .iter()
                .zip(&layer)
                .filter(|(_, &l)| l <= beyond + 1)
                .map(|(t, _)| t.clone())
                .collect();
            assert_eq!(layers(&subset, beyond), want, "beyond {beyond}");
        }
        assert_eq!(layers(&subset, 0), lowest_order(&subset));
    }
}

fn with_beyond(mut model: Model, k: u32) -> Model {
    model.lagrangian.beyond_leading = k;
    model.rayleigh.beyond_leading = k;
    model
}

fn survivors(model: &Model, density: Density, order: u32) -> Vec<Vec<String>> {
    analyse(model, density, order)
        .unwrap()
        .fields
        .iter()
        .map(|f| f.survivors.iter().map(Term::to_string).collect())
        .collect()
}

#[test]
fn the_larva_at_the_next_order() {
    let larva = Model::larva();
    let next = with_beyond(larva.clone(), 1);
    // Beyond 0 is Table 1.
    for density in [Density::Lagrangian, Density::Rayleigh] {
        assert_eq!(
            survivors(&with_beyond(larva.clone(), 0), density, 4),
            survivors(&larva, density, 4)
        );
    }
    assert_eq!(
        survivors(&next, Density::Lagrangian, 4),
        [
            vec!["(∂t φ)²", "(∂s φ)²", "(∂s φ)⁴", "(∂ss φ)²"],
            vec!["(∂t φ)²", "(∂s φ)²", "(∂s φ)⁴", "(∂ss φ)²"],
            vec!["(∂t φ)²", "(∂ss φ)²"],
            vec!["(∂t φ)²", "(∂ss φ)²"],
        ]
    );
    assert_eq!(
        survivors(&next, Density::Rayleigh, 4),
        [
            vec!["(∂ts φ)²", "(∂tss φ)²"],
            vec!["(∂ts φ)²", "(∂tss φ)²"],
            vec!["(∂tss φ)²"],
            vec!["(∂tss φ)²"],
        ]
    );
    // The bending fields gain (∂sss φ)² at order 6 (their quartic terms lie beyond σ = 6).
    assert_eq!(
        survivors(&next, Density::Lagrangian, 6)[2],
        ["(∂t φ)²", "(∂ss φ)²", "(∂sss φ)²"]
    );
}

#[test]
fn the_axial_field_gains_a_cubic_stress() {
    // L = ½(∂t x)² − ½c1(∂s x)² − ½c2(∂s x)⁴ − ½c3(∂ss x)², by hand:
    // ∂t²x = ∂s(c1 ∂s x + 2c2 (∂s x)³) − c3 ∂s⁴x = c1 ∂s²x + 6c2 (∂s x)²∂s²x − c3 ∂s⁴x.
    let next = with_beyond(Model::larva(), 1);
    let (equations, _) = derive_nonlinear(&next, 4, Basis::Powers).unwrap();
    let x = &equations[0];
    let terms: Vec<(String, String, String)> = x
        .rhs
        .iter()
        .map(|t| {
            let mono: Vec<String> = t
                .monomial
                .iter()
                .map(|(d, n)| format!("{}:{}^{n}", d.t, d.s))
                .collect();
            (t.coefficient.clone(), mono.join(" "), t.value.to_string())
        })
        .collect();
    for want in [
        ("c1_x", "0:2^1", "1"),
        ("c3_x", "0:4^1", "-1"),
        ("c2_x", "0:1^2 0:2^1", "6"),
        ("c'1_x", "1:2^1", "2"),
        ("c'2_x", "1:4^1", "-2"),
    ] {
        let want = (want.0.to_string(), want.1.to_string(), want.2.to_string());
        assert!(terms.contains(&want), "{want:?} not in {terms:?}");
    }
    assert_eq!(terms.len(), 5, "{terms:?}");
}

#[test]
fn a_model_file_keeps_the_next_order_and_bounds_it() {
    let text = include_str!("../tables/models/tethered.toml");
    let with = |k: u32| {
        text.replace(
            "\n[lagrangian]\n",
            &format!("\n[lagrangian]\nbeyond_leading = {k}\n"),
        )
    };
    let model = Model::from_toml(&with(1)).unwrap();
    assert_eq!(model.lagrangian.beyond_leading, 1);
    // Tethered, by part: the potential's lowest order is every power of u (τ = σ = 0), its
    // next the tension (∂s u)²; the kinetic term stays alone (KIN admits no other).
    assert_eq!(
        survivors(&model, Density::Lagrangian, 4)[0],
        ["(∂t φ)²", "φ", "φ²", "φ³", "φ⁴", "(∂s φ)²"]
    );
    let err = Model::from_toml(&with(9)).unwrap_err().to_string();
    assert!(err.contains("at most 8"), "{err}");
}
