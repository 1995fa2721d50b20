//! Tracking noise, measured for what it is (Gittes et al. 1993 look where the body stops and
//! the noise goes on): white position noise σ per coordinate at the K tracked points.
//!
//! A frame's turning angles ψ at the tracked points (d = K − 2 of them, segment lengths ℓᵢ in
//! body lengths) move under small position errors δr as δψ = J δr, and isotropic white errors
//! give Cov(δψ) = σ² M with M = D A Dᵀ: D the difference ψⱼ = φⱼ₊₁ − φⱼ of the segment angles
//! φ, A their covariance per σ², Aᵢᵢ = 2/ℓᵢ², Aᵢ,ᵢ₊₁ = −cos ψᵢ₊₁/(ℓᵢℓᵢ₊₁) (averaged over frames).
//! The angles' covariance is C = B + σ² M with B ⪰ 0 the body's, so the least generalised
//! eigenvalue of (C, M) is σ² plus the body's least share: an upper bound, and σ² itself
//! where the body leaves a direction to the noise alone (a smooth body tracked at more points
//! than it has modes). The same holds for half the covariance of the frame-to-frame change,
//! C_Δ = B_Δ + σ² M, whose body part is small for modes slow against the frame rate; the
//! smaller of the two is reported. The noise-only eigenvalues of a finite sample spread over
//! the Marchenko–Pastur band: σ² is the mean of those in the band of the least, and it is
//! called *measured* when at least two lie there (two directions hold noise alone), else an
//! upper bound.
//!
//! Cost is budgeted: every frame while an animal has fewer than [`EVERY`] frames, then every
//! second pair, every fourth, … (the stride doubles with the count), so a 10⁶-frame recording
//! costs about 7·10⁴ frames' angles.

use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::merge_moments;
use super::observe::{segment_angles, size, sizes};

/// The most tracked points the measure uses: of more, every k-th (the work per frame grows as
/// the square of the points, the final eigenproblem as the cube).
pub const MAX_POINTS: usize = 101;

/// Frames taken one by one before the stride starts to double.
const EVERY: usize = 1 << 14;

/// The noise-only eigenvalues of a sample of `n` frames in d dimensions spread over the
/// Marchenko–Pastur band σ²(1 ± √(d/n))²: those within it of the least are taken as noise
/// alone, σ² their mean (the least alone is biased low by (1 − √(d/n))²), and the count says
/// whether there were at least two.
fn plateau(sorted: &[f64], n: f64) -> (f64, usize) {
    let r = (sorted.len() as f64 / n).sqrt().min(0.5);
    let band = ((1.0 + r) / (1.0 - r)).powi(2);
    let least = sorted[0].max(0.0);
    let noise: Vec<f64> = sorted
        .iter()
        .copied()
        .take_while(|&e| e <= least * band)
        .collect();
    let mean = noise.iter().sum::<f64>() / noise.len().max(1) as f64;
    (mean.max(least), noise.len())
}

/// What one pass collects of the tracked points' turning angles (one K; pieces add up).
#[derive(Clone, Debug)]
pub(crate) struct Jitter {
    /// Points per frame in the file, the step between those used, and how many are used.
    tracked: usize,
    step: usize,
    points: usize,
    frames: f64,
    mean: Vec<f64>,
    comoment: Vec<Vec<f64>>,
    /// Σ ΔψΔψᵀ over pairs of consecutive recorded frames, and how many.
    change: Vec<Vec<f64>>,
    pairs: f64,
    /// Σ 1/ℓᵢ² per segment and Σ cos ψⱼ/(ℓⱼℓⱼ₊₁) per joint, lengths in body lengths.
    inverse_square: Vec<f64>,
    joint: Vec<f64>,
    /// The animal's recorded frames so far (for the stride), and the last sampled frame's angles
    /// with its number.
    seen: usize,
    last: Option<(usize, Vec<f64>)>,
    /// Scratch: this frame's angles, segments, lengths and distances from the means.
    angles: Vec<f64>,
    segments: Vec<(f64, f64)>,
    lengths: Vec<f64>,
    delta: Vec<f64>,
}

/// The tracking noise printed by `fit`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackingNoise {
    /// σ: position noise per coordinate, body lengths.
    pub sigma: f64,
    /// Whether σ is only an upper bound (the body moves at the finest tracked scale).
    pub bound: bool,
    /// The points it was measured at: every tracked one, or every k-th of more than
    /// [`MAX_POINTS`].
    pub points: usize,
    /// The points tracked.
    pub tracked: usize,
    /// The frames it used (all up to 16 384 per animal, then a thinning sample).
    pub frames: usize,
}

impl Jitter {
    /// For midlines of `tracked` points (at least 4: two angles); of more than
    /// [`MAX_POINTS`], every k-th is used.
    pub(crate) fn new(tracked: usize) -> Option<Jitter> {
        let step = tracked.saturating_sub(1).div_ceil(MAX_POINTS - 1).max(1);
        let points = tracked.saturating_sub(1) / step + 1;
        let d = points.checked_sub(2).filter(|&d| d >= 2)?;
        Some(Jitter {
            tracked,
            step,
            points,
            frames: 0.0,
            mean: vec![0.0; d],
            comoment: vec![vec![0.0; d]; d],
            change: vec![vec![0.0; d]; d],
            pairs: 0.0,
            inverse_square: vec![0.0; d + 1],
            joint: vec![0.0; d],
            seen: 0,
            last: None,
            angles: Vec::with_capacity(d),
            segments: Vec::with_capacity(d + 1),
            lengths: Vec::with_capacity(d + 1),
            delta: Vec::with_capacity(d),
        })
    }

    /// One recorded frame (x₁, y₁, x₂, …), `follows` when it is the frame right after the
    /// previous recorded one (no loss, nothing bridged between).
    pub(crate) fn frame(&mut self, values: &[f64], follows: bool) {
        let n = self.seen;
        self.seen += 1;
        if !follows {
            self.last = None;
        }
        // Pairs (n, n + 1) with n a multiple of the stride.
        let stride = (n + 1).next_power_of_two().div_ceil(EVERY).max(1);
        // The stride is a power of two: the remainder by a mask (a division per frame was
        // measurable over a million frames).
        let phase = n & (stride - 1);
        if phase > 1 || values.len() != 2 * self.tracked {
            return;
        }
        if stride > 1 && phase == 0 {
            self.last = None;
        }
        if !self.angles_of(values) {
            self.last = None;
            return;
        }
        self.frames += 1.0;
        let (lengths, angles) = (&self.lengths, &self.angles);
        for (i, l) in lengths.iter().enumerate() {
            self.inverse_square[i] += 1.0 / (l * l);
            if let (Some(next), Some(a)) = (lengths.get(i + 1), angles.get(i)) {
                self.joint[i] += a.cos() / (l * next);
            }
        }
        // Welford: δ against the old means, M += δδᵀ(n − 1)/n (the upper triangle; `estimate`
        // reads it so).
        let shrink = (self.frames - 1.0) / self.frames;
        self.delta.clear();
        self.delta
            .extend(angles.iter().zip(&self.mean).map(|(a, mu)| a - mu));
        for (mu, d) in self.mean.iter_mut().zip(&self.delta) {
            *mu += d / self.frames;
        }
        for (i, (row, x)) in self.comoment.iter_mut().zip(&self.delta).enumerate() {
            for (c, y) in row[i..].iter_mut().zip(&self.delta[i..]) {
                *c += x * y * shrink;
            }
        }
        let mut before = match self.last.take() {
            Some((m, mut before)) if m + 1 == n => {
                self.pairs += 1.0;
                for (b, a) in before.iter_mut().zip(angles) {
                    *b = a - *b;
                }
                for (i, (row, x)) in self.change.iter_mut().zip(&before).enumerate() {
                    for (c, y) in row[i..].iter_mut().zip(&before[i..]) {
                        *c += x * y;
                    }
                }
                before
            }
            Some((_, before)) => before,
            None => Vec::with_capacity(angles.len()),
        };
        before.clear();
        before.extend_from_slice(angles);
        self.last = Some((n, before));
    }

    /// The frame's turning angles into `self.angles`, its segment lengths in body lengths into
    /// `self.lengths`; false for a frame without them.
    fn angles_of(&mut self, values: &[f64]) -> bool {
        let (seg, lengths) = (&mut self.segments, &mut self.lengths);
        // Segments between the points used, and the body's length over every tracked point (the
        // same segments, summed in the same order, when every point is used).
        let used = values.chunks_exact(2).step_by(self.step).take(self.points);
        seg.clear();
        seg.extend(
            used.clone()
                .zip(used.skip(1))
                .map(|(a, b)| (b[0] - a[0], b[1] - a[1])),
        );
        sizes(seg.iter().copied(), lengths);
        let total: f64 = if self.step == 1 {
            lengths.iter().sum()
        } else {
            values
                .chunks_exact(2)
                .zip(values.chunks_exact(2).skip(1))
                .map(|(a, b)| size(b[0] - a[0], b[1] - a[1]))
                .sum()
        };
        if !(total.is_finite() && lengths.iter().all(|&l| l > 0.0)) {
            return false;
        }
        lengths.iter_mut().for_each(|l| *l /= total);
        segment_angles(seg, &mut self.angles);
        true
    }

    /// Add another animal's (same K).
    pub(crate) fn absorb(&mut self, other: &Jitter) {
        if other.tracked != self.tracked || other.frames == 0.0 {
            return;
        }
        let n = merge_moments(
            (&mut self.mean, &mut self.comoment, self.frames),
            (&other.mean, &other.comoment, other.frames),
            1.0,
        );
        for (mine, theirs) in self.change.iter_mut().zip(&other.change) {
            for (a, b) in mine.iter_mut().zip(theirs) {
                *a += b;
            }
        }
        for (a, b) in self.inverse_square.iter_mut().zip(&other.inverse_square) {
            *a += b;
        }
        for (a, b) in self.joint.iter_mut().zip(&other.joint) {
            *a += b;
        }
        self.frames = n;
        self.pairs += other.pairs;
    }

    /// σ from what was collected: `None` with fewer frames than 4d (or 50).
    pub(crate) fn estimate(&self) -> Option<TrackingNoise> {
        let d = self.mean.len();
        if self.frames < (4 * d).max(50) as f64 {
            return None;
        }
        let f = self.frames;
        // A = per σ² covariance of the segment angles; M = D A Dᵀ.
        let a = |i: usize, j: usize| match i.abs_diff(j) {
            0 => 2.0 * self.inverse_square[i] / f,
            1 => -self.joint[i.min(j)] / f,
            _ => 0.0,
        };
        let m = DMatrix::from_fn(d, d, |j, k| {
            let mut s = 0.0;
            for (p, dp) in [(j + 1, 1.0), (j, -1.0)] {
                for (q, dq) in [(k + 1, 1.0), (k, -1.0)] {
                    s += dp * dq * a(p, q);
                }
            }
            s
        });
        let chol = m.clone().cholesky()?;
        let li = chol.l().try_inverse()?;
        let plateau = |c: DMatrix<f64>, samples: f64| -> (f64, usize) {
            let w = &li * c * li.transpose();
            let w = (&w + w.transpose()) * 0.5;
            let mut e: Vec<f64> = SymmetricEigen::new(w).eigenvalues.iter().copied().collect();
            e.sort_by(f64::total_cmp);
            plateau(&e, samples)
        };
        let upper = |m: &[Vec<f64>], i: usize, j: usize| m[i.min(j)][i.max(j)];
        let c = DMatrix::from_fn(d, d, |i, j| upper(&self.comoment, i, j) / (f - 1.0));
        let mut best = plateau(c, f);
        if self.pairs >= (4 * d).max(50) as f64 {
            let p = self.pairs;
            let change = DMatrix::from_fn(d, d, |i, j| upper(&self.change, i, j) / (2.0 * p));
            let other = plateau(change, p);
            if other.0 < best.0 {
                best = other;
            }
        }
        let (variance, directions) = best;
        let sigma = variance.sqrt();
        (sigma.is_finite() && sigma > 0.0).then_some(TrackingNoise {
            sigma,
            bound: directions < 2,
            points: self.points,
            tracked: self.tracked,
            frames: f as usize,
        })
    }
}

impl std::fmt::Display for TrackingNoise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sigma = format!("{:.2e}", self.sigma);
        let frames = self.frames;
        let points = if self.points == self.tracked {
            format!("{} tracked points", self.points)
        } else {
            format!("{} of the {} tracked points", self.points, self.tracked)
        };
        if self.bound {
            write!(
                f,
                "tracking noise: σ ≤ {sigma} body lengths per coordinate (an upper bound: the body moves at the finest scale of its {points}, so its own motion and the noise cannot be told apart there; {frames} frames)"
            )
        } else {
            write!(
                f,
                "tracking noise: σ = {sigma} body lengths per coordinate (the white part of the turning angles at {points} where the body leaves them to noise alone; {frames} frames)"
            )
        }
    }
}
