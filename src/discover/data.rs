//! A recording as `discover` reads it: `fit` reads and projects every frame (the trackers'
//! formats, lost frames, bridged gaps), and each frame's posture is put back on the model's
//! points ([`crate::fit::Projector::posture`]); runs split where frames are lost.

use super::DiscoverError;
use crate::fit::{fit_inputs, FitReport, FitSettings, Input, Projector, SinkError};
use crate::modal::Params;
use crate::model::Model;

/// At most this many frames × points are held (postures are kept in memory).
pub const MAX_VALUES: usize = 50_000_000;

/// One animal's frames on the model's points.
#[derive(Debug, Clone)]
pub(super) struct Recording {
    /// Its name in reports.
    pub name: String,
    /// The sampling interval.
    pub dt: f64,
    /// Runs of consecutive frames, each a list of postures on the model's points.
    pub runs: Vec<Vec<Vec<f64>>>,
    /// The grid's non-zero mode shapes on the model's points.
    pub shapes: Vec<Vec<f64>>,
    /// The index of the first of them (zero modes counted).
    pub first_mode: usize,
    /// The fit of the same recording (modes, resolution, tracking noise).
    pub fit: FitReport,
}

/// Read one input.
pub(super) fn read(
    input: Input<'_>,
    name: String,
    model: &Model,
    settings: &FitSettings,
) -> Result<Recording, DiscoverError> {
    let mut frames: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut shapes: Option<Vec<Vec<f64>>> = None;
    let mut first_mode = 0;
    let mut partial = false;
    let mut too_many = false;
    let mut each = |p: &Projector, t: f64, q: &[f64]| -> Result<(), SinkError> {
        if shapes.is_none() {
            shapes = Some(p.shapes.clone());
            first_mode = p.first_mode;
        }
        match p.posture(q) {
            Some(posture) if (frames.len() + 1) * posture.len() <= MAX_VALUES => {
                frames.push((t, posture))
            }
            Some(_) => too_many = true,
            None => partial = true,
        }
        Ok(())
    };
    let fit = fit_inputs(
        vec![input],
        model,
        &Params::default(),
        settings,
        Some(&mut each),
    )
    .map_err(DiscoverError::Fit)?;
    if partial {
        return Err(DiscoverError::PartialRing);
    }
    if too_many {
        return Err(DiscoverError::TooLarge { max: MAX_VALUES });
    }
    let dt = fit.sample_interval;
    let mut runs: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut last = f64::NEG_INFINITY;
    for (t, posture) in frames {
        // A step longer than one interval (within the reader's 1 %) is a gap.
        if t - last > 1.5 * dt || runs.is_empty() {
            runs.push(Vec::new());
        }
        last = t;
        if let Some(run) = runs.last_mut() {
            run.push(posture);
        }
    }
    Ok(Recording {
        name,
        dt,
        runs,
        shapes: shapes.unwrap_or_default(),
        first_mode,
        fit,
    })
}
