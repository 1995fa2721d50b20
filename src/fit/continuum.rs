//! The projector on a field's continuum modes (see the module header of `project`).
//!
//! **Continuum coordinates.** A midline of a field whose continuum modes are known (a beam or
//! a string with ends) is projected on those modes, not on the N-point ones: the turning
//! angles c_j that the continuum mode j gives through the same resampling are the columns of
//! C, and Q = G·C⁺o with G the diagonal of the N-point projector's gains on them (so Q keeps
//! the N-point coordinates' scale). The N-point modes of a coarse grid mix the body's
//! neighbouring modes (a clamped end at N = 12 puts 18–75 % of the variance of modes 2–5 into
//! each other's coordinates), and that leakage biased variances and damping ratios; what is
//! left is the aliasing of modes beyond the N − 2 fitted.

use super::observe::observe;
use super::InputKind;

/// The amplitude (body lengths) of the continuum shapes put through the observation map: small
/// enough that turning angles are linear in it to 1e-8.
pub(super) const CONTINUUM_AMPLITUDE: f64 = 1e-4;

/// What the observation map depends on: the input, the grid and the field's operator.
pub(super) struct Grid {
    pub(super) kind: InputKind,
    pub(super) input_points: usize,
    pub(super) points: usize,
    pub(super) stencil: u32,
    pub(super) boundary: crate::boundary::Boundary,
}

impl Grid {
    /// Continuum mode `j` (0-based) as a midline of the input's points, tail first, at
    /// [`CONTINUUM_AMPLITUDE`]; `None` for lengths or a field without continuum shapes.
    pub(super) fn continuum_midline(&self, j: usize) -> Option<Vec<f64>> {
        if self.kind != InputKind::Midline || self.input_points < 3 {
            return None;
        }
        let shape = crate::modal::continuum_shape(self.stencil, self.boundary, j + 1)?;
        let last = (shape.len() - 1) as f64;
        let k = self.input_points;
        Some(
            (0..k)
                .flat_map(|p| {
                    let s = p as f64 / (k - 1) as f64;
                    let x = s * last;
                    let (i, f) = (x.floor() as usize, x - x.floor());
                    let y = shape[i] + f * (shape[(i + 1).min(shape.len() - 1)] - shape[i]);
                    [s, CONTINUUM_AMPLITUDE * y]
                })
                .collect(),
        )
    }

    /// The projector on the continuum modes and its design (see the module header), from the
    /// N-point projector `rows`; `None` where a shape is missing or C is ill-conditioned.
    #[allow(clippy::type_complexity)]
    pub(super) fn continuum(&self, rows: &[Vec<f64>]) -> Option<(Vec<Vec<f64>>, Vec<Vec<f64>>)> {
        let columns: Vec<Vec<f64>> = (0..rows.len())
            .map(|j| {
                let values = self.continuum_midline(j)?;
                let o = observe(self.kind, &values, self.points, None).ok()?;
                Some(o.iter().map(|v| v / CONTINUUM_AMPLITUDE).collect())
            })
            .collect::<Option<_>>()?;
        let obs = columns.first()?.len();
        let c = nalgebra::DMatrix::from_fn(obs, columns.len(), |i, j| columns[j][i]);
        let svd = c.svd(true, true);
        let (big, small) = svd
            .singular_values
            .iter()
            .fold((0.0f64, f64::INFINITY), |(b, s), &v| (b.max(v), s.min(v)));
        if small.is_nan() || small <= 1e-8 * big {
            return None;
        }
        let pinv = svd.pseudo_inverse(0.0).ok()?;
        let gains: Vec<f64> = rows
            .iter()
            .zip(&columns)
            .map(|(r, c)| r.iter().zip(c).map(|(a, b)| a * b).sum())
            .collect();
        if gains
            .iter()
            .any(|g: &f64| !(g.abs() > 0.0 && g.is_finite()))
        {
            return None;
        }
        let projector = (0..columns.len())
            .map(|j| (0..obs).map(|i| gains[j] * pinv[(j, i)]).collect())
            .collect();
        let design = columns
            .iter()
            .zip(&gains)
            .map(|(c, g)| c.iter().map(|v| v / g).collect())
            .collect();
        Some((projector, design))
    }
}
