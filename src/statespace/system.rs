//! The exact likelihood of a linear system of several coupled modes: the multivariate form of
//! the module header's filter, for `discover`'s linear library (forces that couple modes, such
//! as an active ∂s³ force on a free body, are not a sum of independent oscillators).
//!
//! **Model.** State x = (q, q̇) of M modal coordinates, dx = F x dt + G dW with
//! F = [[0, I], [−K, −D]] and GGᵀ = [[0, 0], [0, N]]; observed yₙ = qₙ + eₙ, eₙ ~ N(0, R) (R
//! the tracking noise's covariance: a projection correlates it between modes).
//! Sampled every Δt it is xₙ₊₁ = Φ xₙ + wₙ, wₙ ~ N(0, Q), Φ and Q by Van Loan
//! ([`super::discretise`]). Each series starts from the stationary covariance P∞ = Φ P∞ Φᵀ + Q
//! (by doubling: P ← P + A P Aᵀ, A ← A², from P = Q, A = Φ), so a system that is not stable
//! (some eigenvalue of Φ on or outside the unit circle) has no likelihood.
//!
//! **Filter.** −ln L = ½ Σₙ [ln det(2π Sₙ) + vₙᵀ Sₙ⁻¹ vₙ] over observed frames; a lost frame (any
//! NaN) is a prediction without an update. Every series (and every series after a lost frame)
//! starts from the same covariance, so the sequence of gains from P∞ is computed once per
//! likelihood and kept (`Gains`) until it settles; then the steady gain is used.

use nalgebra::{DMatrix, DVector};

use super::{discretise, StateSpaceError};

/// A sampled linear system of M coupled modes, the first `noise.nrows()` of them seen through
/// white noise (the rest latent).
#[derive(Debug, Clone)]
pub struct System {
    /// Φ (2M × 2M).
    pub phi: DMatrix<f64>,
    /// Q (2M × 2M).
    pub q: DMatrix<f64>,
    /// The observation noise's covariance R over the observed modes.
    pub noise: DMatrix<f64>,
}

/// Most gains kept before the filter is taken as settled anyway.
const MAX_TRANSIENT: usize = 4096;

impl System {
    /// The system q̈ = −K q − D q̇ + noise of covariance `force_noise` (M × M), sampled every
    /// `dt`, the first `noise.nrows()` modes observed with noise of covariance `noise`.
    pub fn new(
        k: &DMatrix<f64>,
        d: &DMatrix<f64>,
        force_noise: &DMatrix<f64>,
        noise: DMatrix<f64>,
        dt: f64,
    ) -> Result<System, StateSpaceError> {
        let m = k.nrows();
        let mut f = DMatrix::zeros(2 * m, 2 * m);
        let mut gg = DMatrix::zeros(2 * m, 2 * m);
        for i in 0..m {
            f[(i, m + i)] = 1.0;
            for j in 0..m {
                f[(m + i, j)] = -k[(i, j)];
                f[(m + i, m + j)] = -d[(i, j)];
                gg[(m + i, m + j)] = force_noise[(i, j)];
            }
        }
        let (phi, q) = discretise(&f, &gg, dt)?;
        Ok(System { phi, q, noise })
    }

    /// P∞ by doubling; `None` when the system is not stable (the sum does not settle).
    pub fn stationary(&self) -> Option<DMatrix<f64>> {
        let mut p = self.q.clone();
        let mut a = self.phi.clone();
        for _ in 0..64 {
            let add = &a * &p * a.transpose();
            let scale = p.norm().max(f64::MIN_POSITIVE);
            let added = add.norm();
            p += add;
            a = &a * &a;
            if !added.is_finite() || !p.norm().is_finite() {
                return None;
            }
            if added <= 1e-14 * scale && a.norm() < 1e-6 {
                return Some(0.5 * (&p + p.transpose()));
            }
        }
        None
    }

    /// −ln L of each of `series` (frames × M values in time order, NaN for a lost frame,
    /// means removed), each from the stationary state: one value per series. `None` when
    /// the system is not stable or a covariance is not positive definite.
    pub fn negative_log_likelihoods(&self, series: &[&[Vec<f64>]]) -> Option<Vec<f64>> {
        let terms = self.frame_terms(series)?;
        Some(terms.iter().map(|t| t.iter().sum()).collect())
    }

    /// Each observed frame's term ½[ln det(2πSₙ) + vₙᵀSₙ⁻¹vₙ] of −ln L, series by series (a
    /// lost frame adds none): the prediction-error decomposition, whose terms' derivatives are
    /// the score's martingale differences.
    pub fn frame_terms(&self, series: &[&[Vec<f64>]]) -> Option<Vec<Vec<f64>>> {
        let p0 = self.stationary()?;
        let gains = Gains::new(self, &p0)?;
        series.iter().map(|s| self.run(s, &gains)).collect()
    }

    fn run(&self, frames: &[Vec<f64>], gains: &Gains) -> Option<Vec<f64>> {
        let n = self.phi.nrows();
        // The first `noise.nrows()` modes are observed (the rest are latent).
        let m = self.noise.nrows();
        let mut x = DVector::zeros(n);
        let mut scratch = DVector::zeros(n);
        let mut v = DVector::zeros(m);
        let mut terms = Vec::with_capacity(frames.len());
        let mut sv = DVector::zeros(m);
        // Frames since the last fresh start (the cached gains apply), or a covariance of
        // our own after a lost frame.
        let mut since = 0usize;
        let mut own: Option<DMatrix<f64>> = None;
        for y in frames {
            let lost = y.iter().any(|v| !v.is_finite());
            if lost {
                // Predict only: the covariance leaves the cached sequence.
                let p = match own.take() {
                    Some(p) => p,
                    None => gains.predicted(since),
                };
                own = Some(self.predict(&p));
                scratch.gemv(1.0, &self.phi, &x, 0.0);
                std::mem::swap(&mut x, &mut scratch);
                continue;
            }
            for i in 0..m {
                v[i] = y[i] - x[i];
            }
            let fresh;
            let step = match own.take() {
                Some(p) => {
                    fresh = Step::of(&p, &self.noise)?;
                    let posterior = &p - &fresh.gain * p.rows(0, m);
                    let next = self.predict(&posterior);
                    // Back on the cached sequence once it has settled to the steady gain.
                    if (&next - &gains.settled_prediction).norm() > 1e-10 * next.norm() {
                        own = Some(next);
                    } else {
                        since = usize::MAX;
                    }
                    &fresh
                }
                None => {
                    let s = gains.at(since);
                    since = since.saturating_add(1);
                    s
                }
            };
            sv.gemv(1.0, &step.inverse, &v, 0.0);
            let term = 0.5 * (step.log_det + v.dot(&sv));
            if !term.is_finite() {
                return None;
            }
            terms.push(term);
            x.gemv(1.0, &step.gain, &v, 1.0);
            scratch.gemv(1.0, &self.phi, &x, 0.0);
            std::mem::swap(&mut x, &mut scratch);
        }
        Some(terms)
    }

    fn predict(&self, posterior: &DMatrix<f64>) -> DMatrix<f64> {
        let p = &self.phi * posterior * self.phi.transpose() + &self.q;
        0.5 * (&p + p.transpose())
    }
}

/// One update's gain, S⁻¹ and ln det(2πS).
#[derive(Debug, Clone)]
struct Step {
    gain: DMatrix<f64>,
    inverse: DMatrix<f64>,
    log_det: f64,
}

impl Step {
    fn of(p: &DMatrix<f64>, noise: &DMatrix<f64>) -> Option<Step> {
        let m = noise.nrows();
        let s = p.view((0, 0), (m, m)) + noise;
        let chol = s.cholesky()?;
        let log_det = 2.0 * chol.l().diagonal().iter().map(|d| d.ln()).sum::<f64>()
            + m as f64 * (2.0 * std::f64::consts::PI).ln();
        let inverse = chol.inverse();
        let gain = p.columns(0, m) * &inverse;
        Some(Step {
            gain,
            inverse,
            log_det,
        })
    }
}

/// The filter's steps from P∞ until the prediction settles.
struct Gains {
    steps: Vec<Step>,
    /// The predicted covariance before each step.
    predictions: Vec<DMatrix<f64>>,
    settled_prediction: DMatrix<f64>,
}

impl Gains {
    fn new(system: &System, p0: &DMatrix<f64>) -> Option<Gains> {
        let m = system.noise.nrows();
        let mut steps = Vec::new();
        let mut predictions = Vec::new();
        let mut p = p0.clone();
        loop {
            let step = Step::of(&p, &system.noise)?;
            let posterior = &p - &step.gain * p.rows(0, m);
            let next = system.predict(&posterior);
            let moved = (&next - &p).norm();
            predictions.push(p);
            steps.push(step);
            if moved <= 1e-12 * next.norm() || steps.len() >= MAX_TRANSIENT {
                return Some(Gains {
                    steps,
                    predictions,
                    settled_prediction: next,
                });
            }
            p = next;
        }
    }

    /// The step `k` frames after a fresh start (the steady one past the transient).
    fn at(&self, k: usize) -> &Step {
        &self.steps[k.min(self.steps.len() - 1)]
    }

    /// The predicted covariance `k` frames after a fresh start.
    fn predicted(&self, k: usize) -> DMatrix<f64> {
        if k < self.predictions.len() {
            self.predictions[k].clone()
        } else {
            self.settled_prediction.clone()
        }
    }
}
