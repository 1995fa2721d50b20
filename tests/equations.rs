//! Scenario: equations of motion from the survivors, checked term by term against variational
//! derivatives worked out by hand (including term shapes the larva does not use).

use num_rational::Rational64;
use theory_search::equations::{derive, json, variational_derivative, Linear};
use theory_search::model::{Density, Model};
use theory_search::reduce::DensityTerm;

fn r(n: i64) -> Rational64 {
    Rational64::from_integer(n)
}

/// `sign · prefactor · c · term`.
fn dt(term: &str, sign: i64, prefactor: Rational64, param: Option<&str>) -> DensityTerm {
    DensityTerm {
        term: term.parse().unwrap(),
        sign,
        prefactor,
        parameter: param.map(String::from),
    }
}

fn derivative(density: Density, term: DensityTerm) -> Vec<(u32, u32, Rational64)> {
    let mut out = Linear::new();
    assert!(variational_derivative(density, &term, &mut out));
    out.into_iter().map(|((d, _), v)| (d.t, d.s, v)).collect()
}

/// (density, term, sign, prefactor, expected Σ value·∂tᵗ∂sˢφ as (t, s, value)).
type Case = (Density, &'static str, i64, Rational64, Vec<(u32, u32, i64)>);

#[test]
fn variational_derivatives_match_hand_calculations() {
    let half = Rational64::new(1, 2);
    let c = Some("c");
    use Density::{Lagrangian as L, Rayleigh as R};
    // (density, term, sign, prefactor, expected Σ value·∂ᵗˢφ), each worked out by hand from
    // δF/δu = Σ (−1)^|α| ∂^α ∂F/∂(∂^α u).
    let cases: Vec<Case> = vec![
        // ½(∂tφ)²: ∂L/∂φt = φt, −∂t φt.
        (L, "(∂t φ)²", 1, half, vec![(2, 0, -1)]),
        // −½c(∂sφ)²: ∂L/∂φs = −cφs, −∂s(−cφs) = cφss.
        (L, "(∂s φ)²", -1, half, vec![(0, 2, 1)]),
        // −½c(∂ssφ)²: +∂s²(−cφss) = −cφssss.
        (L, "(∂ss φ)²", -1, half, vec![(0, 4, -1)]),
        // −½c(∂sssφ)²: −∂s³(−cφsss) = +cφ₆ₛ.
        (L, "(∂sss φ)²", -1, half, vec![(0, 6, 1)]),
        // −½c(∂ssssφ)²: +∂s⁴(−cφ₄ₛ) = −cφ₈ₛ.
        (L, "(∂ssss φ)²", -1, half, vec![(0, 8, -1)]),
        // ½k(∂tsφ)² (Rayleigh's rotary inertia): +∂t∂s(kφts) = kφttss.
        (L, "(∂ts φ)²", 1, half, vec![(2, 2, 1)]),
        // cφtφs: −∂t(cφs) − ∂s(cφt) = −2cφts.
        (L, "∂t φ·∂s φ", 1, r(1), vec![(1, 1, -2)]),
        // cφφss: cφss + ∂s²(cφ) = 2cφss.
        (L, "φ·∂ss φ", 1, r(1), vec![(0, 2, 2)]),
        // Rayleigh terms, in v = ∂tφ:
        // c'(∂tφ)² = c'v²: 2c'v.
        (R, "(∂t φ)²", 1, r(1), vec![(1, 0, 2)]),
        // c'(∂tsφ)² = c'vs²: −∂s(2c'vs) = −2c'φtss.
        (R, "(∂ts φ)²", 1, r(1), vec![(1, 2, -2)]),
        // c'(∂tssφ)²: +∂s²(2c'vss) = 2c'φt₄ₛ.
        (R, "(∂tss φ)²", 1, r(1), vec![(1, 4, 2)]),
        // c'(∂tsssφ)²: −∂s³(2c'vsss) = −2c'φt₆ₛ.
        (R, "(∂tsss φ)²", 1, r(1), vec![(1, 6, -2)]),
        // c'·v·φs: only v varies: c'φs.
        (R, "∂t φ·∂s φ", 1, r(1), vec![(0, 1, 1)]),
    ];
    for (density, term, sign, pre, want) in cases {
        let got = derivative(density, dt(term, sign, pre, c));
        let want: Vec<(u32, u32, Rational64)> =
            want.into_iter().map(|(t, s, v)| (t, s, r(v))).collect();
        assert_eq!(got, want, "{density} {term}");
    }
}

#[test]
fn potential_terms_give_stable_equations_at_every_order() {
    // −½c(∂sᵏφ)² must give ∂t²φ = ±c ∂s²ᵏφ whose Fourier symbol ±c(ik)²ᵏ is negative.
    for k in 1..=8u32 {
        let got = derivative(
            Density::Lagrangian,
            dt(
                &format!("(∂s^{k} φ)²"),
                -1,
                Rational64::new(1, 2),
                Some("c"),
            ),
        );
        assert_eq!(got.len(), 1);
        let (t, s, v) = got[0];
        assert_eq!((t, s), (0, 2 * k));
        // δL/δφ = v·∂s²ᵏφ + (−∂t²φ) = 0 ⇒ ∂t²φ = v·∂s²ᵏφ; symbol v·(−1)ᵏ k²ᵏ.
        let symbol_sign = if k % 2 == 0 { v } else { -v };
        assert!(symbol_sign < r(0), "k = {k}: {v}");
        // Likewise the Kelvin damping −δR/δv must be dissipative: symbol of −(δR/δv) < 0.
        let got = derivative(
            Density::Rayleigh,
            dt(&format!("(∂ts^{k} φ)²"), 1, r(1), Some("c'")),
        );
        let (_, s, v) = got[0];
        assert_eq!(s, 2 * k);
        let symbol = if k % 2 == 0 { v } else { -v };
        assert!(symbol > r(0), "R, k = {k}");
    }
}

/// (t, s, sign, coefficient, prefactor).
type Rhs = (u32, u32, i64, String, String);

#[test]
fn larva_gives_wave_and_beam_equations_with_kelvin_damping() {
    let (eqs, notes) = derive(&Model::larva(), 4).unwrap();
    assert!(notes.is_empty());
    let rows: Vec<Vec<Rhs>> = eqs
        .iter()
        .map(|e| {
            e.rhs
                .iter()
                .map(|t| {
                    (
                        t.deriv.t,
                        t.deriv.s,
                        t.sign,
                        t.coefficient.clone(),
                        t.prefactor.to_string(),
                    )
                })
                .collect()
        })
        .collect();
    let row = |s: u32, sign: i64, sym: &str| {
        vec![
            (0, s, sign, format!("c_{sym}"), "1".to_string()),
            (1, s, sign, format!("c'_{sym}"), "2".to_string()),
        ]
    };
    assert_eq!(
        rows,
        [
            row(2, 1, "x"),
            row(2, 1, "θ"),
            row(4, -1, "y"),
            row(4, -1, "z")
        ]
    );
    assert_eq!(eqs[0].text(), "∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x");
    assert_eq!(eqs[2].text(), "∂t² y = −c_y ∂s⁴ y − 2 c'_y ∂t∂s⁴ y");
    for order in 5..=10 {
        let (more, _) = derive(&Model::larva(), order).unwrap();
        assert_eq!(
            more.iter().map(|e| e.text()).collect::<Vec<_>>(),
            eqs.iter().map(|e| e.text()).collect::<Vec<_>>()
        );
    }
}

#[test]
fn json_contract() {
    let (eqs, notes) = derive(&Model::larva(), 4).unwrap();
    let v = json(4, &eqs, &notes);
    assert_eq!(v["equations"][0]["field"], "x");
    assert_eq!(
        v["equations"][0]["rhs"][0],
        serde_json::json!({"t": 0, "s": 2, "sign": 1, "coefficient": "c_x", "prefactor": "1",
            "claim": {"sign": "positive",
                      "reason": "the energy must be bounded below, ω² > 0 as q → 0 and as q → ∞"},
            "kind": "conservative"})
    );
    assert_eq!(v["equations"][0]["rhs"][1]["kind"], "dissipative");
    assert_eq!(v["equations"][0]["rhs"][1]["coefficient"], "c'_x");
    assert_eq!(v["equations"][1]["field"], "theta");
    assert_eq!(v["equations"][2]["rhs"][0]["sign"], -1);
    assert_eq!(v["equations"][2]["rhs"][0]["s"], 4);
}

#[test]
fn low_orders_drop_missing_terms_and_say_so() {
    let (eqs, notes) = derive(&Model::larva(), 3).unwrap();
    assert_eq!(eqs[2].text(), "∂t² y = 0");
    assert!(notes.iter().any(|n| n.contains("L_y: no potential term")));
    // At order 1 nothing kinetic survives: there is no ∂t²φ to solve for.
    let err = derive(&Model::larva(), 1).unwrap_err().to_string();
    assert!(err.contains("no kinetic term"), "{err}");
}

#[test]
fn sign_claims_are_derived_with_their_reasons() {
    use theory_search::enumerate::Basis;
    use theory_search::equations::{derive_basis, SignClaim};
    // KIN read narrowly (not on x) lets the gyroscopic ∂t x·∂s x survive, with k_x.
    let narrow = Model::larva_toml().replace(
        "x = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
        "x = [\"OST\", \"TRAN\", \"REF\"]",
    );
    let (eqs, _) = derive_basis(&Model::from_toml(&narrow).unwrap(), 4, Basis::Monomials).unwrap();
    let model = Model::larva();
    let x = &eqs[0];
    let claim = |name: &str| {
        x.rhs
            .iter()
            .find(|t| t.coefficient == name)
            .unwrap_or_else(|| panic!("{name} in {}", x.text()))
            .claim
    };
    assert!(matches!(claim("c_x"), SignClaim::Positive(r) if r.contains("energy")));
    assert!(matches!(claim("c'_x"), SignClaim::Positive(r) if r.contains("dissipation")));
    assert!(matches!(claim("k_x"), SignClaim::Free(r) if r.contains("s → −s")));
    // Independently: every claimed-positive stiffness gives ω² > 0 at small and large q, every
    // damping a decaying mode, for each field of the powers basis at orders 2, 4 and 6.
    for order in [2, 4, 6] {
        let (eqs, _) = derive_basis(&model, order, Basis::Powers).unwrap();
        for e in &eqs {
            for t in &e.rhs {
                if let SignClaim::Positive(_) = t.claim {
                    // c·∂sᵇ with c > 0 adds sign·(i q)ᵇ c to −ω²: its share of ω² is
                    // −sign·iᵇ, which must be positive for b even.
                    let i_b = if (t.deriv.s / 2) % 2 == 0 { 1 } else { -1 };
                    assert!(-t.sign * i_b > 0, "{}: {:?}", e.text(), t);
                }
            }
        }
    }
}

/// Every right-hand-side term of every shipped model, linear or not, at orders 4 and 6, says
/// what kind of force it is, and the kind agrees with time reversal, checked independently of
/// where the engine took it from: these models' L and R are even under t → −t, so E(L) has an
/// even number of time derivatives in every monomial and δR/δv an odd one; a term that the
/// model without its `[active]` section does not have is active.
#[test]
fn every_rhs_term_says_its_kind() {
    use theory_search::enumerate::Basis;
    use theory_search::equations::{derive_nonlinear_each, ForceKind};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/models");
    let mut seen = std::collections::BTreeSet::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let model = Model::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
        for order in [4, 6] {
            let Ok(d) = derive_nonlinear_each(&model, order, Basis::Powers) else {
                continue;
            };
            // The same model without its `[active]` section: every term it lacks is active.
            let mut passive = model.clone();
            passive.active = None;
            let without = derive_nonlinear_each(&passive, order, Basis::Powers).unwrap();
            for (e, p) in d.equations.iter().zip(&without.equations) {
                for t in &e.rhs {
                    let times: u32 = t.monomial.iter().map(|(d, n)| d.t * n).sum();
                    // The section's forces: a linear ∂tᵃ∂sᵇ is variational (gyroscopic,
                    // conservative) exactly when a + b is even; a nonlinear one is active here.
                    let variational = match t.monomial.as_slice() {
                        [(d, 1)] => (d.t + d.s) % 2 == 0,
                        _ => t.kind == ForceKind::Conservative && times % 2 == 1,
                    };
                    let want = if !p.rhs.contains(t) {
                        match variational {
                            true => ForceKind::Conservative,
                            false => ForceKind::Active,
                        }
                    } else if times % 2 == 1 {
                        ForceKind::Dissipative
                    } else {
                        ForceKind::Conservative
                    };
                    assert_eq!(t.kind, want, "{}: {} {:?}", path.display(), e.text(), t);
                    seen.insert(format!("{:?}", t.kind));
                }
            }
        }
    }
    assert_eq!(seen.len(), 3, "{seen:?}");
}

#[test]
fn no_force_enters_an_equation_twice_in_either_basis() {
    use theory_search::enumerate::Basis;
    // The crawler's gyroscopic ∂t∂s x is also E(∂tx·∂sx) when the Lagrangian keeps monomials;
    // without REF (a TRAN-only axial field) more of the active forces are the densities' own.
    let crawler = include_str!("../tables/models/crawler.toml");
    let tran_only = crawler
        .replace(
            "x = [\"OST\", \"TRAN\", \"REF\"]",
            "x = [\"OST\", \"TRAN\"]",
        )
        .replace(
            "x = [\"DIS\", \"TRAN\", \"GAL\", \"REF\"]",
            "x = [\"DIS\", \"TRAN\", \"GAL\"]",
        )
        .replace(
            "x = [\"OST\", \"TRAN\", \"REF\", \"GAL\"]",
            "x = [\"OST\", \"TRAN\"]",
        );
    assert_ne!(tran_only, crawler);
    let mut merged = 0;
    for text in [crawler.to_string(), tran_only] {
        let model = Model::from_toml(&text).expect("model");
        for basis in [Basis::Powers, Basis::Monomials] {
            let (equations, notes) =
                theory_search::equations::derive_basis(&model, 4, basis).expect("equations");
            for e in &equations {
                let mut derivs: Vec<_> = e.rhs.iter().map(|t| (t.deriv.t, t.deriv.s)).collect();
                let all = derivs.len();
                derivs.sort();
                derivs.dedup();
                assert_eq!(
                    derivs.len(),
                    all,
                    "{basis:?}, field {}: {:?}",
                    e.field.id,
                    e.rhs
                );
            }
            merged += notes.iter().filter(|n| n.contains("enters once")).count();
        }
    }
    // The crawler's monomial basis and the TRAN-only field each merged at least one force.
    assert!(merged >= 2, "{merged}");
}
