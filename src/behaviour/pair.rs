//! Statistical mechanics of a degenerate pair at fixed momentum (paper §3.3.3–3.3.4, App. J):
//! partition function, free energy, amplitudes, and a Metropolis sampler to check them.

use super::{finite, positive, BehaviourError};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};
use crate::theory::Theory;

/// Statistics of a degenerate pair at inverse temperature β with conserved momentum M
/// (paper §3.3.3–3.3.4, App. J). Phase-space density ∝ exp(−β[p_A² + M²/A² + ω²A²]/2) on
/// A > 0, φ ∈ [0, 2π), p_A ∈ ℝ.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PairStatistics {
    /// Z = 2π²/(βω)·e^{−β|M|ω}.
    pub partition_function: f64,
    /// The same Z by numerical quadrature of the phase-space integral.
    pub partition_function_quadrature: f64,
    /// F = −ln Z/β = ln(βω/2π²)/β + |M|ω.
    pub free_energy: f64,
    /// ∂F/∂M = ω·sign(M): the kink at M = 0 jumps from −ω to +ω.
    pub free_energy_slope: f64,
    /// The minimum of U_eff = ½(M²/A² + ω²A²): A* = √(|M|/ω).
    pub amplitude_at_minimum: f64,
    /// ⟨A⟩ = √(2β)|M|·e^{z}K₁(z)/√π, z = β|M|ω (at M = 0: √2/(ω√(πβ))).
    pub mean_amplitude: f64,
}

/// ω given for a pair (`stats pair`, `asymmetry`): scales beside it would have no effect, so
/// they are refused rather than ignored.
pub fn given_pair_frequency(omega: f64, scales_given: bool) -> Result<f64, BehaviourError> {
    if scales_given {
        return Err(BehaviourError::Invalid(
            "omega gives ω itself: parameters (--param, --params) would have no effect (give one or the other)".into(),
        ));
    }
    Ok(omega)
}

/// ω of the first degenerate pair of `theory`'s axial field, for `behaviour`.
pub fn pair_frequency(theory: &Theory, behaviour: &str) -> Result<f64, BehaviourError> {
    let f = super::role_fields(&theory.model, behaviour)?[0];
    let fm = &theory.modes[f];
    let (i, _) = *fm.degenerate_pairs.first().ok_or_else(|| {
        BehaviourError::Body(format!(
            "{behaviour}: the axial field {} of model {:?} has no degenerate pair (give omega)",
            fm.field.id, theory.model.name
        ))
    })?;
    Ok(fm.modes[i].frequency)
}

/// An interval of the adaptive Simpson rule with its end and mid values and its estimate.
#[derive(Clone, Copy)]
struct Panel {
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
}

impl Panel {
    fn new(f: &dyn Fn(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64) -> Panel {
        let fm = f(0.5 * (a + b));
        Panel {
            a,
            b,
            fa,
            fm,
            fb,
            whole: (b - a) / 6.0 * (fa + 4.0 * fm + fb),
        }
    }

    fn refine(self, f: &dyn Fn(f64) -> f64, tol: f64, depth: u32) -> f64 {
        let m = 0.5 * (self.a + self.b);
        let left = Panel::new(f, self.a, m, self.fa, self.fm);
        let right = Panel::new(f, m, self.b, self.fm, self.fb);
        let sum = left.whole + right.whole;
        if depth == 0 || !sum.is_finite() || (sum - self.whole).abs() <= 15.0 * tol {
            return sum + (sum - self.whole) / 15.0;
        }
        left.refine(f, tol / 2.0, depth - 1) + right.refine(f, tol / 2.0, depth - 1)
    }
}

/// Adaptive Simpson quadrature of `f` on [a, b] to absolute tolerance `tol`: 16 panels refined
/// at most 24 times each, so a tolerance below the integrand's own rounding noise costs at most
/// 16·2²⁴ evaluations, never a hang.
pub fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let panels = 16;
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|i| {
            let (x0, x1) = (a + i as f64 * h, a + (i + 1) as f64 * h);
            Panel::new(f, x0, x1, f(x0), f(x1)).refine(f, tol / panels as f64, 24)
        })
        .sum()
}

/// e^z·K₁(z) for z > 0, from K₁(z) = ∫₀^∞ e^{−z cosh t} cosh t dt.
pub fn scaled_bessel_k1(z: f64) -> f64 {
    // The integrand e^{−z(cosh t − 1)} cosh t is below e^{−60} beyond cosh t = 1 + 60/z.
    let t_max = (1.0 + 60.0 / z).acosh() + 1.0;
    integrate(
        &|t: f64| (-z * (t.cosh() - 1.0)).exp() * t.cosh(),
        0.0,
        t_max,
        1e-13 / z.min(1.0),
    )
}

/// The unnormalised amplitude density of a pair, exp(−β(M²/A² + ω²A²)/2 + β|M|ω) for A > 0
/// (its limit at A = 0, 0 below): scaled by e^{β|M|ω} so that its peak, at A* = √(|M|/ω), is 1. Written as
/// exp(−β(|M|/A − ωA)²/2), which it equals, so no large exponents cancel.
pub fn pair_amplitude_weight(omega: f64, beta: f64, momentum: f64, a: f64) -> f64 {
    let m = momentum.abs();
    if a < 0.0 || (a == 0.0 && m > 0.0) {
        0.0
    } else if a == 0.0 {
        // The limit A → 0 at M = 0: the density is continuous there.
        1.0
    } else {
        let d = m / a - omega * a;
        (-0.5 * beta * d * d).exp()
    }
}

/// The scales a pair's statistics need stay representable: the amplitude width 1/(ω√β), the
/// orbit A* = √(|M|/ω) and 2π²/(βω).
fn check_scales(omega: f64, beta: f64, m: f64) -> Result<(), BehaviourError> {
    let width = 1.0 / (omega * beta.sqrt());
    let orbit = (m / omega).sqrt();
    let z0 = 1.0 / (beta * omega);
    if [width, orbit, z0]
        .iter()
        .all(|v| v.is_finite() && *v < 1e150)
        && width > 1e-150
    {
        Ok(())
    } else {
        Err(BehaviourError::new(format!(
            "ω = {omega:?}, β = {beta:?}, M = {m:?} put the amplitude scales 1/(ω√β) = {width:.3e} and √(|M|/ω) = {orbit:.3e} outside 1e-150…1e150"
        )))
    }
}

/// The analytic statistics of a pair, with a quadrature check of Z.
pub fn pair_statistics(
    omega: f64,
    beta: f64,
    momentum: f64,
) -> Result<PairStatistics, BehaviourError> {
    let omega = positive("ω", omega)?;
    let beta = positive("β", beta)?;
    let m = finite("M", momentum)?.abs();
    check_scales(omega, beta, m)?;
    let z = beta * m * omega;
    let pi = std::f64::consts::PI;
    let partition_function = 2.0 * pi * pi / (beta * omega) * (-z).exp();
    // Z = 2π·√(2π/β)·∫₀^∞ exp(−β(M²/A² + ω²A²)/2) dA, the last integral by quadrature. The
    // integrand peaks at A* and is negligible beyond A* + 12/(ω√β).
    let weight = |a: f64| pair_amplitude_weight(omega, beta, m, a);
    // |M/A − ωA| ≥ ω|A − A*| on both sides, so the window A* ± 12/(ω√β) holds all but e^{−72}.
    let half = 12.0 / (omega * beta.sqrt());
    let (lower, upper) = (
        ((m / omega).sqrt() - half).max(0.0),
        (m / omega).sqrt() + half,
    );
    // A tolerance relative to the integral's size, √(π/2β)/ω: an absolute one would drive the
    // adaptive rule to its depth limit when ω is small.
    let scale = (pi / (2.0 * beta)).sqrt() / omega;
    let amplitude_integral = integrate(&weight, lower, upper, 1e-14 * scale) * (-z).exp();
    let partition_function_quadrature = 2.0 * pi * (2.0 * pi / beta).sqrt() * amplitude_integral;
    let mean_amplitude = if m == 0.0 {
        2f64.sqrt() / (omega * (pi * beta).sqrt())
    } else {
        (2.0 * beta).sqrt() * m * scaled_bessel_k1(z) / pi.sqrt()
    };
    Ok(PairStatistics {
        partition_function,
        partition_function_quadrature,
        // −ln Z/β in closed form: Z itself underflows beyond β|M|ω ≈ 745.
        free_energy: ((beta * omega / (2.0 * pi * pi)).ln() + z) / beta,
        free_energy_slope: if momentum == 0.0 {
            0.0
        } else {
            omega * momentum.signum()
        },
        amplitude_at_minimum: (m / omega).sqrt(),
        mean_amplitude,
    })
}

/// A Metropolis sample of a pair's phase space (A, φ, p_A) at fixed M.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PairSamples {
    /// Sampled amplitudes.
    #[serde(skip)]
    pub amplitude: Vec<f64>,
    /// Sampled phases.
    #[serde(skip)]
    pub phase: Vec<f64>,
    /// Sampled momenta conjugate to A.
    #[serde(skip)]
    pub momentum: Vec<f64>,
    /// Mean of the sampled amplitudes.
    pub mean_amplitude: f64,
    /// Fraction of accepted proposals.
    pub acceptance_rate: f64,
    /// Effective sample size of A (initial positive sequence of autocorrelations).
    pub effective_sample_size: f64,
}

/// Draw `samples` states by random-walk Metropolis (seeded ChaCha8).
pub fn sample_pair(
    omega: f64,
    beta: f64,
    momentum: f64,
    samples: usize,
    seed: u64,
) -> Result<PairSamples, BehaviourError> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal, Uniform};
    let omega = positive("ω", omega)?;
    let beta = positive("β", beta)?;
    let m = finite("M", momentum)?.abs();
    // Fewer than 100 draws give no meaningful mean or autocorrelation.
    if !(100..=100_000_000).contains(&samples) {
        return Err(BehaviourError::new(format!(
            "--samples must be between 100 and 10⁸, not {samples}"
        )));
    }
    let energy = |a: f64, p: f64| 0.5 * (p * p + m * m / (a * a) + omega * omega * a * a);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let uniform = Uniform::new(0.0, 1.0).map_err(|e| BehaviourError::new(e.to_string()))?;
    // Steps scaled to the thermal widths; start at the minimum.
    let (step_a, step_p) = (1.0 / (omega * beta.sqrt()), 1.0 / beta.sqrt());
    let (mut a, mut p) = ((m / omega).sqrt().max(step_a), 0.0);
    let mut phi: f64 = 0.0;
    let (mut amplitude, mut phase, mut moment) = (
        Vec::with_capacity(samples),
        Vec::with_capacity(samples),
        Vec::with_capacity(samples),
    );
    let mut accepted = 0usize;
    let burn = samples / 10 + 1000;
    for i in 0..samples + burn {
        let na =
            a + step_a * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng);
        let np =
            p + step_p * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng);
        let nphi = (phi
            + 2.0 * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng))
        .rem_euclid(2.0 * std::f64::consts::PI);
        let u: f64 = uniform.sample(&mut rng);
        if na > 0.0 && u < (-beta * (energy(na, np) - energy(a, p))).exp() {
            (a, p, phi) = (na, np, nphi);
            if i >= burn {
                accepted += 1;
            }
        }
        if i >= burn {
            amplitude.push(a);
            phase.push(phi);
            moment.push(p);
        }
    }
    let n = amplitude.len() as f64;
    let mean = amplitude.iter().sum::<f64>() / n;
    let var = amplitude.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    // Geyer's initial positive sequence: sum autocorrelations while pairs stay positive.
    let rho = |lag: usize| -> f64 {
        amplitude
            .iter()
            .zip(&amplitude[lag..])
            .map(|(x, y)| (x - mean) * (y - mean))
            .sum::<f64>()
            / (n * var)
    };
    let mut tau = 1.0;
    let mut lag = 1;
    while lag + 1 < amplitude.len().min(10_000) {
        let pair = rho(lag) + rho(lag + 1);
        if pair <= 0.0 {
            break;
        }
        tau += 2.0 * pair;
        lag += 2;
    }
    Ok(PairSamples {
        mean_amplitude: mean,
        acceptance_rate: accepted as f64 / samples as f64,
        effective_sample_size: n / tau,
        amplitude,
        phase,
        momentum: moment,
    })
}

/// `stats pair`: the statistics at (ω, β, M), with a Metropolis run when samples were asked.
#[derive(Debug, Clone)]
pub struct PairReport {
    /// ω.
    pub omega: f64,
    /// β.
    pub beta: f64,
    /// M.
    pub momentum: f64,
    /// The sampler's seed.
    pub seed: u64,
    /// The exact statistics.
    pub stats: PairStatistics,
    /// The Metropolis run, if any.
    pub samples: Option<PairSamples>,
}

impl PairReport {
    /// The statistics, and `samples` Metropolis samples with `seed` if given.
    pub fn new(
        omega: f64,
        beta: f64,
        momentum: f64,
        samples: Option<usize>,
        seed: u64,
    ) -> Result<PairReport, BehaviourError> {
        Ok(PairReport {
            omega,
            beta,
            momentum,
            seed,
            stats: pair_statistics(omega, beta, momentum)?,
            samples: samples
                .map(|k| sample_pair(omega, beta, momentum, k, seed))
                .transpose()?,
        })
    }
}

impl Report for PairReport {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(&self.stats)?;
        if let Some(m) = &self.samples {
            check_finite(m)?;
            check_finite(&(&m.amplitude, &m.phase, &m.momentum))?;
        }
        Ok(())
    }

    fn text(&self) -> String {
        let s = &self.stats;
        let mut t = format!(
            "Degenerate pair, ω = {}, β = {}, M = {}\n  Z = 2π²/(βω)·e^(−β|M|ω) = {} (quadrature {})\n  F = −ln Z/β = {:.12}, ∂F/∂M = {} (kink at M = 0: ∓ω)\n  A* = √(|M|/ω) = {:.12}, ⟨A⟩ = {:.12}\n",
            number(self.omega), number(self.beta), number(self.momentum),
            fixed_or_exponent(s.partition_function), fixed_or_exponent(s.partition_function_quadrature), s.free_energy,
            s.free_energy_slope, s.amplitude_at_minimum, s.mean_amplitude
        );
        if let Some(m) = &self.samples {
            t += &format!(
                "  Metropolis ({} samples, seed {}): ⟨A⟩ = {:.6}, acceptance {:.3}, effective sample size {:.0}\n",
                m.amplitude.len(), self.seed, m.mean_amplitude, m.acceptance_rate, m.effective_sample_size
            );
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        let mut v = to_json(&self.stats);
        if let Some(s) = &self.samples {
            v["samples"] = to_json(s);
        }
        v
    }

    fn csv(&self) -> Option<String> {
        let s = &self.stats;
        Some(match &self.samples {
            Some(m) => csv_numbers(
                &["amplitude", "phase", "momentum_a"],
                (0..m.amplitude.len()).map(|i| vec![m.amplitude[i], m.phase[i], m.momentum[i]]),
            ),
            None => csv_numbers(
                &[
                    "partition_function",
                    "free_energy",
                    "amplitude_at_minimum",
                    "mean_amplitude",
                ],
                [vec![
                    s.partition_function,
                    s.free_energy,
                    s.amplitude_at_minimum,
                    s.mean_amplitude,
                ]],
            ),
        })
    }
}

/// Twelve decimals, or 12 significant digits in exponent form where twelve decimals would
/// print a tiny or huge Z as 0.000000000000 or a wall of digits.
fn fixed_or_exponent(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e8).contains(&v.abs()) {
        format!("{v:.11e}")
    } else {
        format!("{v:.12}")
    }
}
