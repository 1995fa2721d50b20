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

    /// Add the periodograms |X̂|² of one mean-removed, tapered segment: the last W frames of
    /// `frames` (frames × channels), `work` holding the buffers between calls.
    pub(super) fn add(
        &self,
        frames: &VecDeque<Vec<f64>>,
        acc: &mut [Vec<f64>],
        work: &mut FftWork,
    ) {
        let len = self.len();
        let FftWork {
            columns,
            data,
            scratch,
        } = work;
        // Channels as contiguous columns: each is read twice (mean, taper).
        columns.clear();
        columns.resize(len * acc.len(), 0.0);
        for (i, v) in frames.range(frames.len() - len..).enumerate() {
            for (c, x) in v.iter().enumerate().take(acc.len()) {
                columns[c * len + i] = *x;
            }
        }
        // Two real channels a, b in one complex transform Z of a + ib:
        // Â(k) = (Z(k) + Z̄(W−k))/2, B̂(k) = (Z(k) − Z̄(W−k))/2i.
        data.resize(len, Complex::new(0.0, 0.0));
        scratch.resize(self.fft.get_inplace_scratch_len(), Complex::new(0.0, 0.0));
        let window = self.window.as_slice();
        fn taper<'a>(column: &'a [f64], window: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
            let mean = column.iter().sum::<f64>() / column.len() as f64;
            column.iter().zip(window).map(move |(x, w)| (x - mean) * w)
        }
        for (pair, acc) in columns.chunks(2 * len).zip(acc.chunks_mut(2)) {
            let (a, b) = pair.split_at(len);
            data[..len]
                .iter_mut()
                .for_each(|d| *d = Complex::new(0.0, 0.0));
            for (d, x) in data.iter_mut().zip(taper(a, window)) {
                d.re = x;
            }
            for (d, y) in data.iter_mut().zip(taper(b, window)) {
                d.im = y;
            }
            self.fft.process_with_scratch(&mut data[..len], scratch);
            let (first, second) = acc.split_at_mut(1);
            for k in 0..first[0].len() {
                let (z, mirror) = (data[k], data[(len - k) % len].conj());
                first[0][k] += (z + mirror).norm_sqr() / 4.0;
                if let Some(second) = second.first_mut() {
                    second[k] += (z - mirror).norm_sqr() / 4.0;
                }
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

/// The buffers of [`Plan::add`], kept between segments.
#[derive(Default)]
pub(super) struct FftWork {
    columns: Vec<f64>,
    data: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

/// Welch spectra of the modal coordinates: window, segments averaged, frequencies, densities.
pub(super) struct Spectra {
    pub(super) window: usize,
    pub(super) segments: usize,
    pub(super) frequencies: Vec<f64>,
    pub(super) psd: Vec<Vec<f64>>,
}

/// The Welch windows accumulated in one pass: the user's one, or a ladder of powers of two
/// for the fit to choose from once the modes' frequencies are known.
#[derive(Clone)]
pub(super) struct Ladder {
    pub(super) plans: Vec<Plan>,
}

/// The windows tried when none is given: 16, 32, … 4096 frames.
pub(super) const LADDER: std::ops::RangeInclusive<u32> = 4..=12;

impl Ladder {
    /// One window `W`, or the ladder.
    pub(super) fn new(window: Option<usize>) -> Ladder {
        let plans = match window {
            Some(w) => vec![Plan::new(w)],
            None => LADDER.map(|k| Plan::new(1 << k)).collect(),
        };
        Ladder { plans }
    }

    fn longest(&self) -> usize {
        self.plans.iter().map(Plan::len).max().unwrap_or(0)
    }
}

/// Raw Welch sums at one window: Σ|X̂(f)|² per channel and frequency, and the segments.
#[derive(Clone, Debug, Default)]
pub(super) struct WelchSums {
    pub(super) sums: Vec<Vec<f64>>,
    pub(super) segments: f64,
}

/// The sufficient statistics of some frames (one run, an animal, a pool, a resample).
#[derive(Clone, Debug, Default)]
pub(super) struct Stats {
    /// Frames.
    pub(super) count: f64,
    pub(super) mean: Vec<f64>,
    pub(super) comoment: Vec<Vec<f64>>,
    /// The Welch sums at each window of the ladder, in its order.
    pub(super) welch: Vec<WelchSums>,
    /// Σ of each frame's point spacing (data length units).
    pub(super) spacing: f64,
    /// When no run filled the shortest window: the longest run, for one short segment of its
    /// own.
    pub(super) short: Vec<Vec<f64>>,
}

impl Stats {
    pub(super) fn new(m: usize, ladder: &Ladder) -> Stats {
        Stats {
            mean: vec![0.0; m],
            comoment: vec![vec![0.0; m]; m],
            welch: ladder
                .plans
                .iter()
                .map(|p| WelchSums {
                    sums: vec![vec![0.0; p.len() / 2 + 1]; m],
                    segments: 0.0,
                })
                .collect(),
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
        for (mine, theirs) in self.welch.iter_mut().zip(&other.welch) {
            for (acc, add) in mine.sums.iter_mut().zip(&theirs.sums) {
                for (a, b) in acc.iter_mut().zip(add) {
                    *a += times * b;
                }
            }
            mine.segments += times * theirs.segments;
        }
        self.count = n;
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

    /// The spectra at every window of the ladder that holds a segment, shortest first; without
    /// any, one segment over the longest run (at least 8 frames). Empty when there is neither.
    pub(super) fn spectra(&self, ladder: &Ladder, fs: f64) -> Vec<Spectra> {
        let whole: Vec<Spectra> = ladder
            .plans
            .iter()
            .zip(&self.welch)
            .filter(|(_, w)| w.segments > 0.0)
            .map(|(p, w)| p.density(&w.sums, w.segments, fs))
            .collect();
        if !whole.is_empty() || self.short.len() < 8 {
            return whole;
        }
        let own = Plan::new(self.short.len());
        let mut sums = vec![vec![0.0; own.len() / 2 + 1]; self.mean.len()];
        own.add(
            &self.short.iter().cloned().collect(),
            &mut sums,
            &mut FftWork::default(),
        );
        vec![own.density(&sums, 1.0, fs)]
    }
}

/// Streams one run's frames into its [`Stats`]: running moments, Welch segments at half
/// overlap at every window of the ladder. For a bootstrap over time it accumulates consecutive
/// blocks of frames instead (each segment in the block where it ends), the run being their
/// sum; past [`MAX_BLOCKS`] blocks, neighbours merge and the block length doubles.
pub(super) struct Run {
    pub(super) stats: Stats,
    buffer: VecDeque<Vec<f64>>,
    /// Frames since each window's last segment.
    since: Vec<usize>,
    ladder: Ladder,
    /// The finished blocks and the block length, when a bootstrap over time is wanted.
    blocks: Option<(Vec<Stats>, usize)>,
    /// The run's frames, the blocks included.
    frames: usize,
    /// Scratch: the new frame's distance from the running mean.
    delta: Vec<f64>,
    /// Scratch of the transforms.
    work: FftWork,
}

/// The most blocks one run keeps for a bootstrap over time.
pub(super) const MAX_BLOCKS: usize = 256;

/// The first block length, in frames.
const FIRST_BLOCK: usize = 64;

impl Run {
    /// A run of `m` coordinates; `blocks` keeps it in blocks for a bootstrap over time.
    pub(super) fn new(m: usize, ladder: &Ladder, blocks: bool) -> Run {
        Run {
            stats: Stats::new(m, ladder),
            buffer: VecDeque::with_capacity(ladder.longest()),
            since: vec![0; ladder.plans.len()],
            ladder: ladder.clone(),
            blocks: blocks.then(|| (Vec::new(), FIRST_BLOCK)),
            frames: 0,
            delta: Vec::with_capacity(m),
            work: FftWork::default(),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.frames
    }

    /// Close the current block: into the run's total and the list (merging pairs past the cap).
    fn close_block(&mut self) {
        let Some((blocks, length)) = &mut self.blocks else {
            return;
        };
        let fresh = Stats::new(self.stats.mean.len(), &self.ladder);
        let block = std::mem::replace(&mut self.stats, fresh);
        if block.count == 0.0 {
            return;
        }
        blocks.push(block);
        if blocks.len() > MAX_BLOCKS {
            let old = std::mem::take(blocks);
            for pair in old.chunks(2) {
                let mut merged = pair[0].clone();
                if let Some(b) = pair.get(1) {
                    merged.absorb(b, 1.0);
                }
                blocks.push(merged);
            }
            *length *= 2;
        }
    }

    /// One frame's modal coordinates `q` and point spacing.
    pub(super) fn push(&mut self, q: &[f64], spacing: f64) {
        self.frames += 1;
        if let Some((_, length)) = &self.blocks {
            if self.stats.count as usize >= *length {
                self.close_block();
            }
        }
        let s = &mut self.stats;
        s.count += 1.0;
        s.spacing += spacing;
        self.delta.clear();
        self.delta.extend(q.iter().zip(&s.mean).map(|(a, b)| a - b));
        for (mu, d) in s.mean.iter_mut().zip(&self.delta) {
            *mu += d / s.count;
        }
        for (row, d) in s.comoment.iter_mut().zip(&self.delta) {
            for (c, (a, mu)) in row.iter_mut().zip(q.iter().zip(&s.mean)) {
                *c += d * (a - mu);
            }
        }
        // The oldest frame's storage takes the new one: no allocation once the buffer is full.
        let mut slot = if self.buffer.len() == self.ladder.longest() {
            self.buffer.pop_front().unwrap_or_default()
        } else {
            Vec::with_capacity(q.len())
        };
        slot.clear();
        slot.extend_from_slice(q);
        self.buffer.push_back(slot);
        for ((plan, since), w) in self
            .ladder
            .plans
            .iter()
            .zip(&mut self.since)
            .zip(&mut s.welch)
        {
            let len = plan.len();
            *since += 1;
            // The first segment as soon as the window fills (then `since` = W), then every W/2.
            if self.buffer.len() >= len && *since >= len / 2 {
                *since = 0;
                w.segments += 1.0;
                plan.add(&self.buffer, &mut w.sums, &mut self.work);
            }
        }
    }

    /// The run's statistics, keeping its frames when it never filled the shortest window, and
    /// its blocks (empty unless asked for).
    pub(super) fn finish(mut self) -> (Stats, Vec<Stats>) {
        let blocks = if self.blocks.is_some() {
            self.close_block();
            let blocks = self.blocks.take().map(|b| b.0).unwrap_or_default();
            let mut total = Stats::new(self.stats.mean.len(), &self.ladder);
            for b in &blocks {
                total.absorb(b, 1.0);
            }
            self.stats = total;
            blocks
        } else {
            Vec::new()
        };
        if self.stats.welch.iter().all(|w| w.segments == 0.0) {
            self.stats.short = self.buffer.into_iter().collect();
        }
        (self.stats, blocks)
    }
}
