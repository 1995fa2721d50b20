//! Active forces as a basis of a quotient. Two active monomials can add up to a variational
//! force: (∂s³y)² and ∂s²y·∂s⁴y are each active, yet E((∂s²y)³)/6 = 3(∂s³y)² + 3∂s²y·∂s⁴y…
//! is conservative, so they span one active direction, not two. Within one block of equal
//! (ε, τ, σ) the forces are reduced modulo the image of the Euler operator and of the Rayleigh
//! map δ/δv on the velocity jet's densities (exact rational elimination of Helmholtz residuals,
//! `reduce_block`): the forces that add a direction are kept in canonical order, and each other
//! one is written as a combination of those kept, modulo a variational or Rayleigh force.

use std::collections::BTreeMap;

use num_rational::{BigRational, Rational64};
use num_traits::{One, Zero};

use crate::jet::{euler_lagrange, poly_of, space_euler, JetMono, JetPoly};
use crate::term::{Deriv, Term};

/// An active monomial that adds no direction: the listed forces give it, up to a
/// variational or Rayleigh force.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Dependent {
    /// The term, in the field's symbol.
    pub term: String,
    /// Its combination of listed forces, in words.
    pub why: String,
}

/// The monomials of `degree` factors ∂tᵃ∂sᵇφ with Σa = `tau`, Σb = `sigma` (each a = 1 on the
/// velocity jet).
pub(super) fn jets(degree: u32, tau: u32, sigma: u32, velocity: bool) -> Vec<JetMono> {
    let derivs: Vec<Deriv> = (0..=tau)
        .flat_map(|a| (0..=sigma).map(move |b| Deriv::new(a, b)))
        .filter(|d| !velocity || d.t == 1)
        .collect();
    let mut out = Vec::new();
    let mut stack: JetMono = Vec::new();
    fn walk(derivs: &[Deriv], left: (u32, u32, u32), stack: &mut JetMono, out: &mut Vec<JetMono>) {
        let (n, t, s) = left;
        if n == 0 {
            if t == 0 && s == 0 {
                out.push(stack.clone());
            }
            return;
        }
        let Some((&d, rest)) = derivs.split_first() else {
            return;
        };
        for k in (0..=n).rev() {
            if d.t * k > t || d.s * k > s {
                continue;
            }
            if k > 0 {
                stack.push((d, k));
            }
            walk(rest, (n - k, t - d.t * k, s - d.s * k), stack, out);
            if k > 0 {
                stack.pop();
            }
        }
    }
    walk(&derivs, (degree, tau, sigma), &mut stack, &mut out);
    out
}

/// A jet polynomial in exact rationals of any size: eliminations at order 6 overflow i64.
type Poly = BTreeMap<JetMono, BigRational>;

pub(super) fn big(p: &JetPoly) -> Poly {
    p.iter()
        .map(|(m, v)| {
            let q = BigRational::new((*v.numer()).into(), (*v.denom()).into());
            (m.clone(), q)
        })
        .collect()
}

/// An echelon basis: each row's largest monomial is its pivot, with the row's combination of
/// kept forces (a row from a density has none).
#[derive(Default)]
pub(super) struct Echelon {
    rows: Vec<(Poly, Vec<BigRational>)>,
    pivots: BTreeMap<JetMono, usize>,
}

impl Echelon {
    /// `p` less the rows it reaches, and the combination of kept forces taken off.
    pub(super) fn reduce(&self, mut p: Poly, kept: usize) -> (Poly, Vec<BigRational>) {
        p.retain(|_, v| !v.is_zero());
        let mut combo = vec![BigRational::zero(); kept];
        while let Some((m, &r)) = p.keys().rev().find_map(|m| Some((m, self.pivots.get(m)?))) {
            let (row, rc) = &self.rows[r];
            let a = &p[m] / &row[m];
            for (k, v) in row {
                let e = p.entry(k.clone()).or_insert_with(BigRational::zero);
                *e -= &a * v;
                if e.is_zero() {
                    p.remove(k);
                }
            }
            for (c, v) in combo.iter_mut().zip(rc) {
                *c += &a * v;
            }
        }
        (p, combo)
    }

    pub(super) fn push(&mut self, mut p: Poly, combo: Vec<BigRational>) {
        p.retain(|_, v| !v.is_zero());
        if let Some(m) = p.keys().next_back().cloned() {
            self.pivots.insert(m, self.rows.len());
            self.rows.push((p, combo));
        }
    }
}

/// u·p/(ε + 1) for `p` of degree ε: the homotopy density of a homogeneous force.
pub(super) fn times(p: &JetPoly, u: Deriv, degree: u32) -> JetPoly {
    let w = Rational64::new(1, i64::from(degree) + 1);
    p.iter()
        .map(|(m, c)| {
            let mut m = m.clone();
            match m.iter_mut().find(|(d, _)| *d == u) {
                Some((_, n)) => *n += 1,
                None => {
                    m.push((u, 1));
                    m.sort();
                }
            }
            (m, c * w)
        })
        .collect()
}

/// E(φ·f)/(ε + 1) − f: zero exactly when the force `f` of degree ε is variational (the
/// homotopy formula on the jet space), and linear in f.
fn helmholtz(f: &JetPoly, degree: u32) -> Poly {
    let mut p = big(&euler_lagrange(&times(f, Deriv::new(0, 0), degree)));
    for (m, c) in big(f) {
        let e = p.entry(m).or_insert_with(BigRational::zero);
        *e -= c;
    }
    p
}

/// Which of `forces` (one block of equal orders, canonical order) are kept as a basis modulo
/// variational and Rayleigh forces, and why each other one is not (`name` renders a term).
/// A combination f = Σ cᵢfᵢ is variational iff its Helmholtz residual E(φf)/(ε+1) − f vanishes,
/// and that residual is linear: the dependent forces are the kernel of the residuals of the
/// block's forces and of its Rayleigh forces δR/δv (velocity densities of degree ε + 1, only
/// when τ = ε), so one Euler operator per force suffices instead of one per density.
pub(super) fn reduce_block(
    forces: &[Term],
    name: &dyn Fn(&Term) -> String,
) -> (Vec<usize>, Vec<Dependent>) {
    let Some(first) = forces.first() else {
        return (Vec::new(), Vec::new());
    };
    let o = first.orders();
    let one = |m: JetMono| JetPoly::from([(m, Rational64::from_integer(1))]);
    let mut basis = Echelon::default();
    if o.tau == o.epsilon {
        let rayleigh = jets(o.epsilon + 1, o.tau + 1, o.sigma, true)
            .into_iter()
            .filter_map(|m| space_euler(&one(m)).remove(&1));
        for p in rayleigh {
            let (r, _) = basis.reduce(helmholtz(&p, o.epsilon), 0);
            basis.push(r, Vec::new());
        }
    }
    let (mut kept, mut dependent) = (Vec::new(), Vec::new());
    for (i, t) in forces.iter().enumerate() {
        let (rest, combo) = basis.reduce(helmholtz(&poly_of(t), o.epsilon), kept.len());
        if rest.is_empty() {
            dependent.push(Dependent {
                term: name(t),
                why: words(&combo, &kept, forces, name),
            });
            continue;
        }
        let mut own: Vec<BigRational> = combo.iter().map(|c| -c).collect();
        own.push(BigRational::one());
        for row in &mut basis.rows {
            row.1.push(BigRational::zero());
        }
        kept.push(i);
        basis.push(rest, own);
    }
    (kept, dependent)
}

/// "= c₁ T₁ + c₂ T₂ + a variational or Rayleigh force".
fn words(
    combo: &[BigRational],
    kept: &[usize],
    forces: &[Term],
    name: &dyn Fn(&Term) -> String,
) -> String {
    let parts: Vec<String> = combo
        .iter()
        .zip(kept)
        .filter(|(c, _)| !c.is_zero())
        .map(|(c, &i)| format!("({c})·{}", name(&forces[i])))
        .collect();
    format!(
        "= {} + a variational or Rayleigh force: no direction of its own (its coefficient is theirs)",
        if parts.is_empty() { "0".to_string() } else { parts.join(" + ") }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jets_count_the_monomials_of_a_block() {
        // Degree 2, τ = 0, σ = 2: φ·∂s²φ, (∂sφ)².
        assert_eq!(jets(2, 0, 2, false).len(), 2);
        // Degree 2 on the velocity jet, σ = 1: ∂tφ·∂t∂sφ.
        assert_eq!(jets(2, 2, 1, true).len(), 1);
    }

    #[test]
    fn two_active_squares_of_one_variational_sum_are_one_direction() {
        let a: Term = "(∂sss φ)^2".parse().expect("term");
        let b: Term = "∂ss φ·∂ssss φ".parse().expect("term");
        let (kept, dependent) = reduce_block(&[a, b], &|t| format!("{t:?}"));
        assert_eq!(kept.len(), 1);
        assert_eq!(dependent.len(), 1);
    }
}
