//! A thermal Euler–Bernoulli beam simulated independently of the engine, for the fit's tests:
//! the continuous beam (free–free or clamped–free, its modes from the beam's own characteristic
//! equation) whose modes are thermally driven damped oscillators, sampled exactly, tracked at K
//! points with position noise, and written as the CSV `fit` reads.
#![allow(dead_code)]

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use theory_search::fit::{fit, FitReport, FitSettings};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::InputKind;

/// A simulated body: its ends, κ (ωₙ = κ rₙ², body length 1), the first mode's damping ratio
/// (ζₙ ∝ rₙ², Kelvin damping), the first mode's rms amplitude, tracked points, position noise
/// (body lengths), frames.
#[derive(Clone, Copy)]
pub struct Body {
    pub clamped: bool,
    pub kappa: f64,
    pub zeta1: f64,
    pub amplitude: f64,
    pub points: usize,
    pub noise: f64,
    pub frames: usize,
    pub modes: usize,
}

/// The n-th root (n = 1, 2, …) of cos r cosh r = 1 (free–free) or −1 (clamped–free).
pub fn root(clamped: bool, n: usize) -> f64 {
    let target = if clamped { -1.0 } else { 1.0 };
    let centre = if clamped {
        n as f64 - 0.5
    } else {
        n as f64 + 0.5
    } * std::f64::consts::PI;
    let g = |r: f64| r.cos() - target / r.cosh();
    let (mut a, mut b) = (centre - 0.5, centre + 0.5);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if g(a) * g(m) <= 0.0 {
            b = m
        } else {
            a = m
        }
    }
    0.5 * (a + b)
}

/// The n-th mode shape at s ∈ [0, 1] (unit mean square).
pub fn shape(clamped: bool, r: f64, s: f64) -> f64 {
    let x = r * s;
    if clamped {
        let sigma = (r.cosh() + r.cos()) / (r.sinh() + r.sin());
        x.cosh() - x.cos() - sigma * (x.sinh() - x.sin())
    } else {
        let sigma = (r.cosh() - r.cos()) / (r.sinh() - r.sin());
        x.cosh() + x.cos() - sigma * (x.sinh() + x.sin())
    }
}

/// Exact samples (interval 1) of a damped oscillator of stationary variance `var`, under- or
/// over-damped (cos and sin become cosh and sinh past ζ = 1).
pub fn oscillator(omega: f64, zeta: f64, var: f64, n: usize, rng: &mut impl rand::Rng) -> Vec<f64> {
    let g = zeta * omega;
    let e = (-g).exp();
    // (cos d, sin d / d) of the damped frequency d, or their hyperbolic forms.
    let (c, sd) = if zeta < 1.0 {
        let d = (omega * omega - g * g).sqrt();
        (d.cos(), d.sin() / d)
    } else if zeta > 1.0 {
        let d = (g * g - omega * omega).sqrt();
        (d.cosh(), d.sinh() / d)
    } else {
        (1.0, 1.0)
    };
    let phi = [
        [e * (c + g * sd), e * sd],
        [-e * omega * omega * sd, e * (c - g * sd)],
    ];
    let sig = [var, omega * omega * var];
    let q = |i: usize, j: usize| {
        let m = if i == j { sig[i] } else { 0.0 };
        m - (0..2).map(|k| phi[i][k] * sig[k] * phi[j][k]).sum::<f64>()
    };
    let l00 = q(0, 0).sqrt();
    let l10 = q(1, 0) / l00;
    let l11 = (q(1, 1) - l10 * l10).max(0.0).sqrt();
    let mut z = || -> f64 { StandardNormal.sample(rng) };
    let (mut x, mut v) = (var.sqrt() * z(), sig[1].sqrt() * z());
    (0..n)
        .map(|_| {
            let (a, b) = (z(), z());
            let nx = phi[0][0] * x + phi[0][1] * v + l00 * a;
            let nv = phi[1][0] * x + phi[1][1] * v + l10 * a + l11 * b;
            (x, v) = (nx, nv);
            x
        })
        .collect()
}

/// A travelling wave y = A sin(k s − Ω t) over the body (s ∈ [0, 1], t in frames), as a
/// crawling animal's driven rhythm: every mode at the one frequency Ω, phase-locked.
#[derive(Clone, Copy)]
pub struct Wave {
    pub amplitude: f64,
    /// Wavenumber k (radians per body length).
    pub k: f64,
    /// Angular frequency Ω (radians per frame).
    pub omega: f64,
}

/// The recording as the CSV `fit` reads: `t, x₁, y₁, …`, body length 100 length units.
pub fn record(body: &Body, seed: u64) -> String {
    record_with(body, None, seed)
}

/// [`record`] with a travelling wave added to the thermal modes (none with `body.modes` 0).
/// The wave draws nothing from the generator, so a seed's thermal part is [`record`]'s.
pub fn record_with(body: &Body, wave: Option<Wave>, seed: u64) -> String {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let r1 = root(body.clamped, 1);
    let s: Vec<f64> = (0..body.points)
        .map(|j| j as f64 / (body.points - 1) as f64)
        .collect();
    let mut y = vec![vec![0.0; body.points]; body.frames];
    for n in 1..=body.modes {
        let r = root(body.clamped, n);
        let omega = body.kappa * r * r;
        let zeta = body.zeta1 * (r / r1).powi(2);
        // Equipartition: variance ∝ 1/λ ∝ r⁻⁴.
        let var = body.amplitude.powi(2) * (r1 / r).powi(4);
        let phi: Vec<f64> = s.iter().map(|&s| shape(body.clamped, r, s)).collect();
        let a = oscillator(omega, zeta, var, body.frames, &mut rng);
        for (row, a) in y.iter_mut().zip(&a) {
            for (v, p) in row.iter_mut().zip(&phi) {
                *v += a * p;
            }
        }
    }
    if let Some(w) = wave {
        for (t, row) in y.iter_mut().enumerate() {
            for (v, &s) in row.iter_mut().zip(&s) {
                *v += w.amplitude * (w.k * s - w.omega * t as f64).sin();
            }
        }
    }
    let mut out = String::from("t");
    for j in 1..=body.points {
        out += &format!(",x{j},y{j}");
    }
    out.push('\n');
    let mut noise = || -> f64 {
        let e: f64 = StandardNormal.sample(&mut rng);
        body.noise * e
    };
    for (t, row) in y.iter().enumerate() {
        out += &t.to_string();
        for (s, y) in s.iter().zip(row) {
            out += &format!(",{},{}", 100.0 * (s + noise()), 100.0 * (y + noise()));
        }
        out.push('\n');
    }
    out
}

pub fn model(clamped: bool) -> Model {
    if clamped {
        Model::from_toml(include_str!("../../tables/models/zebrafish.toml")).expect("shipped model")
    } else {
        Model::larva()
    }
}

pub fn fitted(text: &str, clamped: bool, points: usize, window: Option<usize>) -> FitReport {
    let mut s = FitSettings::new(InputKind::Midline);
    s.recording.points = points;
    s.window = window;
    fitted_with(text, clamped, &s)
}

/// The fit of `text` with settings `s`.
pub fn fitted_with(text: &str, clamped: bool, s: &FitSettings) -> FitReport {
    // Point 1 (s = 0 here, the clamped end) is read as the head: the zebrafish model clamps
    // its head.
    fit(
        std::io::Cursor::new(text.as_bytes()),
        &model(clamped),
        &Params::default(),
        s,
    )
    .expect("fits")
}

/// `job(r)` for r = 0 … runs − 1 on two threads, in order.
pub fn on_two_cores<T: Send>(runs: u64, job: impl Fn(u64) -> T + Sync) -> Vec<T> {
    let mut out: Vec<(u64, T)> = std::thread::scope(|scope| {
        let job = &job;
        let workers: Vec<_> = (0..2u64)
            .map(|w| {
                scope.spawn(move || {
                    (0..runs)
                        .filter(|r| r % 2 == w)
                        .map(|r| (r, job(r)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|h| h.join().expect("a worker"))
            .collect()
    });
    out.sort_by_key(|(r, _)| *r);
    out.into_iter().map(|(_, t)| t).collect()
}

/// The free–free thermal beam the fit's tests share: κ = 0.01, first mode ζ = 0.05, 25 tracked
/// points with position noise 2e-5 body lengths, 20 000 frames, six modes.
pub const FREE_BEAM: Body = Body {
    clamped: false,
    kappa: 0.01,
    zeta1: 0.05,
    amplitude: 0.01,
    points: 25,
    noise: 2e-5,
    frames: 20_000,
    modes: 6,
};

/// The clamped–free beam (the zebrafish model clamps its head): its modes spread faster
/// (rₙ² grows from 3.5), so κ is larger to keep three of them under Nyquist, and its position
/// noise smaller.
pub const CLAMPED_BEAM: Body = Body {
    clamped: true,
    kappa: 0.04,
    zeta1: 0.03,
    noise: 5e-6,
    points: 41,
    ..FREE_BEAM
};
