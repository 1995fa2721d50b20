//! Numerics the behaviour models (and `fit`) share: one classical Runge–Kutta step, one phase
//! unwrapper, one PCA on faer.

use std::f64::consts::PI;

/// One classical fourth-order Runge–Kutta step of `y' = f(t, y)` from `(t, y)` over `h`.
pub fn rk4_step<const D: usize>(
    f: impl Fn(f64, [f64; D]) -> [f64; D],
    t: f64,
    y: [f64; D],
    h: f64,
) -> [f64; D] {
    let k1 = f(t, y);
    let k2 = f(t + h / 2.0, std::array::from_fn(|i| y[i] + h / 2.0 * k1[i]));
    let k3 = f(t + h / 2.0, std::array::from_fn(|i| y[i] + h / 2.0 * k2[i]));
    let k4 = f(t + h, std::array::from_fn(|i| y[i] + h * k3[i]));
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The running total of an angle sampled often enough that it moves by less than π per sample.
#[derive(Debug, Clone, Copy, Default)]
pub struct PhaseUnwrap {
    last: Option<f64>,
    total: f64,
}

impl PhaseUnwrap {
    /// Add the next sample of the wrapped angle; returns the unwrapped change since the first.
    pub fn push(&mut self, angle: f64) -> f64 {
        if let Some(last) = self.last {
            let mut d = angle - last;
            d -= (d / (2.0 * PI)).round() * 2.0 * PI;
            self.total += d;
        }
        self.last = Some(angle);
        self.total
    }

    /// The unwrapped change so far.
    pub fn total(&self) -> f64 {
        self.total
    }
}

/// Why principal components cannot be taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum PcaError {
    /// An entry of the covariance is infinite or not a number.
    #[error("the covariance is not finite")]
    NotFinite,
    /// The eigensolver did not converge.
    #[error("eigensolver failed to converge")]
    NoConvergence,
}

/// Principal components of a symmetric (covariance) matrix on faer: the variances, descending,
/// and the unit components as rows in the same order.
pub fn principal_components(cov: &[Vec<f64>]) -> Result<(Vec<f64>, Vec<Vec<f64>>), PcaError> {
    let n = cov.len();
    // Refused before the eigensolver when any entry is not finite (a NaN escapes a max).
    if cov.iter().flatten().any(|v| !v.is_finite()) {
        return Err(PcaError::NotFinite);
    }
    // Scaled to unit size: a covariance of subnormal or huge numbers has the same components.
    let scale = cov.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (cov[i][j] + cov[j][i]) / scale);
    let evd = m
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| PcaError::NoConvergence)?;
    let (s, u) = (evd.S().column_vector(), evd.U());
    // faer sorts ascending.
    Ok((
        (0..n).rev().map(|k| s[k] * scale).collect(),
        (0..n)
            .rev()
            .map(|k| (0..n).map(|i| u[(i, k)]).collect())
            .collect(),
    ))
}
