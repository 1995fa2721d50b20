//! The jet algebra of one field: monomials and polynomials in its derivatives ∂tᵃ∂sᵇφ with
//! exact coefficients, total derivatives D_t and D_s by the product rule, and the Euler
//! operators, `E(L) = Σ_α (−D)^α ∂L/∂u_α` over the whole jet and `E_a` in s alone over each
//! time order. A term whose Euler–Lagrange expression vanishes identically is a total
//! derivative (a null Lagrangian) and changes no equation of motion; a Rayleigh term enters only
//! through δR/δ(∂tφ) over the velocity jet at fixed time, `E_1`.

use std::collections::BTreeMap;

use num_rational::Rational64;
use num_traits::Zero;

use crate::model::Density;
use crate::term::{Deriv, Factor, Term};

/// A monomial in the jet variables of one field (its derivatives), as a sorted list of
/// (derivative, power); empty is the constant 1. (The symmetry algebra of
/// [`crate::rules::Poly`] has its own monomials, over several fields, s, t and a parameter.)
pub type JetMono = Vec<(Deriv, u32)>;

/// A polynomial in the jet variables of one field, exact coefficients.
pub type JetPoly = BTreeMap<JetMono, Rational64>;

/// The monomial of a single-field term.
pub fn mono_of(term: &Term) -> JetMono {
    let mut m: JetMono = term.factors().iter().map(|f| (f.deriv, f.power)).collect();
    m.sort();
    m
}

/// The term of a non-empty monomial.
pub fn term_of(m: &JetMono) -> Option<Term> {
    Term::new(m.iter().map(|&(deriv, power)| Factor {
        field: 0,
        deriv,
        power,
    }))
    .ok()
}

pub(crate) fn add_to(p: &mut JetPoly, m: JetMono, c: Rational64) {
    let e = p.entry(m.clone()).or_insert_with(Rational64::zero);
    *e += c;
    if e.is_zero() {
        p.remove(&m);
    }
}

/// `m` with one factor `d` (power reduced by one) replaced by `replacement` (if any).
fn swap_factor(m: &JetMono, i: usize, replacement: Option<Deriv>) -> JetMono {
    let mut out: JetMono = Vec::with_capacity(m.len() + 1);
    for (j, &(d, n)) in m.iter().enumerate() {
        let n = if j == i { n - 1 } else { n };
        if n > 0 {
            out.push((d, n));
        }
    }
    if let Some(r) = replacement {
        match out.iter_mut().find(|(d, _)| *d == r) {
            Some(entry) => entry.1 += 1,
            None => out.push((r, 1)),
        }
        out.sort();
    }
    out
}

/// `D_t m` (time) or `D_s m` (space) by the product rule.
pub fn total_derivative(m: &JetMono, time: bool) -> JetPoly {
    let mut out = JetPoly::new();
    for (i, &(d, n)) in m.iter().enumerate() {
        let up = if time {
            Deriv::new(d.t + 1, d.s)
        } else {
            Deriv::new(d.t, d.s + 1)
        };
        add_to(
            &mut out,
            swap_factor(m, i, Some(up)),
            Rational64::from_integer(n as i64),
        );
    }
    out
}

pub(crate) fn derivative_of_poly(p: &JetPoly, time: bool) -> JetPoly {
    let mut out = JetPoly::new();
    for (m, c) in p {
        for (mm, cc) in total_derivative(m, time) {
            add_to(&mut out, mm, c * cc);
        }
    }
    out
}

/// The Euler–Lagrange expression `E(L) = Σ_α (−D_t)^a (−D_s)^b ∂L/∂u_(a,b)`.
pub fn euler_lagrange(l: &JetPoly) -> JetPoly {
    // ∂L/∂u_α for every α that occurs.
    let mut partials: BTreeMap<Deriv, JetPoly> = BTreeMap::new();
    for (m, c) in l {
        for (i, &(d, n)) in m.iter().enumerate() {
            add_to(
                partials.entry(d).or_default(),
                swap_factor(m, i, None),
                c * Rational64::from_integer(n as i64),
            );
        }
    }
    let mut out = JetPoly::new();
    for (d, mut p) in partials {
        for _ in 0..d.t {
            p = derivative_of_poly(&p, true);
        }
        for _ in 0..d.s {
            p = derivative_of_poly(&p, false);
        }
        let sign = if (d.t + d.s) % 2 == 0 { 1 } else { -1 };
        for (m, c) in p {
            add_to(&mut out, m, c * Rational64::from_integer(sign));
        }
    }
    out
}

/// The Euler operators in s alone, one per time order a, treating each wₐ = ∂tᵃφ as a field
/// of s: `E_a(P) = Σ_b (−D_s)^b ∂P/∂(∂sᵇ wₐ)`. P is a total s-derivative exactly when every
/// E_a(P) vanishes; a separate implementation from the reduction, for checking it.
pub fn space_euler(p: &JetPoly) -> BTreeMap<u32, JetPoly> {
    let mut partials: BTreeMap<Deriv, JetPoly> = BTreeMap::new();
    for (m, c) in p {
        for (i, &(d, n)) in m.iter().enumerate() {
            add_to(
                partials.entry(d).or_default(),
                swap_factor(m, i, None),
                c * Rational64::from_integer(n as i64),
            );
        }
    }
    let mut out: BTreeMap<u32, JetPoly> = BTreeMap::new();
    for (d, mut q) in partials {
        for _ in 0..d.s {
            q = derivative_of_poly(&q, false);
        }
        let sign = Rational64::from_integer(if d.s % 2 == 0 { 1 } else { -1 });
        let e = out.entry(d.t).or_default();
        for (m, c) in q {
            add_to(e, m, c * sign);
        }
    }
    out.retain(|_, q| !q.is_empty());
    out
}

/// The polynomial of one single-field term, coefficient 1.
pub fn poly_of(term: &Term) -> JetPoly {
    JetPoly::from([(mono_of(term), Rational64::from_integer(1))])
}

/// Whether `term` changes no equation of motion in `density`: a Lagrangian term whose
/// Euler–Lagrange expression vanishes identically (a total derivative), or a Rayleigh term whose
/// δR/δ(∂tφ) over the velocity jet at fixed time vanishes (a total s-derivative there, or no
/// dependence on the velocity at all).
pub fn is_null(density: Density, term: &Term) -> bool {
    let p = poly_of(term);
    match density {
        Density::Lagrangian => euler_lagrange(&p).is_empty(),
        Density::Rayleigh => !space_euler(&p).contains_key(&1),
    }
}
