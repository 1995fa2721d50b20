//! The loop closed: the discovered equation simulated (the onward `simulate` line, in the
//! library) and read back as the recording was, so its modal spectra and variances sit beside
//! the observed ones.
//!
//! The run has the recording's frames, sampling interval and grid, five steps per frame, the
//! onward line's start (the lowest used mode at its rms amplitude, so an undamped body, which
//! the Langevin noise cannot move, still moves), and Langevin noise at the temperature that
//! gives the lowest used mode the observed variance: one run at the onward line's kT (or 1),
//! then kT ← kT·σ²_observed/σ²_simulated (exact in one step for a linear
//! body; a fixed point for a nonlinear one, at most [`MATCH_RUNS`] runs, to
//! [`MATCH_TOLERANCE`]). Each frame's field becomes the tracker's
//! midlines (or segment lengths) with no tracking noise, and `fit` projects it as it did the
//! recording.

use serde::Serialize;

use super::data::Recording;
use super::{DiscoverError, DiscoveredTerm};
use crate::body::{Body, Start};
use crate::dynamics::{Config, Halt, Sample, MAX_WORK};
use crate::fit::{fit_tracks, FitReport, FitSettings};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::{Frame, InputKind, Track};

/// Steps of the simulation per frame of the recording.
pub const STEPS_PER_FRAME: u64 = 5;

/// At most this many runs to match the lowest mode's variance.
pub const MATCH_RUNS: usize = 4;

/// The lowest mode's variance is matched when within this share.
pub const MATCH_TOLERANCE: f64 = 0.02;

/// Observed and simulated spectra and variances of the modes the regression used.
#[derive(Debug, Clone, Serialize)]
pub struct Replay {
    /// Mode indices.
    pub modes: Vec<usize>,
    /// Welch frequencies (cycles per time unit), observed.
    pub frequencies: Vec<f64>,
    /// Observed PSD per mode.
    pub observed: Vec<Vec<f64>>,
    /// Welch frequencies of the simulation.
    pub simulated_frequencies: Vec<f64>,
    /// Simulated PSD per mode.
    pub simulated: Vec<Vec<f64>>,
    /// Observed variance per mode.
    pub observed_variance: Vec<f64>,
    /// Simulated variance per mode.
    pub simulated_variance: Vec<f64>,
    /// The temperature kT of the replay.
    pub temperature: f64,
    /// Frames simulated.
    pub frames: usize,
}

/// The per-mode numbers of a fit for `modes`.
fn picked(fit: &FitReport, modes: &[usize]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let at = |m: usize| fit.modes.iter().position(|x| x.index == m);
    let psd = modes
        .iter()
        .map(|&m| {
            at(m)
                .and_then(|k| fit.psd.get(k).cloned())
                .unwrap_or_default()
        })
        .collect();
    let var = modes
        .iter()
        .map(|&m| at(m).map_or(f64::NAN, |k| fit.modes[k].variance))
        .collect();
    (psd, var)
}

/// The body the onward `simulate` line makes: every library coefficient set (0 where not
/// selected). `simulate` refuses exactly what this refuses (a selection with no stiffness, a
/// stiffness of the wrong sign), so its error is why no onward line is printed.
pub(super) fn discovered_body(
    model: &Model,
    order: u32,
    library: &[DiscoveredTerm],
) -> Result<Body, crate::body::BodyError> {
    let given: Vec<(String, f64)> = library
        .iter()
        .map(|t| (t.name.clone(), if t.selected { t.on_points } else { 0.0 }))
        .collect();
    Body::new(model.clone(), order, None, Params::default(), &given)
}

/// Simulate `library`'s discovered coefficients and fit the run as `rec` was fitted.
pub(super) fn replay(
    rec: &Recording,
    model: &Model,
    leading: &Model,
    settings: &FitSettings,
    library: &[DiscoveredTerm],
    modes: &[usize],
    onward: Option<&super::Onward>,
) -> Result<Replay, DiscoverError> {
    let body = discovered_body(model, settings.recording.order, library)?;
    let points = onward.map_or(rec.fit.model_points, |o| o.points);
    let observed_frames: usize = rec.runs.iter().map(Vec::len).sum();
    // As many frames as the recording had, within the simulation's work budget.
    let per_frame = (points * STEPS_PER_FRAME as usize).max(1) as f64;
    let frames = observed_frames
        .min((MAX_WORK / per_frame / 4.0) as usize)
        .max(2);
    let start = Start {
        initial: onward
            .map(|o| {
                let (field, mode, displacement) = o.initial.clone();
                vec![crate::dynamics::Initial {
                    field,
                    mode,
                    displacement,
                    velocity: 0.0,
                }]
            })
            .unwrap_or_default(),
        ..Start::default()
    };
    let run = |temperature: f64| -> Result<FitReport, DiscoverError> {
        let config = Config {
            points,
            order: settings.recording.order,
            dt: rec.dt / STEPS_PER_FRAME as f64,
            steps: (frames as u64 - 1) * STEPS_PER_FRAME,
            every: STEPS_PER_FRAME,
            temperature,
            seed: 1,
            initial: Vec::new(),
            forcing: Vec::new(),
        };
        let mut track = Track {
            name: "replay".into(),
            frames: Vec::with_capacity(frames),
        };
        let field = rec.fit.field.clone();
        body.simulate(&config, &start, |ids: &[String], s: &Sample| {
            let Some(i) = ids.iter().position(|id| *id == field) else {
                return Err(Halt::Stop);
            };
            track.frames.push(Frame {
                t: s.t,
                values: Some(tracked(settings.recording.kind, &s.positions[i])),
            });
            Ok(())
        })?;
        fit_tracks(vec![track], leading, &Params::default(), settings).map_err(DiscoverError::Fit)
    };
    // The recording's fit measured strains against its first frame; the replay starts at rest,
    // so both are put on the recording's mean segment (`Recording::scale`).
    let (mut observed, mut observed_variance) = picked(&rec.fit, modes);
    let square = rec.scale * rec.scale;
    for v in observed
        .iter_mut()
        .flatten()
        .chain(observed_variance.iter_mut())
    {
        *v *= square;
    }
    // kT ← kT·σ²_observed/σ²_simulated until the lowest mode's variance matches: one step for
    // a linear body (the variance is kT times a constant), a few for a stiffening one.
    let mut temperature = onward.map_or(1.0, |o| o.temperature);
    let mut last = run(temperature)?;
    for _ in 1..MATCH_RUNS {
        let (_, trial) = picked(&last, modes);
        let ratio = observed_variance
            .first()
            .zip(trial.first())
            .map(|(o, s)| o / s)
            .filter(|r| r.is_finite() && *r > 0.0);
        match ratio {
            Some(r) if (r - 1.0).abs() > MATCH_TOLERANCE => {
                temperature *= r;
                last = run(temperature)?;
            }
            _ => break,
        }
    }
    let (simulated, simulated_variance) = picked(&last, modes);
    Ok(Replay {
        modes: modes.to_vec(),
        frequencies: rec.fit.frequencies.clone(),
        observed,
        simulated_frequencies: last.frequencies.clone(),
        simulated,
        observed_variance,
        simulated_variance,
        temperature,
        frames,
    })
}

/// One frame of the field on the grid (spacing units) as a tracker writes it, head first:
/// a midline (s, y) in body lengths with the rigid part removed, or the segment lengths.
fn tracked(kind: InputKind, u: &[f64]) -> Vec<f64> {
    let n = u.len();
    let h = 1.0 / (n as f64 - 1.0);
    match kind {
        InputKind::Midline => {
            let s: Vec<f64> = (0..n).map(|i| i as f64 * h).collect();
            let ms = 0.5;
            let my = u.iter().sum::<f64>() / n as f64 * h;
            let vs: f64 = s.iter().map(|x| (x - ms).powi(2)).sum();
            let b = s.iter().zip(u).map(|(x, y)| (x - ms) * y * h).sum::<f64>() / vs;
            (0..n)
                .rev()
                .flat_map(|i| [s[i], u[i] * h - my - b * (s[i] - ms)])
                .collect()
        }
        InputKind::Lengths => (0..n - 1)
            .rev()
            .map(|i| h * (1.0 + u[i + 1] - u[i]))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equations::ForceKind;

    fn term(name: &str, kind: ForceKind, on_points: f64, selected: bool) -> DiscoveredTerm {
        DiscoveredTerm {
            term: name.into(),
            name: name.into(),
            kind,
            coefficient: on_points,
            on_points,
            interval: None,
            inclusion: None,
            selected,
        }
    }

    /// The onward line is made only of what `simulate` takes: a selection without the bending
    /// stiffness (the line would pass c_y = 0) or with a negative one is refused, with why.
    #[test]
    fn an_equation_simulate_would_refuse_has_no_onward_line() {
        let larva = Model::larva();
        let damping = |on| term("c'_y", ForceKind::Dissipative, 0.1, on);
        let stiffness = |v| term("c_y", ForceKind::Conservative, v, true);
        let without = [
            term("c_y", ForceKind::Conservative, 0.0, false),
            damping(true),
        ];
        let Err(e) = discovered_body(&larva, 4, &without) else {
            panic!("a selection without c_y is refused")
        };
        assert!(e.to_string().contains("c_y"), "{e}");
        let negative = [stiffness(-2.0), damping(true)];
        assert!(discovered_body(&larva, 4, &negative).is_err());
        let passive = [stiffness(2.0), damping(true)];
        assert!(discovered_body(&larva, 4, &passive).is_ok());
    }
}
