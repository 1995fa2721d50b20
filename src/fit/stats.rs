//! What a pass over the frames accumulates, in pieces that add up: for each run of frames
//! between gaps, the count, mean and co-moment of the modal coordinates (merged by Chan's
//! formula: for pieces a and b with δ = μ_b − μ_a, M = M_a + M_b + δδᵀ·n_a n_b/(n_a + n_b)) and
//! the raw Welch sums Σ|X̂(f)|² of its Hann-windowed segments. A piece taken c times (a bootstrap
//! draw) counts c·n frames, c·M and c times the sums: pooling animals, one animal alone and a
//! resample are the same operation.

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
    /// every channel of `ring`, `work` holding the buffers between calls.
    pub(super) fn add(&self, ring: &Ring, acc: &mut [Vec<f64>], work: &mut FftWork) {
        self.add_ending(ring, 0, acc, work);
    }

    /// [`Plan::add`] for the segment that ends `back` frames before the ring's newest.
    fn add_ending(&self, ring: &Ring, back: usize, acc: &mut [Vec<f64>], work: &mut FftWork) {
        let len = self.len();
        let FftWork { data, scratch } = work;
        data.resize(len, Complex::new(0.0, 0.0));
        scratch.resize(self.fft.get_inplace_scratch_len(), Complex::new(0.0, 0.0));
        let window = self.window.as_slice();
        let mean = |c: &[f64]| lanes_sum(c) / len as f64;
        // Two real channels a, b in one complex transform Z of a + ib:
        // Â(k) = (Z(k) + Z̄(W−k))/2, B̂(k) = (Z(k) − Z̄(W−k))/2i.
        for (c, acc) in (0..acc.len()).step_by(2).zip(acc.chunks_mut(2)) {
            let a = ring.ending(c, len, back);
            let (ma, b) = (
                mean(a),
                (acc.len() == 2).then(|| ring.ending(c + 1, len, back)),
            );
            match b {
                Some(b) => {
                    let mb = mean(b);
                    for (((d, x), y), w) in data.iter_mut().zip(a).zip(b).zip(window) {
                        *d = Complex::new((x - ma) * w, (y - mb) * w);
                    }
                }
                None => {
                    for ((d, x), w) in data.iter_mut().zip(a).zip(window) {
                        *d = Complex::new((x - ma) * w, 0.0);
                    }
                }
            }
            self.fft.process_with_scratch(&mut data[..len], scratch);
            let (first, second) = acc.split_at_mut(1);
            let (first, mut second) = (&mut first[0], second.first_mut());
            for (k, f) in first.iter_mut().enumerate() {
                let (z, mirror) = (data[k], data[if k == 0 { 0 } else { len - k }].conj());
                *f += (z + mirror).norm_sqr() / 4.0;
                if let Some(second) = second.as_deref_mut() {
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

/// Chan's merge of (mean, co-moment, count) b, taken `times` times, into a: returns the count.
pub(super) fn merge_moments(
    (mean, comoment, na): (&mut [f64], &mut [Vec<f64>], f64),
    (other_mean, other_comoment, count): (&[f64], &[Vec<f64>], f64),
    times: f64,
) -> f64 {
    let nb = times * count;
    let n = na + nb;
    let delta: Vec<f64> = other_mean
        .iter()
        .zip(mean.iter())
        .map(|(b, a)| b - a)
        .collect();
    for (mu, d) in mean.iter_mut().zip(&delta) {
        *mu += d * nb / n;
    }
    let w = na * nb / n;
    for (i, row) in comoment.iter_mut().enumerate() {
        for (j, c) in row.iter_mut().enumerate() {
            *c += times * other_comoment[i][j] + w * delta[i] * delta[j];
        }
    }
    n
}

/// Σ x in eight independent lanes: the compiler vectorises it (a plain fold is one serial
/// chain of additions, which was half the time of a segment).
fn lanes_sum(x: &[f64]) -> f64 {
    let mut lanes = [0.0; 8];
    let chunks = x.chunks_exact(8);
    let tail: f64 = chunks.remainder().iter().sum();
    for c in chunks {
        for (l, v) in lanes.iter_mut().zip(c) {
            *l += v;
        }
    }
    lanes.iter().sum::<f64>() + tail
}

/// The buffers of [`Plan::add`], kept between segments.
#[derive(Default)]
pub(super) struct FftWork {
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
        let n = merge_moments(
            (&mut self.mean, &mut self.comoment, self.count),
            (&other.mean, &other.comoment, other.count),
            times,
        );
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

    /// The co-moment's lower triangle from its upper one (a run accumulates only that).
    fn symmetrise(&mut self) {
        for i in 0..self.comoment.len() {
            for j in 0..i {
                self.comoment[i][j] = self.comoment[j][i];
            }
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
        own.add(&Ring::of(&self.short), &mut sums, &mut FftWork::default());
        vec![own.density(&sums, 1.0, fs)]
    }
}

/// The last frames of a run, channel by channel: every value is written twice (at i and
/// i + cap), so the last W ≤ cap frames of a channel are one contiguous slice and a Welch
/// segment reads them without a copy. The capacity doubles as the run grows, up to the
/// ladder's longest window (a run of a few frames holds a few).
pub(super) struct Ring {
    channels: usize,
    longest: usize,
    cap: usize,
    data: Vec<f64>,
    /// Where the next frame goes, and how many frames are held.
    pos: usize,
    held: usize,
}

impl Ring {
    pub(super) fn new(channels: usize, longest: usize) -> Ring {
        Ring {
            channels,
            longest: longest.max(1),
            cap: 0,
            data: Vec::new(),
            pos: 0,
            held: 0,
        }
    }

    /// How many frames are held.
    pub(super) fn len(&self) -> usize {
        self.held
    }

    pub(super) fn push(&mut self, q: &[f64]) {
        if self.held == self.cap && self.cap < self.longest {
            let frames = self.frames();
            self.cap = (2 * self.cap).max(16).min(self.longest);
            self.data = vec![0.0; 2 * self.cap * self.channels];
            (self.pos, self.held) = (0, 0);
            for f in &frames {
                self.push(f);
            }
        }
        let cap = self.cap;
        for (c, x) in q.iter().enumerate().take(self.channels) {
            let base = 2 * cap * c + self.pos;
            self.data[base] = *x;
            self.data[base + cap] = *x;
        }
        self.pos = (self.pos + 1) % cap;
        self.held = (self.held + 1).min(cap);
    }

    /// The last `w` frames of channel `c` (w ≤ the frames held).
    pub(super) fn last(&self, c: usize, w: usize) -> &[f64] {
        self.ending(c, w, 0)
    }

    /// The `w` frames of channel `c` that end `back` frames before the newest
    /// (w + back ≤ the frames held).
    pub(super) fn ending(&self, c: usize, w: usize, back: usize) -> &[f64] {
        let end = 2 * self.cap * c + self.pos + self.cap - back;
        &self.data[end - w..end]
    }

    /// The frames held, oldest first, each a vector of channels.
    pub(super) fn frames(&self) -> Vec<Vec<f64>> {
        (0..self.held)
            .map(|i| {
                (0..self.channels)
                    .map(|c| self.last(c, self.held)[i])
                    .collect()
            })
            .collect()
    }

    fn of(frames: &[Vec<f64>]) -> Ring {
        let channels = frames.first().map_or(0, Vec::len);
        let mut ring = Ring::new(channels, frames.len());
        for f in frames {
            ring.push(f);
        }
        ring
    }
}

/// Streams one run's frames into its [`Stats`]: running moments, Welch segments at half
/// overlap at every window of the ladder. For a bootstrap over time it accumulates consecutive
/// blocks of frames instead (each segment in the block where it ends), the run being their
/// sum; past [`MAX_BLOCKS`] blocks, neighbours merge and the block length doubles.
pub(super) struct Run {
    pub(super) stats: Stats,
    ring: Ring,
    /// Frames since each window's last segment.
    since: Vec<usize>,
    /// Segments due but not yet transformed: (window, the run's frame count when it was due).
    pending: Vec<(usize, usize)>,
    ladder: Ladder,
    /// The finished blocks and the block length, when a bootstrap over time is wanted.
    blocks: Option<(Vec<Stats>, usize)>,
    /// The run's frames, the blocks included.
    frames: usize,
    /// Scratch: the new frame's distance from the running mean.
    delta: Vec<f64>,
    /// Scratch of the transforms, one per thread of a flush.
    work: [FftWork; 2],
}

/// The most blocks one run keeps for a bootstrap over time.
pub(super) const MAX_BLOCKS: usize = 256;

/// How many frames a due segment may wait for its transform: the segments of that many frames
/// are transformed together, over two cores when there are two.
const DEFER: usize = 2048;

/// The work (W·log₂W per channel, summed) worth a helper thread.
const PARALLEL_WORK: f64 = 65536.0;

/// Whether a second core is there to share a flush.
fn second_core() -> bool {
    static TWO: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *TWO.get_or_init(|| std::thread::available_parallelism().is_ok_and(|n| n.get() > 1))
}

/// The first block length, in frames.
const FIRST_BLOCK: usize = 64;

impl Run {
    /// A run of `m` coordinates; `blocks` keeps it in blocks for a bootstrap over time.
    pub(super) fn new(m: usize, ladder: &Ladder, blocks: bool) -> Run {
        Run {
            stats: Stats::new(m, ladder),
            ring: Ring::new(m, ladder.longest() + DEFER),
            since: vec![0; ladder.plans.len()],
            pending: Vec::new(),
            ladder: ladder.clone(),
            blocks: blocks.then(|| (Vec::new(), FIRST_BLOCK)),
            frames: 0,
            delta: Vec::with_capacity(m),
            work: Default::default(),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.frames
    }

    /// Close the current block: into the run's total and the list (merging pairs past the cap).
    fn close_block(&mut self) {
        // A segment counts in the block where it ends.
        self.flush();
        let Some((blocks, length)) = &mut self.blocks else {
            return;
        };
        let fresh = Stats::new(self.stats.mean.len(), &self.ladder);
        let mut block = std::mem::replace(&mut self.stats, fresh);
        block.symmetrise();
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
        if let Some((_, length)) = &self.blocks {
            if self.stats.count as usize >= *length {
                self.close_block();
            }
        }
        // Counted with the ring: a flush reads segments back from the newest frame.
        self.frames += 1;
        let s = &mut self.stats;
        s.count += 1.0;
        s.spacing += spacing;
        self.delta.clear();
        self.delta.extend(q.iter().zip(&s.mean).map(|(a, b)| a - b));
        for (mu, d) in s.mean.iter_mut().zip(&self.delta) {
            *mu += d / s.count;
        }
        // The upper triangle only: the run's matrix is made whole when its stats leave it.
        for (i, (row, d)) in s.comoment.iter_mut().zip(&self.delta).enumerate() {
            for (c, (a, mu)) in row[i..].iter_mut().zip(q[i..].iter().zip(&s.mean[i..])) {
                *c += d * (a - mu);
            }
        }
        self.ring.push(q);
        for (i, ((plan, since), w)) in self
            .ladder
            .plans
            .iter()
            .zip(&mut self.since)
            .zip(&mut s.welch)
            .enumerate()
        {
            let len = plan.len();
            *since += 1;
            // The first segment as soon as the window fills (then `since` = W), then every W/2.
            if self.ring.len() >= len && *since >= len / 2 {
                *since = 0;
                w.segments += 1.0;
                self.pending.push((i, self.frames));
            }
        }
        if let Some(&(_, first)) = self.pending.first() {
            if self.frames - first >= DEFER {
                self.flush();
            }
        }
    }

    /// Transform the pending segments, the windows split in two groups of about equal work and
    /// one group on a helper thread when there is enough work and a second core. Each window's
    /// segments are added in the order they came due, so the sums are the same either way.
    fn flush(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        let pending = std::mem::take(&mut self.pending);
        let (frames, ring, plans) = (self.frames, &self.ring, &self.ladder.plans);
        let channels = self.stats.mean.len().max(1) as f64;
        let mut work_of = vec![0.0; plans.len()];
        for &(i, _) in &pending {
            let w = plans[i].len() as f64;
            work_of[i] += w * w.log2().max(1.0) * channels;
        }
        // Greedy halves, costliest window first.
        let mut order: Vec<usize> = (0..plans.len()).collect();
        order.sort_by(|a, b| work_of[*b].total_cmp(&work_of[*a]));
        let (mut mine, mut theirs, mut helper) = (0.0, 0.0, vec![false; plans.len()]);
        for i in order {
            if theirs < mine {
                helper[i] = true;
                theirs += work_of[i];
            } else {
                mine += work_of[i];
            }
        }
        let split = theirs >= PARALLEL_WORK && second_core();
        type Group<'a> = Vec<(&'a Plan, &'a mut WelchSums, Vec<usize>)>;
        let (mut here, mut there): (Group<'_>, Group<'_>) = (Vec::new(), Vec::new());
        for (i, (plan, w)) in plans.iter().zip(&mut self.stats.welch).enumerate() {
            let backs: Vec<usize> = pending
                .iter()
                .filter(|p| p.0 == i)
                .map(|p| frames - p.1)
                .collect();
            if backs.is_empty() {
                continue;
            }
            if split && helper[i] {
                &mut there
            } else {
                &mut here
            }
            .push((plan, w, backs));
        }
        let transform = |group: Group<'_>, work: &mut FftWork| {
            for (plan, w, backs) in group {
                for back in backs {
                    plan.add_ending(ring, back, &mut w.sums, work);
                }
            }
        };
        let [work, other] = &mut self.work;
        if there.is_empty() {
            transform(here, work);
        } else {
            std::thread::scope(|scope| {
                scope.spawn(|| transform(there, other));
                transform(here, work);
            });
        }
    }

    /// The run's statistics, keeping its frames when it never filled the shortest window, and
    /// its blocks (empty unless asked for).
    pub(super) fn finish(mut self) -> (Stats, Vec<Stats>) {
        self.flush();
        if self.blocks.is_none() {
            self.stats.symmetrise();
        }
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
            self.stats.short = self.ring.frames();
        }
        (self.stats, blocks)
    }
}
