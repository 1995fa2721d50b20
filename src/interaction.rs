//! Interaction densities L_I, R_I: terms that couple two fields.
//!
//! Candidates are products over two placeholder fields φ₁, φ₂ that involve both. For a pair of
//! model fields (f₁, f₂) a candidate must satisfy the density's structural interaction rules
//! as a whole (the model's `interaction` list, e.g. OST and KIN) and each field's own symmetry
//! rules with only that field transformed (ROT for y transforms φ₂ = y, not φ₁ = x).
//!
//! The table lists the lowest-order candidates (the Pareto front in (τ, σ)) among those that
//! the symmetries the two fields share allow, each with every verdict. Of the admitted ones, the
//! lowest are *kept* only if no free-field survivor of either field dominates them: at long
//! wavelengths a dominated coupling is negligible (the seed's argument for a free theory).

use crate::enumerate::{interaction_monomials, Bounds};
use crate::model::{Density, Model};
use crate::reduce::{analyse, dominates, lowest_order, OrderError};
use crate::rules::{self, Check, Verdict};
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

/// What one pair of fields can couple through.
#[derive(Debug, Clone)]
pub struct Pair {
    /// The two field ids.
    pub fields: (String, String),
    /// The symmetry rules both fields require.
    pub shared: Vec<&'static str>,
    /// The lowest-order candidates those shared symmetries allow, with verdicts.
    pub rows: Vec<PairRow>,
    /// The lowest-order admitted candidates (over all candidates, not only `rows`).
    pub admitted: Vec<Term>,
    /// Those admitted terms that no free survivor of either field dominates.
    pub kept: Vec<Term>,
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
    /// Every unordered pair of fields.
    pub pairs: Vec<Pair>,
}

fn symmetry_codes(model: &Model, density: Density, field: &str) -> Vec<&'static str> {
    model
        .requirements(density, field)
        .into_iter()
        .filter(|r| matches!(r.check, Check::Symmetry(_)))
        .map(|r| r.code)
        .collect()
}

fn verdicts(model: &Model, density: Density, pair: (&str, &str), term: &Term) -> Vec<PairVerdict> {
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
    for (placeholder, field) in [(1u8, pair.0), (2u8, pair.1)] {
        for code in symmetry_codes(model, density, field) {
            let Some(rule) = rules::rule(code) else {
                continue;
            };
            let Check::Symmetry(tr) = rule.check else {
                continue;
            };
            let verdict = match tr.check_invariant_field(term, placeholder) {
                Ok(()) => Verdict::Pass,
                Err(why) => Verdict::Reject { rule: code, why },
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

/// Analyse the interactions of every pair of fields of `model` in `density` at `order`.
pub fn interactions(
    model: &Model,
    density: Density,
    order: u32,
) -> Result<Interactions, OrderError> {
    let free = analyse(model, density, order)?;
    let bounds = free.bounds;
    let candidates = interaction_monomials(&bounds);
    let mut pairs = Vec::new();
    for (i, f1) in model.fields.iter().enumerate() {
        for (j, f2) in model.fields.iter().enumerate().skip(i + 1) {
            let ids = (f1.id.as_str(), f2.id.as_str());
            let (s1, s2) = (
                symmetry_codes(model, density, ids.0),
                symmetry_codes(model, density, ids.1),
            );
            let shared: Vec<&'static str> = s1.iter().copied().filter(|c| s2.contains(c)).collect();
            let allowed_by_shared: Vec<Term> = candidates
                .iter()
                .filter(|t| {
                    shared
                        .iter()
                        .all(|code| match rules::rule(code).map(|r| r.check) {
                            Some(Check::Symmetry(tr)) => tr.check_invariant(t).is_ok(),
                            _ => true,
                        })
                })
                .cloned()
                .collect();
            let rows = lowest_order(&allowed_by_shared)
                .into_iter()
                .map(|term| PairRow {
                    verdicts: verdicts(model, density, ids, &term),
                    term,
                })
                .collect();
            let all_admitted: Vec<Term> = candidates
                .iter()
                .filter(|t| {
                    verdicts(model, density, ids, t)
                        .iter()
                        .all(|v| v.verdict.passed())
                })
                .cloned()
                .collect();
            let admitted = lowest_order(&all_admitted);
            let free_terms: Vec<&Term> = free.fields[i]
                .survivors
                .iter()
                .chain(&free.fields[j].survivors)
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
            pairs.push(Pair {
                fields: (ids.0.to_string(), ids.1.to_string()),
                shared,
                rows,
                admitted,
                kept,
            });
        }
    }
    Ok(Interactions {
        density,
        order,
        bounds,
        pairs,
    })
}

impl Interactions {
    /// True if no pair keeps a coupling: the long-wavelength theory is free.
    pub fn is_free(&self) -> bool {
        self.pairs.iter().all(|p| p.kept.is_empty())
    }

    /// The analysis as text, one block per pair.
    pub fn text(&self, model: &Model) -> String {
        let sym = |id: &str| {
            model
                .field(id)
                .map(|f| f.symbol.clone())
                .unwrap_or_default()
        };
        let mut out = format!(
            "{} interactions at order {} ({}); φ₁, φ₂ are the pair's first and second field\n",
            self.density, self.order, self.bounds
        );
        for p in &self.pairs {
            let (a, b) = (sym(&p.fields.0), sym(&p.fields.1));
            out += &format!(
                "\n{a}–{b}: lowest candidates the shared symmetries ({}) allow:\n",
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
                let shown = row
                    .term
                    .render(&|k| if k == 1 { a.clone() } else { b.clone() });
                out += &format!(
                    "  {shown:<28} (τ, σ) = ({}, {})  {verdict}\n",
                    o.tau, o.sigma
                );
            }
            let render = |t: &Term| t.render(&|k| if k == 1 { a.clone() } else { b.clone() });
            if p.admitted.is_empty() {
                out += "  admitted: none at this order\n";
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
                    out += "  dominated by the free-field terms of the two fields: negligible at long wavelengths\n";
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
