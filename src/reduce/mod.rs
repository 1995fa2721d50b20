//! Decide every candidate against every rule, and keep each field's lowest-order admitted terms.
//!
//! A field *admits* a term that passes all the rules the model requires of that field. Of the
//! admitted terms it keeps those on the Pareto front in (τ, σ): no other admitted term has
//! τ′ ≤ τ and σ′ ≤ σ with one of them strict. These survivors dominate at long length and time
//! scales. The survivors become a density with free coefficients, written the paper's way:
//! `L_x = ½(∂t x)² − ½ c_x (∂s x)²`, `R_x = c'_x (∂ts x)²`.

use num_rational::Rational64;
use num_traits::One;

use crate::enumerate::{candidates, count_products, Basis, Bounds, MAX_CANDIDATES, MAX_ORDER};
use crate::jet::is_null;
use crate::model::{Density, Dominance, Field, Model};
use crate::rules::{PreparedRule, Rule};
use crate::term::{Orders, Term};

mod budget;
mod render;
mod stream;
pub use budget::{check_candidates, check_work, check_work_within, OrderError};
pub use render::{prefactor_text, sign_joiner};
pub use stream::{analyse_streamed, for_each_row, MAX_STREAMED};

/// How many orders past the requested one a missing part is looked for on the monomial basis.
const MONOMIAL_LOOK_AHEAD: u32 = 4;

/// One candidate term with its verdicts.
#[derive(Debug, Clone)]
pub struct Row {
    /// The candidate.
    pub term: Term,
    /// Its orders.
    pub orders: Orders,
    /// Per column of the density, in column order: does the term satisfy the rule?
    pub passed: Marks,
    /// Per field (model order): does the field admit the term?
    pub admitted: Marks,
    /// Per field (model order): is the term one of the field's survivors?
    pub included: Marks,
}

/// A short row of yes/no marks (rule columns or fields, at most 64), one word instead of a
/// vector per candidate: the tables hold 10⁵ rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Marks {
    bits: u64,
    len: u8,
}

impl Marks {
    /// At most 64 marks.
    pub const MAX: usize = 64;

    /// How many marks.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// True when there are no marks.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The marks in order.
    pub fn iter(&self) -> impl Iterator<Item = bool> + use<> {
        let Marks { bits, len } = *self;
        (0..len).map(move |i| bits >> i & 1 == 1)
    }
}

impl FromIterator<bool> for Marks {
    /// The marks in order (those past [`Marks::MAX`] are dropped; models and the registry stay
    /// far below it).
    fn from_iter<I: IntoIterator<Item = bool>>(values: I) -> Marks {
        let mut m = Marks::default();
        for v in values.into_iter().take(Self::MAX) {
            m.bits |= (v as u64) << m.len;
            m.len += 1;
        }
        m
    }
}

impl std::ops::Index<usize> for Marks {
    type Output = bool;

    fn index(&self, i: usize) -> &bool {
        assert!(i < self.len(), "mark {i} of {}", self.len);
        if self.bits >> i & 1 == 1 {
            &true
        } else {
            &false
        }
    }
}

/// A term of a surviving density with its coefficient `sign · prefactor · parameter`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DensityTerm {
    /// The term.
    pub term: Term,
    /// +1 or −1.
    pub sign: i64,
    /// Exact positive rational prefactor (½ for Lagrangian terms).
    pub prefactor: Rational64,
    /// Name of the free positive coefficient, or `None` for the fixed kinetic term.
    pub parameter: Option<String>,
}

/// What one field keeps.
#[derive(Debug, Clone)]
pub struct FieldResult {
    /// The field.
    pub field: Field,
    /// Admitted terms, canonical order.
    pub admitted: Vec<Term>,
    /// Survivors (the Pareto front in (τ, σ)), canonical order (by part, kinetic first, under
    /// [`Dominance::ByPart`]).
    pub survivors: Vec<Term>,
    /// The surviving density with its coefficients.
    pub density: Vec<DensityTerm>,
    /// What is missing at this order, said plainly (empty if nothing is).
    pub missing: Vec<String>,
}

/// The full analysis of one density at one order.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// Which density.
    pub density: Density,
    /// The requested order.
    pub order: u32,
    /// The candidate bounds that order means here.
    pub bounds: Bounds,
    /// Which candidates were enumerated.
    pub basis: Basis,
    /// The rules shown as columns.
    pub columns: Vec<&'static Rule>,
    /// Every candidate, canonical order; empty for a streamed analysis ([`analyse_streamed`]),
    /// whose rows [`for_each_row`] decides again as they are written.
    pub rows: Vec<Row>,
    /// How many candidates (`rows.len()` when they are held).
    pub candidates: usize,
    /// One result per field, model order.
    pub fields: Vec<FieldResult>,
}

/// True if `u` is of lower order than `t`: τ′ ≤ τ, σ′ ≤ σ, one strictly.
pub fn dominates(u: &Orders, t: &Orders) -> bool {
    u.tau <= t.tau && u.sigma <= t.sigma && (u.tau < t.tau || u.sigma < t.sigma)
}

/// The terms of `terms` that no other term dominates, in the given order. O(n log n): over the
/// distinct (τ, σ) in ascending order, a group's least σ is on the front exactly when it is
/// below every σ seen at smaller τ; the group's other σ are dominated by it.
pub fn lowest_order(terms: &[Term]) -> Vec<Term> {
    let orders: Vec<(u32, u32)> = terms
        .iter()
        .map(|t| {
            let o = t.orders();
            (o.tau, o.sigma)
        })
        .collect();
    let mut distinct = orders.clone();
    distinct.sort_unstable();
    distinct.dedup();
    let mut front = std::collections::HashSet::new();
    let mut best = u32::MAX;
    let mut last_tau = None;
    for &(tau, sigma) in &distinct {
        if last_tau == Some(tau) {
            continue;
        }
        last_tau = Some(tau);
        if sigma < best {
            front.insert((tau, sigma));
            best = sigma;
        }
    }
    terms
        .iter()
        .zip(&orders)
        .filter(|(_, o)| front.contains(o))
        .map(|(t, _)| t.clone())
        .collect()
}

/// The rules of a density prepared once for an order (their images of the factor kinds), with
/// each field's requirements as a mask over the columns: what deciding a candidate needs.
struct Decider {
    columns: Vec<&'static Rule>,
    prepared: Vec<PreparedRule>,
    masks: Vec<u64>,
}

impl Decider {
    fn new(model: &Model, density: Density, bounds: &Bounds) -> Decider {
        let columns = model.columns(density);
        let prepared = columns.iter().map(|r| r.prepare(bounds.delta)).collect();
        let masks = model
            .fields
            .iter()
            .map(|f| {
                let req = model.requirements(density, &f.id);
                Marks::from_iter(columns.iter().map(|c| req.iter().any(|r| r.code == c.code))).bits
            })
            .collect();
        Decider {
            columns,
            prepared,
            masks,
        }
    }

    /// The row of `term`: its verdicts and which fields admit it.
    fn row(&self, term: Term) -> Row {
        let passed = Marks::from_iter(self.prepared.iter().map(|r| r.passes(&term)));
        let admitted = Marks::from_iter(self.masks.iter().map(|&m| passed.bits & m == m));
        Row {
            orders: term.orders(),
            term,
            passed,
            admitted,
            included: Marks::default(),
        }
    }
}

/// Candidates, verdicts and admission per field, without reduction.
fn decide(
    model: &Model,
    density: Density,
    bounds: &Bounds,
    basis: Basis,
) -> (Vec<&'static Rule>, Vec<Row>) {
    let decider = Decider::new(model, density, bounds);
    let rows = candidates(basis, bounds)
        .into_iter()
        .map(|term| decider.row(term))
        .collect();
    (decider.columns, rows)
}

/// Enumerate, decide and reduce `density` of `model` at `order`, on pure powers (Table 1).
pub fn analyse(model: &Model, density: Density, order: u32) -> Result<Analysis, OrderError> {
    analyse_basis(model, density, order, Basis::Powers)
}

/// Enumerate `basis`, decide and reduce `density` of `model` at `order`.
pub fn analyse_basis(
    model: &Model,
    density: Density,
    order: u32,
    basis: Basis,
) -> Result<Analysis, OrderError> {
    check_work(model, &[density], order, basis)?;
    let bounds = Bounds::for_order(model.density(density).bound, order);
    let (columns, mut rows) = decide(model, density, &bounds, basis);
    let admitted = (0..model.fields.len())
        .map(|i| {
            rows.iter()
                .filter(|r| r.admitted[i])
                .map(|r| r.term.clone())
                .collect()
        })
        .collect();
    let fields = field_results(model, density, order, basis, admitted);
    for row in &mut rows {
        row.included = Marks::from_iter(
            (0..fields.len()).map(|i| row.admitted[i] && fields[i].survivors.contains(&row.term)),
        );
    }
    Ok(Analysis {
        density,
        order,
        bounds,
        basis,
        columns,
        candidates: rows.len(),
        rows,
        fields,
    })
}

/// Each field's survivors, density and missing parts from the terms it admits.
fn field_results(
    model: &Model,
    density: Density,
    order: u32,
    basis: Basis,
    admitted: Vec<Vec<Term>>,
) -> Vec<FieldResult> {
    model
        .fields
        .iter()
        .zip(admitted)
        .enumerate()
        .map(|(i, (field, admitted))| {
            // Terms that change no equation (total derivatives, or R terms without velocity
            // dependence) never win the selection: the next admitted terms do.
            let live: Vec<Term> = admitted
                .iter()
                .filter(|t| !is_null(density, t))
                .cloned()
                .collect();
            let spec = model.density(density);
            let survivors = survivors(&live, spec.dominance, spec.beyond_leading, density);
            let mut missing = null_note(density, field, &admitted, &survivors);
            missing.extend(missing_parts(model, density, order, basis, i, &survivors));
            FieldResult {
                field: field.clone(),
                density: coefficients(density, field, &survivors),
                admitted,
                survivors,
                missing,
            }
        })
        .collect()
}

/// A note naming the null terms that would have been among the lowest order had they counted.
fn null_note(
    density: Density,
    field: &Field,
    admitted: &[Term],
    survivors: &[Term],
) -> Vec<String> {
    let passed: Vec<String> = lowest_order(admitted)
        .iter()
        .filter(|t| !survivors.contains(t) && is_null(density, t))
        .map(|t| t.render(&|_| field.symbol.clone()))
        .collect();
    if passed.is_empty() {
        return Vec::new();
    }
    let why = match density {
        Density::Lagrangian => "a total derivative: the Euler–Lagrange expression vanishes",
        Density::Rayleigh => "δR/δ(∂tφ) over the velocity jet at fixed time vanishes",
    };
    let one = passed.len() == 1;
    vec![format!(
        "{}_{}: {} {} no equation ({why}) and {} no part in the lowest-order selection",
        density.letter(),
        field.symbol,
        passed.join(", "),
        if one { "changes" } else { "change" },
        if one { "takes" } else { "take" },
    )]
}

/// The lowest-order terms of `admitted` and `beyond` layers more: all competing together
/// (canonical order), or each part of the density among its own kind ([`Dominance::ByPart`];
/// kinetic terms first, each part in canonical order).
fn survivors(admitted: &[Term], dominance: Dominance, beyond: u32, density: Density) -> Vec<Term> {
    match dominance {
        Dominance::Joint => layers(admitted, beyond),
        Dominance::ByPart => parts(density)
            .into_iter()
            .flat_map(|(_, is_part)| {
                let part: Vec<Term> = admitted.iter().filter(|t| is_part(t)).cloned().collect();
                layers(&part, beyond)
            })
            .collect(),
    }
}

/// The terms of the first 1 + `beyond` layers of `terms`, in the given order: layer 1 is the
/// lowest order ([`lowest_order`]), layer k + 1 the lowest order of what layers 1 … k leave.
pub fn layers(terms: &[Term], beyond: u32) -> Vec<Term> {
    // A set: tens of thousands of [active] candidates meet thousands kept.
    let mut kept: std::collections::HashSet<Term> = std::collections::HashSet::new();
    for _ in 0..=beyond {
        let left: Vec<Term> = terms
            .iter()
            .filter(|t| !kept.contains(t))
            .cloned()
            .collect();
        if left.is_empty() {
            break;
        }
        kept.extend(lowest_order(&left));
    }
    terms.iter().filter(|t| kept.contains(t)).cloned().collect()
}

/// A test on a term.
type TermTest = fn(&Term) -> bool;

/// The parts a density needs: a Lagrangian a kinetic and a potential term, a Rayleigh density
/// any term. Each is (name, test on a term).
fn parts(density: Density) -> Vec<(&'static str, TermTest)> {
    match density {
        Density::Lagrangian => vec![
            ("kinetic", |t: &Term| t.has_time_derivative()),
            ("potential", |t: &Term| !t.has_time_derivative()),
        ],
        Density::Rayleigh => vec![("dissipative", |_: &Term| true)],
    }
}

fn missing_parts(
    model: &Model,
    density: Density,
    order: u32,
    basis: Basis,
    field: usize,
    survivors: &[Term],
) -> Vec<String> {
    let symbol = &model.fields[field].symbol;
    let mut notes = Vec::new();
    for (part, is_part) in parts(density) {
        if survivors.iter().any(is_part) {
            continue;
        }
        // Look for the first order at which the field admits such a term at all.
        // Pure powers are few at every order; monomials grow too fast to look far ahead.
        // The look-ahead stays within the candidate budget (order 8 looking at order 12 would
        // decide 13 million Rayleigh products).
        let within = |k: u32| {
            let bounds = Bounds::for_order(model.density(density).bound, k);
            count_products(&bounds, 1) <= MAX_CANDIDATES
        };
        let horizon = match basis {
            Basis::Powers => MAX_ORDER,
            Basis::Monomials => (order + 1..=(order + MONOMIAL_LOOK_AHEAD).min(MAX_ORDER))
                .take_while(|&k| within(k))
                .last()
                .unwrap_or(order),
        };
        let first = (order + 1..=horizon).find_map(|k| {
            let bounds = Bounds::for_order(model.density(density).bound, k);
            let (_, rows) = decide(model, density, &bounds, basis);
            let admitted: Vec<Term> = rows
                .into_iter()
                .filter(|r| r.admitted[field] && is_part(&r.term) && !is_null(density, &r.term))
                .map(|r| r.term)
                .collect();
            // The lowest of them, the standard kinetic term (∂tφ)² first when it is one.
            let lowest = lowest_order(&admitted);
            let standard = Term::power(1, 0, 2);
            lowest
                .iter()
                .find(|t| **t == standard)
                .or(lowest.first())
                .map(|t| (k, t.clone()))
        });
        let letter = density.letter();
        notes.push(match first {
            Some((k, term)) => format!(
                "{letter}_{symbol}: no {part} term survives at order {order}; the first admitted one, {}, needs --order {k}",
                term.render(&|_| symbol.clone())
            ),
            None if basis == Basis::Monomials => format!(
                "{letter}_{symbol}: no {part} term is admitted at any order up to {horizon} (monomials are searched at most {MONOMIAL_LOOK_AHEAD} orders ahead, within the {MAX_CANDIDATES}-candidate limit)"
            ),
            None => format!(
                "{letter}_{symbol}: no {part} term is admitted at any order up to {horizon}"
            ),
        });
    }
    notes
}

fn coefficients(density: Density, field: &Field, survivors: &[Term]) -> Vec<DensityTerm> {
    let half = Rational64::new(1, 2);
    let standard_kinetic = Term::power(1, 0, 2);
    let sym = &field.symbol;
    // (sign, prefactor, parameter letter) for each survivor; the kinetic term is fixed.
    let shaped: Vec<(i64, Rational64, Option<&str>)> = survivors
        .iter()
        .map(|t| match density {
            Density::Lagrangian if *t == standard_kinetic => (1, half, None),
            Density::Lagrangian if !t.has_time_derivative() => (-1, half, Some("c")),
            Density::Lagrangian => (1, half, Some("k")),
            Density::Rayleigh => (1, Rational64::one(), Some("c'")),
        })
        .collect();
    let count = |letter: &str| shaped.iter().filter(|s| s.2 == Some(letter)).count();
    let mut seen: Vec<&str> = Vec::new();
    survivors
        .iter()
        .zip(&shaped)
        .map(|(term, &(sign, prefactor, letter))| {
            let parameter = letter.map(|l| {
                seen.push(l);
                let index = seen.iter().filter(|&&s| s == l).count();
                if count(l) > 1 {
                    format!("{l}{index}_{sym}")
                } else {
                    format!("{l}_{sym}")
                }
            });
            DensityTerm {
                term: term.clone(),
                sign,
                prefactor,
                parameter,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_incomparable_terms() {
        let terms: Vec<Term> = ["(∂t φ)²", "(∂ss φ)²", "(∂ts φ)²", "(∂ss φ)⁴"]
            .iter()
            .map(|t| t.parse().unwrap())
            .collect();
        let kept: Vec<String> = lowest_order(&terms).iter().map(|t| t.to_string()).collect();
        assert_eq!(kept, ["(∂t φ)²", "(∂ss φ)²"]);
    }

    #[test]
    fn formulas_read_like_the_seed() {
        let m = Model::larva();
        let l = analyse(&m, Density::Lagrangian, 4).unwrap();
        assert_eq!(
            l.fields[0].formula(Density::Lagrangian),
            "L_x = ½(∂t x)² − ½ c_x (∂s x)²"
        );
        assert_eq!(
            l.fields[2].formula(Density::Lagrangian),
            "L_y = ½(∂t y)² − ½ c_y (∂ss y)²"
        );
        let r = analyse(&m, Density::Rayleigh, 4).unwrap();
        assert_eq!(
            r.fields[1].formula(Density::Rayleigh),
            "R_θ = c'_θ (∂ts θ)²"
        );
        assert_eq!(
            r.fields[3].formula(Density::Rayleigh),
            "R_z = c'_z (∂tss z)²"
        );
    }

    #[test]
    fn missing_potential_is_said_plainly() {
        let l = analyse(&Model::larva(), Density::Lagrangian, 3).unwrap();
        assert_eq!(
            l.fields[2].missing,
            ["L_y: no potential term survives at order 3; the first admitted one, (∂ss y)², needs --order 4"]
        );
        assert!(l.fields[0].missing.is_empty());
    }

    #[test]
    fn orders_out_of_range_are_errors() {
        let m = Model::larva();
        assert!(analyse(&m, Density::Lagrangian, 0).is_err());
        assert!(analyse(&m, Density::Lagrangian, MAX_ORDER + 1).is_err());
    }
}
