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

use super::held::HeldPoints;
use super::observe::observe;
use super::InputKind;

/// The amplitude (body lengths) of the continuum shapes put through the observation map: small
/// enough that turning angles are linear in it to 1e-8.
pub(crate) const CONTINUUM_AMPLITUDE: f64 = 1e-4;

/// What the observation map depends on: the input, the grid and the field's operator.
pub(crate) struct Grid {
    pub(crate) kind: InputKind,
    pub(crate) input_points: usize,
    pub(crate) points: usize,
    pub(crate) stencil: u32,
    pub(crate) boundary: crate::boundary::Boundary,
    /// Points held at (tail, head) on the model's N points.
    pub(crate) held: (usize, usize),
}

impl Grid {
    /// Continuum mode `j` (0-based) as a midline of the input's points, tail first, at
    /// [`CONTINUUM_AMPLITUDE`]; `None` for lengths or a field without continuum shapes.
    pub(crate) fn continuum_midline(&self, j: usize) -> Option<Vec<f64>> {
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

    /// The held points of the straight body at rest: where the shapes put through the
    /// observation map are held (a recording's are its reference frame's).
    pub(crate) fn rest(&self) -> Option<HeldPoints> {
        HeldPoints::of(&self.straight()?, self.points, self.held)
    }

    /// The straight midline of the input's points, tail first; `None` for lengths.
    fn straight(&self) -> Option<Vec<f64>> {
        if self.kind != InputKind::Midline || self.input_points < 3 {
            return None;
        }
        let k = self.input_points;
        Some(
            (0..k)
                .flat_map(|p| [p as f64 / (k - 1) as f64, 0.0])
                .collect(),
        )
    }

    /// The covariance (up to the noise's variance) that white, independent noise on every
    /// tracked coordinate gives the observations, J Jᵀ with J the observation map's Jacobian at
    /// a straight midline (central differences: the map is smooth there). `None` for lengths.
    pub(crate) fn noise_covariance(&self) -> Option<nalgebra::DMatrix<f64>> {
        let straight = self.straight()?;
        let k = self.input_points;
        let rest = self.rest();
        let h = 1e-5;
        let columns: Vec<Vec<f64>> = (0..2 * k)
            .map(|c| {
                let at = |d: f64| {
                    let mut v = straight.clone();
                    v[c] += d;
                    observe(self.kind, &v, self.points, None, rest.as_ref()).ok()
                };
                let (up, down) = (at(h)?, at(-h)?);
                Some(
                    up.iter()
                        .zip(&down)
                        .map(|(a, b)| (a - b) / (2.0 * h))
                        .collect(),
                )
            })
            .collect::<Option<_>>()?;
        let obs = columns.first()?.len();
        let j = nalgebra::DMatrix::from_fn(obs, 2 * k, |i, c| columns[c][i]);
        Some(&j * j.transpose())
    }

    /// The projector on the continuum modes and its design (see the module header), from the
    /// N-point projector `rows` and design `lattice` (Sv_j); `None` where a shape is missing.
    ///
    /// **Regularised by choosing the columns.** The continuum shapes beyond what N points
    /// resolve are nearly dependent on the lower ones once observed (a clamped end at 19 points
    /// gave C⁺ a gain of 9.8·10³ from the grid's mode 17 into the lowest coordinate), so C⁺
    /// amplifies tracking noise. The design keeps the first M continuum columns and completes
    /// them with the grid's own Sv_j for j > M, M the largest for which white tracking noise
    /// reaches no coordinate with more than [`NOISE_GAIN`] times its standard deviation under
    /// the N-point projector ([`noise_gains`]). Coordinates past M are the N-point ones
    /// (as before the continuum projector existed); M = N − 2 wherever C⁺ is well behaved,
    /// which is the free–free beam at every N tested.
    #[allow(clippy::type_complexity)]
    pub(crate) fn continuum(
        &self,
        rows: &[Vec<f64>],
        lattice: &[Vec<f64>],
    ) -> Option<(Vec<Vec<f64>>, Vec<Vec<f64>>, usize)> {
        let rest = self.rest();
        let columns: Vec<Vec<f64>> = (0..rows.len())
            .map(|j| {
                let values = self.continuum_midline(j)?;
                let o = observe(self.kind, &values, self.points, None, rest.as_ref()).ok()?;
                Some(o.iter().map(|v| v / CONTINUUM_AMPLITUDE).collect())
            })
            .collect::<Option<_>>()?;
        // The N-point projector's gain on each continuum shape keeps Q at the grid's scale.
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
        let noise = self.noise_covariance()?;
        let build = |m: usize| -> Option<(Vec<Vec<f64>>, Vec<Vec<f64>>)> {
            let (design, scales): (Vec<Vec<f64>>, Vec<f64>) = (0..rows.len())
                .map(|j| match j < m {
                    true => (columns[j].iter().map(|v| v / gains[j]).collect(), gains[j]),
                    false => (lattice[j].clone(), 1.0),
                })
                .unzip();
            let projector = solve(&columns, &design, &scales, m)?;
            let worst = noise_gains(&noise, &projector, rows)
                .into_iter()
                .fold(0.0f64, f64::max);
            (worst <= NOISE_GAIN).then_some((projector, design))
        };
        // The largest M that keeps every gain bounded, by bisection (M = 0 is the grid's own
        // projector, gain 1); one solve where the whole continuum basis is well behaved.
        let n = rows.len();
        if let Some((p, d)) = build(n) {
            return Some((p, d, n));
        }
        let (mut good, mut bad) = (0, n);
        let mut best = None;
        while bad - good > 1 {
            let mid = (good + bad) / 2;
            match build(mid) {
                Some(found) => (good, best) = (mid, Some(found)),
                None => bad = mid,
            }
        }
        let (p, d) = best.or_else(|| build(0))?;
        Some((p, d, good))
    }
}

/// The most a projected coordinate's tracking noise may exceed the N-point projector's.
pub(crate) const NOISE_GAIN: f64 = 2.0;

/// Each coordinate's white-noise standard deviation under `projector` over that under the
/// N-point `rows`: √(pⱼ Σ pⱼᵀ / rⱼ Σ rⱼᵀ), Σ the observations' noise covariance.
pub(crate) fn noise_gains(
    noise: &nalgebra::DMatrix<f64>,
    projector: &[Vec<f64>],
    rows: &[Vec<f64>],
) -> Vec<f64> {
    let form = |v: &[f64]| {
        let v = nalgebra::DVector::from_column_slice(v);
        (v.transpose() * noise * &v)[(0, 0)]
    };
    projector
        .iter()
        .zip(rows)
        .map(|(p, r)| (form(p) / form(r)).sqrt())
        .map(|g| if g.is_finite() { g } else { f64::INFINITY })
        .collect()
}

/// The projector rows of a design: diag(`scales`)·D⁺, D's first `m` columns the continuum's
/// (`columns`, the pseudo-inverse of C itself, so that M = N − 2 is the plain C⁺ to the bit),
/// the rest `design`'s; `None` when the design is ill-conditioned.
fn solve(
    columns: &[Vec<f64>],
    design: &[Vec<f64>],
    scales: &[f64],
    m: usize,
) -> Option<Vec<Vec<f64>>> {
    let obs = columns.first()?.len();
    let used = |j: usize| if j < m { &columns[j] } else { &design[j] };
    let c = nalgebra::DMatrix::from_fn(obs, design.len(), |i, j| used(j)[i]);
    let svd = c.svd(true, true);
    let (big, small) = svd
        .singular_values
        .iter()
        .fold((0.0f64, f64::INFINITY), |(b, s), &v| (b.max(v), s.min(v)));
    if small.is_nan() || small <= 1e-8 * big {
        return None;
    }
    let pinv = svd.pseudo_inverse(0.0).ok()?;
    Some(
        (0..design.len())
            .map(|j| (0..obs).map(|i| scales[j] * pinv[(j, i)]).collect())
            .collect(),
    )
}
