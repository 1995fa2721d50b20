//! Candidate terms under explicit bounds on their orders.
//!
//! The paper's Table 1 holds every pure power `(∂tᵃ∂sᵇφ)ⁿ` with δ ≤ 4, ε ≤ 4 and τ+σ ≤ 4
//! (27 terms). `--order N` gives each density its [`Bounds`] from the model's [`BoundShape`];
//! the candidates come out in canonical [`Term`] order, each once.

use std::fmt;

use itertools::iproduct;
use serde::{Deserialize, Serialize};

use crate::term::{Deriv, Factor, Orders, Term};

/// How `--order N` bounds the candidate terms of a density.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundShape {
    /// δ ≤ N, ε ≤ N, τ+σ ≤ N (the paper's Table 1).
    TauPlusSigma,
    /// δ ≤ N, ε ≤ N, τ ≤ N, σ ≤ N.
    TauAndSigma,
}

/// The largest `--order` the tool accepts. Far beyond any physical use (the long-wavelength
/// survivors settle at order 4), it keeps every coefficient of the exact expansions within i64.
pub const MAX_ORDER: u32 = 32;

/// Upper bounds on the orders of a candidate term; `None` means unbounded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bounds {
    /// δ ≤ this.
    pub delta: u32,
    /// ε ≤ this.
    pub epsilon: u32,
    /// τ ≤ this.
    pub tau: Option<u32>,
    /// σ ≤ this.
    pub sigma: Option<u32>,
    /// τ + σ ≤ this.
    pub tau_plus_sigma: Option<u32>,
}

impl Bounds {
    /// The bounds that `--order order` means for a density of this shape.
    pub fn for_order(shape: BoundShape, order: u32) -> Bounds {
        let base = Bounds {
            delta: order,
            epsilon: order,
            tau: None,
            sigma: None,
            tau_plus_sigma: None,
        };
        match shape {
            BoundShape::TauPlusSigma => Bounds {
                tau_plus_sigma: Some(order),
                ..base
            },
            BoundShape::TauAndSigma => Bounds {
                tau: Some(order),
                sigma: Some(order),
                ..base
            },
        }
    }

    /// True if a term of these orders is within the bounds.
    pub fn admits(&self, o: &Orders) -> bool {
        let within = |bound: Option<u32>, v: u32| bound.is_none_or(|b| v <= b);
        o.delta <= self.delta
            && o.epsilon <= self.epsilon
            && within(self.tau, o.tau)
            && within(self.sigma, o.sigma)
            && within(self.tau_plus_sigma, o.tau + o.sigma)
    }
}

impl fmt::Display for Bounds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "δ ≤ {}, ε ≤ {}", self.delta, self.epsilon)?;
        for (name, bound) in [
            ("τ", self.tau),
            ("σ", self.sigma),
            ("τ+σ", self.tau_plus_sigma),
        ] {
            if let Some(b) = bound {
                write!(f, ", {name} ≤ {b}")?;
            }
        }
        Ok(())
    }
}

/// Every pure power `(∂tᵃ∂sᵇφ)ⁿ`, n ≥ 1, within `bounds`, in canonical order.
pub fn pure_powers(bounds: &Bounds) -> Vec<Term> {
    let d = bounds.delta;
    let mut terms: Vec<Term> = iproduct!(1..=bounds.epsilon, 0..=d, 0..=d)
        .filter(|&(_, a, b)| a + b <= d)
        .map(|(n, a, b)| Term::power(a, b, n))
        .filter(|t| bounds.admits(&t.orders()))
        .collect();
    terms.sort();
    terms
}

/// Which candidate terms to enumerate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Basis {
    /// Pure powers of one derivative, `(∂tᵃ∂sᵇφ)ⁿ`: the paper's Table 1.
    #[default]
    Powers,
    /// Every product of derivative factors of the field, e.g. `∂t φ·∂s φ`, `φ·∂ss φ`.
    Monomials,
}

/// The candidates of `basis` within `bounds`, canonical order.
pub fn candidates(basis: Basis, bounds: &Bounds) -> Vec<Term> {
    match basis {
        Basis::Powers => pure_powers(bounds),
        Basis::Monomials => monomials(bounds),
    }
}

/// The most candidates an analysis enumerates; beyond it the tool refuses rather than run for
/// minutes and gigabytes (the monomial basis grows roughly like N⁴·e^N).
pub const MAX_CANDIDATES: u128 = 1_000_000;

/// How many products of factors of `fields` placeholder fields lie within `bounds` (an upper
/// bound on the interaction candidates, which must involve every field), from the generating
/// function ∏ 1/(1 − x·u^a·v^b) over the factor kinds, without enumerating them.
pub fn count_products(bounds: &Bounds, fields: u32) -> u128 {
    let n = bounds.epsilon as usize;
    let cap = |b: Option<u32>| b.map_or(usize::MAX, |v| v as usize);
    let (tmax, smax, wmax) = (
        cap(bounds.tau),
        cap(bounds.sigma),
        cap(bounds.tau_plus_sigma),
    );
    // τ and σ of a product are at most ε·δ.
    let reach = (n * bounds.delta as usize).min(tmax.min(wmax));
    let sreach = (n * bounds.delta as usize).min(smax.min(wmax));
    let mut c = vec![vec![vec![0u128; sreach + 1]; reach + 1]; n + 1];
    c[0][0][0] = 1;
    for _ in 0..fields {
        for a in 0..=bounds.delta as usize {
            for b in 0..=(bounds.delta as usize - a) {
                for e in 1..=n {
                    for t in a..=reach {
                        for s in b..=sreach {
                            let add = c[e - 1][t - a][s - b];
                            c[e][t][s] = c[e][t][s].saturating_add(add);
                        }
                    }
                }
            }
        }
    }
    let mut total: u128 = 0;
    for plane in c.iter().skip(1) {
        for (t, row) in plane.iter().enumerate() {
            for (s, &count) in row.iter().enumerate() {
                if t + s <= wmax {
                    total = total.saturating_add(count);
                }
            }
        }
    }
    total
}

/// Every product `∏ (∂tᵃ∂sᵇφ)^{n_ab}` (single field, total power ≥ 1) within `bounds`, in
/// canonical order.
pub fn monomials(bounds: &Bounds) -> Vec<Term> {
    products(bounds, &[0])
}

/// Every product over the placeholder fields φ₁ … φ_k that involves all k of them, within
/// `bounds`: the candidates of a k-field interaction density.
pub fn interaction_monomials(bounds: &Bounds, k: u8) -> Vec<Term> {
    let fields: Vec<u8> = (1..=k).collect();
    products(bounds, &fields)
        .into_iter()
        .filter(|t| t.fields().len() == k as usize)
        .collect()
}

/// Every product of derivative factors of the placeholder `fields` within `bounds`, in
/// canonical order without a comparison sort: the walk yields each (δ, ε) class already in
/// factor-lexicographic order, and a stable bucketing by (δ, ε) puts the classes in order.
fn products(bounds: &Bounds, fields: &[u8]) -> Vec<Term> {
    let mut found = Vec::new();
    walk(
        &kinds(bounds, fields),
        0,
        &mut Vec::new(),
        ZERO,
        bounds,
        &mut |o, prefix| found.push((*o, Term::from_canonical(prefix.to_vec()))),
    );
    // Stable counting sort by (δ, ε).
    let width = bounds.epsilon as usize + 1;
    let key = |o: &Orders| o.delta as usize * width + o.epsilon as usize;
    let mut starts = vec![0usize; (bounds.delta as usize + 1) * width + 1];
    for (o, _) in &found {
        starts[key(o) + 1] += 1;
    }
    for i in 1..starts.len() {
        starts[i] += starts[i - 1];
    }
    let mut slots: Vec<Option<Term>> = vec![None; found.len()];
    for (o, t) in found {
        let k = key(&o);
        slots[starts[k]] = Some(t);
        starts[k] += 1;
    }
    slots.into_iter().flatten().collect()
}

const ZERO: Orders = Orders {
    delta: 0,
    epsilon: 0,
    tau: 0,
    sigma: 0,
};

/// The factor kinds of a walk, in the order a canonical term lists its factors (by field, then
/// derivative order), with where each one's field ends.
struct Kinds {
    list: Vec<Factor>,
    /// The index of the first kind of the next field.
    next_field: Vec<usize>,
}

/// The factor kinds of `fields` within `bounds`.
fn kinds(bounds: &Bounds, fields: &[u8]) -> Kinds {
    let d = bounds.delta;
    let mut list: Vec<Factor> = iproduct!(fields.iter().copied(), 0..=d, 0..=d)
        .filter(|&(_, a, b)| a + b <= d)
        .map(|(field, a, b)| Factor {
            field,
            deriv: Deriv::new(a, b),
            power: 1,
        })
        .collect();
    list.sort();
    let next_field = (0..list.len())
        .map(|j| {
            (j..list.len())
                .find(|&k| list[k].field != list[j].field)
                .unwrap_or(list.len())
        })
        .collect();
    Kinds { list, next_field }
}

/// The single-field products of [`monomials`], in the same canonical order, handed to `f` one at
/// a time: for tables too large to hold as terms. They are kept compactly while the walk runs
/// (4 bytes a factor, bucketed by (δ, ε)), then built and handed out bucket by bucket.
pub fn for_each_monomial(bounds: &Bounds, f: &mut dyn FnMut(Term)) {
    let width = bounds.epsilon as usize + 1;
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); (bounds.delta as usize + 1) * width];
    walk(
        &kinds(bounds, &[0]),
        0,
        &mut Vec::new(),
        ZERO,
        bounds,
        &mut |o, prefix| {
            let bucket = &mut buckets[o.delta as usize * width + o.epsilon as usize];
            bucket.push(prefix.len() as u32);
            // Orders are at most MAX_ORDER = 32, so each part fits a byte.
            bucket.extend(
                prefix
                    .iter()
                    .map(|p| p.deriv.t << 16 | p.deriv.s << 8 | p.power),
            );
        },
    );
    for bucket in buckets {
        let mut rest = bucket.as_slice();
        while let Some((&n, tail)) = rest.split_first() {
            let (packed, next) = tail.split_at(n as usize);
            let factors = packed
                .iter()
                .map(|&p| Factor {
                    field: 0,
                    deriv: Deriv::new(p >> 16, p >> 8 & 0xff),
                    power: p & 0xff,
                })
                .collect();
            f(Term::from_canonical(factors));
            rest = next;
        }
    }
}

/// Depth-first in factor-lexicographic order: a prefix comes before its extensions, and the
/// extensions by kind j and power n follow in (j, n) order, which is exactly how canonical
/// terms compare factor by factor. Prunes as soon as a product is out of bounds (every order
/// only grows as factors are added).
fn walk(
    kinds: &Kinds,
    from: usize,
    prefix: &mut Vec<Factor>,
    orders: Orders,
    bounds: &Bounds,
    emit: &mut dyn FnMut(&Orders, &[Factor]),
) {
    if !prefix.is_empty() {
        emit(&orders, prefix);
    }
    if orders.epsilon >= bounds.epsilon {
        // No factor fits any more: the many leaves at full power end here.
        return;
    }
    // The highest derivative order one more factor may have within the τ, σ budgets.
    let left = |bound: Option<u32>, used: u32| bound.map_or(u32::MAX, |b| b.saturating_sub(used));
    let room = left(bounds.tau_plus_sigma, orders.tau + orders.sigma)
        .min(left(bounds.tau, orders.tau).saturating_add(left(bounds.sigma, orders.sigma)));
    let mut j = from;
    while let Some(kind) = kinds.list.get(j) {
        if kind.deriv.order() > room {
            // A field's kinds go up in order: none of this field's later kinds fits either.
            j = kinds.next_field[j];
            continue;
        }
        let (a, b) = (kind.deriv.t, kind.deriv.s);
        for n in 1.. {
            let o = Orders {
                delta: orders.delta.max(a + b),
                epsilon: orders.epsilon + n,
                tau: orders.tau + n * a,
                sigma: orders.sigma + n * b,
            };
            if !bounds.admits(&o) {
                break;
            }
            prefix.push(Factor { power: n, ..*kind });
            walk(kinds, j + 1, prefix, o, bounds, emit);
            prefix.pop();
        }
        j += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streamed_monomials_are_the_monomials_in_order() {
        for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
            for order in 1..=6 {
                let bounds = Bounds::for_order(shape, order);
                let mut streamed = Vec::new();
                for_each_monomial(&bounds, &mut |t| streamed.push(t));
                assert_eq!(streamed, monomials(&bounds), "{shape:?} {order}");
            }
        }
    }

    #[test]
    fn table_one_has_27_rows() {
        let b = Bounds::for_order(BoundShape::TauPlusSigma, 4);
        assert_eq!(b.to_string(), "δ ≤ 4, ε ≤ 4, τ+σ ≤ 4");
        assert_eq!(pure_powers(&b).len(), 27);
    }

    #[test]
    fn rayleigh_bound_holds_eq_64() {
        let b = Bounds::for_order(BoundShape::TauAndSigma, 4);
        let terms = pure_powers(&b);
        for t in ["(∂ts φ)²", "(∂ts φ)⁴", "(∂tss φ)²"] {
            assert!(terms.contains(&t.parse().unwrap()), "{t}");
        }
    }
}
