//! `discover` on several animals: each animal's own answer beside the pooled one, and how much
//! the animals' coefficients differ.
//!
//! **Each animal.** The exact estimator runs on each recording alone, with the pool's library
//! and settings: its selected terms, their intervals and its verdict, or why it is refused. A
//! refused animal does not stop the pool; the pool's modes are chosen on the first animal that
//! is answered alone (an animal whose lowest mode is lost in its own noise would refuse them
//! all).
//!
//! **Between animals.** For each coefficient the pool selects, over the animals whose own
//! selection keeps it with an interval: Cochran's Q on k − 1 degrees of freedom, I², the
//! DerSimonian–Laird τ² and the random-effects mean with its Hartung–Knapp–Sidik–Jonkman
//! interval (`fit::spread`, the statistics `fit` uses for κ). The pooled interval is already
//! drawn over whole animals (the bootstrap's units are the recordings), so it describes the
//! population; where the animals differ (Q's p < 0.05) the pooled value is a population's mean,
//! not each animal's constant, and the report says so.

use serde::Serialize;

use super::report::DiscoverReport;
use super::verdict::Conclusion;
use crate::fit::Spread;
use crate::report::short;

/// One animal's answer alone.
#[derive(Debug, Clone, Serialize)]
pub struct AnimalAnswer {
    /// The recording.
    pub recording: String,
    /// Its verdict when it was answered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conclusion: Option<Conclusion>,
    /// The verdict's first finding, in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub finding: Option<String>,
    /// Its selected coefficients: name, estimate (body lengths and the data's time unit) and
    /// interval.
    pub selected: Vec<AnimalTerm>,
    /// The modes it used.
    pub modes: Vec<usize>,
    /// Why it was refused.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
}

/// One selected coefficient of one animal.
#[derive(Debug, Clone, Serialize)]
pub struct AnimalTerm {
    /// The coefficient's name.
    pub name: String,
    /// Its estimate.
    pub coefficient: f64,
    /// Its 95 % interval.
    pub interval: Option<[f64; 2]>,
}

/// How one pooled coefficient differs between the animals.
#[derive(Debug, Clone, Serialize)]
pub struct CoefficientSpread {
    /// The coefficient's name.
    pub name: String,
    /// The statistics.
    pub spread: Spread,
}

impl AnimalAnswer {
    /// An answered animal.
    pub(super) fn answered(report: &DiscoverReport) -> AnimalAnswer {
        AnimalAnswer {
            recording: report.recordings.first().cloned().unwrap_or_default(),
            conclusion: report.verdict.as_ref().map(|v| v.conclusion),
            finding: (report.verdict.as_ref())
                .and_then(|v| v.findings.first())
                .map(super::verdict::Finding::text),
            selected: (report.selected.iter())
                .map(|t| AnimalTerm {
                    name: t.name.clone(),
                    coefficient: t.coefficient,
                    interval: t.interval,
                })
                .collect(),
            modes: report.modes.iter().map(|m| m.0).collect(),
            refused: None,
        }
    }

    /// A refused animal.
    pub(super) fn refused(recording: &str, why: String) -> AnimalAnswer {
        AnimalAnswer {
            recording: recording.to_string(),
            conclusion: None,
            finding: None,
            selected: Vec::new(),
            modes: Vec::new(),
            refused: Some(why),
        }
    }
}

/// Several recordings: each animal's answer alone by the exact estimator (after the unread
/// ones), and the first one answered moved to the front, whose modes the pool uses. One
/// recording: none.
pub(super) fn alone(
    recordings: &mut [super::data::Recording],
    model: &crate::model::Model,
    settings: &super::DiscoverSettings,
    (whole, names): (&[crate::dynamics::Candidate], &super::linear::Nested),
    field: &str,
    unread: Vec<AnimalAnswer>,
) -> Vec<AnimalAnswer> {
    if recordings.len() + unread.len() < 2 {
        return Vec::new();
    }
    let each: Vec<AnimalAnswer> = (recordings.iter())
        .map(|r| {
            let one = std::slice::from_ref(r);
            match super::linear::estimate(one, model, settings, whole, names, field) {
                Ok(Ok(mut report)) => {
                    let order = settings.recording.order;
                    let held = r.fit.held_movement;
                    report.verdict = Some(super::verdict::Verdict::of(&report, model, order, held));
                    AnimalAnswer::answered(&report)
                }
                Ok(Err(why)) => AnimalAnswer::refused(&r.name, why.to_string()),
                Err(e) => AnimalAnswer::refused(&r.name, e.to_string()),
            }
        })
        .collect();
    if let Some(k) = each.iter().position(|a| a.refused.is_none()) {
        recordings[..=k].rotate_right(1);
    }
    unread.into_iter().chain(each).collect()
}

/// `report` with the animals' answers alone and the spread of its selected coefficients; each
/// pooled interval widened to hold its random-effects interval over the animals (Hartung–Knapp:
/// t on k − 1 degrees of freedom). Five pooled animals' draws alone covered c′_y in 16 of 20:
/// five units are too few for percentiles, and animals may differ.
pub(super) fn attach(mut report: DiscoverReport, each: Vec<AnimalAnswer>) -> DiscoverReport {
    let selected: Vec<String> = report.selected.iter().map(|t| t.name.clone()).collect();
    report.between = spreads(&selected, &each);
    for b in &report.between {
        let Some([lo, hi]) = b.spread.interval else {
            continue;
        };
        let terms = report.selected.iter_mut().chain(report.library.iter_mut());
        for t in terms.filter(|t| t.name == b.name) {
            t.interval = t.interval.map(|[a, z]| [a.min(lo), z.max(hi)]);
        }
    }
    report.animals = each;
    report
}

/// The spread of each of `selected`'s coefficients over `animals`.
pub(super) fn spreads(selected: &[String], animals: &[AnimalAnswer]) -> Vec<CoefficientSpread> {
    selected
        .iter()
        .filter_map(|name| {
            let each: Vec<(f64, [f64; 2])> = (animals.iter())
                .flat_map(|a| a.selected.iter().filter(|t| &t.name == name))
                .filter_map(|t| Some((t.coefficient, t.interval?)))
                .collect();
            Some(CoefficientSpread {
                name: name.clone(),
                spread: crate::fit::spread_of(&each)?,
            })
        })
        .collect()
}

/// The animals' block of the text report (empty for one recording).
pub(super) fn text(report: &DiscoverReport) -> String {
    if report.animals.is_empty() {
        return String::new();
    }
    let count = |c: Conclusion| {
        (report.animals.iter())
            .filter(|a| a.conclusion == Some(c))
            .count()
    };
    let refused = report
        .animals
        .iter()
        .filter(|a| a.refused.is_some())
        .count();
    let mut out = format!(
        "\nEach animal alone ({} recordings, the same library and estimator): the theory holds in {}, does not hold in {}, undecided in {}, refused {}:\n",
        report.animals.len(),
        count(Conclusion::Holds),
        count(Conclusion::DoesNotHold),
        count(Conclusion::Undecided),
        refused,
    );
    for a in &report.animals {
        let name = crate::markup::clip(&a.recording);
        out += &match (&a.refused, a.conclusion) {
            (Some(why), _) => format!("  {name}: refused: {why}\n"),
            (None, conclusion) => {
                let terms: Vec<String> = (a.selected.iter())
                    .map(|t| {
                        format!(
                            "{} {} {}",
                            t.name,
                            short(t.coefficient),
                            super::report::interval_text(t.interval).trim_end()
                        )
                    })
                    .collect();
                let modes: Vec<String> = a.modes.iter().map(usize::to_string).collect();
                format!(
                    "  {name}: {}{}; {}; modes {}\n",
                    conclusion.map_or("no verdict", Conclusion::words),
                    a.finding
                        .as_ref()
                        .map_or(String::new(), |f| format!(" ({f})")),
                    if terms.is_empty() {
                        "no term selected".to_string()
                    } else {
                        terms.join(", ")
                    },
                    modes.join(", ")
                )
            }
        };
    }
    for c in &report.between {
        let s = &c.spread;
        out += &format!(
            "Between animals, {} (the {} animals that select it): Q = {:.1} on {} degrees of freedom (p {}), I² = {:.0} %, τ = {:.0} % of the mean; random-effects mean {} {}{}\n",
            c.name,
            s.animals,
            s.q,
            s.dof,
            s.p_words(),
            100.0 * s.i2,
            100.0 * s.tau_share,
            short(s.mean),
            super::report::interval_text(s.interval).trim_end(),
            if s.differ {
                ": the animals differ, so the pooled value is the population's mean, not each animal's"
            } else {
                ": the animals agree within their errors"
            }
        );
    }
    out
}
