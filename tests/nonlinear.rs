//! Equations for every survivor set: the exact nonlinear Euler–Lagrange path against an
//! independent oracle (the first variation of the action, computed exactly on polynomials over
//! the unit square with a bump that vanishes on its edges), and a sweep over the requirement
//! subsets of the larva's columns.

mod common;

use std::collections::BTreeMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
use theory_search::enumerate::Basis;
use theory_search::equations::{derive_basis, derive_nonlinear, EquationError};
use theory_search::model::{Density, Model};
use theory_search::reduce::analyse_basis;

type Q = BigRational;
/// A polynomial in (s, t, ε): exponents → coefficient.
type P = BTreeMap<(u32, u32, u32), Q>;

fn q(n: i64, d: i64) -> Q {
    Q::new(BigInt::from(n), BigInt::from(d))
}

fn mul(a: &P, b: &P) -> P {
    let mut out = P::new();
    for (ea, ca) in a {
        for (eb, cb) in b {
            let e = (ea.0 + eb.0, ea.1 + eb.1, ea.2 + eb.2);
            *out.entry(e).or_insert_with(Q::zero) += ca * cb;
        }
    }
    out.retain(|_, c| !c.is_zero());
    out
}

fn add(a: &mut P, b: &P, scale: &Q) {
    for (e, c) in b {
        *a.entry(*e).or_insert_with(Q::zero) += c * scale;
    }
    a.retain(|_, c| !c.is_zero());
}

/// ∂tᵃ∂sᵇ of a polynomial.
fn derive(p: &P, a: u32, b: u32) -> P {
    let mut out = P::new();
    for (&(s, t, e), c) in p {
        if s < b || t < a {
            continue;
        }
        let falling = |n: u32, k: u32| (0..k).map(|i| (n - i) as i64).product::<i64>();
        let v = c * q(falling(s, b) * falling(t, a), 1);
        *out.entry((s - b, t - a, e)).or_insert_with(Q::zero) += v;
    }
    out.retain(|_, c| !c.is_zero());
    out
}

/// ∫₀¹∫₀¹ ds dt, per power of ε.
fn integrate(p: &P) -> BTreeMap<u32, Q> {
    let mut out = BTreeMap::new();
    for (&(s, t, e), c) in p {
        *out.entry(e).or_insert_with(Q::zero) += c * q(1, (s as i64 + 1) * (t as i64 + 1));
    }
    out
}

/// A product of derivatives of `f`, as the jet monomial says.
fn evaluate(m: &[(theory_search::term::Deriv, u32)], f: &P) -> P {
    let mut out: P = [((0, 0, 0), Q::one())].into_iter().collect();
    for &(d, n) in m {
        let g = derive(f, d.t, d.s);
        for _ in 0..n {
            out = mul(&out, &g);
        }
    }
    out
}

/// The field φ(s, t) and the bump η = (s(1 − s)t(1 − t))⁴, which vanishes with its first three
/// derivatives on the edges, so no boundary term survives the integrations by parts.
fn field_and_bump() -> (P, P) {
    let phi: P = [
        ((1, 0, 0), q(1, 3)),
        ((2, 1, 0), q(-2, 5)),
        ((0, 2, 0), q(3, 7)),
        ((3, 0, 0), q(1, 2)),
        ((1, 1, 0), q(1, 1)),
    ]
    .into_iter()
    .collect();
    let s1: P = [((1, 0, 0), q(1, 1)), ((2, 0, 0), q(-1, 1))]
        .into_iter()
        .collect();
    let t1: P = [((0, 1, 0), q(1, 1)), ((0, 2, 0), q(-1, 1))]
        .into_iter()
        .collect();
    let mut bump = mul(&s1, &t1);
    let base = bump.clone();
    for _ in 0..3 {
        bump = mul(&bump, &base);
    }
    (phi, bump)
}

/// For a Lagrangian L of one field: d/dε ∫∫ L(φ + εη) at ε = 0 must equal ∫∫ E(L)(φ)·η.
fn variation_matches(
    l: &[(Vec<(theory_search::term::Deriv, u32)>, Q)],
    e: &[(Vec<(theory_search::term::Deriv, u32)>, Q)],
) -> bool {
    let (phi, bump) = field_and_bump();
    let mut moved = phi.clone();
    let eps_bump: P = bump
        .iter()
        .map(|(&(s, t, _), c)| ((s, t, 1), c.clone()))
        .collect();
    add(&mut moved, &eps_bump, &Q::one());
    let mut action = P::new();
    for (m, c) in l {
        // Only the ε¹ part is needed: drop higher powers as they appear.
        let mut v = evaluate(m, &moved);
        v.retain(|k, _| k.2 <= 1);
        add(&mut action, &v, c);
    }
    let first = integrate(&action).remove(&1).unwrap_or_else(Q::zero);
    let mut el = P::new();
    for (m, c) in e {
        add(&mut el, &evaluate(m, &phi), c);
    }
    let other = integrate(&mul(&el, &bump))
        .remove(&0)
        .unwrap_or_else(Q::zero);
    first == other
}

/// For a Rayleigh density R of the velocity jet: d/dε ∫∫ R with v = ∂tφ moved to v + εη(s)
/// must equal ∫∫ (δR/δv)·η, η = (s(1 − s))⁴ (at every t, so also integrated over t).
fn velocity_variation_matches(
    r: &[(Vec<(theory_search::term::Deriv, u32)>, Q)],
    e: &[(Vec<(theory_search::term::Deriv, u32)>, Q)],
) -> bool {
    let (phi, _) = field_and_bump();
    let s1: P = [((1, 0, 0), q(1, 1)), ((2, 0, 0), q(-1, 1))]
        .into_iter()
        .collect();
    let mut bump = s1.clone();
    for _ in 0..3 {
        bump = mul(&bump, &s1);
    }
    let eps_bump: P = bump
        .iter()
        .map(|(&(s, t, _), c)| ((s, t, 1), c.clone()))
        .collect();
    let mut total = P::new();
    for (m, c) in r {
        let mut v: P = [((0, 0, 0), Q::one())].into_iter().collect();
        for &(d, n) in m {
            let mut g = derive(&phi, d.t, d.s);
            if d.t == 1 {
                add(&mut g, &derive(&eps_bump, 0, d.s), &Q::one());
            }
            for _ in 0..n {
                v = mul(&v, &g);
                v.retain(|k, _| k.2 <= 1);
            }
        }
        add(&mut total, &v, c);
    }
    let first = integrate(&total).remove(&1).unwrap_or_else(Q::zero);
    let mut el = P::new();
    for (m, c) in e {
        add(&mut el, &evaluate(m, &phi), c);
    }
    first
        == integrate(&mul(&el, &bump))
            .remove(&0)
            .unwrap_or_else(Q::zero)
}

/// A density's terms as (jet monomial, signed exact coefficient), every parameter 1.
fn polynomial(
    density: &[theory_search::reduce::DensityTerm],
) -> Vec<(Vec<(theory_search::term::Deriv, u32)>, Q)> {
    density
        .iter()
        .map(|dt| {
            let c = q(*dt.prefactor.numer(), *dt.prefactor.denom()) * q(dt.sign, 1);
            (theory_search::parts::mono_of(&dt.term), c)
        })
        .collect()
}

fn mono(d: &[(u32, u32, u32)]) -> Vec<(theory_search::term::Deriv, u32)> {
    d.iter()
        .map(|&(t, s, n)| (theory_search::term::Deriv::new(t, s), n))
        .collect()
}

#[test]
fn the_oracle_sees_a_wrong_euler_lagrange_expression() {
    // L = (∂s φ)³: E = −D_s(3(∂s φ)²) = −6 ∂s φ·∂ss φ, and nothing else.
    let l = vec![(mono(&[(0, 1, 3)]), q(1, 1))];
    let right = vec![(mono(&[(0, 1, 1), (0, 2, 1)]), q(-6, 1))];
    let wrong = vec![(mono(&[(0, 1, 1), (0, 2, 1)]), q(6, 1))];
    assert!(variation_matches(&l, &right));
    assert!(!variation_matches(&l, &wrong));
}

/// The larva's Lagrangian requirements with only the codes in `keep` (per field the same).
fn with_requirements(lagrangian: &[&str]) -> Model {
    with_both(lagrangian, &["DIS", "TRAN", "GAL", "REF"])
}

/// The larva with these Lagrangian and Rayleigh requirements on every field.
fn with_both(lagrangian: &[&str], rayleigh: &[&str]) -> Model {
    let mut text = Model::larva_toml().to_string();
    let list = |codes: &[&str]| {
        codes
            .iter()
            .map(|c| format!("\"{c}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let lagrangian_lines = [
        "x = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
        "theta = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
        "y = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]",
        "z = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]",
    ];
    let rayleigh_lines = [
        "x = [\"DIS\", \"TRAN\", \"GAL\", \"REF\"]",
        "theta = [\"DIS\", \"TRAN\", \"GAL\", \"REF\"]",
        "y = [\"DIS\", \"TRAN\", \"GAL\", \"REF\", \"SPIN\"]",
        "z = [\"DIS\", \"TRAN\", \"GAL\", \"REF\", \"SPIN\"]",
    ];
    for (lines, codes) in [(lagrangian_lines, lagrangian), (rayleigh_lines, rayleigh)] {
        for line in lines {
            let field = line.split(' ').next().unwrap();
            assert!(text.contains(line), "{line}");
            text = text.replacen(line, &format!("{field} = [{}]", list(codes)), 1);
        }
    }
    Model::from_toml(&text).unwrap()
}

#[test]
fn every_requirement_subset_with_a_kinetic_term_has_equations() {
    let codes = ["OST", "TRAN", "REF", "KIN", "ROT"];
    let (mut derived, mut nonlinear, mut checked) = (0, 0, 0);
    for mask in 0..(1u32 << codes.len()) {
        let keep: Vec<&str> = (0..codes.len())
            .filter(|i| mask & (1 << i) != 0)
            .map(|i| codes[i])
            .collect();
        let model = with_requirements(&keep);
        let l = analyse_basis(&model, Density::Lagrangian, 4, Basis::Powers).unwrap();
        let kinetic = theory_search::term::Term::power(1, 0, 2);
        let has_kinetic = l.fields.iter().all(|f| f.survivors.contains(&kinetic));
        match derive_nonlinear(&model, 4, Basis::Powers) {
            Ok((eqs, _)) => {
                derived += 1;
                let linear = derive_basis(&model, 4, Basis::Powers);
                if matches!(linear, Err(EquationError::NotQuadratic { .. })) {
                    nonlinear += 1;
                }
                checked += checked_by_oracle(&l, &eqs, &format!("{keep:?}"));
            }
            Err(EquationError::NoKinetic { .. }) => {
                assert!(!has_kinetic, "{keep:?}: a kinetic term survives");
            }
            Err(other) => panic!("{keep:?}: {other}"),
        }
    }
    // No subset leaves a nonlinear survivor at order 4 now that total derivatives (the linear
    // ∂s φ of the REF-less subsets) never win; the tethered model checks the nonlinear path.
    assert!(
        derived >= 8 && nonlinear == 0 && checked >= 10,
        "{derived} {nonlinear} {checked}"
    );
}

/// Each field's equation against the oracle's variation of its own Lagrangian `l`, one
/// parameter at a time; how many (field, parameter) pairs were checked.
fn checked_by_oracle(
    l: &theory_search::reduce::Analysis,
    eqs: &[theory_search::equations::NonlinearEquation],
    what: &str,
) -> usize {
    eqs.iter()
        .enumerate()
        .map(|(i, e)| checked_by_oracle_field(l, i, e, what))
        .sum()
}

/// The shipped tethered filament has neither TRAN nor REF: its potential c₁u + … + c₄u⁴ keeps
/// the kinetic term only because kinetic and potential terms each keep their own lowest order
/// (`dominance = "by-part"`), and its cubic term reaches the equation as −(3/2)c₃u².
#[test]
fn the_tethered_model_has_its_cubic_term_in_its_equation() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml");
    let model = Model::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(
        model.density(Density::Lagrangian).dominance,
        theory_search::model::Dominance::ByPart
    );
    let l = analyse_basis(&model, Density::Lagrangian, 4, Basis::Powers).unwrap();
    let survivors: Vec<String> = l.fields[0]
        .survivors
        .iter()
        .map(|t| t.to_string())
        .collect();
    assert_eq!(survivors, ["(∂t φ)²", "φ", "φ²", "φ³", "φ⁴"]);
    assert!(matches!(
        derive_basis(&model, 4, Basis::Powers),
        Err(EquationError::NotQuadratic { .. })
    ));
    let (eqs, _) = derive_nonlinear(&model, 4, Basis::Powers).unwrap();
    let cubic = eqs[0]
        .rhs
        .iter()
        .find(|t| t.coefficient == "c3_u")
        .expect("the cubic term's force");
    assert_eq!(cubic.value, num_rational::Rational64::new(-3, 2));
    assert_eq!(
        cubic.monomial,
        vec![(theory_search::term::Deriv::new(0, 0), 2)]
    );
    assert_eq!(checked_by_oracle(&l, &eqs, "tethered"), 4);
    // Under the paper's joint dominance the constant-order potential outranks (∂t u)².
    let mut joint = model.clone();
    joint.lagrangian.dominance = theory_search::model::Dominance::Joint;
    assert!(matches!(
        derive_nonlinear(&joint, 4, Basis::Powers),
        Err(EquationError::NoKinetic { .. })
    ));
}

#[test]
fn quadratic_survivors_give_the_linear_equations() {
    for basis in [Basis::Powers, Basis::Monomials] {
        let model = Model::larva();
        let (lin, _) = derive_basis(&model, 4, basis).unwrap();
        let (non, _) = derive_nonlinear(&model, 4, basis).unwrap();
        assert_eq!(
            lin.len(),
            non.len(),
            "{basis:?}: one equation per field on both paths"
        );
        assert!(!lin.is_empty());
        for (a, b) in lin.iter().zip(&non) {
            let mut x: Vec<_> = a
                .rhs
                .iter()
                .map(|t| {
                    (
                        vec![(t.deriv, 1)],
                        t.prefactor * num_rational::Rational64::from_integer(t.sign),
                        t.coefficient.clone(),
                    )
                })
                .collect();
            let mut y: Vec<_> = b
                .rhs
                .iter()
                .map(|t| (t.monomial.clone(), t.value, t.coefficient.clone()))
                .collect();
            x.sort();
            y.sort();
            assert_eq!(x, y, "{} vs {}", a.text(), b.text());
        }
    }
}

#[test]
fn every_rayleigh_subset_gives_equations_that_vary_right() {
    let codes = ["DIS", "TRAN", "GAL", "REF", "SPIN"];
    let mut checked = 0;
    for mask in 0..(1u32 << codes.len()) {
        let keep: Vec<&str> = (0..codes.len())
            .filter(|i| mask & (1 << i) != 0)
            .map(|i| codes[i])
            .collect();
        let model = with_both(&["OST", "TRAN", "REF", "KIN", "ROT"], &keep);
        let r = analyse_basis(&model, Density::Rayleigh, 4, Basis::Powers).unwrap();
        let (eqs, _) =
            derive_nonlinear(&model, 4, Basis::Powers).unwrap_or_else(|e| panic!("{keep:?}: {e}"));
        for (i, e) in eqs.iter().enumerate() {
            // R enters through the velocity jet at fixed time whatever it holds.
            rayleigh_matches_oracle(&r, i, e, &format!("{keep:?}"));
            checked += 1;
        }
    }
    assert!(checked >= 32, "{checked}");
}

#[test]
fn the_command_falls_back_to_the_exact_equations() {
    // Without REF the linear ∂s x is admitted at the lowest order, but it is a total
    // derivative: it is passed over with a note, and the equations stay the larva's.
    let text = Model::larva_toml().replace(
        "x = [\"OST\", \"TRAN\", \"REF\", \"KIN\"]",
        "x = [\"OST\", \"TRAN\", \"KIN\"]",
    );
    let dir_held = common::scratch("nonlinear");
    let dir = dir_held.path();
    let path = dir.join("noref.toml");
    std::fs::write(&path, text).unwrap();
    for format in ["text", "json", "latex"] {
        let mut out = Vec::new();
        theory_search::cli::run(
            [
                "theory-search",
                "equations",
                "--model",
                path.to_str().unwrap(),
                "--format",
                format,
            ],
            &mut out,
        )
        .unwrap();
        let out = String::from_utf8(out).unwrap();
        match format {
            "text" => assert!(
                out.contains("∂s x changes no equation")
                    && out.contains("∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x"),
                "{out}"
            ),
            "json" => assert!(!out.contains("\"nonlinear\": true"), "{out}"),
            _ => assert!(out.contains("\\begin{align*}"), "{out}"),
        }
    }
    // A body whose survivors are not all quadratic takes the exact path in every format.
    let tethered = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml");
    for format in ["text", "json", "latex"] {
        let mut out = Vec::new();
        theory_search::cli::run(
            [
                "theory-search",
                "equations",
                "--model",
                tethered,
                "--format",
                format,
            ],
            &mut out,
        )
        .unwrap();
        let out = String::from_utf8(out).unwrap();
        match format {
            "text" => assert!(out.contains("3/2 c3_u u²"), "{out}"),
            "json" => assert!(out.contains("\"nonlinear\": true"), "{out}"),
            _ => assert!(out.contains("\\begin{align*}"), "{out}"),
        }
    }
}

/// The commands that still need a linear equation (operators, the behaviours) refuse the
/// tethered filament in one line with a usage exit code, naming the term they cannot discretise;
/// `modes` and `simulate` take it (`tests/nonlinear_dynamics.rs`).
#[test]
fn linear_commands_refuse_the_tethered_model_cleanly() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/tethered.toml");
    // (`operators` linearises it: tests/nonlinear_operators.rs.)
    let args: Vec<String> = ["theory-search", "behave", "rearing", "--model", path]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let err = theory_search::cli::run(args, &mut Vec::new()).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let text = err.to_string();
    assert!(
        text.contains("needs the exact modal theory") && !text.contains('\n'),
        "{text}"
    );
}

/// A deterministic generator (xorshift), so a failing model can be rebuilt.
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn subset<'a>(&mut self, codes: &[&'a str]) -> Vec<&'a str> {
        codes
            .iter()
            .copied()
            .filter(|_| self.next() % 2 == 0)
            .collect()
    }
}

/// A model of the fields `(id, lagrangian codes, rayleigh codes)`, free ends.
fn random_model(fields: &[(&str, Vec<&str>, Vec<&str>)], by_part: bool) -> Model {
    let list = |codes: &[&str]| {
        codes
            .iter()
            .map(|c| format!("\"{c}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut text = "name = \"random\"\ndescription = \"random requirements\"\n".to_string();
    for (id, _, _) in fields {
        text += &format!(
            "[[fields]]\nid = \"{id}\"\nsymbol = \"{id}\"\nmeaning = \"{id}\"\nboundary = \"free\"\n"
        );
    }
    text += "[lagrangian]\nbound = \"tau-plus-sigma\"\ncolumns = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]\n";
    if by_part {
        text += "dominance = \"by-part\"\n";
    }
    text += "[lagrangian.requirements]\n";
    for (id, l, _) in fields {
        text += &format!("{id} = [{}]\n", list(l));
    }
    text += "[rayleigh]\nbound = \"tau-and-sigma\"\ncolumns = [\"DIS\", \"TRAN\", \"GAL\", \"REF\", \"SPIN\"]\n[rayleigh.requirements]\n";
    for (id, _, r) in fields {
        text += &format!("{id} = [{}]\n", list(r));
    }
    Model::from_toml(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Random one- and two-field models (random requirement subsets, both dominances, both bases,
/// orders 4 and 6): every derived equation matches the oracle, L's parameters by the action's
/// variation and R's by the variation of the velocity alone; and a field's equation is the one
/// it has alone.
#[test]
fn random_models_give_the_oracles_equations_whatever_the_other_fields() {
    let lagrangian = ["OST", "TRAN", "REF", "KIN", "ROT"];
    let rayleigh = ["DIS", "TRAN", "GAL", "REF", "SPIN"];
    let mut draw = Draw(0x5eed_1234_abcd_0001);
    let (mut models, mut checked, mut compared) = (0, 0, 0);
    let mut combos = std::collections::BTreeSet::new();
    for case in 0..40 {
        let two = case % 2 == 1;
        let by_part = draw.next() % 2 == 0;
        let basis = if draw.next() % 3 == 0 {
            Basis::Monomials
        } else {
            Basis::Powers
        };
        let order = if draw.next() % 2 == 0 { 6 } else { 4 };
        combos.insert((basis == Basis::Monomials, order));
        // OST always: without it the Lagrangian is not of second order in time.
        let mut l_a = draw.subset(&lagrangian[1..]);
        l_a.insert(0, "OST");
        let r_a = draw.subset(&rayleigh);
        let mut fields = vec![("a", l_a.clone(), r_a.clone())];
        if two {
            let mut l_b = draw.subset(&lagrangian[1..]);
            l_b.insert(0, "OST");
            fields.push(("b", l_b, draw.subset(&rayleigh)));
        }
        let model = random_model(&fields, by_part);
        let alone = random_model(&fields[..1], by_part);
        let what = format!("case {case}: {fields:?} by-part {by_part} {basis:?} order {order}");
        let Ok(derived) = theory_search::equations::derive_nonlinear_each(&model, order, basis)
        else {
            continue;
        };
        models += 1;
        let l = analyse_basis(&model, Density::Lagrangian, order, basis).unwrap();
        let r = analyse_basis(&model, Density::Rayleigh, order, basis).unwrap();
        for e in &derived.equations {
            let i = model
                .fields
                .iter()
                .position(|f| f.id == e.field.id)
                .unwrap();
            // L's parameters, one at a time, against the action's first variation.
            checked += checked_by_oracle_field(&l, i, e, &what);
            // R's parameters together against the variation of the velocity alone.
            rayleigh_matches_oracle(&r, i, e, &what);
            checked += 1;
            // The field alone derives the same equation.
            if e.field.id == "a" {
                let solo = theory_search::equations::derive_nonlinear_each(&alone, order, basis)
                    .unwrap_or_else(|err| panic!("{what}: alone: {err}"));
                assert_eq!(solo.equations.len(), 1, "{what}");
                assert_eq!(solo.equations[0].text(), e.text(), "{what}");
                compared += 1;
            }
        }
    }
    assert!(
        models >= 20 && checked >= 40 && compared >= 10,
        "{models} {checked} {compared}"
    );
    // Both bases at both orders were drawn.
    assert_eq!(combos.len(), 4, "{combos:?}");
}

/// [`checked_by_oracle`] for one field's equation.
fn checked_by_oracle_field(
    l: &theory_search::reduce::Analysis,
    i: usize,
    e: &theory_search::equations::NonlinearEquation,
    what: &str,
) -> usize {
    let terms = polynomial(&l.fields[i].density);
    assert_eq!(
        terms.len(),
        l.fields[i].density.len(),
        "one polynomial per density term"
    );
    // Per parameter (set to 1 one at a time): the Lagrangian's part of the right-hand side is
    // E(L − ½(∂tφ)²), the kinetic part giving −∂t²φ.
    let params: std::collections::BTreeSet<String> =
        e.rhs.iter().map(|t| t.coefficient.clone()).collect();
    let mut checked = 0;
    for p in params.iter().filter(|p| !p.contains('\'')) {
        let own: Vec<_> = l.fields[i]
            .density
            .iter()
            .zip(&terms)
            .filter(|(dt, _)| dt.parameter.as_deref() == Some(p.as_str()))
            .map(|(_, t)| t.clone())
            .collect();
        let rhs: Vec<_> = e
            .rhs
            .iter()
            .filter(|t| &t.coefficient == p)
            .map(|t| (t.monomial.clone(), q(*t.value.numer(), *t.value.denom())))
            .collect();
        assert!(variation_matches(&own, &rhs), "{what}: {}: {p}", e.text());
        checked += 1;
    }
    checked
}

/// Field `i`'s R part of the right-hand side (the primed parameters' terms) is −δR/δv: checked
/// by the oracle, which moves v = ∂tφ alone and leaves every other factor as it is.
fn rayleigh_matches_oracle(
    r: &theory_search::reduce::Analysis,
    i: usize,
    e: &theory_search::equations::NonlinearEquation,
    what: &str,
) {
    let own = polynomial(&r.fields[i].density);
    let minus: Vec<_> = e
        .rhs
        .iter()
        .filter(|t| t.coefficient.contains('\''))
        .map(|t| (t.monomial.clone(), -q(*t.value.numer(), *t.value.denom())))
        .collect();
    assert!(
        velocity_variation_matches(&own, &minus),
        "{what}: {}",
        e.text()
    );
}
