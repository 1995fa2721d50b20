//! Interaction densities L_I, R_I: terms that couple two or more fields.
//!
//! For every set of k ≥ 2 model fields (f₁, …, f_k), the candidates are products over the
//! placeholders φ₁ … φ_k that involve all of them. A candidate must satisfy the density's
//! structural interaction rules as a whole (the model's `interaction` list, e.g. OST and KIN) and
//! each field's own symmetry rules with only that field transformed (ROT for y transforms the
//! placeholder standing for y, not the one for x).
//!
//! The table lists the lowest-order candidates (the Pareto front in (τ, σ)) among those that
//! the symmetries all the fields share allow, each with every verdict. Of the admitted ones, the
//! lowest are *kept* only if no free-field survivor of a participating field dominates them: at
//! long wavelengths a dominated coupling is negligible (the paper's argument for a free theory).

use crate::enumerate::{interaction_monomials, Bounds};
use crate::model::{Density, Model};
use crate::reduce::{analyse, check_candidates, dominates, lowest_order, OrderError};
use crate::rules::{self, Check, PreparedRule, Verdict};
use crate::term::Term;

/// One verdict in an interaction row: the rule, which field it was applied to (None: the whole
/// term), and the outcome.
#[derive(Debug, Clone)]
pub struct PairVerdict {
    /// Rule code.
    pub rule: &'static str,
    /// The field transformed, for symmetry rules.
    pub field: Option<String>,
    /// The outcome.
    pub verdict: Verdict,
}

/// One candidate of a pair with its verdicts.
#[derive(Debug, Clone)]
pub struct PairRow {
    /// The candidate (φ₁ is the pair's first field, φ₂ its second).
    pub term: Term,
    /// Every verdict.
    pub verdicts: Vec<PairVerdict>,
}

impl PairRow {
    /// True if every verdict passed.
    pub fn admitted(&self) -> bool {
        self.verdicts.iter().all(|v| v.verdict.passed())
    }
}

/// What one set of fields can couple through.
#[derive(Debug, Clone)]
pub struct Coupling {
    /// The field ids; placeholder φᵢ stands for `fields[i − 1]`.
    pub fields: Vec<String>,
    /// The symmetry rules all the fields require.
    pub shared: Vec<&'static str>,
    /// The lowest-order candidates those shared symmetries allow, with verdicts.
    pub rows: Vec<PairRow>,
    /// The lowest-order admitted candidates (over all candidates, not only `rows`).
    pub admitted: Vec<Term>,
    /// Those admitted terms that no free survivor of a participating field dominates.
    pub kept: Vec<Term>,
    /// When nothing is admitted at the order asked: the first higher order that admits a
    /// product, and its lowest admitted terms, or `Err(last order searched)` within the budget.
    pub later: Option<Result<(u32, Vec<Term>), u32>>,
}

/// Candidates the look-ahead of one coupling may decide, in all.
const LOOK_AHEAD_CANDIDATES: u128 = 100_000;

/// The first order above `order` (at most 4 more) at which `ids` admit a product, within
/// [`LOOK_AHEAD_CANDIDATES`]; `Err(last order searched)` otherwise.
fn look_ahead(
    model: &Model,
    density: Density,
    ids: &[String],
    order: u32,
) -> Result<(u32, Vec<Term>), u32> {
    let mut spent = 0u128;
    let k = ids.len() as u32;
    for next in order + 1..=(order + 4).min(crate::enumerate::MAX_ORDER) {
        let bounds = Bounds::for_order(model.density(density).bound, next);
        spent = spent.saturating_add(crate::enumerate::count_products(&bounds, k));
        if k > bounds.epsilon || spent > LOOK_AHEAD_CANDIDATES {
            return Err(next - 1);
        }
        let admission = Admission::new(model, density, ids, &bounds);
        let admitted: Vec<Term> = interaction_monomials(&bounds, k as u8)
            .into_iter()
            .filter(|t| admission.admits(t))
            .collect();
        if !admitted.is_empty() {
            return Ok((next, lowest_order(&admitted)));
        }
    }
    Err((order + 4).min(crate::enumerate::MAX_ORDER))
}

/// The interaction analysis of one density.
#[derive(Debug, Clone)]
pub struct Interactions {
    /// Which density.
    pub density: Density,
    /// The order.
    pub order: u32,
    /// The candidate bounds.
    pub bounds: Bounds,
    /// Every set of two or more fields, pairs first.
    pub couplings: Vec<Coupling>,
}

fn symmetry_codes(model: &Model, density: Density, field: &str) -> Vec<&'static str> {
    model
        .requirements(density, field)
        .into_iter()
        .filter(|r| matches!(r.check, Check::Symmetry(_)))
        .map(|r| r.code)
        .collect()
}

fn verdicts(model: &Model, density: Density, fields: &[String], term: &Term) -> Vec<PairVerdict> {
    let mut out: Vec<PairVerdict> = model
        .density(density)
        .interaction
        .iter()
        .filter_map(|c| rules::rule(c))
        .map(|r| PairVerdict {
            rule: r.code,
            field: None,
            verdict: r.verdict(term),
        })
        .collect();
    for (i, field) in fields.iter().enumerate() {
        let placeholder = i as u8 + 1;
        for code in symmetry_codes(model, density, field) {
            let Some(rule) = rules::rule(code) else {
                continue;
            };
            let Check::Symmetry(tr) = rule.check else {
                continue;
            };
            let verdict = match tr.check_invariant_field(term, placeholder) {
                Ok(()) => Verdict::Pass,
                Err(why) => Verdict::Reject {
                    rule: code,
                    why: why.to_string(),
                },
            };
            out.push(PairVerdict {
                rule: code,
                field: Some(field.to_string()),
                verdict,
            });
        }
    }
    out
}

/// The same decision as `verdicts(…)` all passing, without building explanations: the rules
/// prepared once for the bounds (their images of the factor kinds), decided per term.
struct Admission {
    /// Structural rules on the whole product.
    structural: Vec<PreparedRule>,
    /// Each participating field's symmetries, applied to that field alone.
    fields: Vec<Vec<PreparedRule>>,
}

impl Admission {
    fn new(model: &Model, density: Density, ids: &[String], bounds: &Bounds) -> Admission {
        let prepare = |codes: Vec<&str>| -> Vec<PreparedRule> {
            codes
                .into_iter()
                .filter_map(rules::rule)
                .map(|r| r.prepare(bounds.delta))
                .collect()
        };
        let interaction = model
            .density(density)
            .interaction
            .iter()
            .map(String::as_str);
        Admission {
            structural: prepare(interaction.collect()),
            fields: ids
                .iter()
                .map(|id| prepare(symmetry_codes(model, density, id)))
                .collect(),
        }
    }

    fn admits(&self, term: &Term) -> bool {
        self.structural.iter().all(|r| r.passes(term))
            && self
                .fields
                .iter()
                .enumerate()
                .all(|(i, rules)| rules.iter().all(|r| r.passes_field(term, i as u8 + 1)))
    }
}

/// Every subset of `0..n` with at least two elements, smaller sets first.
fn subsets(n: usize) -> Vec<Vec<usize>> {
    let mut all: Vec<Vec<usize>> = (0u32..1 << n)
        .map(|mask| (0..n).filter(|i| mask & (1 << i) != 0).collect::<Vec<_>>())
        .filter(|s| s.len() >= 2)
        .collect();
    all.sort_by_key(|s| (s.len(), s.clone()));
    all
}

/// The most candidate products the interaction tables of one density may decide (over every
/// set of fields), counted by the generating function before any is built: about ten seconds.
pub const MAX_INTERACTION_CANDIDATES: u128 = 3_000_000;

/// Refuse, before any work, interaction tables over [`MAX_INTERACTION_CANDIDATES`].
pub fn check_interaction_work(
    model: &Model,
    density: Density,
    order: u32,
) -> Result<(), OrderError> {
    let bounds = crate::enumerate::Bounds::for_order(model.density(density).bound, order);
    let count: u128 = subsets(model.fields.len())
        .iter()
        .filter(|s| s.len() as u32 <= bounds.epsilon)
        .map(|s| crate::enumerate::count_products(&bounds, s.len() as u32))
        .fold(0u128, |a, b| a.saturating_add(b));
    if count > MAX_INTERACTION_CANDIDATES {
        return Err(OrderError::TooManyInteractions {
            density: density.key().into(),
            order,
            count,
            limit: MAX_INTERACTION_CANDIDATES,
        });
    }
    Ok(())
}

/// Analyse the interactions of every set of two or more fields of `model` in `density` at
/// `order`.
pub fn interactions(
    model: &Model,
    density: Density,
    order: u32,
) -> Result<Interactions, OrderError> {
    check_interaction_work(model, density, order)?;
    let free = analyse(model, density, order)?;
    let bounds = free.bounds;
    let mut couplings = Vec::new();
    // A k-field product has ε ≥ k, so k ≤ ε's bound.
    for set in subsets(model.fields.len())
        .into_iter()
        .filter(|s| s.len() as u32 <= bounds.epsilon)
    {
        let ids: Vec<String> = set.iter().map(|&i| model.fields[i].id.clone()).collect();
        check_candidates(order, &bounds, set.len() as u32)?;
        let candidates = interaction_monomials(&bounds, set.len() as u8);
        let mut shared = symmetry_codes(model, density, &ids[0]);
        for id in &ids[1..] {
            let own = symmetry_codes(model, density, id);
            shared.retain(|c| own.contains(c));
        }
        let shared_rules: Vec<PreparedRule> = shared
            .iter()
            .filter_map(|c| rules::rule(c))
            .map(|r| r.prepare(bounds.delta))
            .collect();
        let allowed_by_shared: Vec<Term> = candidates
            .iter()
            .filter(|t| shared_rules.iter().all(|r| r.passes(t)))
            .cloned()
            .collect();
        let rows = lowest_order(&allowed_by_shared)
            .into_iter()
            .map(|term| PairRow {
                verdicts: verdicts(model, density, &ids, &term),
                term,
            })
            .collect();
        let admission = Admission::new(model, density, &ids, &bounds);
        let all_admitted: Vec<Term> = candidates
            .iter()
            .filter(|t| admission.admits(t))
            .cloned()
            .collect();
        let admitted = lowest_order(&all_admitted);
        let free_terms: Vec<&Term> = set
            .iter()
            .flat_map(|&i| &free.fields[i].survivors)
            .collect();
        let kept = admitted
            .iter()
            .filter(|t| {
                !free_terms
                    .iter()
                    .any(|f| dominates(&f.orders(), &t.orders()))
            })
            .cloned()
            .collect();
        let later = admitted
            .is_empty()
            .then(|| look_ahead(model, density, &ids, order));
        couplings.push(Coupling {
            fields: ids,
            shared,
            rows,
            admitted,
            kept,
            later,
        });
    }
    Ok(Interactions {
        density,
        order,
        bounds,
        couplings,
    })
}

impl Interactions {
    /// True if no set of fields keeps a coupling: the long-wavelength theory is free.
    pub fn is_free(&self) -> bool {
        self.couplings.iter().all(|p| p.kept.is_empty())
    }

    /// The analysis as text, one block per coupling.
    pub fn text(&self, model: &Model) -> String {
        let sym = |id: &str| model.symbol(id);
        let mut out = format!(
            "{} interactions at order {} ({}); each coupling's terms are shown in its fields\n",
            self.density, self.order, self.bounds
        );
        for p in &self.couplings {
            let symbols: Vec<String> = p.fields.iter().map(|f| sym(f)).collect();
            let name = |k: u8| symbols.get(k as usize - 1).cloned().unwrap_or_default();
            out += &format!(
                "\n{}: lowest candidates the shared symmetries ({}) allow:\n",
                symbols.join("–"),
                if p.shared.is_empty() {
                    "none".to_string()
                } else {
                    p.shared.join(" ")
                }
            );
            for row in &p.rows {
                let o = row.term.orders();
                let failed: Vec<String> = row
                    .verdicts
                    .iter()
                    .filter(|v| !v.verdict.passed())
                    .map(|v| match &v.field {
                        Some(f) => format!("{}({})", v.rule, sym(f)),
                        None => v.rule.to_string(),
                    })
                    .collect();
                let verdict = if failed.is_empty() {
                    "admitted".to_string()
                } else {
                    format!("fails {}", failed.join(" "))
                };
                let shown = row.term.render(&name);
                out += &format!(
                    "  {shown:<28} (τ, σ) = ({}, {})  {verdict}\n",
                    o.tau, o.sigma
                );
            }
            let render = |t: &Term| t.render(&name);
            if p.admitted.is_empty() {
                out += &match &p.later {
                    Some(Ok((next, terms))) => {
                        let shown: Vec<String> = terms
                            .iter()
                            .map(|t| {
                                let o = t.orders();
                                format!("{} ({}, {})", render(t), o.tau, o.sigma)
                            })
                            .collect();
                        format!(
                            "  admitted: none at order {}; the first at order {next} (--order {next}): {}\n",
                            self.order,
                            shown.join(", ")
                        )
                    }
                    Some(Err(last)) if *last > self.order => format!(
                        "  admitted: none up to order {last} (looking further is over the budget)\n"
                    ),
                    _ => format!("  admitted: none at order {}\n", self.order),
                };
            } else {
                let admitted: Vec<String> = p
                    .admitted
                    .iter()
                    .map(|t| {
                        let o = t.orders();
                        format!("{} ({}, {})", render(t), o.tau, o.sigma)
                    })
                    .collect();
                out += &format!("  admitted at lowest order: {}\n", admitted.join(", "));
                if p.kept.is_empty() {
                    out += "  dominated by the free-field terms of its fields: negligible at long wavelengths\n";
                } else {
                    let kept: Vec<String> = p.kept.iter().map(render).collect();
                    out += &format!(
                        "  kept (not dominated by the free fields): {}\n",
                        kept.join(", ")
                    );
                }
            }
        }
        out += if self.is_free() {
            "\nNo coupling survives at long wavelengths: the theory is free.\n"
        } else {
            "\nSome couplings survive at long wavelengths (see \"kept\").\n"
        };
        out
    }
}

/// `interactions`: the analyses of one or both densities of a model, as one printable result.
pub struct InteractionsReport<'a> {
    /// The model.
    pub model: &'a Model,
    /// One analysis per density asked for.
    pub analyses: Vec<Interactions>,
}

impl<'a> InteractionsReport<'a> {
    /// The analyses of `densities` at `order`, every density's budget checked before any
    /// density's work.
    pub fn new(
        model: &'a Model,
        densities: &[Density],
        order: u32,
    ) -> Result<InteractionsReport<'a>, OrderError> {
        crate::reduce::check_work(model, densities, order, crate::enumerate::Basis::Powers)?;
        for &d in densities {
            check_interaction_work(model, d, order)?;
        }
        let analyses = densities
            .iter()
            .map(|&d| interactions(model, d, order))
            .collect::<Result<_, _>>()?;
        Ok(InteractionsReport { model, analyses })
    }

    /// Every verdict of every candidate row as (density, fields, term, rule, field, passed).
    fn verdict_rows(&self) -> Vec<Vec<String>> {
        let mut rows = Vec::new();
        for a in &self.analyses {
            for c in &a.couplings {
                let name = |k: u8| self.model.symbol(&c.fields[k as usize - 1]);
                for row in &c.rows {
                    for v in &row.verdicts {
                        rows.push(vec![
                            a.density.key().to_string(),
                            c.fields.join(" "),
                            row.term.render(&name),
                            v.rule.to_string(),
                            v.field.clone().unwrap_or_default(),
                            v.verdict.passed().to_string(),
                        ]);
                    }
                }
            }
        }
        rows
    }
}

impl crate::report::Report for InteractionsReport<'_> {
    fn text(&self) -> String {
        self.analyses
            .iter()
            .map(|a| a.text(self.model) + "\n")
            .collect()
    }

    fn json(&self) -> serde_json::Value {
        use serde_json::json;
        let analyses: Vec<_> = self
            .analyses
            .iter()
            .map(|a| {
                let couplings: Vec<_> = a
                    .couplings
                    .iter()
                    .map(|c| {
                        let name = |k: u8| self.model.symbol(&c.fields[k as usize - 1]);
                        let terms = |ts: &[Term]| -> Vec<String> {
                            ts.iter().map(|t| t.render(&name)).collect()
                        };
                        let rows: Vec<_> = c
                            .rows
                            .iter()
                            .map(|r| {
                                let verdicts: Vec<_> = r
                                    .verdicts
                                    .iter()
                                    .map(|v| json!({"rule": v.rule, "field": v.field, "passed": v.verdict.passed()}))
                                    .collect();
                                json!({"term": r.term.render(&name), "admitted": r.admitted(), "verdicts": verdicts})
                            })
                            .collect();
                        let later = match &c.later {
                            Some(Ok((order, ts))) => json!({"order": order, "terms": terms(ts)}),
                            Some(Err(last)) => json!({"none_up_to": last}),
                            None => serde_json::Value::Null,
                        };
                        json!({
                            "fields": c.fields,
                            "shared": c.shared,
                            "rows": rows,
                            "admitted": terms(&c.admitted),
                            "kept": terms(&c.kept),
                            "later": later,
                        })
                    })
                    .collect();
                json!({
                    "density": a.density.key(),
                    "order": a.order,
                    "free": a.is_free(),
                    "couplings": couplings,
                })
            })
            .collect();
        json!({"model": self.model.name, "analyses": analyses})
    }

    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["density", "fields", "term", "rule", "field", "passed"],
            self.verdict_rows(),
        ))
    }
}
