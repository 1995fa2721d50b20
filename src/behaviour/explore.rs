//! Unbiased exploration (paper §3.3.4): planar postures with Gaussian modal coordinates, the
//! 3-point bend distribution and β refitted from the sampled variances.

use super::{positive, role_fields, BehaviourError};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};
use crate::theory::Theory;

/// Unbiased exploration (paper §3.3.4): planar postures with Gaussian modal coordinates.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Exploration {
    /// Points along the body.
    pub points: usize,
    /// Inverse temperature used.
    pub beta: f64,
    /// The sampled 3-point bend angles (turning angle at the midpoint, radians).
    #[serde(skip)]
    pub bend: Vec<f64>,
    /// Standard deviation of the sampled bend angles.
    pub bend_sd: f64,
    /// The small-amplitude prediction: √(Σᵢ (w·vᵢ)²/(βω²λᵢ)), w the linearised bend.
    pub bend_sd_linear: f64,
    /// Sample variance of each non-zero modal coordinate.
    pub modal_variance: Vec<f64>,
    /// The equipartition variance 1/(βω²λᵢ).
    pub theory_variance: Vec<f64>,
    /// β fitted to the sampled modal variances by least squares.
    pub fitted_beta: f64,
}

/// β by least squares from modal variances: minimise Σ(vᵢ − cᵢ/β)², cᵢ = 1/(ω²λᵢ).
pub fn fit_beta(variances: &[f64], c: &[f64]) -> Result<f64, BehaviourError> {
    if variances.is_empty() || variances.len() != c.len() {
        return Err(BehaviourError::new("need one variance per mode"));
    }
    if variances
        .iter()
        .chain(c)
        .any(|v| !v.is_finite() || *v <= 0.0)
    {
        return Err(BehaviourError::new(
            "variances must be positive finite numbers",
        ));
    }
    let x = variances.iter().zip(c).map(|(v, ci)| v * ci).sum::<f64>()
        / c.iter().map(|ci| ci * ci).sum::<f64>();
    Ok(1.0 / x)
}

/// Sample `samples` planar postures of the lateral field at inverse temperature `beta`.
pub fn explore(
    theory: &Theory,
    beta: f64,
    samples: usize,
    seed: u64,
) -> Result<Exploration, BehaviourError> {
    let points = theory.points;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let beta = positive("β", beta)?;
    if !(1..=10_000_000).contains(&samples) {
        return Err(BehaviourError::new("samples must be between 1 and 10⁷"));
    }
    let y = role_fields(&theory.model, "stats explore")?[0];
    let f = &theory.modes[y];
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError::new("no shapes"))?;
    // n: the body's points (held ones stay at zero); count: the non-zero modes.
    let (n, null) = (shapes.nrows(), f.spectrum.nullity);
    let count = f.spectrum.size - null;
    let omega = f.omega;
    let c: Vec<f64> = f.modes[null..]
        .iter()
        .map(|m| 1.0 / (omega * omega * m.eigenvalue))
        .collect();
    let sd: Vec<f64> = c.iter().map(|ci| (ci / beta).sqrt()).collect();
    // Midline: arc length s_j = j/(N−1), lateral y_j; the bend is the turning angle at the middle
    // between the tail half (tail → middle) and the head half (middle → head).
    let mid = |v: &dyn Fn(usize) -> f64| {
        if n % 2 == 1 {
            v(n / 2)
        } else {
            0.5 * (v(n / 2 - 1) + v(n / 2))
        }
    };
    let half = 0.5;
    let bend_of = |yv: &dyn Fn(usize) -> f64| {
        let ym = mid(yv);
        let (a1, a2) = ((ym - yv(0)).atan2(half), (yv(n - 1) - ym).atan2(half));
        a2 - a1
    };
    // Linearised bend: w·y with w = (e_head − 2·e_mid + e_tail)/(L/2).
    let w = |j: usize| -> f64 {
        let mut v = 0.0;
        if j == 0 || j == n - 1 {
            v += 1.0;
        }
        if n % 2 == 1 && j == n / 2 {
            v -= 2.0;
        } else if n % 2 == 0 && (j == n / 2 - 1 || j == n / 2) {
            v -= 1.0;
        }
        v / half
    };
    let bend_sd_linear = (0..count)
        .map(|k| {
            let dot: f64 = (0..n).map(|j| w(j) * shapes[(j, null + k)]).sum();
            dot * dot * c[k] / beta
        })
        .sum::<f64>()
        .sqrt();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut bend = Vec::with_capacity(samples);
    let (mut sum, mut sq) = (vec![0.0; count], vec![0.0; count]);
    let mut q = vec![0.0; count];
    for _ in 0..samples {
        for (k, qk) in q.iter_mut().enumerate() {
            *qk = sd[k] * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng);
            sum[k] += *qk;
            sq[k] += *qk * *qk;
        }
        let yv = |j: usize| {
            (0..q.len())
                .map(|k| q[k] * shapes[(j, null + k)])
                .sum::<f64>()
        };
        bend.push(bend_of(&yv));
    }
    let s = samples as f64;
    let modal_variance: Vec<f64> = sum
        .iter()
        .zip(&sq)
        .map(|(a, b)| b / s - (a / s).powi(2))
        .collect();
    let mean = bend.iter().sum::<f64>() / s;
    let bend_sd = (bend.iter().map(|b| (b - mean).powi(2)).sum::<f64>() / s).sqrt();
    Ok(Exploration {
        points,
        beta,
        fitted_beta: fit_beta(&modal_variance, &c)?,
        theory_variance: c.iter().map(|ci| ci / beta).collect(),
        modal_variance,
        bend,
        bend_sd,
        bend_sd_linear,
    })
}

impl Report for Exploration {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)?;
        check_finite(&self.bend)
    }

    fn text(&self) -> String {
        let mut t = format!(
            "Unbiased exploration, β = {}, N = {}, {} postures\n  3-point bend: sd {:.6} rad (small-amplitude prediction {:.6})\n  β refitted from the modal variances: {:.6}\n  histogram of the bend angle:\n",
            number(self.beta),
            self.points,
            self.bend.len(),
            self.bend_sd,
            self.bend_sd_linear,
            self.fitted_beta
        );
        let lim = 4.0 * self.bend_sd;
        let bins = 21usize;
        let mut counts = vec![0usize; bins];
        for b in &self.bend {
            let k = ((b + lim) / (2.0 * lim) * bins as f64).floor();
            if k >= 0.0 && (k as usize) < bins {
                counts[k as usize] += 1;
            }
        }
        let top = counts.iter().copied().max().unwrap_or(1).max(1);
        for (k, c) in counts.iter().enumerate() {
            let centre = -lim + (k as f64 + 0.5) * 2.0 * lim / bins as f64;
            t += &format!("  {centre:>+9.4}  {}\n", "█".repeat(c * 50 / top));
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_numbers(&["bend"], self.bend.iter().map(|b| vec![*b])))
    }
}
