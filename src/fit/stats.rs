//! What a pass over the frames accumulates, in pieces that add up: for each run of frames
//! between gaps, the count, mean and co-moment of the modal coordinates (merged by Chan's
//! formula: for pieces a and b with δ = μ_b − μ_a, M = M_a + M_b + δδᵀ·n_a n_b/(n_a + n_b)) and
//! the raw Welch sums Σ|X̂(f)|² of its Hann-windowed segments. A piece taken c times (a bootstrap
//! draw) counts c·n frames, c·M and c times the sums: pooling animals, one animal alone and a
//! resample are the same operation.

use std::collections::VecDeque;
use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// The windows of a Welch estimate of length `len`: Hann taper and FFT plan, shared.
#[derive(Clone)]
pub(super) struct Plan {
    pub(super) window: Arc<Vec<f64>>,
    fft: Arc<dyn Fft<f64>>,
}

impl Plan {
    pub(super) fn new(len: usize) -> Plan {
        let window = (0..len)
            .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / len as f64).cos())
            .collect();
        Plan {
            window: Arc::new(window),
            fft: FftPlanner::new().plan_fft_forward(len),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.window.len()
    }

    /// Add the periodograms |X̂|² of one mean-removed, tapered segment (frames × channels).
    fn add(&self, frames: &VecDeque<Vec<f64>>, acc: &mut [Vec<f64>]) {
        let len = self.len();
        let mut data = vec![Complex::new(0.0, 0.0); len];
        for (c, acc) in acc.iter_mut().enumerate() {
            let mean = frames.iter().map(|v| v[c]).sum::<f64>() / len as f64;
            for (i, v) in frames.iter().enumerate() {
                data[i] = Complex::new((v[c] - mean) * self.window[i], 0.0);
            }
            self.fft.process(&mut data);
            for (k, a) in acc.iter_mut().enumerate() {
                *a += data[k].norm_sqr();
            }
        }
    }

    /// One-sided density (per cycle per time unit) at sampling rate `fs` from the sums of
    /// `segments` periodograms.
    pub(super) fn density(&self, sums: &[Vec<f64>], segments: f64, fs: f64) -> Spectra {
        let len = self.len();
        let norm = fs * self.window.iter().map(|w| w * w).sum::<f64>() * segments;
        let frequencies = (0..=len / 2).map(|k| k as f64 * fs / len as f64).collect();
        let psd = sums
            .iter()
            .map(|acc| {
                acc.iter()
                    .enumerate()
                    .map(|(k, a)| {
                        let twice = k != 0 && !(len % 2 == 0 && k == len / 2);
                        a / norm * if twice { 2.0 } else { 1.0 }
                    })
                    .collect()
            })
            .collect();
        Spectra {
            window: len,
            segments: segments.round() as usize,
            frequencies,
            psd,
        }
    }
}

/// Welch spectra of the modal coordinates: window, segments averaged, frequencies, densities.
pub(super) struct Spectra {
    pub(super) window: usize,
    pub(super) segments: usize,
    pub(super) frequencies: Vec<f64>,
    pub(super) psd: Vec<Vec<f64>>,
}

/// The sufficient statistics of some frames (one run, an animal, a pool, a resample).
#[derive(Clone, Debug, Default)]
pub(super) struct Stats {
    /// Frames.
    pub(super) count: f64,
    pub(super) mean: Vec<f64>,
    pub(super) comoment: Vec<Vec<f64>>,
    /// Σ|X̂|² per channel and frequency over the Welch segments.
    pub(super) sums: Vec<Vec<f64>>,
    pub(super) segments: f64,
    /// Σ of each frame's point spacing (data length units).
    pub(super) spacing: f64,
    /// When no run filled a window: the longest run, for one short segment of its own.
    pub(super) short: Vec<Vec<f64>>,
}

impl Stats {
    pub(super) fn new(m: usize, window: usize) -> Stats {
        Stats {
            mean: vec![0.0; m],
            comoment: vec![vec![0.0; m]; m],
            sums: vec![vec![0.0; window / 2 + 1]; m],
            ..Stats::default()
        }
    }

    /// Add `other` taken `times` times.
    pub(super) fn absorb(&mut self, other: &Stats, times: f64) {
        if other.count == 0.0 || times == 0.0 {
            return;
        }
        let (na, nb) = (self.count, times * other.count);
        let n = na + nb;
        let delta: Vec<f64> = other
            .mean
            .iter()
            .zip(&self.mean)
            .map(|(b, a)| b - a)
            .collect();
        for (mu, d) in self.mean.iter_mut().zip(&delta) {
            *mu += d * nb / n;
        }
        let w = na * nb / n;
        for (i, row) in self.comoment.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += times * other.comoment[i][j] + w * delta[i] * delta[j];
            }
        }
        for (acc, add) in self.sums.iter_mut().zip(&other.sums) {
            for (a, b) in acc.iter_mut().zip(add) {
                *a += times * b;
            }
        }
        self.count = n;
        self.segments += times * other.segments;
        self.spacing += times * other.spacing;
        if other.short.len() > self.short.len() {
            self.short = other.short.clone();
        }
    }

    /// Covariance of the modal coordinates (n − 1 normalisation).
    pub(super) fn covariance(&self) -> Vec<Vec<f64>> {
        let d = (self.count - 1.0).max(1.0);
        self.comoment
            .iter()
            .map(|r| r.iter().map(|c| c / d).collect())
            .collect()
    }

    /// The spectra: the Welch average, or without a whole window one segment over the
    /// longest run (at least 8 frames). `None` when there is neither.
    pub(super) fn spectra(&self, plan: &Plan, fs: f64) -> Option<Spectra> {
        if self.segments > 0.0 {
            return Some(plan.density(&self.sums, self.segments, fs));
        }
        if self.short.len() < 8 {
            return None;
        }
        let own = Plan::new(self.short.len());
        let mut sums = vec![vec![0.0; own.len() / 2 + 1]; self.mean.len()];
        own.add(&self.short.iter().cloned().collect(), &mut sums);
        Some(own.density(&sums, 1.0, fs))
    }
}

/// Streams one run's frames into its [`Stats`]: running moments, Welch segments at half
/// overlap.
pub(super) struct Run {
    pub(super) stats: Stats,
    buffer: VecDeque<Vec<f64>>,
    since: usize,
    plan: Plan,
}

impl Run {
    pub(super) fn new(m: usize, plan: &Plan) -> Run {
        Run {
            stats: Stats::new(m, plan.len()),
            buffer: VecDeque::with_capacity(plan.len()),
            since: 0,
            plan: plan.clone(),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.stats.count as usize
    }

    /// One frame's modal coordinates `q` and point spacing.
    pub(super) fn push(&mut self, q: Vec<f64>, spacing: f64) {
        let s = &mut self.stats;
        s.count += 1.0;
        s.spacing += spacing;
        let delta: Vec<f64> = q.iter().zip(&s.mean).map(|(a, b)| a - b).collect();
        for (mu, d) in s.mean.iter_mut().zip(&delta) {
            *mu += d / s.count;
        }
        for (i, row) in s.comoment.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += delta[i] * (q[j] - s.mean[j]);
            }
        }
        let len = self.plan.len();
        if self.buffer.len() == len {
            self.buffer.pop_front();
        }
        self.buffer.push_back(q);
        self.since += 1;
        if self.buffer.len() == len && (s.segments == 0.0 || self.since >= len / 2) {
            self.since = 0;
            s.segments += 1.0;
            self.plan.add(&self.buffer, &mut s.sums);
        }
    }

    /// The run's statistics, keeping its frames when it never filled a window.
    pub(super) fn finish(mut self) -> Stats {
        if self.stats.segments == 0.0 {
            self.stats.short = self.buffer.into_iter().collect();
        }
        self.stats
    }
}
