//! One derivation path: terms that change no equation never win the selection, the Rayleigh
//! density enters through the velocity jet at fixed time on both paths, a field's equation
//! does not depend on the other fields, and a field without an equation does not block the rest.

mod common;

use num_rational::Rational64;
use theory_search::enumerate::Basis;
use theory_search::equations::{
    derive_each, derive_nonlinear_each, variational_derivative, Linear,
};
use theory_search::jet::{is_null, poly_of, space_euler};
use theory_search::model::{Density, Model};
use theory_search::reduce::{analyse_basis, lowest_order, DensityTerm};
use theory_search::term::{Deriv, Factor, Term};

const SHIPPED: [&str; 6] = [
    "larva",
    "worm",
    "planar",
    "zebrafish",
    "channel_worm",
    "tethered",
];

fn shipped(name: &str) -> Model {
    let path = format!("{}/tables/models/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Model::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// One field: `lagrangian` and `rayleigh` requirement lists, free ends.
fn one_field(lagrangian: &str, rayleigh: &str, extra: &str) -> Model {
    Model::from_toml(&format!(
        r#"
name = "probe"
description = "a probe"
[[fields]]
id = "a"
symbol = "a"
meaning = "a field"
boundary = "free"
{extra}
[lagrangian]
bound = "tau-plus-sigma"
columns = ["OST", "TRAN", "REF", "KIN", "GAL"]
[lagrangian.requirements]
a = [{lagrangian}]
{}
[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS", "TRAN", "REF"]
[rayleigh.requirements]
a = [{rayleigh}]
{}
"#,
        if extra.is_empty() {
            ""
        } else {
            "b = [\"OST\", \"TRAN\"]"
        },
        if extra.is_empty() {
            ""
        } else {
            "b = [\"DIS\", \"TRAN\"]"
        },
    ))
    .unwrap()
}

#[test]
fn shipped_survivors_hold_no_null_term_and_are_what_the_plain_front_gives() {
    let mut fields = 0;
    for name in SHIPPED {
        let model = shipped(name);
        for order in [4, 6] {
            for density in Density::ALL {
                let a = analyse_basis(&model, density, order, Basis::Powers).unwrap();
                assert_eq!(a.fields.len(), model.fields.len());
                for f in &a.fields {
                    assert!(f.survivors.iter().all(|t| !is_null(density, t)), "{name}");
                    // The front of every admitted term holds no null term either: the rule
                    // changed nothing for the shipped bodies (Table 1 included).
                    let plain = lowest_order(&f.admitted);
                    assert!(plain.iter().all(|t| !is_null(density, t)), "{name} {order}");
                    fields += 1;
                }
            }
        }
    }
    assert!(fields >= 40, "{fields}");
}

#[test]
fn total_derivatives_give_way_to_the_next_terms() {
    // OST and TRAN only: ∂t a and ∂s a are admitted and of lowest order, but null.
    let model = one_field("\"OST\", \"TRAN\"", "\"TRAN\"", "");
    let l = analyse_basis(&model, Density::Lagrangian, 4, Basis::Powers).unwrap();
    let survivors: Vec<String> = l.fields[0]
        .survivors
        .iter()
        .map(|t| t.to_string())
        .collect();
    assert!(survivors.contains(&"(∂t φ)²".to_string()), "{survivors:?}");
    assert!(survivors.contains(&"(∂s φ)²".to_string()), "{survivors:?}");
    assert!(
        l.fields[0].missing.iter().any(|n| n.contains("∂t a, ∂s a")),
        "{:?}",
        l.fields[0].missing
    );
    let r = analyse_basis(&model, Density::Rayleigh, 4, Basis::Powers).unwrap();
    assert!(!r.fields[0].survivors.is_empty());
    assert!(r.fields[0]
        .survivors
        .iter()
        .all(|t| !is_null(Density::Rayleigh, t)));
    // Null terms, exactly: total derivatives and velocity-free Rayleigh terms.
    let t = |s: &str| s.parse::<Term>().unwrap();
    assert!(is_null(Density::Lagrangian, &t("∂t φ")));
    assert!(is_null(Density::Lagrangian, &t("∂s φ·∂ss φ")));
    assert!(!is_null(Density::Lagrangian, &t("(∂ss φ)²")));
    assert!(is_null(Density::Rayleigh, &t("(∂ss φ)²")));
    assert!(is_null(Density::Rayleigh, &t("∂ts φ")));
    assert!(!is_null(Density::Rayleigh, &t("∂t φ")));
    assert!(!is_null(Density::Rayleigh, &t("(∂tss φ)²")));
}

#[test]
fn the_linear_path_takes_r_through_the_velocity_jet_as_the_general_one() {
    let mut compared = 0;
    let kinds: Vec<Deriv> = (0..=2)
        .flat_map(|t| (0..=3).map(move |s| Deriv::new(t, s)))
        .collect();
    for (i, &a) in kinds.iter().enumerate() {
        for &b in &kinds[i..] {
            let term = Term::new([a, b].map(|deriv| Factor {
                field: 0,
                deriv,
                power: 1,
            }))
            .unwrap();
            let dt = DensityTerm {
                term: term.clone(),
                sign: 1,
                prefactor: Rational64::from_integer(1),
                parameter: Some("c".into()),
            };
            let mut linear = Linear::new();
            assert!(variational_derivative(Density::Rayleigh, &dt, &mut linear));
            linear.retain(|_, v| *v != Rational64::from_integer(0));
            // The general path: E₁(R), the Euler operator in s of the velocity v = ∂tφ.
            let general = space_euler(&poly_of(&term)).remove(&1).unwrap_or_default();
            let general: Vec<(Deriv, Rational64)> = general
                .into_iter()
                .map(|(m, v)| {
                    assert_eq!(m.len(), 1, "{term}: linear in φ");
                    assert_eq!(m[0].1, 1, "{term}");
                    (m[0].0, v)
                })
                .collect();
            let linear: Vec<(Deriv, Rational64)> =
                linear.into_iter().map(|((d, _), v)| (d, v)).collect();
            assert_eq!(linear, general, "{term}");
            compared += 1;
        }
    }
    assert_eq!(compared, kinds.len() * (kinds.len() + 1) / 2);
}

#[test]
fn a_fields_equation_does_not_depend_on_the_other_fields() {
    let req = ("\"OST\", \"TRAN\", \"REF\"", "\"DIS\", \"TRAN\", \"REF\"");
    let alone = one_field(req.0, req.1, "");
    let with_b = one_field(
        req.0,
        req.1,
        "[[fields]]\nid = \"b\"\nsymbol = \"b\"\nmeaning = \"b\"\nboundary = \"free\"\n",
    );
    for order in [4, 6] {
        // Alone, a's equation is linear; beside b (whose R holds a linear force, so the
        // model takes the general path) it comes from the general derivation: the same.
        let a = derive_each(&alone, order, Basis::Powers).unwrap();
        assert_eq!(a.equations.len(), 1);
        let linear: Vec<(Deriv, Rational64, String)> = a.equations[0]
            .rhs
            .iter()
            .map(|t| {
                (
                    t.deriv,
                    t.prefactor * Rational64::from_integer(t.sign),
                    t.coefficient.clone(),
                )
            })
            .collect();
        let b = derive_nonlinear_each(&with_b, order, Basis::Powers).unwrap();
        let general: Vec<(Deriv, Rational64, String)> = b.equations[0]
            .rhs
            .iter()
            .map(|t| {
                assert_eq!(t.monomial.len(), 1);
                (t.monomial[0].0, t.value, t.coefficient.clone())
            })
            .collect();
        let sorted = |mut v: Vec<(Deriv, Rational64, String)>| {
            v.sort();
            v
        };
        assert!(!linear.is_empty());
        assert_eq!(sorted(linear), sorted(general), "order {order}");
    }
}

#[test]
fn a_field_without_an_equation_does_not_block_the_others() {
    let dir_held = common::scratch("derivation");
    let dir = dir_held.path();
    let path = dir.join("two.toml");
    let text = r#"
name = "two"
description = "two fields"
[[fields]]
id = "a"
symbol = "a"
meaning = "a"
boundary = "free"
[[fields]]
id = "b"
symbol = "b"
meaning = "b"
boundary = "free"
[lagrangian]
bound = "tau-plus-sigma"
columns = ["OST", "TRAN", "REF", "GAL"]
[lagrangian.requirements]
a = ["OST", "TRAN", "REF"]
b = ["OST", "TRAN", "REF", "GAL"]
[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS", "TRAN", "REF"]
[rayleigh.requirements]
a = ["DIS", "TRAN", "REF"]
b = ["DIS", "TRAN", "REF"]
"#;
    std::fs::write(&path, text).unwrap();
    let mut out = Vec::new();
    let err = theory_search::cli::run(
        [
            "theory-search",
            "equations",
            "--model",
            path.to_str().unwrap(),
        ],
        &mut out,
    )
    .unwrap_err();
    let printed = String::from_utf8(out).unwrap();
    assert!(printed.contains("∂t² a ="), "{printed}");
    assert!(
        printed.contains("note: field b: no kinetic term"),
        "{printed}"
    );
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("1 of the 2 fields"), "{err}");
    // Dominance means nothing for a one-part Rayleigh density: refused in one line.
    let refused = text.replace("[rayleigh]\n", "[rayleigh]\ndominance = \"by-part\"\n");
    let e = Model::from_toml(&refused).unwrap_err().to_string();
    assert!(e.contains("[rayleigh] dominance"), "{e}");
}
