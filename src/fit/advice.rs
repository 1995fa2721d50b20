//! What would decide the tests when they are undetermined: for each mode that does not vote,
//! lowest first, the change to this recording or its options that its note points to, with
//! numbers from the recording (`f` the mode's fitted frequency Ω/2π, `f_s` the frame rate, `W`
//! the Welch window in frames, `T = f_s/f` its period in frames):
//! * under [`RESOLVED_BINS`] bins above zero (`f < RESOLVED_BINS·f_s/W`): a window of
//!   `W' = ⌈W·RESOLVED_BINS/bins⌉` frames; Welch needs ≥ 4 half-overlapping segments, so
//!   `⌈2.5 W'⌉` frames in runs. With lost frames, the exact likelihood needs a run of half a
//!   period (`fit/timedomain.rs`); the advice asks for a whole one, `⌈T⌉`, since `f` is then
//!   the unresolved estimate: the least `--fill-gaps K` that joins runs that long
//!   ([`super::bridging::smallest`]), with the share of frames it would synthesise, or runs of
//!   `⌈T⌉` frames;
//! * near or above Nyquist (an alias, or a line past it): a frame rate at which its line
//!   `f(1 + 3ζ)` lies under 0.4 `f_s` (0.8 × Nyquist, where the exact fit tells it from its
//!   alias);
//! * not resolved by the model's grid: twice the model's points (`--points`), up to the
//!   tracked ones, or more tracked points.
//!
//! Modes whose note no option changes (over-damped, under the white floor, a leak) are left
//! out. Each test needs [`NEEDED`] voting modes.

use super::bridging::{smallest, Bridge};
use super::note::{ModeNote, RESOLVED_BINS};
use super::report::FitReport;
use super::timedomain::Series;
use super::verdict::Verdict;
use crate::report::fixed;
use std::fmt;

/// Voting modes a test needs.
const NEEDED: usize = 3;

/// What would decide the undetermined tests.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Advice {
    /// Modes voting now.
    pub voting: usize,
    /// Modes a test needs.
    pub needed: usize,
    /// For each mode that does not vote and an option could change: what would.
    pub steps: Vec<Step>,
    /// The time unit of the frame rates.
    pub time_unit: String,
}

/// One change that would bring `mode` into the vote.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "change", rename_all = "snake_case")]
pub enum Step {
    /// A longer `--window` (the recording holds it).
    Window {
        /// The mode.
        mode: usize,
        /// The window, in frames.
        frames: usize,
    },
    /// `--fill-gaps K`.
    FillGaps {
        /// The mode.
        mode: usize,
        /// K.
        fill_gaps: usize,
        /// The longest run it makes, in frames.
        longest: usize,
        /// The run the mode needs (its period), in frames.
        needed: usize,
        /// The share of the frames used then synthesised.
        share: f64,
    },
    /// A longer recording.
    Frames {
        /// The mode.
        mode: usize,
        /// Frames in all.
        frames: usize,
        /// The least run, in frames.
        run: usize,
    },
    /// A faster frame rate.
    Rate {
        /// The mode.
        mode: usize,
        /// The least rate, per time unit.
        rate: f64,
        /// The recording's.
        now: f64,
    },
    /// More points on the model.
    Points {
        /// The mode.
        mode: usize,
        /// `--points N` (≤ the tracked points), or 0 when the model already uses them all:
        /// more tracked points.
        points: usize,
        /// The tracked points.
        tracked: usize,
    },
}

/// Whether any test is undetermined.
fn undetermined(report: &FitReport) -> bool {
    let t = &report.tests;
    [&t.equipartition, &t.dispersion, &t.damping]
        .iter()
        .any(|x| x.verdict == Verdict::Undetermined)
}

/// The advice for `report`, whose animals' series are `series`; `None` when every test is
/// decided.
pub(super) fn of(report: &FitReport, series: &[Series]) -> Option<Advice> {
    if !undetermined(report) {
        return None;
    }
    let fs = 1.0 / report.sample_interval;
    let (window, rec) = (report.welch.0, &report.recording);
    let tau = 2.0 * std::f64::consts::PI;
    let step = |m: &super::verdict::ModeSpectralFit| -> Option<Step> {
        let (mode, f) = (m.mode, m.omega / tau);
        match m.note.as_ref()? {
            ModeNote::TooFewBins { bins } if *bins > 0.0 && f > 0.0 => {
                let frames = (window as f64 * RESOLVED_BINS / bins).ceil() as usize;
                let run = (fs / f).ceil() as usize;
                if rec.gaps == 0 && report.frames as f64 >= 2.5 * frames as f64 {
                    return Some(Step::Window { mode, frames });
                }
                if rec.gaps == 0 {
                    let frames = (2.5 * frames as f64).ceil() as usize;
                    return Some(Step::Frames { mode, frames, run });
                }
                Some(match smallest(series, rec, report.frames, run) {
                    Some(Bridge {
                        fill_gaps,
                        longest,
                        share,
                    }) => Step::FillGaps {
                        mode,
                        fill_gaps,
                        longest,
                        needed: run,
                        share,
                    },
                    None => Step::Frames {
                        mode,
                        frames: report.frames.max(run),
                        run,
                    },
                })
            }
            // An alias's own frequency is unknown: the λ law's, from the mode below it.
            ModeNote::Alias { below } => {
                let b = report.modes_fit.iter().find(|b| b.mode == *below)?;
                let f = b.omega / tau * (m.lambda / b.lambda).sqrt();
                Some(Step::Rate {
                    mode,
                    rate: f / 0.4,
                    now: fs,
                })
            }
            ModeNote::AboveNyquist
            | ModeNote::NearAlias
            | ModeNote::LinePastNyquist
            | ModeNote::BroadNearNyquist { .. } => Some(Step::Rate {
                mode,
                rate: f * (1.0 + 3.0 * m.zeta.min(1.0)) / 0.4,
                now: fs,
            }),
            ModeNote::GridOff { .. } | ModeNote::Mixed { .. } => Some(Step::Points {
                mode,
                // None (0) when the model already uses every tracked point.
                points: if report.model_points < report.points {
                    (2 * report.model_points).min(report.points)
                } else {
                    0
                },
                tracked: report.points,
            }),
            _ => None,
        }
    };
    let voting = report.modes_fit.iter().filter(|m| m.votes).count();
    let mut steps: Vec<Step> = Vec::new();
    for s in report
        .modes_fit
        .iter()
        .filter(|m| !m.votes)
        .filter_map(step)
    {
        // More points serve every mode the grid misses, and a faster rate brings the modes
        // under Nyquist lowest first: each said once, for the lowest mode.
        let kind = std::mem::discriminant(&s);
        let again = matches!(s, Step::Points { .. } | Step::Rate { .. })
            && steps.iter().any(|t| std::mem::discriminant(t) == kind);
        if !again {
            steps.push(s);
        }
    }
    Some(Advice {
        voting,
        needed: NEEDED,
        steps,
        time_unit: (report.units.time.as_deref())
            .unwrap_or("time unit")
            .to_string(),
    })
}

impl Step {
    /// The option of `fit` that makes this change (`--window 29`), where one does.
    pub(super) fn option(&self) -> Option<String> {
        match self {
            Step::Window { frames, .. } => Some(format!("--window {frames}")),
            Step::FillGaps { fill_gaps, .. } => Some(format!("--fill-gaps {fill_gaps}")),
            Step::Points { points, .. } if *points > 0 => Some(format!("--points {points}")),
            _ => None,
        }
    }

    /// In words, frame rates per `unit`.
    fn words(&self, unit: &str) -> String {
        let f = &mut String::new();
        // Writing to a String cannot fail.
        let _ = self.write(f, unit);
        std::mem::take(f)
    }

    fn write(&self, f: &mut impl fmt::Write, unit: &str) -> fmt::Result {
        match self {
            Step::Window { mode, frames } => write!(f, "mode {mode}: --window {frames}"),
            Step::FillGaps {
                mode,
                fill_gaps,
                longest,
                needed,
                share,
            } => write!(
                f,
                "mode {mode}: --fill-gaps {fill_gaps} (a run of {longest} frames, its period {needed}; {} % of the frames synthesised)",
                fixed(100.0 * share, 1)
            ),
            Step::Frames { mode, frames, run } => write!(
                f,
                "mode {mode}: a recording of ≥ {frames} frames in runs of ≥ {run} frames (its period)"
            ),
            Step::Rate { mode, rate, now } => write!(
                f,
                "mode {mode}: a frame rate ≥ {} per {unit} (now {})",
                fixed(*rate, 1),
                fixed(*now, 1)
            ),
            Step::Points {
                mode,
                points,
                tracked,
            } if *points > 0 => {
                write!(f, "mode {mode}: --points {points}")
            }
            Step::Points { mode, tracked, .. } => {
                write!(f, "mode {mode}: more than {tracked} tracked points")
            }
        }
    }
}

impl fmt::Display for Advice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "to decide the tests ({} voting mode(s), {} needed): ",
            self.voting, self.needed
        )?;
        if self.steps.is_empty() {
            return write!(
                f,
                "no option names one: the modes out of the vote are over-damped, not converged, under the white floor or leaks (their notes say which); a longer recording adds frames to every fit"
            );
        }
        let steps: Vec<String> = (self.steps.iter())
            .map(|s| s.words(&self.time_unit))
            .collect();
        write!(f, "{}", steps.join("; "))
    }
}
