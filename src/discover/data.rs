//! A recording as `discover` reads it: `fit` reads and projects every frame (the trackers'
//! formats, lost frames, bridged gaps), and each frame's posture is put back on the model's
//! points ([`crate::fit::Projector::posture`]); runs split where frames are lost.

use super::DiscoverError;
use crate::fit::{fit_inputs, FitReport, FitSettings, Input, SinkError};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::Projector;

/// At most this many frames × points are held over every recording (postures are kept in
/// memory).
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
    /// The strains' factor from `fit`'s reference length to the recording's mean one
    /// ([`Restrain`]; 1 for midlines): the fit's modal amplitudes times this are the postures'.
    pub scale: f64,
    /// Each frame's time and modal coordinates as the projector gives them, in time order.
    pub modal: Vec<(f64, Vec<f64>)>,
    /// How the coordinates read the body's modes ([`Basis`]).
    pub basis: Basis,
    /// The covariance between the coordinates (as `mode_data` reads them: divided by their
    /// gains) of white noise of unit variance on every tracked coordinate of a body of unit
    /// length; `None` for lengths.
    pub noise: Option<nalgebra::DMatrix<f64>>,
}

/// What the modal coordinates measure.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Basis {
    /// The leading `gains.len()` coordinates are the body's continuum modes, coordinate j
    /// reading its continuum amplitude (body lengths, unit-mean-square shapes) times
    /// `gains[j]`; the field's stencil and boundary give the shapes.
    Continuum {
        gains: Vec<f64>,
        stencil: u32,
        boundary: crate::boundary::Boundary,
    },
    /// The grid's unit-norm modes.
    Grid,
}

impl Basis {
    /// Coordinate j's gain on its continuum mode (1 past them and on the grid).
    pub fn gain(&self, j: usize) -> f64 {
        match self {
            Basis::Continuum { gains, .. } => gains.get(j).copied().unwrap_or(1.0),
            Basis::Grid => 1.0,
        }
    }
}

/// Read one input, `held` values already held by the recordings before it.
pub(super) fn read(
    input: Input<'_>,
    name: String,
    model: &Model,
    settings: &FitSettings,
    held: usize,
) -> Result<Recording, DiscoverError> {
    let mut frames: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut shapes: Option<Vec<Vec<f64>>> = None;
    let mut first_mode = 0;
    let mut partial = false;
    let mut too_many = false;
    let mut restrain = Restrain::default();
    let mut modal: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut basis = Basis::Grid;
    let mut noise = None;
    let mut each = |p: &Projector, t: f64, q: &[f64]| -> Result<(), SinkError> {
        if shapes.is_none() {
            shapes = Some(p.shapes.clone());
            first_mode = p.first_mode;
            restrain = Restrain::of(p);
            basis = basis_of(p);
            noise = tracking_shape(p, &basis);
        }
        modal.push((t, q.to_vec()));
        restrain.add(q);
        match p.posture(q) {
            Some(posture) if held + (frames.len() + 1) * posture.len() <= MAX_VALUES => {
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
    let scale = restrain.apply(&mut frames);
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
        scale,
        modal,
        basis,
        noise,
    })
}

/// White tracking noise's covariance between `p`'s coordinates, each divided by its gain in
/// `basis`.
fn tracking_shape(p: &Projector, basis: &Basis) -> Option<nalgebra::DMatrix<f64>> {
    let c = p.noise_covariance()?;
    let r = nalgebra::DMatrix::from_fn(c.nrows(), c.ncols(), |i, j| {
        c[(i, j)] / (basis.gain(i) * basis.gain(j))
    });
    r.iter().all(|v| v.is_finite()).then_some(r)
}

/// The basis of `p`'s coordinates: its leading continuum ones with their gains, or the grid's.
fn basis_of(p: &Projector) -> Basis {
    let gains: Vec<f64> = p
        .continuum_gains()
        .into_iter()
        .take(p.continuum_modes)
        .map_while(|g| g)
        .collect();
    if gains.is_empty() {
        Basis::Grid
    } else {
        Basis::Continuum {
            gains,
            stencil: p.stencil,
            boundary: p.boundary,
        }
    }
}

impl Recording {
    /// Frames × points held.
    pub fn values(&self) -> usize {
        self.runs.iter().flatten().map(Vec::len).sum()
    }
}

/// Lengths of a free chain are read as strains against the first frame's mean segment ℓ₀
/// (`fit` streams, so it takes the first frame's). A uniform strain offset is harmless to a
/// linear theory but not to a nonlinear one ((e + e₀)³ has a square term), so `discover`,
/// which holds every frame, measures them against the mean over all frames ℓ̄ instead:
/// ê = L/ℓ₀ − 1 becomes e = L/ℓ̄ − 1 = a·ê + (a − 1) with a = ℓ₀/ℓ̄ = 1/(1 + ⟨ê⟩). Postures
/// are linear in the strains, so x = a·x̂ + (a − 1)·P(1), P(1) the posture of unit strain.
#[derive(Debug, Default)]
struct Restrain {
    /// Each mode's mean observation (its design row's mean): ⟨ê⟩ of a frame is Σ qⱼ·this.
    means: Vec<f64>,
    /// The posture of unit strain everywhere.
    unit: Vec<f64>,
    /// Σ over frames of the frame's mean strain, and frames.
    sum: f64,
    frames: f64,
}

impl Restrain {
    /// For a projector of lengths against a fixed rest length; inert otherwise (midlines, or
    /// a ring's lengths, each frame divided by its own mean).
    fn of(p: &Projector) -> Restrain {
        if p.kind != crate::recording::InputKind::Lengths || p.reference_length.is_none() {
            return Restrain::default();
        }
        let mean = |row: &Vec<f64>| row.iter().sum::<f64>() / row.len().max(1) as f64;
        let ones: Vec<f64> = p.rows.iter().map(|r| r.iter().sum()).collect();
        match p.posture(&ones) {
            Some(unit) => Restrain {
                means: p.design.iter().map(mean).collect(),
                unit,
                ..Restrain::default()
            },
            None => Restrain::default(),
        }
    }

    fn add(&mut self, q: &[f64]) {
        if self.unit.is_empty() {
            return;
        }
        self.sum += q.iter().zip(&self.means).map(|(a, b)| a * b).sum::<f64>();
        self.frames += 1.0;
    }

    /// Re-measure `frames`; returns a (1 when inert).
    fn apply(&self, frames: &mut [(f64, Vec<f64>)]) -> f64 {
        if self.unit.is_empty() || self.frames == 0.0 {
            return 1.0;
        }
        let a = 1.0 / (1.0 + self.sum / self.frames);
        if !a.is_finite() || a <= 0.0 {
            return 1.0;
        }
        for (_, posture) in frames.iter_mut() {
            for (x, u) in posture.iter_mut().zip(&self.unit) {
                *x = a * *x + (a - 1.0) * u;
            }
        }
        a
    }
}
