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
    // Each multiset once: the next factor's derivative is one of `derivs` (in order), taken k ≥ 1
    // times (most first), so no branch walks through the derivatives it does not take.
    fn walk(derivs: &[Deriv], left: (u32, u32, u32), stack: &mut JetMono, out: &mut Vec<JetMono>) {
        let (n, t, s) = left;
        if n == 0 {
            if t == 0 && s == 0 {
                out.push(stack.clone());
            }
            return;
        }
        for (j, &d) in derivs.iter().enumerate() {
            // Past φ itself every factor takes a derivative: n of them need n ≤ t + s.
            if (d.t, d.s) != (0, 0) && n > t + s {
                return;
            }
            for k in (1..=n).rev() {
                if d.t * k > t || d.s * k > s {
                    continue;
                }
                stack.push((d, k));
                walk(
                    &derivs[j + 1..],
                    (n - k, t - d.t * k, s - d.s * k),
                    stack,
                    out,
                );
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

/// 2⁶¹ − 1, a prime: a rank modulo it is the rational rank unless it divides a minor of the
/// residuals (whose entries are small rationals), so the count of dependent forces is exact
/// but for that chance.
const P: u64 = (1 << 61) - 1;

fn mul(a: u64, b: u64) -> u64 {
    ((u128::from(a) * u128::from(b)) % u128::from(P)) as u64
}

fn inverse(a: u64) -> u64 {
    let (mut base, mut e, mut out) = (a, P - 2, 1);
    while e > 0 {
        if e & 1 == 1 {
            out = mul(out, base);
        }
        base = mul(base, base);
        e >>= 1;
    }
    out
}

fn residue(q: &Rational64) -> u64 {
    let m = |v: i64| v.rem_euclid(P as i64) as u64;
    mul(m(*q.numer()), inverse(m(*q.denom())))
}

/// A sparse row modulo [`P`], its monomials by number ([`Columns`]).
type Row = BTreeMap<u32, u64>;

/// Monomials numbered as first seen: any fixed order of the columns gives the same rank.
#[derive(Default)]
struct Columns(std::collections::HashMap<JetMono, u32>);

impl Columns {
    /// The Helmholtz residual ([`helmholtz`]) modulo [`P`].
    fn helmholtz(&mut self, f: &JetPoly, degree: u32) -> Row {
        let mut p = Row::new();
        let image = euler_lagrange(&times(f, Deriv::new(0, 0), degree));
        let terms = image.iter().map(|(m, c)| (m, residue(c)));
        for (m, c) in terms.chain(f.iter().map(|(m, c)| (m, (P - residue(c)) % P))) {
            let n = self.0.len() as u32;
            let id = *self.0.entry(m.clone()).or_insert(n);
            let e = p.entry(id).or_insert(0);
            *e = (*e + c) % P;
        }
        p.retain(|_, v| *v != 0);
        p
    }
}

/// Which of `forces` (one block, canonical order) add no direction, as [`reduce_block`]
/// decides it, by sparse elimination modulo [`P`]: machine words where the exact
/// elimination's rationals grow (a loose `[active]` section's blocks at order 6, 688 forces,
/// took minutes). The exact elimination is kept for the blocks whose forces are listed,
/// which need the combinations.
pub(super) fn dependent_modulo_prime(forces: &[Term]) -> Vec<usize> {
    let Some(first) = forces.first() else {
        return Vec::new();
    };
    let o = first.orders();
    let mut columns = Columns::default();
    let mut rows: Vec<Row> = Vec::new();
    let mut pivots: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
    // Reduced by the rows (each row's pivot is its largest column, 1 there; so the scan for
    // the next pivot goes on below the last), then pushed when anything is left: is it new?
    let mut push = |mut p: Row| -> bool {
        let mut below = u32::MAX;
        loop {
            let next = p
                .range(..=below)
                .rev()
                .find_map(|(m, _)| Some((*m, *pivots.get(m)?)));
            let Some((m, r)) = next else { break };
            let a = p[&m];
            for (k, v) in &rows[r] {
                let e = p.entry(*k).or_insert(0);
                *e = (*e + P - mul(a, *v)) % P;
                if *e == 0 {
                    p.remove(k);
                }
            }
            match m.checked_sub(1) {
                Some(b) => below = b,
                None => break,
            }
        }
        let Some((&m, &lead)) = p.iter().next_back() else {
            return false;
        };
        let scale = inverse(lead);
        p.values_mut().for_each(|v| *v = mul(*v, scale));
        pivots.insert(m, rows.len());
        rows.push(p);
        true
    };
    if o.tau == o.epsilon {
        let one = |m: JetMono| JetPoly::from([(m, Rational64::from_integer(1))]);
        for m in jets(o.epsilon + 1, o.tau + 1, o.sigma, true) {
            if let Some(p) = space_euler(&one(m)).remove(&1) {
                push(columns.helmholtz(&p, o.epsilon));
            }
        }
    }
    (0..forces.len())
        .filter(|&i| !push(columns.helmholtz(&poly_of(&forces[i]), o.epsilon)))
        .collect()
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
