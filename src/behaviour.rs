//! Behaviour models of the seed that need more than the linear modal dynamics.
//!
//! * Forward/backward asymmetry (App. C): a degenerate axial pair with the cubic dissipative
//!   self-interaction `Ẍᵢ + ω²Xᵢ = c·φ̇·Xᵢ`, `φ̇ = X₁Ẋ₂ − X₂Ẋ₁`. The travelling wave
//!   `X₁ = A cos ω_s t, X₂ = A sin ω_s t` has `φ̇ = A²ω_s`, hence `ω_s² + cA²ω_s − ω² = 0`. The seed
//!   prints `cAω_s` (Eq. 94–96), which agrees only at A = 1; we solve the correct equation and
//!   confirm both roots by integrating the nonlinear pair (RK4) and measuring the phase advance.
//! * Axial–transverse resonance (App. D): the Mathieu equation `Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0`.
//!   The monodromy matrix M over one period 2π/ω (RK4 on the two fundamental solutions) has
//!   det M = 1; the motion is stable when |tr M| ≤ 2. The first instability tongue sits at
//!   ω = 2λ, between ω/λ = 2√(1 − ε) and 2√(1 + ε) for small ε.

mod righting;
pub use righting::{
    decay_rate, righting_sweep, self_righting, Attachment, Righting, RightingFrame,
    RightingSettings, SweepPoint,
};

/// A bad parameter of a behaviour model.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BehaviourError(pub String);

fn finite(name: &str, v: f64) -> Result<f64, BehaviourError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(BehaviourError(format!(
            "{name} must be a finite number, not {v}"
        )))
    }
}

fn positive(name: &str, v: f64) -> Result<f64, BehaviourError> {
    if finite(name, v)? > 0.0 {
        Ok(v)
    } else {
        Err(BehaviourError(format!("{name} must be positive, not {v}")))
    }
}

/// The index of field `id` in `model`.
fn field_index(model: &crate::model::Model, id: &str) -> Result<usize, BehaviourError> {
    model.fields.iter().position(|f| f.id == id).ok_or_else(|| {
        BehaviourError(format!(
            "unknown field {id:?} (the model has {})",
            model
                .fields
                .iter()
                .map(|f| f.id.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })
}

/// The index of field `id` and the modes (with shapes) of every field at order 4.
fn field_and_modes(
    model: &crate::model::Model,
    params: &crate::modal::Params,
    points: usize,
    id: &str,
) -> Result<(usize, Vec<crate::modal::FieldModes>), BehaviourError> {
    let index = field_index(model, id)?;
    let modes = crate::modal::field_modes(model, 4, points, params, None, true)
        .map_err(|e| BehaviourError(e.to_string()))?;
    Ok((index, modes))
}

/// Forward and backward frequencies of the self-interacting axial pair.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Asymmetry {
    /// The positive root of ω_s² + cA²ω_s − ω² = 0.
    pub forward: f64,
    /// The negative root.
    pub backward: f64,
    /// |backward / forward|.
    pub ratio: f64,
    /// The forward frequency measured by integrating the nonlinear pair.
    pub simulated_forward: f64,
    /// The backward frequency measured likewise.
    pub simulated_backward: f64,
}

/// Integrate `Ẍᵢ + ω²Xᵢ = c·φ̇·Xᵢ` from the travelling-wave state of frequency `ws` and return
/// the mean phase velocity of (X₁, X₂) over `periods` periods.
pub fn simulate_pair(c: f64, a: f64, omega: f64, ws: f64, periods: f64) -> f64 {
    let rhs = |x: [f64; 4]| {
        let (x1, x2, v1, v2) = (x[0], x[1], x[2], x[3]);
        let phi_dot = x1 * v2 - x2 * v1;
        [
            v1,
            v2,
            -omega * omega * x1 + c * phi_dot * x1,
            -omega * omega * x2 + c * phi_dot * x2,
        ]
    };
    let t_end = periods * 2.0 * std::f64::consts::PI / ws.abs();
    let steps = (periods * 2000.0).ceil() as usize;
    let h = t_end / steps as f64;
    let mut x = [a, 0.0, 0.0, a * ws];
    let mut angle = 0.0;
    let mut last = x[1].atan2(x[0]);
    for _ in 0..steps {
        let k1 = rhs(x);
        let k2 = rhs(std::array::from_fn(|i| x[i] + 0.5 * h * k1[i]));
        let k3 = rhs(std::array::from_fn(|i| x[i] + 0.5 * h * k2[i]));
        let k4 = rhs(std::array::from_fn(|i| x[i] + h * k3[i]));
        x = std::array::from_fn(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        // Unwrap the polar angle of (X₁, X₂).
        let now = x[1].atan2(x[0]);
        let mut d = now - last;
        d -= (d / (2.0 * std::f64::consts::PI)).round() * 2.0 * std::f64::consts::PI;
        angle += d;
        last = now;
    }
    angle / t_end
}

/// The forward (positive) and backward (negative) roots of ω_s² + cA²ω_s − ω² = 0, computed
/// stably (their product is −ω²). `omega` must be positive.
pub fn asymmetry_roots(c: f64, a: f64, omega: f64) -> (f64, f64) {
    let b = c * a * a;
    let root = (b * b + 4.0 * omega * omega).sqrt();
    let big = if b >= 0.0 {
        -(b + root) / 2.0
    } else {
        (root - b) / 2.0
    };
    let small = -omega * omega / big;
    if big > 0.0 {
        (big, small)
    } else {
        (small, big)
    }
}

/// The asymmetry for coupling `c`, amplitude `a` and free frequency `omega`.
pub fn asymmetry(c: f64, a: f64, omega: f64) -> Result<Asymmetry, BehaviourError> {
    let c = finite("the coupling", c)?;
    let a = positive("the amplitude", a)?;
    let omega = positive("the frequency", omega)?;
    let (forward, backward) = asymmetry_roots(c, a, omega);
    Ok(Asymmetry {
        forward,
        backward,
        ratio: (backward / forward).abs(),
        simulated_forward: simulate_pair(c, a, omega, forward, 20.0),
        simulated_backward: simulate_pair(c, a, omega, backward, 20.0),
    })
}

/// The monodromy matrix of `Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0` over one period 2π/ω.
pub fn mathieu_monodromy(lambda: f64, epsilon: f64, omega: f64) -> [[f64; 2]; 2] {
    let period = 2.0 * std::f64::consts::PI / omega;
    // 400 RK4 steps per half oscillation of the unforced motion keep tr M to ~1e-10.
    let steps = 400 * (2.0 * lambda / omega).ceil().max(1.0) as usize;
    let h = period / steps as f64;
    let f = |t: f64, y: [f64; 2]| {
        [
            y[1],
            -lambda * lambda * (1.0 - 2.0 * epsilon * (omega * t).cos()) * y[0],
        ]
    };
    let mut cols = [[1.0, 0.0], [0.0, 1.0]];
    for col in &mut cols {
        let mut y = *col;
        for n in 0..steps {
            let t = n as f64 * h;
            let k1 = f(t, y);
            let k2 = f(
                t + h / 2.0,
                [y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]],
            );
            let k3 = f(
                t + h / 2.0,
                [y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]],
            );
            let k4 = f(t + h, [y[0] + h * k3[0], y[1] + h * k3[1]]);
            for i in 0..2 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        *col = y;
    }
    // Columns are the images of (1, 0) and (0, 1): M = [[a, b], [c, d]] row-major.
    [[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]]
}

/// One point of the stability chart.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FloquetPoint {
    /// ω/λ.
    pub frequency_ratio: f64,
    /// ε.
    pub epsilon: f64,
    /// tr M.
    pub trace: f64,
    /// The larger Floquet multiplier modulus.
    pub multiplier: f64,
    /// |tr M| ≤ 2.
    pub stable: bool,
}

/// Floquet analysis at one point.
pub fn floquet(lambda: f64, epsilon: f64, omega: f64) -> Result<FloquetPoint, BehaviourError> {
    let lambda = positive("λ", lambda)?;
    let epsilon = finite("ε", epsilon)?;
    let omega = positive("ω", omega)?;
    let m = mathieu_monodromy(lambda, epsilon, omega);
    let trace = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = trace * trace / 4.0 - det;
    let multiplier = if disc > 0.0 {
        (trace.abs() / 2.0 + disc.sqrt()).max((trace.abs() / 2.0 - disc.sqrt()).abs())
    } else {
        det.abs().sqrt()
    };
    Ok(FloquetPoint {
        frequency_ratio: omega / lambda,
        epsilon,
        trace,
        multiplier,
        stable: trace.abs() <= 2.0 + 1e-9,
    })
}

/// The stability chart over ω/λ ∈ [lo, hi] (`n` points) and ε ∈ [0, ε_max] (`m` points).
pub fn stability_chart(
    lambda: f64,
    ratio: (f64, f64),
    epsilon_max: f64,
    grid: (usize, usize),
) -> Result<Vec<FloquetPoint>, BehaviourError> {
    let (lo, hi) = (
        positive("the lowest ω/λ", ratio.0)?,
        positive("the highest ω/λ", ratio.1)?,
    );
    if lo >= hi {
        return Err(BehaviourError(format!("the ω/λ range {lo}…{hi} is empty")));
    }
    let emax = finite("ε_max", epsilon_max)?;
    let (n, m) = grid;
    if !(2..=2000).contains(&n) || !(2..=2000).contains(&m) {
        return Err(BehaviourError(
            "the grid needs 2 to 2000 points each way".into(),
        ));
    }
    let mut out = Vec::with_capacity(n * m);
    for j in 0..m {
        let eps = emax * j as f64 / (m - 1) as f64;
        for i in 0..n {
            let r = lo + (hi - lo) * i as f64 / (n - 1) as f64;
            out.push(floquet(lambda, eps, r * lambda)?);
        }
    }
    Ok(out)
}

/// Statistics of a degenerate pair at inverse temperature β with conserved momentum M
/// (seed §3.3.3–3.3.4, App. J). Phase-space density ∝ exp(−β[p_A² + M²/A² + ω²A²]/2) on
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
        if depth == 0 || (sum - self.whole).abs() <= 15.0 * tol {
            return sum + (sum - self.whole) / 15.0;
        }
        left.refine(f, tol / 2.0, depth - 1) + right.refine(f, tol / 2.0, depth - 1)
    }
}

/// Adaptive Simpson quadrature of `f` on [a, b] to absolute tolerance `tol`.
pub fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    Panel::new(f, a, b, f(a), f(b)).refine(f, tol, 50)
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
/// (0 otherwise): scaled by e^{β|M|ω} so that its peak, at A* = √(|M|/ω), is 1.
pub fn pair_amplitude_weight(omega: f64, beta: f64, momentum: f64, a: f64) -> f64 {
    let m = momentum.abs();
    if a <= 0.0 {
        0.0
    } else {
        (-0.5 * beta * (m * m / (a * a) + omega * omega * a * a) + beta * m * omega).exp()
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
    let z = beta * m * omega;
    let pi = std::f64::consts::PI;
    let partition_function = 2.0 * pi * pi / (beta * omega) * (-z).exp();
    // Z = 2π·√(2π/β)·∫₀^∞ exp(−β(M²/A² + ω²A²)/2) dA, the last integral by quadrature. The
    // integrand peaks at A* and is negligible beyond A* + 12/(ω√β).
    let weight = |a: f64| pair_amplitude_weight(omega, beta, m, a);
    let upper = (m / omega).sqrt() + 12.0 / (omega * beta.sqrt());
    // A tolerance relative to the integral's size, √(π/2β)/ω: an absolute one would drive the
    // adaptive rule to its depth limit when ω is small.
    let scale = (pi / (2.0 * beta)).sqrt() / omega;
    let amplitude_integral = integrate(&weight, 0.0, upper, 1e-14 * scale) * (-z).exp();
    let partition_function_quadrature = 2.0 * pi * (2.0 * pi / beta).sqrt() * amplitude_integral;
    let mean_amplitude = if m == 0.0 {
        2f64.sqrt() / (omega * (pi * beta).sqrt())
    } else {
        (2.0 * beta).sqrt() * m * scaled_bessel_k1(z) / pi.sqrt()
    };
    Ok(PairStatistics {
        partition_function,
        partition_function_quadrature,
        free_energy: -partition_function.ln() / beta,
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
    if samples == 0 || samples > 100_000_000 {
        return Err(BehaviourError("samples must be between 1 and 10⁸".into()));
    }
    let energy = |a: f64, p: f64| 0.5 * (p * p + m * m / (a * a) + omega * omega * a * a);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let uniform = Uniform::new(0.0, 1.0).map_err(|e| BehaviourError(e.to_string()))?;
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

/// Principal components of simulated postures of one field beside its modes.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EquipartitionCheck {
    /// Field id.
    pub field: String,
    /// Postures used.
    pub frames: usize,
    /// Variance share of each principal component (descending), over the non-zero modes.
    pub pca_variance_share: Vec<f64>,
    /// Equipartition share λᵢ⁻¹/Σλⱼ⁻¹ of the non-zero modes (ascending λ).
    pub theory_variance_share: Vec<f64>,
    /// |cos| between principal component k and the k-th non-zero mode shape.
    pub overlap: Vec<f64>,
}

/// The largest steps × N² that [`equipartition_from_dynamics`] takes (about a minute).
pub const EQUIPARTITION_BUDGET: f64 = 2e10;

/// Run the Langevin dynamics of `model` at temperature `kt` and compare the PCA of the postures
/// of `field` with its modes (seed App. B: equipartition from dynamics).
pub fn equipartition_from_dynamics(
    model: &crate::model::Model,
    params: &crate::modal::Params,
    field: &str,
    points: usize,
    steps: u64,
    kt: f64,
    seed: u64,
) -> Result<EquipartitionCheck, BehaviourError> {
    use crate::dynamics::{simulate, Config};
    // Every step costs O(N²) across the four fields: refuse runs of more than about a minute.
    let work = steps as f64 * (points as f64).powi(2);
    if work > EQUIPARTITION_BUDGET {
        return Err(BehaviourError(format!(
            "{steps} steps on {points} points is {work:.1e} units of work, over the {EQUIPARTITION_BUDGET:.0e} budget (about a minute): use fewer points or steps"
        )));
    }
    let (index, modes) = field_and_modes(model, params, points, field)?;
    let f = &modes[index];
    let n = f.spectrum.size;
    let config = Config {
        points,
        order: 4,
        dt: 0.5,
        steps,
        every: 1,
        temperature: positive("kT", kt)?,
        seed,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    // Accumulate the covariance of the postures after a burn-in of a tenth of the run.
    let burn = steps / 10;
    let (mut sum, mut outer, mut frames) = (vec![0.0; n], vec![vec![0.0; n]; n], 0usize);
    simulate(model, params, &config, |s| {
        if (s.t / config.dt).round() as u64 > burn {
            let q = &s.positions[index];
            for i in 0..n {
                sum[i] += q[i];
                for j in 0..n {
                    outer[i][j] += q[i] * q[j];
                }
            }
            frames += 1;
        }
        Ok(())
    })
    .map_err(|e| BehaviourError(e.to_string()))?;
    let fr = frames as f64;
    let cov =
        faer::Mat::<f64>::from_fn(n, n, |i, j| outer[i][j] / fr - sum[i] * sum[j] / (fr * fr));
    let evd = cov
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| BehaviourError(format!("{e:?}")))?;
    let s = evd.S().column_vector();
    let u = evd.U();
    let nonzero = n - f.spectrum.nullity;
    // Principal components by descending variance; the zero modes carry none.
    let order: Vec<usize> = (0..n).rev().take(nonzero).collect();
    let total: f64 = order.iter().map(|&k| s[k].max(0.0)).sum();
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError("no shapes".into()))?;
    let overlap = order
        .iter()
        .enumerate()
        .map(|(rank, &k)| {
            let mode = f.spectrum.nullity + rank;
            (0..n)
                .map(|i| u[(i, k)] * shapes[(i, mode)])
                .sum::<f64>()
                .abs()
        })
        .collect();
    Ok(EquipartitionCheck {
        field: field.to_string(),
        frames,
        pca_variance_share: order.iter().map(|&k| s[k].max(0.0) / total).collect(),
        theory_variance_share: f.modes[f.spectrum.nullity..]
            .iter()
            .map(|m| m.variance_share)
            .collect(),
        overlap,
    })
}

/// Which degenerate pair to set in motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PairKind {
    /// The first axial cos/sin pair: a travelling compression wave (peristalsis).
    Peristalsis,
    /// The first mediolateral and dorsoventral bending modes: a C-bend rotating about the axis.
    Rolling,
}

/// The minimum-energy orbit of a degenerate pair at momentum M, run with the exact propagators.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PairOrbit {
    /// Which pair.
    pub kind: PairKind,
    /// The pair's frequency ω (natural frequency of its modes).
    pub omega: f64,
    /// The momentum M = Q_a·Q̇_b − Q_b·Q̇_a.
    pub momentum: f64,
    /// The orbit's amplitude A* = √(|M|/ω).
    pub amplitude: f64,
    /// Largest relative change of M over the run.
    pub momentum_drift: f64,
    /// Mean rate of the pair's polar angle, measured (equals ω·sign M).
    pub angular_velocity: f64,
    /// Mean rate at which the wave crest (peristalsis) or the bend direction at the head
    /// (rolling) moves, in body lengths or radians per unit time.
    pub body_rate: f64,
    /// (t, Q_a, Q_b) over the first period.
    pub trajectory: Vec<(f64, f64, f64)>,
    /// The body at eight instants of the first period: (t, field a, field b) at each point.
    pub postures: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

/// Run the minimum-energy orbit of `kind` for `periods` periods, undamped.
pub fn pair_orbit(
    model: &crate::model::Model,
    params: &crate::modal::Params,
    points: usize,
    kind: PairKind,
    momentum: f64,
    periods: f64,
) -> Result<PairOrbit, BehaviourError> {
    use crate::dynamics::{simulate, Config, Initial};
    use crate::modal::field_modes;
    let m = finite("M", momentum)?;
    if m == 0.0 {
        return Err(BehaviourError(
            "M = 0 has no orbit: the pair is at rest".into(),
        ));
    }
    let periods = positive("the number of periods", periods)?;
    // The undamped dynamics: the orbit is a statement about the conservative pair.
    let mut undamped = params.clone();
    for scale in model.fields.iter().map(|f| f.scale().to_string()) {
        undamped
            .set(&format!("zeta_{scale}"), 0.0)
            .map_err(|e| BehaviourError(e.to_string()))?;
    }
    let modes = field_modes(model, 4, points, &undamped, None, true)
        .map_err(|e| BehaviourError(e.to_string()))?;
    let index = |id: &str| field_index(model, id);
    // (field index, mode) of the two members of the pair.
    let (a, b) = match kind {
        PairKind::Peristalsis => {
            let x = index("x")?;
            let (i, j) = *modes[x]
                .degenerate_pairs
                .first()
                .ok_or_else(|| BehaviourError("x has no degenerate pair".into()))?;
            ((x, i), (x, j))
        }
        PairKind::Rolling => {
            let (y, z) = (index("y")?, index("z")?);
            let first = modes[y].spectrum.nullity;
            ((y, first), (z, first))
        }
    };
    let omega = modes[a.0].modes[a.1].frequency;
    if (modes[b.0].modes[b.1].frequency - omega).abs() > 1e-9 * omega {
        return Err(BehaviourError("the two modes are not degenerate".into()));
    }
    let amplitude = (m.abs() / omega).sqrt();
    let id = |f: usize| model.fields[f].id.clone();
    let period = 2.0 * std::f64::consts::PI / omega;
    let steps_per_period = 200u64;
    let dt = period / steps_per_period as f64;
    let steps = (periods * steps_per_period as f64).ceil() as u64;
    let config = Config {
        points,
        order: 4,
        dt,
        steps,
        every: 1,
        temperature: 0.0,
        seed: 0,
        initial: vec![
            Initial {
                field: id(a.0),
                mode: a.1,
                displacement: amplitude,
                velocity: 0.0,
            },
            Initial {
                field: id(b.0),
                mode: b.1,
                displacement: 0.0,
                velocity: m / amplitude,
            },
        ],
        forcing: Vec::new(),
    };
    let n_a = modes[a.0].spectrum.size;
    let unwrap = |last: &mut f64, total: &mut f64, now: f64| {
        let mut d = now - *last;
        d -= (d / (2.0 * std::f64::consts::PI)).round() * 2.0 * std::f64::consts::PI;
        *total += d;
        *last = now;
    };
    let (mut started, mut drift, mut angle, mut last_angle, mut body, mut last_body) =
        (false, 0.0f64, 0.0, 0.0, 0.0, 0.0);
    let mut t_end = 0.0;
    let (mut trajectory, mut postures) = (Vec::new(), Vec::new());
    let mut step = 0u64;
    simulate(model, &undamped, &config, |s| {
        let (qa, qb) = (s.modal[a.0][a.1], s.modal[b.0][b.1]);
        if step <= steps_per_period {
            trajectory.push((s.t, qa, qb));
            if step % (steps_per_period / 8) == 0 && step < steps_per_period {
                postures.push((s.t, s.positions[a.0].clone(), s.positions[b.0].clone()));
            }
        }
        step += 1;
        let (va, vb) = (s.velocity[a.0][a.1], s.velocity[b.0][b.1]);
        drift = drift.max(((qa * vb - qb * va - m) / m).abs());
        let phi = qb.atan2(qa);
        let body_angle = match kind {
            // Crest position: phase of the field's first Fourier component along the body.
            PairKind::Peristalsis => {
                let field = &s.positions[a.0];
                let (mut c, mut sn) = (0.0, 0.0);
                for (j, v) in field.iter().enumerate() {
                    let th = 2.0 * std::f64::consts::PI * j as f64 / n_a as f64;
                    c += v * th.cos();
                    sn += v * th.sin();
                }
                sn.atan2(c)
            }
            // Direction of the bend at the head in the y–z plane.
            PairKind::Rolling => {
                let head = s.positions[a.0].len() - 1;
                s.positions[b.0][head].atan2(s.positions[a.0][head])
            }
        };
        if started {
            unwrap(&mut last_angle, &mut angle, phi);
            unwrap(&mut last_body, &mut body, body_angle);
        } else {
            last_angle = phi;
            last_body = body_angle;
        }
        started = true;
        t_end = s.t;
        Ok(())
    })
    .map_err(|e| BehaviourError(e.to_string()))?;
    let body_rate = match kind {
        PairKind::Peristalsis => body / (2.0 * std::f64::consts::PI) / t_end,
        PairKind::Rolling => body / t_end,
    };
    Ok(PairOrbit {
        kind,
        omega,
        momentum: m,
        amplitude,
        momentum_drift: drift,
        angular_velocity: angle / t_end,
        body_rate,
        trajectory,
        postures,
    })
}

/// A constant generalised force on one mode (rearing: first dorsoventral bending mode; hunching:
/// first axial mode), started from rest.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepResponse {
    /// Field id.
    pub field: String,
    /// Mode index.
    pub mode: usize,
    /// The force.
    pub force: f64,
    /// The shifted equilibrium Q* = F/ωᵢ².
    pub equilibrium: f64,
    /// The equilibrium shape Q*·vᵢ at each point.
    pub shape: Vec<f64>,
    /// (t, Qᵢ(t)) of the transient.
    pub transient: Vec<(f64, f64)>,
    /// Largest deviation of the transient from the analytic step response.
    pub max_error: f64,
}

/// The analytic response of Q̈ + 2ζωQ̇ + ω²Q = F from rest: Q*(1 − e^{−ζωt}(cos ω_d t +
/// ζω/ω_d sin ω_d t)) (underdamped; the critical and overdamped forms likewise).
pub fn analytic_step(omega: f64, zeta: f64, force: f64, t: f64) -> f64 {
    let q = force / (omega * omega);
    let g = zeta * omega;
    if zeta < 1.0 {
        let wd = omega * (1.0 - zeta * zeta).sqrt();
        q * (1.0 - (-g * t).exp() * ((wd * t).cos() + g / wd * (wd * t).sin()))
    } else if zeta == 1.0 {
        q * (1.0 - (-omega * t).exp() * (1.0 + omega * t))
    } else {
        let r = omega * (zeta * zeta - 1.0).sqrt();
        let (s1, s2) = (-g + r, -g - r);
        q * (1.0 + (s2 * (s1 * t).exp() - s1 * (s2 * t).exp()) / (s1 - s2))
    }
}

/// Apply `force` to the first non-zero mode of `field` and follow it for `duration`.
pub fn step_response(
    model: &crate::model::Model,
    params: &crate::modal::Params,
    points: usize,
    field: &str,
    force: f64,
    duration: f64,
) -> Result<StepResponse, BehaviourError> {
    use crate::dynamics::{simulate, Config, Forcing};
    let force = finite("the force", force)?;
    let duration = positive("the duration", duration)?;
    let (index, modes) = field_and_modes(model, params, points, field)?;
    let f = &modes[index];
    let mode = f.spectrum.nullity;
    let m = &f.modes[mode];
    let (omega, zeta) = (m.frequency, m.damping_ratio);
    let steps = 400u64;
    let config = Config {
        points,
        order: 4,
        dt: duration / steps as f64,
        steps,
        every: 1,
        temperature: 0.0,
        seed: 0,
        initial: Vec::new(),
        forcing: vec![Forcing {
            field: field.to_string(),
            mode,
            constant: force,
            amplitude: 0.0,
            frequency: 0.0,
            phase: 0.0,
        }],
    };
    let mut transient = Vec::new();
    let mut max_error = 0.0f64;
    simulate(model, params, &config, |s| {
        let q = s.modal[index][mode];
        max_error = max_error.max((q - analytic_step(omega, zeta, force, s.t)).abs());
        transient.push((s.t, q));
        Ok(())
    })
    .map_err(|e| BehaviourError(e.to_string()))?;
    let equilibrium = force / (omega * omega);
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError("no shapes".into()))?;
    Ok(StepResponse {
        field: field.to_string(),
        mode,
        force,
        equilibrium,
        shape: (0..shapes.nrows())
            .map(|j| equilibrium * shapes[(j, mode)])
            .collect(),
        transient,
        max_error,
    })
}

/// Unbiased exploration (seed §3.3.4): planar postures with Gaussian modal coordinates.
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
        return Err(BehaviourError("need one variance per mode".into()));
    }
    if variances
        .iter()
        .chain(c)
        .any(|v| !v.is_finite() || *v <= 0.0)
    {
        return Err(BehaviourError(
            "variances must be positive finite numbers".into(),
        ));
    }
    let x = variances.iter().zip(c).map(|(v, ci)| v * ci).sum::<f64>()
        / c.iter().map(|ci| ci * ci).sum::<f64>();
    Ok(1.0 / x)
}

/// Sample `samples` planar postures of the mediolateral field at inverse temperature `beta`.
pub fn explore(
    model: &crate::model::Model,
    params: &crate::modal::Params,
    points: usize,
    beta: f64,
    samples: usize,
    seed: u64,
) -> Result<Exploration, BehaviourError> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let beta = positive("β", beta)?;
    if !(1..=10_000_000).contains(&samples) {
        return Err(BehaviourError("samples must be between 1 and 10⁷".into()));
    }
    let (y, modes) = field_and_modes(model, params, points, "y")?;
    let f = &modes[y];
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError("no shapes".into()))?;
    let (n, null) = (f.spectrum.size, f.spectrum.nullity);
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
    let bend_sd_linear = (0..n - null)
        .map(|k| {
            let dot: f64 = (0..n).map(|j| w(j) * shapes[(j, null + k)]).sum();
            dot * dot * c[k] / beta
        })
        .sum::<f64>()
        .sqrt();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut bend = Vec::with_capacity(samples);
    let (mut sum, mut sq) = (vec![0.0; n - null], vec![0.0; n - null]);
    let mut q = vec![0.0; n - null];
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
