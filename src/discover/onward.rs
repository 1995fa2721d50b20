//! The onward `simulate` line: the discovered equation run as the recording was taken.
//!
//! The line sets every library coefficient (0 where not selected, by the model's ASCII alias,
//! `cp_y` for `c'_y`, where there is one) and replays the recording: its frames (within
//! `simulate`'s work budget) at its frame interval (`--every K` steps of `--dt` each, K the
//! fewest that keep ωh ≤ [`MAX_PHASE_STEP`] for the fastest mode the regression used), at the
//! equipartition temperature of the modes used (kT = the mean of ωᵢ²σᵢ² weighted by each σᵢ²'s
//! precision, the discovered body's ωᵢ and the recording's modal variances σᵢ², as `fit`'s β;
//! the grid body's coefficients are those nearest the continuum estimate, so its ωᵢ are the
//! recording's, `galerkin::nearest_on_grid`), and with the lowest mode used
//! started at its thermal rms amplitude √kT/ωᵢ, so the first rows are not a body at rest. What
//! `simulate` would refuse is never printed: the report says why instead.

use serde::Serialize;

use super::data::Recording;
use super::report::{short, DiscoverReport};
use super::verdict::Next;
use crate::body::{Body, BodyModes};
use crate::dynamics::MAX_WORK;
use crate::markup::{command_line, shell_word};
use crate::model::Model;
use crate::report::number;

/// The largest ωh of a step for the fastest mode used.
pub const MAX_PHASE_STEP: f64 = 0.2;

/// At most this many rows (frames) in the replay: a longer recording is replayed in its first
/// ones (the line's CSV stays under about 50 MB).
pub const MAX_ROWS: usize = 10_000;

/// How the onward line replays the recording.
#[derive(Debug, Clone, Serialize)]
pub struct Onward {
    /// Each library coefficient's name as `--param` takes it (the library's order).
    pub names: Vec<String>,
    /// The step, the recording's frame interval over `every`.
    pub dt: f64,
    /// Steps between written rows: one row per frame of the recording.
    pub every: u64,
    /// Steps: the recording's frames (at most [`MAX_ROWS`], within the work budget) less one,
    /// times `every`.
    pub steps: u64,
    /// The recording's frames.
    pub frames: usize,
    /// The grid it runs on (`--points`): the report's `replay_points`.
    pub points: usize,
    /// kT, the equipartition temperature of the modes used.
    pub temperature: f64,
    /// The lowest mode used, started at √kT/ωᵢ: (field, mode, displacement).
    pub initial: (String, usize, f64),
}

/// The name `--param` takes without quoting: the ASCII alias (`cp_y`, `cp1_x`) of a name with a
/// prime, where the model's fields give one; the name itself otherwise.
fn ascii_name(name: &str, model: &Model) -> String {
    let alias = name.rsplit_once('_').and_then(|(letter, symbol)| {
        let field = model.fields.iter().find(|f| f.symbol == symbol)?;
        let alias = format!("{}_{}", letter.replace('\'', "p"), field.id);
        alias
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_')
            .then_some(alias)
    });
    alias.unwrap_or_else(|| name.to_string())
}

/// Why the discovered equation gets no onward `simulate` line (the report says so instead).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OnwardRefusal {
    /// `simulate` refuses the body the discovered equation makes.
    #[error("simulate refuses the discovered equation ({0})")]
    Simulate(String),
    /// No mode was used.
    #[error("no mode was used, so no temperature can be measured")]
    NoModes,
    /// The body's modes failed.
    #[error("its modes cannot be computed ({0})")]
    Modes(String),
    /// None of the modes used has a real frequency.
    #[error("the discovered equation has no restoring force on the modes used ({used}; none has a real frequency): no temperature can be measured and a replay would drift")]
    NoRestoringForce {
        /// The modes used, listed.
        used: String,
    },
    /// The variances give no finite temperature.
    #[error("the recording's modal variances give no finite temperature")]
    NoTemperature,
}

/// The replay of `rec` by `body` (the discovered equation), or why `simulate` cannot give one.
pub(super) fn onward(
    report: &DiscoverReport,
    rec: &Recording,
    model: &Model,
    body: &Body,
) -> Result<Onward, OnwardRefusal> {
    let used: Vec<usize> = report.modes.iter().map(|m| m.0).collect();
    let Some(&highest) = used.iter().max() else {
        return Err(OnwardRefusal::NoModes);
    };
    let field = &report.field;
    let modes = body
        .modes(report.replay_points, Some(highest + 1), false)
        .map_err(|e| OnwardRefusal::Modes(crate::markup::one_line(&e.to_string())))?;
    let frequencies: Vec<Option<f64>> = match modes {
        BodyModes::Exact(fields) => fields
            .into_iter()
            .find(|f| f.field.id == *field)
            .map(|f| f.modes.iter().map(|m| Some(m.frequency)).collect()),
        BodyModes::Linearised(fields) => fields
            .into_iter()
            .find(|f| f.field == *field)
            .map(|f| f.frequencies),
    }
    .unwrap_or_default();
    // (ωᵢ, σᵢ², weight) of each mode used with a real frequency and a measured variance: the
    // spectral fit's σ² (tracking noise removed) weighted by its precision (σ²/se)², else the
    // projected variance with equal weights.
    let spectral = |m: usize| {
        let f = rec.fit.modes_fit.iter().find(|x| x.mode == m)?;
        let se = f.variance_error.filter(|e| *e > 0.0 && e.is_finite())?;
        (f.variance > 0.0).then_some((f.variance, (f.variance / se).powi(2)))
    };
    let weighted = used.iter().all(|&m| spectral(m).is_some());
    // On a finer grid than the recording's, each variance in its units (the used modes are the
    // first non-zero ones, in order).
    let gains = match report.replay_points == report.points {
        true => None,
        false => match &rec.basis {
            super::data::Basis::Continuum { gains, .. } => gains.get(..used.len()).and_then(|g| {
                let at = (report.order, field.as_str());
                super::galerkin::replay_gains(model, at, g, report.replay_points)
            }),
            super::data::Basis::Grid => None,
        },
    };
    let gain = |m: usize| {
        let at = used.iter().position(|&u| u == m);
        at.and_then(|j| gains.as_ref().map(|g| g[j])).unwrap_or(1.0)
    };
    let pairs: Vec<(usize, f64, f64, f64)> = used
        .iter()
        .filter_map(|&m| {
            let omega = frequencies.get(m).copied().flatten()?;
            let (variance, weight) = match spectral(m) {
                Some(read) if weighted => read,
                _ => (rec.fit.modes.iter().find(|x| x.index == m)?.variance, 1.0),
            };
            let variance = variance * (rec.scale * gain(m)).powi(2);
            (omega > 0.0 && omega.is_finite() && variance > 0.0 && variance.is_finite())
                .then_some((m, omega, variance, weight))
        })
        .collect();
    let Some(&(lowest, omega_low, _, _)) = pairs.first() else {
        return Err(OnwardRefusal::NoRestoringForce {
            used: used
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", "),
        });
    };
    let temperature = pairs.iter().map(|&(_, w, v, p)| p * w * w * v).sum::<f64>()
        / pairs.iter().map(|p| p.3).sum::<f64>();
    let fastest = pairs.iter().map(|p| p.1).fold(0.0, f64::max);
    let every = (fastest * rec.dt / MAX_PHASE_STEP).ceil().max(1.0);
    if !(temperature.is_finite() && every.is_finite() && every < 1e6) {
        return Err(OnwardRefusal::NoTemperature);
    }
    let every = every as u64;
    // As many frames as the recording had, within half of simulate's budget (its work is
    // steps × modes + rows × values, about (every + 3) × fields × points a frame).
    let recorded: usize = rec.runs.iter().map(Vec::len).sum();
    let per_frame =
        ((every + 3) as usize * model.fields.len() * report.replay_points).max(1) as f64;
    let frames = recorded
        .min(MAX_ROWS)
        .min((MAX_WORK / 2.0 / per_frame) as usize)
        .max(2);
    Ok(Onward {
        names: report
            .library
            .iter()
            .map(|t| ascii_name(&t.name, model))
            .collect(),
        dt: rec.dt / every as f64,
        every,
        steps: (frames as u64 - 1) * every,
        frames: recorded,
        points: report.replay_points,
        temperature,
        initial: (field.clone(), lowest, temperature.sqrt() / omega_low),
    })
}

impl DiscoverReport {
    /// `Next: …`: what to run after the verdict, from the recordings and reading options as the
    /// command line gave them.
    pub fn next_line(&self, next: Next) -> String {
        let discover = |order: u32| {
            let line = command_line("discover", &self.inputs, self.model_argument.as_deref());
            format!("{line} --order {order}")
        };
        match next {
            Next::Replay if self.onward_refused.is_none() => {
                "Next: the Onward line below runs the discovered body as the recording was taken.\n"
                    .into()
            }
            Next::Replay => "Next: nothing to run (the Onward line below says why).\n".into(),
            Next::Active => format!(
                "Next: {} --active (the forces the passive library lacks: active and gyroscopic)\n",
                discover(self.order)
            ),
            Next::Layer {
                order,
                beyond_leading,
                linear,
            } => format!(
                "Next: {}{} --beyond-leading {beyond_leading} (the next layer of the expansion{})\n",
                discover(order),
                if self.active { " --active" } else { "" },
                if linear {
                    ""
                } else {
                    "; nonlinear there, so the weak form estimates it, which needs ≥ 19 frames a period of the slowest mode and many windows"
                }
            ),
            Next::MoreData => {
                "Next: more frames or animals (no term is kept in more than half of the draws).\n"
                    .into()
            }
        }
    }

    /// The onward `simulate` line: every library coefficient set (0 where not selected), and
    /// with [`Onward`] (set by `discover`) the recording's replay.
    pub fn simulate_line(&self) -> String {
        let mut line = String::from("theory-search simulate");
        if let Some(m) = &self.model_argument {
            line += &format!(" --model {}", shell_word(m));
        }
        line += &format!(" --order {}", self.order);
        if self.beyond_leading > 0 {
            line += &format!(" --beyond-leading {}", self.beyond_leading);
        }
        line += &format!(" --points {}", self.replay_points);
        match &self.onward {
            Some(o) => {
                let (field, mode, q) = &o.initial;
                line += &format!(
                    " --dt {} --every {} --steps {} --temperature {} --initial {}",
                    number(o.dt),
                    o.every,
                    o.steps,
                    short(o.temperature),
                    shell_word(&format!("{field}:{mode}={}", short(*q)))
                );
            }
            None => line += &format!(" --dt {}", number(self.dt)),
        }
        for (i, t) in self.library.iter().enumerate() {
            let v = if t.selected { t.on_points } else { 0.0 };
            let name = self
                .onward
                .as_ref()
                .and_then(|o| o.names.get(i))
                .unwrap_or(&t.name);
            line += &format!(" --param {}", shell_word(&format!("{name}={}", short(v))));
        }
        line
    }

    /// What the onward line replays, in words.
    pub(super) fn onward_words(&self) -> Option<String> {
        let o = self.onward.as_ref()?;
        let (_, mode, _) = &o.initial;
        let rows = o.steps / o.every + 1;
        let which = if rows as usize >= o.frames {
            "the recording".to_string()
        } else {
            format!("the first {rows} of the recording's {} frames", o.frames)
        };
        let grid = match self.replay_points == self.points {
            true => String::new(),
            false => format!(
                " on {} points (the continuum coefficients' nearest grid: the recording's {} are too coarse a lattice for the body's modes)",
                self.replay_points, self.points
            ),
        };
        Some(format!(
            "(replays {which}{grid}: rows Δt = {}{} apart, kT = {} from equipartition over modes {}, mode {mode} started at its rms amplitude; ωh ≤ {MAX_PHASE_STEP} for the fastest mode)",
            number(self.dt),
            self.time_unit
                .as_ref()
                .map_or(String::new(), |u| format!(" {u}")),
            short(o.temperature),
            self.modes
                .iter()
                .map(|m| m.0.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_primed_name_is_given_by_its_ascii_alias() {
        let larva = Model::larva();
        assert_eq!(ascii_name("c'_y", &larva), "cp_y");
        assert_eq!(ascii_name("c_y", &larva), "c_y");
        assert_eq!(ascii_name("unknown'", &larva), "unknown'");
    }
}
