//! A continuum Euler–Bernoulli beam with an active force, simulated independently of the
//! engine for the coverage studies of `discover`: the exact solution of the beam's linear SDE
//!
//! ∂ₜ²y = −c ∂ₛ⁴y − c′ ∂ₜ∂ₛ⁴y − γ ∂ₜy + a ∂ₛ³y + ξ(s, t)
//!
//! (lateral displacement y(s, t), body length 1, unit mass per length, s ∈ [0, 1], the clamped
//! end at s = 0) in the beam's own flexible modes φⱼ (unit mean square, λⱼ = rⱼ⁴; the rigid-body
//! modes of a free–free beam, with no restoring force, are left out), with thermal noise of
//! covariance 2T·D (fluctuation–dissipation), sampled exactly every Δt from its stationary
//! state, tracked at K points of equal arc length with position noise, frames lost in bursts,
//! and written as the CSV the tool reads (body length 100 units, the time column in the beam's time unit).
//!
//! The modal equations are q̈ = −K q − D q̇ + A q + η with K = c·diag(λ), D = c′·diag(λ) + γ·I
//! and the active matrix Aᵢⱼ = a ∫₀¹ φᵢ φⱼ‴ ds (by Gauss–Legendre quadrature), not symmetric:
//! with a ≠ 0 the stationary state carries a probability current (E[q q̇ᵀ] ≠ 0).
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, StandardNormal};

use super::beam::root;

/// A simulated continuum beam. Lengths in body lengths, time in the time column's unit.
#[derive(Clone, Copy, Debug)]
pub struct Beam {
    /// Clamped at s = 0 and free at s = 1, or free at both ends.
    pub clamped: bool,
    /// Bending stiffness c (body length⁴/time²): ωₙ = √c rₙ² undamped, κ = √c.
    pub c: f64,
    /// Kelvin (internal) damping c′ (body length⁴/time): c′λₙ damps mode n.
    pub cp: f64,
    /// External damping γ (1/time).
    pub gamma: f64,
    /// The active force's coefficient a (body length³/time²) of a ∂ₛ³y.
    pub a: f64,
    /// The temperature T (body length²/time², the noise 2T·D): with a = 0, ⟨qₙ²⟩ = T/(cλₙ).
    pub temperature: f64,
    /// Flexible modes M kept.
    pub modes: usize,
    /// Tracked points K, at sₖ = k/(K − 1).
    pub points: usize,
    /// Tracking noise's standard deviation on each coordinate (body lengths).
    pub noise: f64,
    /// Frames simulated (before any is lost).
    pub frames: usize,
    /// Frames per period of the slowest mode, undamped: Δt = 2π/(ω₁·fpp).
    pub fpp: f64,
    /// The fraction of frames lost, in bursts of 1–10 frames, omitted from the CSV.
    pub lost: f64,
}

/// The default stiffness: κ = 0.05, ω₁ ≈ 1.12 (free–free) or 0.18 (clamped–free) per time unit.
pub const C: f64 = 2.5e-3;
/// The first mode's default damping ratio (γ = 0: all Kelvin, ζₙ ∝ rₙ²).
pub const ZETA1: f64 = 0.05;
/// The first mode's default rms amplitude with a = 0 (body lengths).
pub const AMPLITUDE: f64 = 0.01;
/// The active coefficient of [`Beam::active`], as a multiple of c (free–free, clamped–free).
pub const ACTIVE: [f64; 2] = [5.0, 5.0];

impl Beam {
    /// The passive beam (a = 0): c = [`C`], γ = 0, c′ giving ζ₁ = [`ZETA1`], T giving the first
    /// mode an rms amplitude [`AMPLITUDE`], 12 modes, 25 points, tracking noise 1 % of that
    /// amplitude, 20 000 frames at 14 per period, 5 % lost.
    pub fn passive(clamped: bool) -> Beam {
        let lambda1 = root(clamped, 1).powi(4);
        Beam {
            clamped,
            c: C,
            cp: 2.0 * ZETA1 * (C / lambda1).sqrt(),
            gamma: 0.0,
            a: 0.0,
            temperature: AMPLITUDE * AMPLITUDE * C * lambda1,
            modes: 12,
            points: 25,
            noise: 0.01 * AMPLITUDE,
            frames: 20_000,
            fpp: 14.0,
            lost: 0.05,
        }
    }

    /// [`Beam::passive`] with the active force a = [`ACTIVE`]·c.
    pub fn active(clamped: bool) -> Beam {
        Beam {
            a: ACTIVE[usize::from(clamped)] * C,
            ..Beam::passive(clamped)
        }
    }

    /// κ = √c (ωₙ = κ rₙ² undamped, body length 1).
    pub fn kappa(&self) -> f64 {
        self.c.sqrt()
    }

    /// The roots rₙ (n = 1 … M) of the flexible modes, λₙ = rₙ⁴.
    pub fn roots(&self) -> Vec<f64> {
        (1..=self.modes).map(|n| root(self.clamped, n)).collect()
    }

    /// Mode n's (n = 1 …) undamped angular frequency √(c λₙ) with a = 0.
    pub fn omega(&self, n: usize) -> f64 {
        self.kappa() * root(self.clamped, n).powi(2)
    }

    /// Mode n's damping ratio (c′λₙ + γ)/(2ωₙ) with a = 0.
    pub fn zeta(&self, n: usize) -> f64 {
        (self.cp * root(self.clamped, n).powi(4) + self.gamma) / (2.0 * self.omega(n))
    }

    /// The coefficients in a length unit of `length` per body length (the CSV's: 100), time
    /// unchanged: (c, c′, γ, a, T, κ) × (L⁴, L⁴, 1, L³, L³, L²), from the equation with s and y
    /// scaled by L (T from ⟨∫Y² dS⟩ = L³ ⟨∫y² ds⟩ per mode at the same cλ).
    pub fn in_units(&self, length: f64) -> [f64; 6] {
        let l = length;
        [
            self.c * l.powi(4),
            self.cp * l.powi(4),
            self.gamma,
            self.a * l.powi(3),
            self.temperature * l.powi(3),
            self.kappa() * l * l,
        ]
    }

    /// The frame interval Δt = 2π/(ω₁·fpp), ω₁ = √(c λ₁).
    pub fn dt(&self) -> f64 {
        2.0 * std::f64::consts::PI / (self.omega(1) * self.fpp)
    }
}

/// The d-th derivative in s of the mode of root r at s (unit mean square): `beam::shape`'s
/// function written without its cancellation (cosh x − σ sinh x = e⁻ˣ + (1 − σ) sinh x with
/// 1 − σ computed directly), exact to rounding at every root.
pub fn derivative(clamped: bool, r: f64, s: f64, d: u32) -> f64 {
    let x = r * s;
    // φ = e⁻ˣ + u sinh x + α cos x + β sin x.
    let (u, mut alpha, mut beta) = if clamped {
        let sigma = (r.cosh() + r.cos()) / (r.sinh() + r.sin());
        let u = (r.sin() - r.cos() - (-r).exp()) / (r.sinh() + r.sin());
        (u, -1.0, sigma)
    } else {
        let sigma = (r.cosh() - r.cos()) / (r.sinh() - r.sin());
        let u = (r.cos() - r.sin() - (-r).exp()) / (r.sinh() - r.sin());
        (u, 1.0, -sigma)
    };
    for _ in 0..d {
        (alpha, beta) = (beta, -alpha);
    }
    let sign = if d % 2 == 0 { 1.0 } else { -1.0 };
    let hyper = if d % 2 == 0 { x.sinh() } else { x.cosh() };
    r.powi(d as i32) * (sign * (-x).exp() + u * hyper + alpha * x.cos() + beta * x.sin())
}

/// Composite Gauss–Legendre on [0, 1]: `panels` panels of `order` nodes, (nodes, weights).
pub fn quadrature(panels: usize, order: usize) -> (Vec<f64>, Vec<f64>) {
    // The Legendre roots on [−1, 1] by Newton from Chebyshev guesses.
    let mut rule = Vec::new();
    for i in 0..order {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (order as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=order {
                let k = k as f64;
                (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
            }
            dp = order as f64 * (x * p1 - p0) / (x * x - 1.0);
            let step = p1 / dp;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        rule.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    let h = 1.0 / panels as f64;
    let mut nodes = Vec::with_capacity(panels * order);
    let mut weights = Vec::with_capacity(panels * order);
    for p in 0..panels {
        for &(x, w) in &rule {
            nodes.push(h * (p as f64 + 0.5 * (x + 1.0)));
            weights.push(0.5 * h * w);
        }
    }
    (nodes, weights)
}

/// ∫₀¹ φᵢ⁽ᵈ¹⁾ φⱼ⁽ᵈ²⁾ ds over the first `modes` flexible modes (200 panels of 12 nodes).
pub fn overlap(clamped: bool, modes: usize, d1: u32, d2: u32) -> DMatrix<f64> {
    let (nodes, weights) = quadrature(200, 12);
    let roots: Vec<f64> = (1..=modes).map(|n| root(clamped, n)).collect();
    let table = |d: u32| -> Vec<Vec<f64>> {
        (roots.iter())
            .map(|&r| {
                nodes
                    .iter()
                    .map(|&s| derivative(clamped, r, s, d))
                    .collect()
            })
            .collect()
    };
    let (f, g) = (table(d1), table(d2));
    DMatrix::from_fn(modes, modes, |i, j| {
        (0..nodes.len())
            .map(|k| weights[k] * f[i][k] * g[j][k])
            .sum()
    })
}

/// The beam's linear SDE dx = F x dt + G dW, x = (q, q̇), sampled exactly every Δt.
pub struct Discrete {
    /// λₙ = rₙ⁴.
    pub lambda: Vec<f64>,
    /// The active matrix Aᵢⱼ = a ∫ φᵢ φⱼ‴ ds.
    pub active: DMatrix<f64>,
    /// The drift F = [[0, I], [−K + A, −D]].
    pub drift: DMatrix<f64>,
    /// G Gᵀ = [[0, 0], [0, 2T·D]].
    pub diffusion: DMatrix<f64>,
    /// Φ = e^{FΔt}.
    pub phi: DMatrix<f64>,
    /// Q = ∫₀^Δt e^{Fs} G Gᵀ e^{Fᵀs} ds.
    pub q: DMatrix<f64>,
    /// The stationary covariance P = Φ P Φᵀ + Q.
    pub stationary: DMatrix<f64>,
    /// F's eigenvalues (re, im).
    pub eigenvalues: Vec<(f64, f64)>,
    /// Δt.
    pub dt: f64,
}

impl Discrete {
    /// The stability margin: −max Re of F's eigenvalues (positive when stable).
    pub fn margin(&self) -> f64 {
        -(self.eigenvalues.iter())
            .map(|e| e.0)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Van Loan's Φ and Q over a step h: exp([[−F, GGᵀ], [0, Fᵀ]] h) = [[·, Φ⁻¹Q], [0, Φᵀ]].
fn van_loan(f: &DMatrix<f64>, gg: &DMatrix<f64>, h: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = f.nrows();
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    m.view_mut((0, 0), (n, n)).copy_from(&(-f * h));
    m.view_mut((0, n), (n, n)).copy_from(&(gg * h));
    m.view_mut((n, n), (n, n)).copy_from(&(f.transpose() * h));
    let e = m.exp();
    let phi = e.view((n, n), (n, n)).transpose();
    let q = &phi * e.view((0, n), (n, n));
    (phi.clone_owned(), symmetric(q))
}

fn symmetric(m: DMatrix<f64>) -> DMatrix<f64> {
    (&m + m.transpose()) * 0.5
}

/// The exact discretisation of `beam`; panics on an unstable drift.
pub fn discretise(beam: &Beam) -> Discrete {
    let m = beam.modes;
    let lambda: Vec<f64> = beam.roots().iter().map(|r| r.powi(4)).collect();
    let active = overlap(beam.clamped, m, 0, 3) * beam.a;
    let mut drift = DMatrix::zeros(2 * m, 2 * m);
    let mut diffusion = DMatrix::zeros(2 * m, 2 * m);
    for i in 0..m {
        let damping = beam.cp * lambda[i] + beam.gamma;
        drift[(i, m + i)] = 1.0;
        drift[(m + i, m + i)] = -damping;
        diffusion[(m + i, m + i)] = 2.0 * beam.temperature * damping;
        for j in 0..m {
            drift[(m + i, j)] = active[(i, j)] - if i == j { beam.c * lambda[i] } else { 0.0 };
        }
    }
    let eigenvalues: Vec<(f64, f64)> = (drift.clone().complex_eigenvalues().iter())
        .map(|z| (z.re, z.im))
        .collect();
    let worst = (eigenvalues.iter()).fold(f64::NEG_INFINITY, |w, e| w.max(e.0));
    assert!(
        worst < 0.0,
        "an unstable beam: an eigenvalue of F with real part {worst:e} (a = {}, c = {}, c′ = {})",
        beam.a,
        beam.c,
        beam.cp
    );
    let dt = beam.dt();
    // Van Loan over a step short enough for the exponential of the stiff block, then doubled:
    // Φ₂ₕ = Φₕ², Q₂ₕ = Φₕ Qₕ Φₕᵀ + Qₕ.
    let norm = drift.abs().row_sum().max();
    let halvings = (norm * dt / 0.25).log2().ceil().max(0.0) as i32;
    let (mut phi, mut q) = van_loan(&drift, &diffusion, dt / 2f64.powi(halvings));
    for _ in 0..halvings {
        q = symmetric(&phi * &q * phi.transpose() + &q);
        phi = &phi * &phi;
    }
    // P = Σₖ Φᵏ Q Φᵏᵀ by doubling.
    let (mut power, mut stationary) = (phi.clone(), q.clone());
    let mut converged = false;
    for _ in 0..64 {
        stationary = symmetric(&stationary + &power * &stationary * power.transpose());
        power = &power * &power;
        if power.amax() < 1e-18 {
            converged = true;
            break;
        }
    }
    assert!(converged, "the discrete Lyapunov equation did not converge");
    Discrete {
        lambda,
        active,
        drift,
        diffusion,
        phi,
        q,
        stationary,
        eigenvalues,
        dt,
    }
}

/// A lower triangular L with L Lᵀ = `m` (positive definite).
fn cholesky(m: &DMatrix<f64>, what: &str) -> DMatrix<f64> {
    m.clone()
        .cholesky()
        .unwrap_or_else(|| panic!("{what} is not positive definite"))
        .l()
}

/// The states x = (q, q̇) at every frame, the first drawn from the stationary covariance.
pub fn states_with(beam: &Beam, d: &Discrete, rng: &mut impl rand::Rng) -> Vec<DVector<f64>> {
    let n = 2 * beam.modes;
    let mut z = || -> DVector<f64> { DVector::from_fn(n, |_, _| StandardNormal.sample(rng)) };
    let (lp, lq) = (cholesky(&d.stationary, "P"), cholesky(&d.q, "Q"));
    let mut x = &lp * z();
    let mut out = Vec::with_capacity(beam.frames);
    for _ in 0..beam.frames {
        out.push(x.clone());
        x = &d.phi * &x + &lq * z();
    }
    out
}

/// [`states_with`] for `seed`, as [`record`] draws them.
pub fn states(beam: &Beam, seed: u64) -> Vec<DVector<f64>> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    states_with(beam, &discretise(beam), &mut rng)
}

/// The tracked points sₖ = k/(K − 1).
pub fn stations(beam: &Beam) -> Vec<f64> {
    (0..beam.points)
        .map(|k| k as f64 / (beam.points - 1) as f64)
        .collect()
}

/// φⱼ(sₖ): K rows, M columns.
pub fn shapes(beam: &Beam) -> DMatrix<f64> {
    let (s, r) = (stations(beam), beam.roots());
    DMatrix::from_fn(beam.points, beam.modes, |k, j| {
        derivative(beam.clamped, r[j], s[k], 0)
    })
}

/// The noiseless midline y(sₖ) of each state.
pub fn midline(beam: &Beam, states: &[DVector<f64>]) -> Vec<DVector<f64>> {
    let phi = shapes(beam);
    (states.iter())
        .map(|x| &phi * x.rows(0, beam.modes))
        .collect()
}

/// Each state's tracked points (x₁, y₁, …), noiseless, as a tracker places them: at equal arc
/// length sₖ on the inextensible body whose tangent angle is ψ = ∂ₛy, x(s) = ∫₀ˢ cos ψ and
/// y(s) = y(0) + ∫₀ˢ sin ψ (Simpson, eight panels a segment). (At x = s and y(s) instead, the
/// points drift apart along a bent body: at the passive beam's amplitude that alone put an
/// active beam's c_y and a_y 4 % high.)
pub fn positions(beam: &Beam, states: &[DVector<f64>]) -> Vec<Vec<f64>> {
    let k = beam.points;
    let at0 = midline(beam, states);
    const SUB: usize = 8;
    let fine = (k - 1) * SUB;
    let r = beam.roots();
    let slope = DMatrix::from_fn(fine + 1, beam.modes, |i, j| {
        derivative(beam.clamped, r[j], i as f64 / fine as f64, 1)
    });
    let h = 1.0 / fine as f64;
    (states.iter().zip(&at0))
        .map(|(x, y)| {
            let psi = &slope * x.rows(0, beam.modes);
            let mut out = vec![0.0, y[0]];
            let (mut px, mut py) = (0.0, y[0]);
            for seg in 0..k - 1 {
                for p in (0..SUB).step_by(2) {
                    let i = seg * SUB + p;
                    let w = [1.0, 4.0, 1.0];
                    for (o, wt) in w.iter().enumerate() {
                        px += h / 3.0 * wt * psi[i + o].cos();
                        py += h / 3.0 * wt * psi[i + o].sin();
                    }
                }
                out.push(px);
                out.push(py);
            }
            out
        })
        .collect()
}

/// Which frames the recording keeps: `lost` of them (rounded) removed in bursts of 1–10 at
/// random positions, the first frame always kept. Its own stream of `seed`, so the loss
/// changes no state or tracking noise.
pub fn kept(beam: &Beam, seed: u64) -> Vec<bool> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(1);
    let mut keep = vec![true; beam.frames];
    let target = (beam.lost * beam.frames as f64).round() as usize;
    let mut lost = 0;
    while lost < target.min(beam.frames.saturating_sub(1)) {
        let start = rng.random_range(1..beam.frames);
        let len: usize = rng.random_range(1..=10);
        let end = (start + len).min(beam.frames);
        for k in keep[start..end].iter_mut() {
            if *k && lost < target {
                *k = false;
                lost += 1;
            }
        }
    }
    keep
}

/// The recording as the CSV the tool reads: `t,x1,y1,…`, t = frame × Δt, lengths × 100 (body
/// length 100 units), each coordinate with tracking noise, lost frames omitted.
pub fn record(beam: &Beam, seed: u64) -> String {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let d = discretise(beam);
    let p = positions(beam, &states_with(beam, &d, &mut rng));
    let keep = kept(beam, seed);
    let mut out = String::from("t");
    for k in 1..=beam.points {
        out += &format!(",x{k},y{k}");
    }
    out.push('\n');
    for (frame, row) in p.iter().enumerate() {
        // Noise is drawn for every frame, kept or not, so the loss shifts nothing.
        let e: Vec<f64> = (0..2 * beam.points)
            .map(|_| {
                let z: f64 = StandardNormal.sample(&mut rng);
                beam.noise * z
            })
            .collect();
        if !keep[frame] {
            continue;
        }
        out += &format!("{}", frame as f64 * d.dt);
        for (v, e) in row.iter().zip(&e) {
            out += &format!(",{}", 100.0 * (v + e));
        }
        out.push('\n');
    }
    out
}
