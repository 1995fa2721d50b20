//! The exact estimator of a linear library: each mode's exact likelihood, then the library's
//! coefficients by minimum distance.
//!
//! **Modes.** Each used mode's coordinate (on the body's continuum modes where the field has
//! them, `galerkin`) is fitted as a thermally driven damped oscillator by its exact sampled
//! likelihood (`statespace::fit_oscillator`: a Kalman filter over the frames, lost frames
//! skipped, tracking noise as observation noise): valid at any frame rate, for over-damped
//! modes and across gaps, with no bridging. Its (ln Ω, ln ζ) and their observed information give
//! yⱼ = (Ωⱼ², 2ζⱼΩⱼ) with a covariance Σⱼ (the delta method).
//!
//! **Coefficients.** A library whose forces are diagonal on the modes (stiffness, Kelvin damping,
//! drag and their higher orders on a free or clamped beam) predicts yⱼ = Xⱼ c, Xⱼ's columns the
//! forces' modal entries (−⟨φⱼ, Lφⱼ⟩, −⟨φⱼ, L′φⱼ⟩). The minimum-distance estimate
//! ĉ = argmin Σⱼ (yⱼ − Xⱼc)ᵀ Σⱼ⁻¹ (yⱼ − Xⱼc) is as efficient as the joint likelihood's
//! asymptotically (the modes' estimates are independent, each efficient), and its statistic J is
//! χ² with 2M − |S| degrees of freedom when the set S holds every force present.
//!
//! **Selection and uncertainty.** Backward elimination by J(S) + |S| ln n (n frames), as the weak
//! form's criterion. A moving-block bootstrap over time (or whole animals) with the one-step
//! estimate of every mode per draw (its blocks' scores and information at the whole
//! recording's estimate, summed over the draw, one Newton step), the selection rerun per draw
//! (inclusion) and the reported set's percentiles.

use nalgebra::{DMatrix, DVector, Matrix2};

use super::data::Recording;
use super::galerkin::ModalForce;
use crate::statespace::{
    fit_oscillator_with, newton_step, score_and_information_with, Oscillator, OscillatorFit,
};

/// At most this many modes are used.
pub const MAX_MODES: usize = 8;

/// Blocks of time per recording for the bootstrap (whole animals when there are several).
pub const BLOCKS: usize = 25;

/// One used mode's data in blocks.
pub(super) struct ModeData {
    /// Each block's frames (NaN for a lost frame), time in frames.
    pub blocks: Vec<Vec<f64>>,
    /// Which unit of the bootstrap each block belongs to.
    pub unit: Vec<usize>,
}

/// The modal series of `recordings` in blocks: mode j's coordinate divided by its continuum
/// gain, less the recording's mean, each recording cut into blocks and each block into its
/// runs between lost frames (time in frames).
pub(super) fn mode_data(recordings: &[Recording], modes: &[usize]) -> Vec<ModeData> {
    let per = BLOCKS.div_ceil(recordings.len()).max(1);
    let several = recordings.len() > 1;
    modes
        .iter()
        .map(|&j| {
            let mut blocks = Vec::new();
            let mut unit = Vec::new();
            for (a, rec) in recordings.iter().enumerate() {
                let gain = rec.basis.gain(j);
                let t0 = rec.modal.first().map_or(0.0, |f| f.0);
                let last = rec.modal.last().map_or(0.0, |f| f.0);
                let frames = ((last - t0) / rec.dt).round() as usize + 1;
                let mut y = vec![f64::NAN; frames];
                for (t, q) in &rec.modal {
                    let k = ((t - t0) / rec.dt).round() as usize;
                    if let (Some(slot), Some(v)) = (y.get_mut(k), q.get(j)) {
                        *slot = v / gain;
                    }
                }
                // One mean per recording: a run's own mean would take its slow part away.
                let (sum, count) = (y.iter().filter(|v| v.is_finite()))
                    .fold((0.0, 0.0), |(s, n), v| (s + v, n + 1.0));
                let mean = if count > 0.0 { sum / count } else { 0.0 };
                y.iter_mut().for_each(|v| *v -= mean);
                let size = frames.div_ceil(per).max(1);
                // Each run between lost frames is its own series (from the stationary state):
                // with the lost frames inside one series as predictions without update,
                // bursts of 1–10 frames at irregular spacing gave mode 1 of the continuum beam
                // ζ = 0.126 for 0.05 (regular bursts did not); to be found in `statespace`.
                for (b, chunk) in y.chunks(size).enumerate() {
                    for run in chunk.split(|v| v.is_nan()).filter(|r| !r.is_empty()) {
                        blocks.push(run.to_vec());
                        unit.push(if several { a } else { b });
                    }
                }
            }
            ModeData { blocks, unit }
        })
        .collect()
}

/// One mode's exact fit: its estimate, the information's covariance of (ln Ω, ln ζ), and
/// each block's score and information at the estimate (for the one-step draws).
pub(super) struct ModeFit {
    pub fit: OscillatorFit,
    pub free: Vec<usize>,
    pub covariance: Matrix2<f64>,
    pub blocks: Vec<(DVector<f64>, DMatrix<f64>)>,
}

/// Fit mode `data` from `start` (time in frames); `None` when the fit or its information fails.
pub(super) fn fit_mode(data: &ModeData, start: Oscillator) -> Option<ModeFit> {
    let refs: Vec<&[f64]> = data.blocks.iter().map(Vec::as_slice).collect();
    let band = (start.omega * 1e-3, 2.0 * std::f64::consts::PI);
    let fit = fit_oscillator_with(&refs, 1.0, start, band, false).ok()?;
    let free = crate::statespace::free_parameters(&fit.estimate);
    let blocks: Vec<(DVector<f64>, DMatrix<f64>)> = refs
        .iter()
        .map(|b| score_and_information_with(&[b], 1.0, &fit.estimate, &free, false))
        .collect();
    let h = blocks
        .iter()
        .fold(DMatrix::zeros(free.len(), free.len()), |h, b| h + &b.1);
    let covariance = log_covariance(&h, &free)?;
    Some(ModeFit {
        fit,
        free,
        covariance,
        blocks,
    })
}

/// The covariance of (ln Ω, ln ζ) from the information `h` over `free`.
fn log_covariance(h: &DMatrix<f64>, free: &[usize]) -> Option<Matrix2<f64>> {
    let inv = h.clone().cholesky()?.inverse();
    let at = |p: usize| free.iter().position(|&f| f == p);
    let (o, z) = (at(0)?, at(1)?);
    Some(Matrix2::new(
        inv[(o, o)],
        inv[(o, z)],
        inv[(z, o)],
        inv[(z, z)],
    ))
}

/// (Ω², 2ζΩ) of `p` and their inverse covariance from that of (ln Ω, ln ζ).
pub(super) fn moments(p: &Oscillator, log_cov: &Matrix2<f64>) -> Option<([f64; 2], Matrix2<f64>)> {
    let (w, z) = (p.omega, p.zeta);
    let y = [w * w, 2.0 * z * w];
    // ∂y/∂(ln Ω, ln ζ).
    let j = Matrix2::new(2.0 * w * w, 0.0, 2.0 * z * w, 2.0 * z * w);
    let cov = j * log_cov * j.transpose();
    Some((y, cov.try_inverse()?))
}

/// The minimum-distance problem: per mode y and weight, the library's columns.
pub(super) struct Distance {
    /// Per mode (Ω², 2ζΩ).
    pub y: Vec<[f64; 2]>,
    /// Per mode the inverse covariance.
    pub weight: Vec<Matrix2<f64>>,
    /// Per candidate, per mode, its (stiffness, damping) entry.
    pub columns: Vec<Vec<[f64; 2]>>,
}

/// A statistic J(S) quadratic in the coefficients, minimised on each subset S of the library:
/// the selection and the criterion built on it.
pub(super) trait Quadratic {
    /// The estimate on `set` (library indices), its covariance and J; `None` when singular.
    fn fit(&self, set: &[usize]) -> Option<(Vec<f64>, DMatrix<f64>, f64)>;

    /// Backward elimination from `all` by J(S) + |S| ln n.
    fn select(&self, all: &[usize], n: f64) -> Vec<usize> {
        let score = |s: &[usize]| self.fit(s).map(|f| f.2 + s.len() as f64 * n.ln());
        let mut set = all.to_vec();
        let mut best = score(&set).unwrap_or(f64::INFINITY);
        loop {
            let trial = (0..set.len())
                .filter_map(|i| {
                    let mut s = set.clone();
                    s.remove(i);
                    score(&s).map(|v| (v, s))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            match trial {
                Some((v, s)) if v <= best => (best, set) = (v, s),
                _ => return set,
            }
        }
    }

    /// The criterion J(S) + |S| ln n.
    fn criterion(&self, set: &[usize], n: f64) -> Option<f64> {
        self.fit(set).map(|f| f.2 + set.len() as f64 * n.ln())
    }
}

impl Quadratic for Distance {
    fn fit(&self, set: &[usize]) -> Option<(Vec<f64>, DMatrix<f64>, f64)> {
        let k = set.len();
        let mut a = DMatrix::zeros(k, k);
        let mut b = DVector::zeros(k);
        let col = |m: usize, j: usize| {
            nalgebra::Vector2::new(self.columns[m][j][0], self.columns[m][j][1])
        };
        for (j, (y, w)) in self.y.iter().zip(&self.weight).enumerate() {
            let y = nalgebra::Vector2::new(y[0], y[1]);
            for (r, &m) in set.iter().enumerate() {
                let wx = w * col(m, j);
                b[r] += wx.dot(&y);
                for (c, &n) in set.iter().enumerate() {
                    a[(r, c)] += wx.dot(&col(n, j));
                }
            }
        }
        if k == 0 {
            return Some((Vec::new(), a, self.objective(set, &[])));
        }
        let chol = a.clone().cholesky()?;
        let beta = chol.solve(&b);
        let beta: Vec<f64> = beta.iter().copied().collect();
        let j = self.objective(set, &beta);
        Some((beta, chol.inverse(), j))
    }
}

impl Distance {
    /// J of `beta` on `set`.
    pub fn objective(&self, set: &[usize], beta: &[f64]) -> f64 {
        self.y
            .iter()
            .zip(&self.weight)
            .enumerate()
            .map(|(j, (y, w))| {
                let mut e = nalgebra::Vector2::new(y[0], y[1]);
                for (&m, b) in set.iter().zip(beta) {
                    e -= nalgebra::Vector2::new(self.columns[m][j][0], self.columns[m][j][1]) * *b;
                }
                (e.transpose() * w * e)[(0, 0)]
            })
            .sum()
    }

    /// Each mode's misfit y − Xβ of `beta` on `set`.
    pub fn residuals(&self, set: &[usize], beta: &[f64]) -> Vec<[f64; 2]> {
        (self.y.iter().enumerate())
            .map(|(j, y)| {
                let mut e = *y;
                for (&m, b) in set.iter().zip(beta) {
                    e[0] -= self.columns[m][j][0] * b;
                    e[1] -= self.columns[m][j][1] * b;
                }
                e
            })
            .collect()
    }

    /// J on `set` of this draw with each mode's `misfit` taken off: a draw about a recording
    /// the theory fits exactly (Hall & Horowitz 1996), so its J strays as J would if the
    /// theory held, at the modes' actual errors whatever their information says.
    pub fn recentred(&self, set: &[usize], misfit: &[[f64; 2]]) -> Option<f64> {
        let shifted = Distance {
            y: (self.y.iter().zip(misfit))
                .map(|(y, e)| [y[0] - e[0], y[1] - e[1]])
                .collect(),
            weight: self.weight.clone(),
            columns: self.columns.clone(),
        };
        shifted.fit(set).map(|f| f.2)
    }
}

/// Each candidate's (stiffness, damping) entries on the used modes (positions in `forces`),
/// and whether every force is diagonal on them (off-diagonal entries under 10⁻³ of the
/// diagonal scale: the continuum matrices' remainder is 10⁻⁴). `None` for a candidate that is not linear.
pub(super) fn columns(forces: &[Option<ModalForce>]) -> (Vec<Option<Vec<[f64; 2]>>>, bool) {
    let mut diagonal = true;
    let cols = forces
        .iter()
        .map(|f| {
            let f = f.as_ref()?;
            let m = f.position.nrows();
            let scale = (0..m)
                .map(|j| f.position[(j, j)].abs().max(f.velocity[(j, j)].abs()))
                .fold(0.0f64, f64::max);
            for i in 0..m {
                for j in 0..m {
                    let off = f.position[(i, j)].abs().max(f.velocity[(i, j)].abs());
                    if i != j && off > 1e-3 * scale.max(f64::MIN_POSITIVE) {
                        diagonal = false;
                    }
                }
            }
            Some(
                (0..m)
                    .map(|j| [-f.position[(j, j)], -f.velocity[(j, j)]])
                    .collect(),
            )
        })
        .collect();
    (cols, diagonal)
}

/// One bootstrap draw's (Ω², 2ζΩ) and weights: each mode's one-step estimate on the drawn
/// units' blocks (`count[u]` times unit u); `None` when some mode's information is singular.
pub(super) fn drawn(fits: &[ModeFit], data: &[ModeData], count: &[usize]) -> Option<Distance> {
    let mut y = Vec::new();
    let mut weight = Vec::new();
    for (f, d) in fits.iter().zip(data) {
        let n = f.free.len();
        let (mut g, mut h) = (DVector::zeros(n), DMatrix::zeros(n, n));
        for ((bg, bh), &u) in f.blocks.iter().zip(&d.unit) {
            let c = count[u] as f64;
            g += bg * c;
            h += bh * c;
        }
        let step = newton_step(&f.fit.estimate, &f.free, (&g, &h))?;
        let cov = log_covariance(&h, &f.free)?;
        let (m, w) = moments(&step.estimate, &cov)?;
        y.push(m);
        weight.push(w);
    }
    Some(Distance {
        y,
        weight,
        columns: Vec::new(),
    })
}
