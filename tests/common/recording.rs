//! Recordings of known theories for `discover`: the tool's own `simulate` (checked against
//! independent integrators in `simulate`, `nonlinear_dynamics` and `active_waves`) with
//! Langevin noise, each frame's rigid part (translation and the linearised rotation, a shear)
//! removed, written as the midlines a tracker gives (head first, body lengths) with tracking
//! noise of a given share of the bending's rms.
#![allow(dead_code)]

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// What to simulate.
pub struct Spec<'a> {
    pub model: &'a str,
    pub field: &'a str,
    pub points: usize,
    pub params: &'a [&'a str],
    pub dt: f64,
    pub every: usize,
    pub frames: usize,
    pub temperature: f64,
    /// Tracking noise per coordinate, as a share of the bending's rms.
    pub noise: f64,
    pub seed: u64,
}

/// `simulate` of `spec` (and `extra` options): each written sample's time and the field's
/// values at the points.
fn simulate(spec: &Spec, extra: &[&str]) -> Vec<(f64, Vec<f64>)> {
    let steps = (spec.frames - 1) * spec.every;
    let (points, dt, steps, every, temperature, seed) = (
        spec.points.to_string(),
        spec.dt.to_string(),
        steps.to_string(),
        spec.every.to_string(),
        spec.temperature.to_string(),
        spec.seed.to_string(),
    );
    let mut args = vec![
        "simulate",
        "--model",
        spec.model,
        "--points",
        &points,
        "--dt",
        &dt,
        "--steps",
        &steps,
        "--every",
        &every,
        "--temperature",
        &temperature,
        "--seed",
        &seed,
    ];
    for p in spec.params {
        args.extend(["--param", p]);
    }
    args.extend(extra);
    let text = crate::common::cli(&args).expect("the simulation runs");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let columns: Vec<usize> = (0..spec.points)
        .map(|i| {
            let name = format!("{}_{i}", spec.field);
            header
                .iter()
                .position(|h| *h == name)
                .expect("the field's column")
        })
        .collect();
    lines
        .map(|line| {
            let v: Vec<f64> = line
                .split(',')
                .map(|x| x.parse().expect("a number"))
                .collect();
            (v[0], columns.iter().map(|&c| v[c]).collect())
        })
        .collect()
}

/// The recording as CSV text (`t x₁ y₁ … x_N y_N`, head first).
pub fn midlines(spec: &Spec) -> String {
    let h = 1.0 / (spec.points as f64 - 1.0);
    let s: Vec<f64> = (0..spec.points).map(|i| i as f64 * h).collect();
    let mean_s = s.iter().sum::<f64>() / s.len() as f64;
    let var_s = s.iter().map(|x| (x - mean_s).powi(2)).sum::<f64>();
    let mut frames = Vec::new();
    for (t, field) in simulate(spec, &[]) {
        let y: Vec<f64> = field.iter().map(|v| v * h).collect();
        // The rigid part a + b·s (least squares) removed.
        let mean_y = y.iter().sum::<f64>() / y.len() as f64;
        let b = s
            .iter()
            .zip(&y)
            .map(|(si, yi)| (si - mean_s) * yi)
            .sum::<f64>()
            / var_s;
        let bend: Vec<f64> = s
            .iter()
            .zip(&y)
            .map(|(si, yi)| yi - mean_y - b * (si - mean_s))
            .collect();
        frames.push((t, bend));
    }
    let all: Vec<f64> = frames.iter().flat_map(|(_, b)| b.iter().copied()).collect();
    let rms = (all.iter().map(|x| x * x).sum::<f64>() / all.len() as f64).sqrt();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed + 1000);
    let normal = Normal::new(0.0, spec.noise * rms).expect("a finite noise");
    let mut out = String::new();
    for (t, bend) in frames {
        out += &t.to_string();
        for i in (0..spec.points).rev() {
            let x = s[i] + normal.sample(&mut rng);
            let y = bend[i] + normal.sample(&mut rng);
            out += &format!(",{x},{y}");
        }
        out += "\n";
    }
    out
}

/// The model one order beyond leading (from the `initial` state, `simulate --initial` values,
/// at `spec.temperature`) as the segment lengths a tracker gives (head first, body lengths): the axial field
/// `spec.field` on `spec.points` points, positions sᵢ + h·xᵢ with tracking noise of a share of
/// the strains' rms times h.
pub fn lengths(spec: &Spec, initial: &[&str]) -> String {
    let mut extra = vec!["--beyond-leading", "1"];
    for i in initial {
        extra.extend(["--initial", i]);
    }
    let frames = simulate(spec, &extra);
    let strains: Vec<f64> = frames
        .iter()
        .flat_map(|(_, x)| x.windows(2).map(|w| w[1] - w[0]))
        .collect();
    let rms = (strains.iter().map(|e| e * e).sum::<f64>() / strains.len() as f64).sqrt();
    let h = 1.0 / (spec.points as f64 - 1.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed + 1000);
    let normal = Normal::new(0.0, spec.noise * rms * h).expect("a finite noise");
    let mut out = String::new();
    for (t, x) in frames {
        let t = t.to_string();
        let p: Vec<f64> = (0..spec.points)
            .rev()
            .map(|i| i as f64 * h + h * x[i] + normal.sample(&mut rng))
            .collect();
        out += &t;
        for w in p.windows(2) {
            out += &format!(",{}", (w[1] - w[0]).abs());
        }
        out += "\n";
    }
    out
}
