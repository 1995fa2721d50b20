//! Scenario: the full monomial basis. Its size against an independent generating-function
//! count, and the machine-checked version of Appendix C's remark: without parity or time
//! reversal the axial field admits the gyroscopic term ∂tx·∂sx at the lowest order, and either
//! symmetry removes it.

use theory_search::enumerate::{monomials, Basis, Bounds};
use theory_search::model::{BoundShape, Density, Model};
use theory_search::reduce::analyse_basis;
use theory_search::term::Term;

/// Number of monomials with 1 ≤ ε ≤ N and the order bounds, from the generating function
/// ∏_{a+b≤N} 1/(1 − x·u^a·v^b), truncated: coefficients c[ε][τ][σ].
fn generating_function_count(order: usize, shape: BoundShape) -> usize {
    let n = order;
    let mut c = vec![vec![vec![0usize; n + 1]; n + 1]; n + 1];
    c[0][0][0] = 1;
    for a in 0..=n {
        for b in 0..=n - a {
            // Multiply by 1/(1 − x u^a v^b) = Σ_k (x u^a v^b)^k: in place, increasing indices.
            for e in 1..=n {
                for t in a..=n {
                    for s in b..=n {
                        c[e][t][s] += c[e - 1][t - a][s - b];
                    }
                }
            }
        }
    }
    let mut total = 0;
    for plane in c.iter().skip(1) {
        for (t, row) in plane.iter().enumerate() {
            for (s, &count) in row.iter().enumerate() {
                let ok = match shape {
                    BoundShape::TauPlusSigma => t + s <= n,
                    BoundShape::TauAndSigma => true,
                };
                if ok {
                    total += count;
                }
            }
        }
    }
    total
}

#[test]
fn monomial_counts_match_the_generating_function() {
    for order in 1..=10u32 {
        for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
            let terms = monomials(&Bounds::for_order(shape, order));
            assert_eq!(
                terms.len(),
                generating_function_count(order as usize, shape),
                "order {order} {shape:?}"
            );
            assert!(terms.windows(2).all(|w| w[0] < w[1]), "sorted, distinct");
            for t in terms.iter().take(200) {
                assert_eq!(t.to_string().parse::<Term>().unwrap(), *t);
            }
        }
    }
    // Pure powers are a subset.
    let b = Bounds::for_order(BoundShape::TauPlusSigma, 4);
    let all = monomials(&b);
    assert!(theory_search::enumerate::pure_powers(&b)
        .iter()
        .all(|p| all.contains(p)));
}

fn axial_survivors(model: &Model) -> Vec<String> {
    let a = analyse_basis(model, Density::Lagrangian, 4, Basis::Monomials).unwrap();
    a.fields[0]
        .survivors
        .iter()
        .map(|t| t.to_string())
        .collect()
}

/// The narrower reading of KIN: on the transverse fields only, not on x and θ.
fn narrow_kin_text() -> String {
    let narrow = Model::larva_toml()
        .replace(
            "x = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
            "x = [\"OST\", \"TRAN\", \"REF\"]",
        )
        .replace(
            "theta = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
            "theta = [\"OST\", \"TRAN\", \"REF\"]",
        );
    assert_ne!(
        narrow,
        Model::larva_toml(),
        "the larva states KIN for x and θ"
    );
    narrow
}

fn with_axial_rule(code: &str) -> Model {
    let text = narrow_kin_text()
        .replace(
            "columns = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]",
            &format!("columns = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\", \"{code}\"]"),
        )
        .replacen(
            "x = [\"OST\", \"TRAN\", \"REF\"]",
            &format!("x = [\"OST\", \"TRAN\", \"REF\", \"{code}\"]"),
            1,
        );
    Model::from_toml(&text).unwrap()
}

#[test]
fn the_readings_of_kin_agree_on_table_1_and_differ_on_monomials() {
    let narrow = Model::from_toml(&narrow_kin_text()).unwrap();
    // The paper's reading (KIN for every field): x keeps the wave equation's two terms (Eq. 40–41).
    assert_eq!(axial_survivors(&Model::larva()), ["(∂t φ)²", "(∂s φ)²"]);
    assert_eq!(
        axial_survivors(&narrow),
        ["∂t φ·∂s φ", "(∂t φ)²", "(∂s φ)²"]
    );
    // Table 1 (pure powers) is the same under both: its rows' verdicts are the rules' own, and
    // its field columns mark the survivors (x admits more under the narrow reading, of higher
    // order, so it keeps the same two).
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a = analyse_basis(&Model::larva(), density, 4, Basis::Powers).unwrap();
        let b = analyse_basis(&narrow, density, 4, Basis::Powers).unwrap();
        for (f, g) in a.fields.iter().zip(&b.fields) {
            assert_eq!(f.survivors, g.survivors, "{}", f.field.id);
        }
    }
}

#[test]
fn the_gyroscopic_term_survives_without_parity_or_time_reversal() {
    let narrow = Model::from_toml(&narrow_kin_text()).unwrap();
    assert_eq!(
        axial_survivors(&narrow),
        ["∂t φ·∂s φ", "(∂t φ)²", "(∂s φ)²"]
    );
    for code in ["PAR", "TREV"] {
        assert_eq!(
            axial_survivors(&with_axial_rule(code)),
            ["(∂t φ)²", "(∂s φ)²"],
            "{code}"
        );
    }
    // It is the only thing the monomials add at this order: the transverse fields and the
    // Rayleigh densities keep the seed's survivors.
    let m = Model::larva();
    let l = analyse_basis(&m, Density::Lagrangian, 4, Basis::Monomials).unwrap();
    assert_eq!(
        l.fields[2]
            .survivors
            .iter()
            .map(|t| t.to_string())
            .collect::<Vec<_>>(),
        ["(∂t φ)²", "(∂ss φ)²"]
    );
    let r = analyse_basis(&m, Density::Rayleigh, 4, Basis::Monomials).unwrap();
    let rs: Vec<String> = r
        .fields
        .iter()
        .map(|f| {
            f.survivors
                .iter()
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    assert_eq!(rs, ["(∂ts φ)²", "(∂ts φ)²", "(∂tss φ)²", "(∂tss φ)²"]);
}

#[test]
fn the_gyroscopic_term_breaks_forward_backward_symmetry() {
    let narrow = Model::from_toml(&narrow_kin_text()).unwrap();
    let (eqs, _) = theory_search::equations::derive_basis(&narrow, 4, Basis::Monomials).unwrap();
    // −k ∂t∂s x: a first-order-in-time, odd-in-space term, absent under PAR or TREV.
    assert_eq!(
        eqs[0].text(),
        "∂t² x = c_x ∂s² x − k_x ∂t∂s x + 2 c'_x ∂t∂s² x"
    );
    let (eqs, _) =
        theory_search::equations::derive_basis(&with_axial_rule("PAR"), 4, Basis::Monomials)
            .unwrap();
    assert_eq!(eqs[0].text(), "∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x");
}

#[test]
fn the_candidate_guard_counts_exactly_and_refuses_absurd_orders() {
    use theory_search::enumerate::count_products;
    for order in 1..=8u32 {
        for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
            let b = Bounds::for_order(shape, order);
            assert_eq!(
                count_products(&b, 1),
                monomials(&b).len() as u128,
                "order {order}"
            );
        }
    }
    let err = analyse_basis(&Model::larva(), Density::Lagrangian, 20, Basis::Monomials)
        .unwrap_err()
        .to_string();
    assert!(err.contains("candidate monomials, more than"), "{err}");
    assert!(analyse_basis(&Model::larva(), Density::Rayleigh, 32, Basis::Monomials).is_err());
    assert!(analyse_basis(&Model::larva(), Density::Lagrangian, 12, Basis::Monomials).is_ok());
}
