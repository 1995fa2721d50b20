//! The engine's laws read against a discovered equation: whether the theory holds here.
//!
//! A selected coefficient whose sign the derivation fixes (`equations`' sign claims: the energy
//! bounded below, dissipation non-negative) with its whole interval on the forbidden side, an
//! equation whose selected forces hold nothing in place (no force of the positions alone: the
//! postures would wander off), no term kept by more than half of the bootstrap draws, or (exact
//! estimator) the modes' frequencies and dampings beyond what the selected theory can give
//! (J against χ² with 2M − k degrees of freedom, p < [`ALPHA`]): each is a finding, and any
//! finding means the theory does not hold on this recording. A wrong sign whose interval reaches
//! the allowed side leaves the verdict undecided. Findings are results, not errors: `discover`
//! exits 0 and prints them.

use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::report::{DiscoverReport, Selection};
use crate::equations::{derive_each, derive_nonlinear_each, SignClaim};
use crate::model::Model;

/// The p-value under which the modes' misfit rejects the selected theory.
pub const ALPHA: f64 = 1e-3;

/// The information-weighted misfit of the selected theory (exact estimator).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Goodness {
    /// J: the modes' (Ω², 2ζΩ) against the theory's, weighted by their information.
    pub j: f64,
    /// 2M − k.
    pub dof: usize,
    /// P(χ²_dof > J).
    pub p: f64,
}

impl Goodness {
    /// J on `dof` degrees of freedom (none when there are none).
    pub fn new(j: f64, dof: usize) -> Option<Goodness> {
        let chi = ChiSquared::new(dof as f64).ok()?;
        (dof > 0 && j.is_finite()).then(|| Goodness {
            j,
            dof,
            p: chi.sf(j.max(0.0)),
        })
    }
}

/// One law the recording contradicts (or cannot decide).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "finding", rename_all = "snake_case")]
pub enum Finding {
    /// A sign-fixed coefficient on the wrong side.
    WrongSign {
        /// The coefficient.
        coefficient: String,
        /// Its value (body lengths).
        value: f64,
        /// Its interval, when there is one.
        interval: Option<[f64; 2]>,
        /// The engine's claim, in words.
        claim: String,
        /// The whole interval lies on the wrong side.
        decided: bool,
    },
    /// No selected force of the positions alone.
    NoRestoringForce {
        /// The selected coefficients.
        selected: Vec<String>,
    },
    /// No term kept in more than half of the draws.
    NoModel {
        /// The draws.
        draws: usize,
        /// The most often kept term and its share.
        best: Option<(String, f64)>,
    },
    /// The modes ask for more than the selected theory gives.
    Misfit(Goodness),
}

impl Finding {
    fn decided(&self) -> bool {
        !matches!(self, Finding::WrongSign { decided: false, .. })
    }

    fn text(&self) -> String {
        let n = crate::report::number;
        match self {
            Finding::WrongSign {
                coefficient,
                value,
                interval,
                claim,
                decided,
            } => format!(
                "{coefficient} = {}{} {} the engine's law ({claim})",
                n(*value),
                interval.map_or(String::new(), |[a, b]| format!(" [{}, {}]", n(a), n(b))),
                if *decided {
                    "breaks"
                } else {
                    "has the wrong sign, its interval reaching the side of"
                },
            ),
            Finding::NoRestoringForce { selected } => format!(
                "no selected force holds the postures in place ({}: none is a force of the positions alone), so they would wander off",
                if selected.is_empty() { "nothing selected".to_string() } else { selected.join(", ") }
            ),
            Finding::NoModel { draws, best } => format!(
                "no term was kept in more than half of the {draws} draws{}: no model is reported",
                best.as_ref().map_or(String::new(), |(t, s)| format!(
                    " (the most often: {t}, {:.0} %)",
                    100.0 * s
                ))
            ),
            Finding::Misfit(g) => format!(
                "the modes' frequencies and dampings are beyond the selected theory: J = {:.1} on {} degrees of freedom (p = {:.1e} < {ALPHA})",
                g.j, g.dof, g.p
            ),
        }
    }
}

/// Whether the theory holds on the recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Conclusion {
    /// No law is broken.
    Holds,
    /// A law is broken.
    DoesNotHold,
    /// Only wrong signs whose intervals reach the allowed side.
    Undecided,
}

/// The conclusion and the findings behind it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// Holds, does not hold, or undecided.
    pub conclusion: Conclusion,
    /// Each law contradicted.
    pub findings: Vec<Finding>,
}

impl Verdict {
    /// The laws of `model` at `order` read against `report`.
    pub fn of(report: &DiscoverReport, model: &Model, order: u32) -> Verdict {
        let mut findings = Vec::new();
        if let Selection::NoModel { best, .. } = &report.selection {
            findings.push(Finding::NoModel {
                draws: report.bootstrap,
                best: best.clone(),
            });
        } else {
            findings.extend(wrong_signs(report, model, order));
            if !restoring(report, model, order) {
                findings.push(Finding::NoRestoringForce {
                    selected: report.selected.iter().map(|t| t.name.clone()).collect(),
                });
            }
        }
        if let Some(g) = report.goodness.filter(|g| g.p < ALPHA) {
            findings.push(Finding::Misfit(g));
        }
        let conclusion = if findings.is_empty() {
            Conclusion::Holds
        } else if findings.iter().any(Finding::decided) {
            Conclusion::DoesNotHold
        } else {
            Conclusion::Undecided
        };
        Verdict {
            conclusion,
            findings,
        }
    }

    /// `Verdict: …` in one paragraph.
    pub fn text(&self) -> String {
        let head = match self.conclusion {
            Conclusion::Holds => "the theory holds here: every selected coefficient has the sign the engine fixes, a force of the positions holds the postures",
            Conclusion::DoesNotHold => "the theory does not hold here",
            Conclusion::Undecided => "undecided",
        };
        let body: Vec<String> = self.findings.iter().map(Finding::text).collect();
        if body.is_empty() {
            format!("Verdict: {head}.\n")
        } else {
            format!("Verdict: {head}: {}.\n", body.join("; "))
        }
    }
}

/// Selected coefficients on the side their sign claim forbids.
fn wrong_signs(report: &DiscoverReport, model: &Model, order: u32) -> Vec<Finding> {
    // Sign claims exist for linear equations only (a nonlinear one is bounded jointly).
    let Ok(derived) = derive_each(model, order, crate::enumerate::Basis::Powers) else {
        return Vec::new();
    };
    let Some(eq) = derived
        .equations
        .iter()
        .find(|e| e.field.id == report.field)
    else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for t in &report.selected {
        let Some(rhs) = eq.rhs.iter().find(|r| r.coefficient == t.name) else {
            continue;
        };
        let sign = match rhs.claim {
            SignClaim::Positive(_) => 1.0,
            SignClaim::Negative(_) => -1.0,
            SignClaim::Free(_) => continue,
        };
        if sign * t.coefficient < 0.0 {
            out.push(Finding::WrongSign {
                coefficient: t.name.clone(),
                value: t.coefficient,
                interval: t.interval,
                claim: rhs.claim.describe(&t.name),
                decided: t
                    .interval
                    .is_some_and(|[a, b]| sign * a < 0.0 && sign * b < 0.0),
            });
        }
    }
    out
}

/// Some selected coefficient multiplies a force of the positions alone (no time derivative).
fn restoring(report: &DiscoverReport, model: &Model, order: u32) -> bool {
    let Ok(derived) = derive_nonlinear_each(model, order, crate::enumerate::Basis::Powers) else {
        // Without the equation nothing can be said: no finding.
        return true;
    };
    let Some(eq) = derived
        .equations
        .iter()
        .find(|e| e.field.id == report.field)
    else {
        return true;
    };
    eq.rhs.iter().any(|r| {
        !r.monomial.is_empty()
            && r.monomial.iter().all(|(d, _)| d.t == 0)
            && report.selected.iter().any(|t| t.name == r.coefficient)
    })
}
