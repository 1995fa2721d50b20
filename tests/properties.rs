//! Properties that must hold for every term and every order.

use proptest::prelude::*;
use theory_search::enumerate::{pure_powers, Bounds, MAX_ORDER};
use theory_search::model::{BoundShape, Density, Model};
use theory_search::reduce::{analyse, dominates};
use theory_search::term::{Deriv, Factor, Term};

fn factor() -> impl Strategy<Value = Factor> {
    (0u8..3, 0u32..7, 0u32..7, 1u32..6).prop_map(|(field, t, s, power)| Factor {
        field,
        deriv: Deriv::new(t, s),
        power,
    })
}

proptest! {
    #[test]
    fn display_and_parse_round_trip(factors in prop::collection::vec(factor(), 1..4)) {
        let term = Term::new(factors).unwrap();
        let text = term.to_string();
        prop_assert_eq!(text.parse::<Term>().unwrap(), term.clone(), "{}", text);
    }

    #[test]
    fn orders_add_up(factors in prop::collection::vec(factor(), 1..4)) {
        let term = Term::new(factors.clone()).unwrap();
        let o = term.orders();
        prop_assert_eq!(o.epsilon, factors.iter().map(|f| f.power).sum::<u32>());
        prop_assert_eq!(o.tau, factors.iter().map(|f| f.power * f.deriv.t).sum::<u32>());
        prop_assert_eq!(o.sigma, factors.iter().map(|f| f.power * f.deriv.s).sum::<u32>());
    }

    #[test]
    fn survivors_are_admitted_and_undominated(order in 1u32..=MAX_ORDER) {
        let model = Model::larva();
        let mut survivors = 0;
        for density in Density::ALL {
            let a = analyse(&model, density, order).unwrap();
            prop_assert_eq!(a.fields.len(), model.fields.len());
            for f in &a.fields {
                // A non-empty admitted set has a non-empty Pareto front.
                prop_assert_eq!(f.admitted.is_empty(), f.survivors.is_empty());
                survivors += f.survivors.len();
                for s in &f.survivors {
                    prop_assert!(f.admitted.contains(s));
                    for t in &f.admitted {
                        prop_assert!(!dominates(&t.orders(), &s.orders()));
                    }
                }
                // Every admitted non-survivor is dominated by some survivor.
                for t in f.admitted.iter().filter(|t| !f.survivors.contains(t)) {
                    prop_assert!(f.survivors.iter().any(|s| dominates(&s.orders(), &t.orders())));
                }
            }
        }
        // From order 2 every larva field keeps a kinetic term: the loops above checked something.
        if order >= 2 {
            prop_assert!(survivors >= 2 * model.fields.len(), "{} survivors", survivors);
        }
    }
}

/// Independent count of the Table 1 candidates: triples (a, b, n) by brute force.
fn brute_count(order: u32, shape: BoundShape) -> usize {
    let mut n_terms = 0;
    for n in 1..=order {
        for a in 0..=order {
            for b in 0..=order {
                let (d, tau, sigma) = (a + b, n * a, n * b);
                let ok = d <= order
                    && match shape {
                        BoundShape::TauPlusSigma => tau + sigma <= order,
                        BoundShape::TauAndSigma => tau <= order && sigma <= order,
                    };
                n_terms += ok as usize;
            }
        }
    }
    n_terms
}

#[test]
fn candidate_counts_match_a_brute_force_count_at_every_order() {
    for order in 1..=MAX_ORDER {
        for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
            let terms = pure_powers(&Bounds::for_order(shape, order));
            assert_eq!(terms.len(), brute_count(order, shape), "order {order}");
            assert!(terms.windows(2).all(|w| w[0] < w[1]), "sorted and distinct");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The generated operators agree with the exact ones at sizes no other test names.
    #[test]
    fn generated_apply_matches_exact_operators(points in 3usize..400, seed in any::<u64>()) {
        use theory_search::discretise::operators;
        use theory_search::generated::operators::OPERATORS;
        let ops = operators(&Model::larva(), 4, points).unwrap();
        let mut state = seed | 1;
        prop_assert_eq!(ops.len(), OPERATORS.len());
        prop_assert!(!ops.is_empty());
        for (op, generated) in ops.iter().zip(OPERATORS) {
            let n = op.size;
            let phi: Vec<f64> = (0..n).map(|_| {
                state ^= state << 13; state ^= state >> 7; state ^= state << 17;
                (state % 2001) as f64 / 1000.0 - 1.0
            }).collect();
            let mut out = vec![0.0; n];
            (generated.apply)(points, &phi, &mut out).unwrap();
            prop_assert_eq!(op.matrix.len(), n);
            for (i, row) in op.matrix.iter().enumerate() {
                prop_assert_eq!(row.len(), n);
                let want: f64 = row.iter().zip(&phi).map(|(&a, b)| a as f64 * b).sum();
                prop_assert!((out[i] - want).abs() <= 1e-12 * (1.0 + want.abs()));
            }
        }
    }
}
