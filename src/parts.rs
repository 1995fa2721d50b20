//! Reduction by parts: admitted terms that differ by a total derivative give the same physics.
//!
//! Total derivatives `D_t`, `D_s` act on monomials of a single field by the product rule and
//! preserve ε while raising τ or σ by one, so the work splits into blocks of fixed (ε, τ, σ). In
//! a block, T is the span of `D_t m` and `D_s m` over *every* monomial m of the blocks below
//! (invariant or not: L and L + D_tK are the same theory whatever K is). The admitted terms are
//! taken in canonical order and one is kept when it is independent of T and of the terms kept
//! before it; every dropped term is recorded as a relation `m ≡ Σ cᵢ kᵢ (mod total derivatives)`,
//! in exact rational arithmetic.
//!
//! Checks: [`euler_lagrange`] is a separate implementation of `E(L) = Σ_α (−D)^α ∂L/∂u_α`; a
//! relation is right exactly when E(m − Σ cᵢ kᵢ) = 0, so the reduced basis gives the same
//! equations of motion as the unreduced set. The number of independent shift-symmetric terms per
//! block also follows from a Hilbert-series count, `(1 − t)(1 − s)·H_V(t, s)`, which is exact for
//! ε ≥ 2 (the horizontal complex is exact there); at ε = 1 the class `D_t ∂sφ = D_s ∂tφ`, whose
//! primitive φ is not shift-symmetric, adds one term at (τ, σ) = (1, 1).

use std::collections::BTreeMap;

use num_rational::Rational64;
use num_traits::{One, Zero};

use crate::enumerate::Basis;
use crate::model::{Density, Model};
use crate::reduce::{analyse_basis, OrderError};
use crate::term::{Deriv, Orders, Term};

use crate::jet::add_to;
pub use crate::jet::{
    euler_lagrange, mono_of, space_euler, term_of, total_derivative, JetMono, JetPoly,
};

/// Every monomial of one field with the given (ε, τ, σ), optionally without the bare field.
pub fn block_monomials(epsilon: u32, tau: u32, sigma: u32, shift_symmetric: bool) -> Vec<JetMono> {
    let kinds: Vec<Deriv> = (0..=tau)
        .flat_map(|a| (0..=sigma).map(move |b| Deriv::new(a, b)))
        .filter(|d| !(shift_symmetric && d.order() == 0))
        .collect();
    let mut out = Vec::new();
    fn walk(
        kinds: &[Deriv],
        i: usize,
        left: (u32, u32, u32),
        cur: &mut JetMono,
        out: &mut Vec<JetMono>,
    ) {
        if left == (0, 0, 0) {
            out.push(cur.clone());
            return;
        }
        if i == kinds.len() || left.0 == 0 {
            return;
        }
        let d = kinds[i];
        let mut n = 0;
        while n * d.t <= left.1 && n * d.s <= left.2 && n <= left.0 {
            if n > 0 {
                cur.push((d, n));
            }
            walk(
                kinds,
                i + 1,
                (left.0 - n, left.1 - n * d.t, left.2 - n * d.s),
                cur,
                out,
            );
            if n > 0 {
                cur.pop();
            }
            n += 1;
        }
    }
    walk(&kinds, 0, (epsilon, tau, sigma), &mut Vec::new(), &mut out);
    for m in &mut out {
        m.sort();
    }
    out
}

/// Incremental row echelon form over the rationals, each row tagged with the combination of
/// kept terms it carries.
struct Echelon {
    /// (pivot monomial, row, tag over kept indices)
    rows: Vec<(JetMono, JetPoly, BTreeMap<usize, Rational64>)>,
}

impl Echelon {
    /// Reduce `v` (with tag) against the rows; returns the remainder and its tag.
    fn reduce(
        &self,
        mut v: JetPoly,
        mut tag: BTreeMap<usize, Rational64>,
    ) -> (JetPoly, BTreeMap<usize, Rational64>) {
        for (pivot, row, rtag) in &self.rows {
            if let Some(c) = v.get(pivot).copied() {
                let f = c / row[pivot];
                for (m, x) in row {
                    add_to(&mut v, m.clone(), -f * x);
                }
                for (k, x) in rtag {
                    let e = tag.entry(*k).or_insert_with(Rational64::zero);
                    *e -= f * x;
                    if e.is_zero() {
                        tag.remove(k);
                    }
                }
            }
        }
        (v, tag)
    }

    /// Add `v` if independent; true if it was.
    fn insert(&mut self, v: JetPoly, tag: BTreeMap<usize, Rational64>) -> bool {
        let (v, tag) = self.reduce(v, tag);
        match v.keys().next().cloned() {
            Some(pivot) => {
                self.rows.push((pivot, v, tag));
                true
            }
            None => false,
        }
    }
}

/// A dropped term: `term ≡ Σ coefficient·kept (mod total derivatives)`.
#[derive(Debug, Clone)]
pub struct Relation {
    /// The dropped term.
    pub term: Term,
    /// (coefficient, kept term) pairs; empty when the term is itself a total derivative.
    pub combination: Vec<(Rational64, Term)>,
}

/// The reduction of one block (ε, τ, σ).
#[derive(Debug, Clone)]
pub struct Block {
    /// The block's orders (δ unused).
    pub orders: Orders,
    /// Admitted terms in the block.
    pub admitted: Vec<Term>,
    /// The independent ones kept, canonical order.
    pub kept: Vec<Term>,
    /// How every dropped one reduces.
    pub relations: Vec<Relation>,
}

/// True when the generators of T may be taken shift-symmetric for these admitted terms.
fn restrict_to_shift_symmetric(admitted: &[Term]) -> bool {
    FULL_GENERATORS.with(|f| !f.get())
        && admitted
            .iter()
            .all(|t| t.factors().iter().all(|f| f.deriv.order() > 0))
}

thread_local! {
    /// Testing switch: always use the generators of every monomial.
    static FULL_GENERATORS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Reduce with T generated by every lower monomial, never restricting to shift-symmetric ones
/// (slower; for checking the restriction).
pub fn reduce_terms_full(terms: &[Term]) -> Vec<Block> {
    FULL_GENERATORS.with(|f| f.set(true));
    let out = reduce_terms(terms);
    FULL_GENERATORS.with(|f| f.set(false));
    out
}

/// Reduce `terms` (single-field, any set) modulo total derivatives, block by block.
pub fn reduce_terms(terms: &[Term]) -> Vec<Block> {
    reduce_in(terms, Density::Lagrangian)
}

/// Reduce `terms` as terms of `density`: a Lagrangian modulo total t- and s-derivatives; a
/// Rayleigh density modulo total s-derivatives only, because it enters through δR/δv at fixed
/// time (v = ∂tφ), which a total s-derivative leaves alone and a total t-derivative does not
/// (R = c·∂tφ is a constant force, not nothing).
pub fn reduce_in(terms: &[Term], density: Density) -> Vec<Block> {
    let with_time = density == Density::Lagrangian;
    let mut blocks: BTreeMap<(u32, u32, u32), Vec<Term>> = BTreeMap::new();
    for t in terms {
        let o = t.orders();
        blocks
            .entry((o.epsilon, o.tau, o.sigma))
            .or_default()
            .push(t.clone());
    }
    blocks
        .into_iter()
        .map(|((e, tau, sigma), mut admitted)| {
            admitted.sort();
            let mut ech = Echelon { rows: Vec::new() };
            // Total derivatives of the monomials of the blocks below. When no admitted term holds
            // the bare field and ε ≥ 2, the shift-symmetric ones span the same part of the
            // admitted space (exactness of the horizontal complex; `tests/parts.rs` compares
            // both). At ε = 1, ∂sφ = D_s φ needs the bare field.
            // The restriction rests on the exactness of the complex in both directions; with
            // s-derivatives alone every lower monomial is taken.
            let shift = with_time && e >= 2 && restrict_to_shift_symmetric(&admitted);
            let time_lower = tau.checked_sub(1).filter(|_| with_time);
            for (time, lower) in [
                (true, time_lower.map(|t| (t, sigma))),
                (false, sigma.checked_sub(1).map(|s| (tau, s))),
            ] {
                if let Some((t, s)) = lower {
                    for m in block_monomials(e, t, s, shift) {
                        ech.insert(total_derivative(&m, time), BTreeMap::new());
                    }
                }
            }
            let (mut kept, mut relations): (Vec<Term>, Vec<Relation>) = (Vec::new(), Vec::new());
            for t in &admitted {
                let v: JetPoly = [(mono_of(t), Rational64::one())].into_iter().collect();
                let tag: BTreeMap<usize, Rational64> =
                    [(kept.len(), Rational64::one())].into_iter().collect();
                let (rest, rtag) = ech.reduce(v.clone(), tag.clone());
                if rest.is_empty() {
                    // t − (−Σ rtag_k k) ∈ T, with rtag holding t's own index (coefficient 1).
                    let combination = rtag
                        .iter()
                        .filter(|(k, _)| **k != kept.len())
                        .map(|(k, c)| (-c, kept[*k].clone()))
                        .collect();
                    relations.push(Relation {
                        term: t.clone(),
                        combination,
                    });
                } else {
                    ech.insert(v, tag);
                    kept.push(t.clone());
                }
            }
            Block {
                orders: Orders {
                    delta: 0,
                    epsilon: e,
                    tau,
                    sigma,
                },
                admitted,
                kept,
                relations,
            }
        })
        .collect()
}

/// One field's reduction.
#[derive(Debug, Clone)]
pub struct FieldReduction {
    /// Field id.
    pub field: String,
    /// Blocks with admitted terms.
    pub blocks: Vec<Block>,
}

/// Reduce every field's admitted monomials of `density` at `order` modulo total derivatives.
pub fn reduce_model(
    model: &Model,
    density: Density,
    order: u32,
) -> Result<Vec<FieldReduction>, OrderError> {
    let a = analyse_basis(model, density, order, Basis::Monomials)?;
    Ok(a.fields
        .iter()
        .map(|f| FieldReduction {
            field: f.field.id.clone(),
            blocks: reduce_in(&f.admitted, density),
        })
        .collect())
}

/// The Hilbert-series count of independent shift-symmetric terms in block (ε, τ, σ):
/// `V(τ,σ) − V(τ−1,σ) − V(τ,σ−1) + V(τ−1,σ−1)`, plus the one ε = 1 class at (1, 1).
pub fn hilbert_count(epsilon: u32, tau: u32, sigma: u32) -> i64 {
    let v = |t: i64, s: i64| {
        if t < 0 || s < 0 {
            0
        } else {
            block_monomials(epsilon, t as u32, s as u32, true).len() as i64
        }
    };
    let (t, s) = (tau as i64, sigma as i64);
    let correction = i64::from(epsilon == 1 && tau == 1 && sigma == 1);
    v(t, s) - v(t - 1, s) - v(t, s - 1) + v(t - 1, s - 1) + correction
}

impl Relation {
    /// `m − Σ cᵢ kᵢ` as a polynomial (zero Euler–Lagrange expression if the relation is right).
    pub fn difference(&self) -> JetPoly {
        let mut p = JetPoly::new();
        add_to(&mut p, mono_of(&self.term), Rational64::one());
        for (c, k) in &self.combination {
            add_to(&mut p, mono_of(k), -c);
        }
        p
    }

    /// `term ≡ c₁ k₁ + …` in text.
    pub fn text(&self, symbol: &str) -> String {
        let r = |t: &Term| t.render(&|_| symbol.to_string());
        if self.combination.is_empty() {
            return format!("{} ≡ 0 (a total derivative)", r(&self.term));
        }
        let mut out = format!("{} ≡", r(&self.term));
        for (i, (c, k)) in self.combination.iter().enumerate() {
            let negative = *c < Rational64::zero();
            out += &crate::reduce::sign_joiner(i, negative, "−");
            let mag = if negative { -c } else { *c };
            if !mag.is_one() {
                out += &format!("{mag}·");
            }
            out += &r(k);
        }
        out
    }
}

/// The reduction as text: per field, the independent terms and the relations used.
pub fn text(model: &Model, density: Density, order: u32, fields: &[FieldReduction]) -> String {
    let mut out = format!(
        "{density} density of the {} model at order {order}: admitted monomials modulo total derivatives\n",
        model.name
    );
    for f in fields {
        let symbol = model.symbol(&f.field);
        let r = |t: &Term| t.render(&|_| symbol.clone());
        let admitted: usize = f.blocks.iter().map(|b| b.admitted.len()).sum();
        let mut kept: Vec<Term> = f.blocks.iter().flat_map(|b| b.kept.clone()).collect();
        kept.sort();
        out += &format!(
            "\n{} ({symbol}): {admitted} admitted, {} independent\n",
            f.field,
            kept.len()
        );
        let front = crate::reduce::lowest_order(&kept);
        out += &format!(
            "  lowest order: {}\n",
            front.iter().map(r).collect::<Vec<_>>().join(", ")
        );
        out += &format!(
            "  basis: {}\n",
            kept.iter().map(r).collect::<Vec<_>>().join(", ")
        );
        for b in &f.blocks {
            for rel in &b.relations {
                out += &format!("  {}\n", rel.text(&symbol));
            }
        }
    }
    out
}

/// `parts`: the reductions of one or both densities of a model, as one printable result.
pub struct PartsReport<'a> {
    /// The model.
    pub model: &'a Model,
    /// The order.
    pub order: u32,
    /// (density, each field's reduction) per density asked for.
    pub reductions: Vec<(Density, Vec<FieldReduction>)>,
}

impl<'a> PartsReport<'a> {
    /// The reductions of `densities` at `order`.
    pub fn new(
        model: &'a Model,
        densities: &[Density],
        order: u32,
    ) -> Result<PartsReport<'a>, OrderError> {
        crate::reduce::check_work(model, densities, order, Basis::Powers)?;
        let reductions = densities
            .iter()
            .map(|&d| Ok((d, reduce_model(model, d, order)?)))
            .collect::<Result<_, OrderError>>()?;
        Ok(PartsReport {
            model,
            order,
            reductions,
        })
    }

    /// One row per admitted term: density, field, term, whether it is kept, and what it
    /// reduces to (empty when kept).
    fn rows(&self) -> Vec<Vec<String>> {
        let mut rows = Vec::new();
        for (density, fields) in &self.reductions {
            for f in fields {
                let symbol = self.model.symbol(&f.field);
                let r = |t: &Term| t.render(&|_| symbol.clone());
                for b in &f.blocks {
                    for t in &b.kept {
                        rows.push(vec![
                            density.key().into(),
                            f.field.clone(),
                            r(t),
                            "true".into(),
                            String::new(),
                        ]);
                    }
                    for rel in &b.relations {
                        rows.push(vec![
                            density.key().into(),
                            f.field.clone(),
                            r(&rel.term),
                            "false".into(),
                            rel.text(&symbol),
                        ]);
                    }
                }
            }
        }
        rows
    }
}

impl crate::report::Report for PartsReport<'_> {
    fn text(&self) -> String {
        self.reductions
            .iter()
            .map(|(d, fields)| text(self.model, *d, self.order, fields) + "\n")
            .collect()
    }

    fn json(&self) -> serde_json::Value {
        use serde_json::json;
        let densities: Vec<_> = self
            .reductions
            .iter()
            .map(|(d, fields)| {
                let fields: Vec<_> = fields
                    .iter()
                    .map(|f| {
                        let symbol = self.model.symbol(&f.field);
                        let r = |t: &Term| t.render(&|_| symbol.clone());
                        let mut kept: Vec<Term> = f.blocks.iter().flat_map(|b| b.kept.clone()).collect();
                        kept.sort();
                        let relations: Vec<_> = f
                            .blocks
                            .iter()
                            .flat_map(|b| &b.relations)
                            .map(|rel| {
                                let combination: Vec<_> = rel
                                    .combination
                                    .iter()
                                    .map(|(c, t)| json!({"coefficient": c.to_string(), "term": r(t)}))
                                    .collect();
                                json!({"term": r(&rel.term), "combination": combination})
                            })
                            .collect();
                        json!({
                            "field": f.field,
                            "admitted": f.blocks.iter().map(|b| b.admitted.len()).sum::<usize>(),
                            "independent": kept.iter().map(r).collect::<Vec<_>>(),
                            "lowest_order": crate::reduce::lowest_order(&kept).iter().map(r).collect::<Vec<_>>(),
                            "relations": relations,
                        })
                    })
                    .collect();
                json!({"density": d.key(), "fields": fields})
            })
            .collect();
        json!({"model": self.model.name, "order": self.order, "densities": densities})
    }

    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["density", "field", "term", "independent", "reduces_to"],
            self.rows(),
        ))
    }
}
