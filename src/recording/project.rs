//! From a frame to modal coordinates: resampling, turning angles or strains, and the
//! projector onto the field's modes (the observation map of the module header); for a field
//! with continuum modes, the projector on those (`continuum`).

use super::continuum::{Grid, CONTINUUM_AMPLITUDE};
use std::borrow::Cow;

use super::held::HeldPoints;
use super::observe::{observe, segment_angles, size, sizes};
pub use super::observe::{turning_angles, FrameError};
use super::{InputKind, LineWhy, RecordingError, RecordingSettings, MAX_POINTS};
use crate::modal::{field_modes, Params};
use crate::model::Model;

/// Work space of [`Projector::project_into`].
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    segments: Vec<(f64, f64)>,
    angles: Vec<f64>,
    sizes: Vec<f64>,
}

/// Work space of a projection: the projector's, and the modal coordinates.
pub(crate) type Work = (Scratch, Vec<f64>);

/// The N-point projector's rows: the S vⱼ are orthogonal with |S vⱼ|² = λⱼ, so
/// Qⱼ = (S vⱼ)·o/λⱼ.
fn lattice_rows(design: &[Vec<f64>], lambdas: &[f64]) -> Vec<Vec<f64>> {
    design
        .iter()
        .zip(lambdas)
        .map(|(d, l)| d.iter().map(|x| x / l).collect())
        .collect()
}

/// A frame in the model's order (tail first): as read, or [`reversed`] when read head first.
pub(crate) fn tail_first(kind: InputKind, values: &[f64], head_first: bool) -> Cow<'_, [f64]> {
    if head_first {
        Cow::Owned(reversed(kind, values))
    } else {
        Cow::Borrowed(values)
    }
}

/// A frame listed head first, reordered head last (the model's orientation): points (x, y)
/// pairs for midlines, segments for lengths.
pub(crate) fn reversed(kind: InputKind, values: &[f64]) -> Vec<f64> {
    match kind {
        InputKind::Midline => values.chunks(2).rev().flatten().copied().collect(),
        InputKind::Lengths => values.iter().rev().copied().collect(),
    }
}

/// The map from one frame's values to the modal coordinates of the observed field's non-zero
/// modes: Qⱼ = (S vⱼ)·o/λⱼ (see the module header).
#[derive(Debug, Clone)]
pub struct Projector {
    /// Input kind.
    pub kind: InputKind,
    /// Points (midline) or segments (lengths) per input frame.
    pub input_points: usize,
    /// Model points N.
    pub points: usize,
    /// The observed field's id.
    pub field: String,
    /// The observed field's scale suffix.
    pub scale: String,
    /// Index of the first non-zero mode.
    pub first_mode: usize,
    /// λⱼ of the non-zero modes.
    pub eigenvalues: Vec<f64>,
    /// The row of the least-squares solve for each fitted mode, over the observations:
    /// (S vⱼ)/λⱼ when the observations cover the body.
    pub rows: Vec<Vec<f64>>,
    /// (S vⱼ) over the observations, for each fitted mode.
    pub design: Vec<Vec<f64>>,
    /// The non-zero mode shapes on the model's points.
    pub shapes: Vec<Vec<f64>>,
    /// Lengths: the rest length strains are measured against (`fit` takes the first frame's
    /// mean). `None` divides each frame by its own mean, which is exact on a closed ring but
    /// hides the total stretch of a free chain.
    pub reference_length: Option<f64>,
    /// The observed field's stencil order k (1: a string or ring, 2: a beam).
    pub stencil: u32,
    /// The observed field's boundary (for the continuum roots).
    pub boundary: crate::boundary::Boundary,
    /// S vⱼ of the grid's modes over the observations (`None` for part of a ring).
    pub lattice: Option<Vec<Vec<f64>>>,
    /// How many leading coordinates are the body's continuum modes' (the rest are the N-point
    /// modes'): the most whose projection keeps tracking noise within twice the N-point gain.
    pub continuum_modes: usize,
    /// [`Projector::mixed_shares`], derived once: a fit's every bootstrap draw asks for them.
    mixed: Vec<Option<f64>>,
    /// Points held at (tail, head) on the model's N points (none for lengths).
    pub(super) held_counts: (usize, usize),
    /// The held points every frame is observed with (the animal's reference frame's).
    pub(super) held: Option<HeldPoints>,
}

impl Projector {
    /// The projector for frames of `width` values after time.
    pub fn new(
        model: &Model,
        params: &Params,
        settings: &RecordingSettings,
        width: usize,
    ) -> Result<Projector, RecordingError> {
        let invalid = |s: String| RecordingError::Invalid(s);
        let (k_in, n) = dimensions(settings, width)?;
        let field_index = observed_field(model, settings)?;
        // Only the observed field's modes: another field's limits must not refuse this fit.
        let all = field_modes(
            &model.only(field_index),
            settings.order,
            n,
            params,
            None,
            true,
        )?;
        let fm = &all[0];
        let shapes = fm
            .spectrum
            .shapes
            .as_ref()
            .ok_or_else(|| invalid("no mode shapes".into()))?;
        let rows = crate::discretise::stencil_rows(fm.k, fm.field.boundary, n)?;
        let expected = match settings.kind {
            InputKind::Midline => n - 2,
            InputKind::Lengths => n - 1,
        };
        if rows.len() != expected {
            return Err(invalid(format!(
            "field {} ({}, k = {}) has {} difference rows on {n} points, but the {} give {expected} observations",
            fm.field.id,
            fm.field.boundary,
            fm.k,
            rows.len(),
            match settings.kind {
                InputKind::Midline => "turning angles",
                InputKind::Lengths => "segment strains",
            }
        )));
        }
        let first_mode = fm.spectrum.nullity;
        // Stencil rows index the unknowns; shapes are on the body, after the held tail points.
        let held = fm.spectrum.held.0;
        let size = shapes.nrows();
        let m = fm.spectrum.size - first_mode;
        if m == 0 {
            return Err(invalid("the field has no non-zero modes".into()));
        }
        let all_lambdas: Vec<f64> = fm.spectrum.eigenvalues[first_mode..].to_vec();
        // The observed rows of S: all of them, or the first K segments of a longer ring.
        let observed = match settings.kind {
            InputKind::Midline => rows.len(),
            InputKind::Lengths => k_in,
        };
        let partial = observed < rows.len();
        let fitted = if partial {
            fitted_of_ring(&all_lambdas, observed).ok_or_else(|| {
                invalid(format!(
                    "{observed} measured segments of a ring of {} resolve no whole mode",
                    rows.len()
                ))
            })?
        } else {
            m
        };
        let lambdas: Vec<f64> = all_lambdas[..fitted].to_vec();
        // design[j][i] = (S vⱼ)ᵢ over the observed rows.
        let design: Vec<Vec<f64>> = (0..fitted)
            .map(|j| {
                rows[..observed]
                    .iter()
                    .map(|r| {
                        r.iter()
                            .map(|&(i, w)| w as f64 * shapes[(i + held, first_mode + j)])
                            .sum::<f64>()
                    })
                    .collect()
            })
            .collect();
        let projector: Vec<Vec<f64>> = if partial {
            least_squares_rows(&design)?
        } else {
            lattice_rows(&design, &lambdas)
        };
        // The grid's own observation pattern S vⱼ, kept for postures on the model's points.
        let lattice = (!partial).then(|| design.clone());
        let held_counts = match settings.kind {
            InputKind::Midline => fm.spectrum.held,
            InputKind::Lengths => (0, 0),
        };
        let grid = Grid {
            kind: settings.kind,
            input_points: k_in,
            points: n,
            stencil: fm.k,
            boundary: fm.field.boundary,
            held: held_counts,
        };
        let (projector, design, continuum_modes) =
            match (partial, grid.continuum(&projector, &design)) {
                (false, Some(continuum)) => continuum,
                _ => (projector, design, 0),
            };
        let mut projector = Projector {
            kind: settings.kind,
            input_points: k_in,
            points: n,
            field: fm.field.id.clone(),
            scale: fm.field.scale().to_string(),
            first_mode,
            rows: projector,
            design,
            shapes: (0..fitted)
                .map(|j| (0..size).map(|p| shapes[(p, first_mode + j)]).collect())
                .collect(),
            eigenvalues: lambdas,
            reference_length: None,
            stencil: fm.k,
            boundary: fm.field.boundary,
            lattice,
            continuum_modes,
            mixed: Vec::new(),
            held_counts,
            held: None,
        };
        projector.mixed = projector.mixing();
        Ok(projector)
    }

    /// Each coordinate's gain of white tracking noise: its standard deviation under this
    /// projector over that under the N-point one, for independent noise of one size on every
    /// tracked coordinate (midlines; `None` for lengths and part of a ring). At most
    /// `NOISE_GAIN` = 2 by construction (see `continuum`).
    pub fn noise_gains(&self) -> Option<Vec<f64>> {
        let lattice = self.lattice.as_ref()?;
        let rows = lattice_rows(lattice, &self.eigenvalues);
        let noise = self.grid().noise_covariance()?;
        Some(super::continuum::noise_gains(&noise, &self.rows, &rows))
    }

    /// The covariance of the coordinates' tracking noise, P Σ Pᵀ, for independent noise of unit
    /// variance on every tracked coordinate (midlines; `None` for lengths and part of a ring).
    pub fn noise_covariance(&self) -> Option<nalgebra::DMatrix<f64>> {
        let noise = self.grid().noise_covariance()?;
        let p = nalgebra::DMatrix::from_fn(self.rows.len(), noise.nrows(), |i, j| self.rows[i][j]);
        Some(&p * noise * p.transpose())
    }

    pub(super) fn grid(&self) -> Grid {
        Grid {
            kind: self.kind,
            input_points: self.input_points,
            points: self.points,
            stencil: self.stencil,
            boundary: self.boundary,
            held: self.held_counts,
        }
    }

    /// The posture on the model's points (zero modes removed, in units of the point spacing)
    /// of one frame's modal coordinates: the observations o = Σ qⱼ·designⱼ, then the grid's
    /// least-squares solution Σ (S vⱼ·o/λⱼ) vⱼ. `None` when the observations cover part of a
    /// ring (then the grid's modes are not all determined).
    pub fn posture(&self, q: &[f64]) -> Option<Vec<f64>> {
        let lattice = self.lattice.as_ref()?;
        let width = self.design.first()?.len();
        let mut o = vec![0.0; width];
        for (qj, d) in q.iter().zip(&self.design) {
            for (oi, di) in o.iter_mut().zip(d) {
                *oi += qj * di;
            }
        }
        let mut posture = vec![0.0; self.shapes.first()?.len()];
        for ((row, shape), lambda) in lattice.iter().zip(&self.shapes).zip(&self.eigenvalues) {
            let qj = row.iter().zip(&o).map(|(a, b)| a * b).sum::<f64>() / lambda;
            for (p, v) in posture.iter_mut().zip(shape) {
                *p += qj * v;
            }
        }
        Some(posture)
    }

    /// The modal coordinates of one frame's values.
    pub fn modal(&self, values: &[f64]) -> Result<Vec<f64>, FrameError> {
        self.modal_held(values, self.held.as_ref())
    }

    pub(super) fn modal_held(
        &self,
        values: &[f64],
        held: Option<&HeldPoints>,
    ) -> Result<Vec<f64>, FrameError> {
        let o = observe(self.kind, values, self.points, self.reference_length, held)?;
        let q: Vec<f64> = self
            .rows
            .iter()
            .map(|p| p.iter().zip(&o).map(|(a, b)| a * b).sum())
            .collect();
        // Strains of absurd lengths can overflow; nothing non-finite goes on to the PCA.
        if q.iter().all(|v| v.is_finite()) {
            Ok(q)
        } else {
            Err(FrameError::Overflow)
        }
    }

    /// One frame's modal coordinates (into `q`) and point spacing, the frame oriented head
    /// last first when `head_first`: [`Projector::modal`] and [`Projector::spacing`] of the
    /// oriented frame, the same numbers, without a new vector for midlines of N points (the
    /// common case, which a long recording repeats a million times).
    pub(crate) fn project_into(
        &self,
        values: &[f64],
        head_first: bool,
        scratch: &mut Scratch,
        q: &mut Vec<f64>,
    ) -> Result<f64, FrameError> {
        q.clear();
        if self.kind != InputKind::Midline || values.len() != 2 * self.points {
            let values = tail_first(self.kind, values, head_first);
            q.extend(self.modal(&values)?);
            return Ok(self.spacing(&values));
        }
        let k = self.points;
        let held = self.held.as_ref();
        let point = |i: usize| {
            if let Some(p) = held.and_then(|h| h.at(i, k)) {
                return p;
            }
            let i = if head_first { k - 1 - i } else { i };
            (values[2 * i], values[2 * i + 1])
        };
        let Scratch {
            segments: seg,
            angles,
            sizes: lengths,
        } = scratch;
        seg.clear();
        seg.extend((0..k - 1).map(|i| {
            let (a, b) = (point(i), point(i + 1));
            (b.0 - a.0, b.1 - a.1)
        }));
        // As `turning_angles`, in its order: overflow before coincidence.
        if seg.iter().any(|s| !(s.0.is_finite() && s.1.is_finite())) {
            return Err(FrameError::Overflow);
        }
        if seg.iter().any(|s| s.0 == 0.0 && s.1 == 0.0) {
            return Err(FrameError::Coincident);
        }
        sizes(seg.iter().copied(), lengths);
        let length: f64 = lengths.iter().sum();
        segment_angles(seg, angles);
        q.extend(
            self.rows
                .iter()
                .map(|p| p.iter().zip(angles.iter()).map(|(a, b)| a * b).sum::<f64>()),
        );
        if !q.iter().all(|v| v.is_finite()) {
            return Err(FrameError::Overflow);
        }
        Ok(length / (self.points - 1) as f64)
    }

    /// Each fitted mode's gain on the body's own continuum mode (midlines of a field with
    /// continuum modes, else `None`): the modal coordinate Qⱼ that a midline of the input's K
    /// points bent by εφⱼ gives, over ε. The N-point modes are not quite the body's, so Qⱼ
    /// reads its continuum amplitude times this gain; equipartition is tested on Var Qⱼ/gainⱼ².
    /// Signed: Qⱼ/gainⱼ is the amplitude of φⱼ as `modal::continuum_shape` draws it, so modes
    /// coupled by a force keep the signs of its matrix ⟨φᵢ, Lφⱼ⟩ (`discover`; without the sign
    /// an active beam's fourth mode entered the coupled likelihood upside down).
    pub fn continuum_gains(&self) -> Vec<Option<f64>> {
        let m = self.eigenvalues.len();
        let grid = self.grid();
        (0..m)
            .map(|j| {
                let values = grid.continuum_midline(j)?;
                let g = self.modal_at_rest(&values).ok()?.get(j)? / CONTINUUM_AMPLITUDE;
                (g != 0.0 && g.is_finite()).then_some(g)
            })
            .collect()
    }

    /// Each coordinate's share of its variance that other continuum modes put in it at these
    /// tracked points, were the body at equipartition (the theory under test): with qⱼ(n) the
    /// coordinate Qⱼ of a midline bent by continuum mode n, and λₙ = (βₙL)^2k,
    /// Σₙ≠ⱼ (λⱼ/λₙ)(qⱼ(n)/qⱼ(j))² over the first 4N modes (the terms fall as n^−2k). A
    /// continuum coordinate takes nothing from the modes it projects out, only from the ones
    /// past them (which the N − 2 coordinates cannot separate); an N-point coordinate takes
    /// from any. `None` where the field has no continuum shapes (lengths, a ring).
    pub fn mixed_shares(&self) -> &[Option<f64>] {
        &self.mixed
    }

    /// [`Projector::mixed_shares`] computed.
    fn mixing(&self) -> Vec<Option<f64>> {
        let grid = self.grid();
        let k = self.stencil as i32;
        let modes: Vec<Option<(f64, Vec<f64>)>> = (0..4 * self.points)
            .map(|n| {
                let beta = crate::modal::continuum_beta(self.stencil, self.boundary, n + 1)?;
                let q = self.modal_at_rest(&grid.continuum_midline(n)?).ok()?;
                Some((beta.powi(2 * k), q))
            })
            .collect();
        (0..self.eigenvalues.len())
            .map(|j| {
                let (lj, own) = modes.get(j)?.as_ref()?;
                let (lj, own) = (*lj, own[j] * own[j]);
                let near = |l: f64| l < NEAR * NEAR * lj && lj < NEAR * NEAR * l;
                let share = (modes.iter().enumerate().filter(|(n, _)| *n != j))
                    .filter_map(|(_, m)| m.as_ref().filter(|(l, _)| near(*l)))
                    .map(|(l, q)| lj / l * q[j] * q[j] / own)
                    .sum::<f64>();
                share.is_finite().then_some(share)
            })
            .collect()
    }

    /// The model point spacing of one frame in the data's length unit: arc length over N − 1
    /// (midlines), the rest segment length (lengths).
    pub fn spacing(&self, values: &[f64]) -> f64 {
        match self.kind {
            InputKind::Midline => {
                let length: f64 = values
                    .chunks(2)
                    .collect::<Vec<_>>()
                    .windows(2)
                    .map(|w| size(w[1][0] - w[0][0], w[1][1] - w[0][1]))
                    .sum();
                length / (self.points - 1) as f64
            }
            InputKind::Lengths => self
                .reference_length
                .unwrap_or_else(|| values.iter().sum::<f64>() / values.len() as f64),
        }
    }
}

/// How far apart (as a ratio of frequencies, √λ) two modes may lie for one's line to bias the
/// other's fit; modes further off show as a white background the spectral fit takes up.
const NEAR: f64 = 4.0;

/// How many of a ring's modes (eigenvalues `lambdas`, ascending) `observed` of its segments
/// fit: at most K − 1 (the constant takes one more unknown), never half of a degenerate pair;
/// `None` when that leaves none.
fn fitted_of_ring(lambdas: &[f64], observed: usize) -> Option<usize> {
    let m = lambdas.len();
    let mut fitted = m.min(observed.saturating_sub(1));
    let same = |i: usize, j: usize| (lambdas[i] - lambdas[j]).abs() <= 1e-9 * lambdas[i];
    if fitted < m && fitted > 0 && same(fitted - 1, fitted) {
        fitted -= 1;
    }
    (fitted > 0).then_some(fitted)
}

/// Values per frame → (measured points or segments K, model points N), checked.
fn dimensions(
    settings: &RecordingSettings,
    width: usize,
) -> Result<(usize, usize), RecordingError> {
    let invalid = |s: String| RecordingError::Invalid(s);
    let line = |why: LineWhy| RecordingError::Line { line: 0, why };
    let (k_in, n) = match settings.kind {
        InputKind::Midline => {
            if width % 2 != 0 {
                return Err(line(LineWhy::Text(format!(
                    "a midline frame is t then x y pairs: {width} values after t is odd"
                ))));
            }
            if settings.points < 3 {
                return Err(invalid(format!(
                    "a midline needs at least 3 model points for one turning angle, not {}",
                    settings.points
                )));
            }
            let k = width / 2;
            // Resampled to more points than were tracked, the midline is straight between
            // tracked points: the extra angles are zero, a white floor no fit sees through.
            if k >= 5 && k < settings.points {
                return Err(invalid(format!(
                    "{k} tracked points per frame cannot resolve N = {} model points: give --points {k} (or fewer)",
                    settings.points
                )));
            }
            (k, settings.points)
        }
        InputKind::Lengths => {
            let ring = settings.ring.unwrap_or(width);
            if ring < width {
                return Err(invalid(format!(
                    "the ring of {ring} segments cannot hold the {width} measured ones"
                )));
            }
            (width, ring.saturating_add(1))
        }
    };
    if n > MAX_POINTS {
        return Err(invalid(format!(
            "{k_in} segments make a ring of {n} points; at most {MAX_POINTS}"
        )));
    }
    let min_k = if settings.kind == InputKind::Midline {
        5
    } else {
        3
    };
    if k_in < min_k {
        return Err(line(LineWhy::Text(format!(
            "{k_in} points per frame; at least {min_k} are needed"
        ))));
    }
    Ok((k_in, n))
}

/// The model field the data observe: `--field`, or the role the input kind implies.
fn observed_field(model: &Model, settings: &RecordingSettings) -> Result<usize, RecordingError> {
    let invalid = |s: String| RecordingError::Invalid(s);
    Ok(match &settings.field {
        Some(id) => model
            .fields
            .iter()
            .position(|f| &f.id == id)
            .ok_or_else(|| invalid(format!("the model has no field {id:?}")))?,
        None => {
            let behaviour = match settings.kind {
                InputKind::Midline => "fit (midlines)",
                InputKind::Lengths => "fit (lengths)",
            };
            crate::behaviour::role_fields(model, behaviour)?[0]
        }
    })
}

/// The rows of (BᵀB)⁻¹Bᵀ for B = [design | 1], the constant absorbing the unknown mean strain of
/// a partial ring; the constant's own row is dropped.
fn least_squares_rows(design: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, RecordingError> {
    let (m, k) = (design.len(), design[0].len());
    let b = nalgebra::DMatrix::from_fn(k, m + 1, |i, j| if j < m { design[j][i] } else { 1.0 });
    let normal = b.transpose() * &b;
    let chol = nalgebra::Cholesky::new(normal).ok_or_else(|| {
        RecordingError::Invalid("the measured segments do not separate the fitted modes".into())
    })?;
    let solved = chol.solve(&b.transpose());
    Ok((0..m)
        .map(|j| solved.row(j).iter().cloned().collect())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame projected on the fast path (segments straight from the row, the batched angles)
    /// is bit for bit the frame through the general one ([`Projector::modal`]: the midline's
    /// turning angles, each row's products summed in order), either way round.
    #[test]
    fn the_fast_projection_is_the_general_one() {
        let (model, params) = (Model::larva(), Params::default());
        let mut next = crate::recording::xorshift(0x3C6E_F372_FE94_F82Bu64);
        let mut unit = move || (next() % 2_000_001) as f64 / 1e6 - 1.0;
        for points in [5, 12, 31] {
            let mut settings = RecordingSettings::new(InputKind::Midline);
            settings.points = points;
            let p = Projector::new(&model, &params, &settings, 2 * points).unwrap();
            let (mut work, mut q) = (Scratch::default(), Vec::new());
            for _ in 0..500 {
                let values: Vec<f64> = (0..points)
                    .flat_map(|i| [i as f64 + 0.05 * unit(), 0.3 * unit()])
                    .collect();
                for head_first in [false, true] {
                    p.project_into(&values, head_first, &mut work, &mut q)
                        .unwrap();
                    let oriented = if head_first {
                        reversed(p.kind, &values)
                    } else {
                        values.clone()
                    };
                    let want = p.modal(&oriented).unwrap();
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&q), bits(&want), "{points} points, {values:?}");
                }
            }
        }
    }
}
