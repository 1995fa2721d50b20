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

use super::report::{DiscoverReport, Selection, MEDIAN_DRAWS};
use crate::enumerate::Basis;
use crate::equations::{derive_field, derive_nonlinear_each, ForceKind, SignClaim};
use crate::model::Model;

/// The p-value under which the modes' misfit rejects the selected theory.
pub const ALPHA: f64 = 1e-3;

/// The information-weighted misfit of the selected theory (exact estimator).
///
/// J is χ² on 2M − k degrees of freedom when each mode's information is its estimate's true
/// precision. On a sharp line or a mode near Nyquist the observed information overstates it
/// (a true beam's J exceeded χ²'s 5 % point in 7 of 20 recordings at 14 frames a period): the
/// bootstrap draws, recentred on the recording's own misfit, measure how far J strays when the
/// theory holds, and J is read against χ² scaled by their mean over the degrees of freedom
/// (never below 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Goodness {
    /// J: the modes' (Ω², 2ζΩ) against the theory's, weighted by their information.
    pub j: f64,
    /// 2M − k.
    pub dof: usize,
    /// The draws' mean recentred J over the degrees of freedom (≥ 1; 1 without draws).
    pub scale: f64,
    /// P(scale·χ²_dof > J).
    pub p: f64,
}

impl Goodness {
    /// J on `dof` degrees of freedom, scaled by the recentred draws' `strays` when there are
    /// [`MEDIAN_DRAWS`] of them (none when there are no degrees of freedom).
    pub fn new(j: f64, dof: usize, strays: &[f64]) -> Option<Goodness> {
        let chi = ChiSquared::new(dof as f64).ok()?;
        let scale = if strays.len() >= MEDIAN_DRAWS {
            (strays.iter().sum::<f64>() / strays.len() as f64 / dof as f64).max(1.0)
        } else {
            1.0
        };
        (dof > 0 && j.is_finite() && scale.is_finite()).then(|| Goodness {
            j,
            dof,
            scale,
            p: chi.sf(j.max(0.0) / scale),
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
    /// The model holds an end in place that the recording shows moving.
    HeldEndMoves {
        /// The held ends' rms displacement over the whole midline's (the worst animal's).
        share: f64,
    },
}

impl Finding {
    fn decided(&self) -> bool {
        !matches!(self, Finding::WrongSign { decided: false, .. })
    }

    pub(super) fn text(&self) -> String {
        let n = crate::report::short;
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
                "no selected force holds the postures in place ({}: none is a force of the positions that an energy gives; an odd-order active force drives, it does not restore), so they would wander off",
                if selected.is_empty() { "nothing selected".to_string() } else { selected.join(", ") }
            ),
            Finding::NoModel { draws, best } => format!(
                "no term was kept in more than half of the {draws} draws{}: no model is reported",
                best.as_ref().map_or(String::new(), |(t, s)| format!(
                    " (the most often: {t}, {:.0} %)",
                    100.0 * s
                ))
            ),
            Finding::HeldEndMoves { share } => format!(
                "the model holds an end of this body in place, but the recording's held end moves ({:.0} % of the whole midline's rms displacement; at most {:.0} % for a held end): a model with that end free fits such a recording",
                100.0 * share,
                100.0 * crate::recording::MOVING_SHARE
            ),
            Finding::Misfit(g) => format!(
                "the modes' frequencies and dampings are beyond the selected theory (a force the library lacks: --active, or the next order): J = {:.1} on {} degrees of freedom, the draws' scale {:.2} (p = {:.1e} < {ALPHA})",
                g.j, g.dof, g.scale, g.p
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

impl Conclusion {
    /// The conclusion in a few words.
    pub fn words(self) -> &'static str {
        match self {
            Conclusion::Holds => "holds",
            Conclusion::DoesNotHold => "does not hold",
            Conclusion::Undecided => "undecided",
        }
    }
}

/// The conclusion and the findings behind it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// Holds, does not hold, or undecided.
    pub conclusion: Conclusion,
    /// Each law contradicted.
    pub findings: Vec<Finding>,
    /// The modes' misfit, when the estimator tests it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goodness: Option<Goodness>,
    /// What to run after this answer.
    pub next: Next,
}

/// What to run after a verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Next {
    /// The theory holds: the onward line runs the discovered body as the recording was taken.
    Replay,
    /// Forces the passive library lacks, which the model's `[active]` section allows.
    Active,
    /// The next layer of the expansion: two orders more (the body's reflection symmetry
    /// steps the orders by two) and one more layer beyond the leading one.
    Layer {
        /// `--order`.
        order: u32,
        /// `--beyond-leading`.
        beyond_leading: u32,
        /// The field's equation there is linear (the exact estimators take it); a nonlinear
        /// one goes to the weak form, which needs finely sampled recordings.
        linear: bool,
    },
    /// No term is kept in more than half of the draws: more frames or animals.
    MoreData,
}

impl Verdict {
    /// The laws of `model` at `order` read against `report`.
    /// `held` is the held ends' movement share (the worst animal's) where the model holds one.
    pub fn of(report: &DiscoverReport, model: &Model, order: u32, held: Option<f64>) -> Verdict {
        let mut findings = Vec::new();
        if let Some(share) = held.filter(|&s| s > crate::recording::MOVING_SHARE) {
            findings.push(Finding::HeldEndMoves { share });
        }
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
        let next = if findings
            .iter()
            .any(|f| matches!(f, Finding::NoModel { .. }))
        {
            Next::MoreData
        } else if conclusion == Conclusion::Holds {
            Next::Replay
        } else if !report.active && model.active.is_some() {
            Next::Active
        } else {
            let mut layer = model.clone();
            layer.set_beyond_leading(report.beyond_leading + 1);
            let field = &report.field;
            let linear =
                derive_field(&layer, order + 2, Basis::Powers, field).is_ok_and(|e| e.is_some());
            Next::Layer {
                order: order + 2,
                beyond_leading: report.beyond_leading + 1,
                linear,
            }
        };
        Verdict {
            conclusion,
            findings,
            goodness: report.goodness,
            next,
        }
    }

    /// `Verdict: …` in one paragraph.
    pub fn text(&self) -> String {
        let head = match (self.conclusion, self.goodness) {
            (Conclusion::Holds, Some(g)) => format!("the theory holds here: every selected coefficient has the sign the engine fixes, a force of the positions holds the postures, and the modes fit it (J = {:.1} on {} degrees of freedom, the draws' scale {:.2}, p = {:.2})", g.j, g.dof, g.scale, g.p),
            (Conclusion::Holds, None) => "the theory holds here as far as its estimator tests it: every selected coefficient has the sign the engine fixes and a force of the positions holds the postures (the weak form and the modes' joint likelihood have no test of the modes' fit yet)".to_string(),
            (Conclusion::DoesNotHold, _) => "the theory does not hold here".to_string(),
            (Conclusion::Undecided, _) => "undecided".to_string(),
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
    // Sign claims exist for linear equations only (a nonlinear one is bounded jointly); the
    // field's own, whatever the other fields' terms.
    let Ok(Some(eq)) = derive_field(model, order, Basis::Powers, &report.field) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for t in &report.selected {
        let Some(rhs) = eq.rhs.iter().find(|r| r.coefficient == t.name) else {
            continue;
        };
        out.extend(wrong_sign(&t.name, t.coefficient, t.interval, &rhs.claim));
    }
    out
}

/// `name` = `value` (its `interval`) against its sign `claim`.
fn wrong_sign(
    name: &str,
    value: f64,
    interval: Option<[f64; 2]>,
    claim: &SignClaim,
) -> Option<Finding> {
    let sign = match claim {
        SignClaim::Positive(_) => 1.0,
        SignClaim::Negative(_) => -1.0,
        SignClaim::Free(_) => return None,
    };
    (sign * value < 0.0).then(|| Finding::WrongSign {
        coefficient: name.to_string(),
        value,
        interval,
        claim: claim.describe(name),
        decided: interval.is_some_and(|[a, b]| sign * a < 0.0 && sign * b < 0.0),
    })
}

/// Some selected coefficient multiplies a force of the positions alone (no time derivative).
fn restoring(report: &DiscoverReport, model: &Model, order: u32) -> bool {
    let Ok(derived) = derive_nonlinear_each(model, order, Basis::Powers) else {
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
        // A force of the positions that is odd in s (the active a∂s³y) drives, it does not
        // restore: on a free body its modal matrix has no diagonal. Only an energy's variation
        // does: a term of the Lagrangian, or a linear force of even order.
        let even_linear = matches!(r.monomial.as_slice(), [(d, 1)] if d.s % 2 == 0);
        !r.monomial.is_empty()
            && r.monomial.iter().all(|(d, _)| d.t == 0)
            && (r.kind != ForceKind::Active || even_linear)
            && report.selected.iter().any(|t| t.name == r.coefficient)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sign_is_broken_only_when_the_whole_interval_is_on_the_forbidden_side() {
        let stiff = SignClaim::Positive("energy bounded below");
        assert_eq!(wrong_sign("c_y", 1.0, Some([0.5, 2.0]), &stiff), None);
        let Some(Finding::WrongSign { decided, .. }) =
            wrong_sign("c_y", -1.0, Some([-2.0, -0.5]), &stiff)
        else {
            panic!("a negative stiffness is a finding");
        };
        assert!(decided);
        let reaching = wrong_sign("c_y", -1.0, Some([-2.0, 0.5]), &stiff).unwrap();
        assert!(!reaching.decided());
        let verdict = Verdict {
            conclusion: Conclusion::Undecided,
            findings: vec![reaching],
            goodness: None,
            next: Next::Active,
        };
        assert!(
            verdict
                .text()
                .starts_with("Verdict: undecided: c_y = -1 [-2, 0.5] has the wrong sign"),
            "{}",
            verdict.text()
        );
        let free = SignClaim::Free("odd in ∂s");
        assert_eq!(wrong_sign("a_y", -1.0, Some([-2.0, -0.5]), &free), None);
        let drag = SignClaim::Negative("stable as printed when negative");
        assert!(wrong_sign("b", 1.0, Some([0.5, 2.0]), &drag).is_some_and(|f| f.decided()));
    }

    #[test]
    fn no_term_in_half_of_the_draws_is_no_model_never_the_elimination() {
        use crate::discover::report::choose;
        let names = ["c_y".to_string(), "a_y".to_string()];
        let (set, rule) = choose(&[3, 6], 20, &[1], &names);
        assert!(set.is_empty());
        assert_eq!(
            rule,
            Selection::NoModel {
                best: Some(("a_y".into(), 0.3))
            }
        );
        assert_eq!(choose(&[11, 6], 20, &[1], &names).0, vec![0]);
        // Too few draws to decide: the elimination's pick, said so.
        assert_eq!(
            choose(&[3, 6], 19, &[1], &names),
            (vec![1], Selection::Elimination)
        );
    }

    #[test]
    fn the_misfit_is_read_against_the_draws_scale() {
        // J = 20 on 4 degrees of freedom: p = 5e-4 as χ², 0.08 when the draws stray 2.5× as far.
        let plain = Goodness::new(20.0, 4, &[]).unwrap();
        assert!(plain.p < ALPHA && plain.scale == 1.0);
        let strays = [10.0; MEDIAN_DRAWS];
        let scaled = Goodness::new(20.0, 4, &strays).unwrap();
        assert!(
            (scaled.scale - 2.5).abs() < 1e-12 && scaled.p > 0.05,
            "{scaled:?}"
        );
        // Draws straying less than χ² never narrow it.
        assert_eq!(
            Goodness::new(20.0, 4, &[1.0; MEDIAN_DRAWS]).unwrap().scale,
            1.0
        );
        assert_eq!(Goodness::new(1.0, 0, &[]), None);
    }
}
