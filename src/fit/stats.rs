//! What a pass over the frames accumulates, in pieces that add up: for each run of frames
//! between gaps, the count, mean and co-moment of the modal coordinates (merged by Chan's
//! formula: for pieces a and b with δ = μ_b − μ_a, M = M_a + M_b + δδᵀ·n_a n_b/(n_a + n_b)) and
//! the raw Welch sums Σ|X̂(f)|² of its Hann-windowed segments. A piece taken c times (a bootstrap
//! draw) counts c·n frames, c·M and c times the sums: pooling animals, one animal alone and a
//! resample are the same operation.

pub(super) use super::welch::Spectra;
use super::welch::{lanes_dot, lanes_sum, FftWork, Ladder, Plan, Ring, WelchSums};
pub(super) use crate::recording::merge_moments;

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
            welch: (ladder.plans.iter().enumerate())
                .map(|(i, p)| WelchSums {
                    sums: vec![vec![0.0; p.len() / 2 + 1]; ladder.channels(i, m)],
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
            .map(|(p, w)| Spectra {
                partial: w.sums.len() < self.mean.len(),
                ..p.density(&w.sums, w.segments, fs)
            })
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

/// Streams one run's frames into its [`Stats`]: moments in batches, Welch segments at half
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
    /// Frames counted but not yet in the mean and co-moment (the newest in the ring).
    unmerged: usize,
    /// Scratch of a batch: its means, and its frames less them, channel after channel.
    batch_mean: Vec<f64>,
    centred: Vec<f64>,
    /// Scratch of the transforms.
    work: FftWork,
}

/// The most blocks one run keeps for a bootstrap over time.
pub(super) const MAX_BLOCKS: usize = 256;

/// How many frames a due segment may wait for its transform: the segments of that many frames
/// are transformed together (4096: 2.6 % less wall time than 2048 on the 10⁶-frame bench when
/// a helper thread shared each batch; 8192 no better, 2 MiB more).
const DEFER: usize = 4096;

/// Frames whose moments are taken together: each channel's batch is one slice of the ring, its
/// mean and centred products summed in independent lanes (two passes, then Chan's merge into the
/// run's: as accurate as a running update, and without a division per frame and coordinate).
const BATCH: usize = 64;

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
            unmerged: 0,
            batch_mean: Vec::with_capacity(m),
            centred: Vec::with_capacity(m * BATCH),
            work: Default::default(),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.frames
    }

    /// Close the current block: into the run's total and the list (merging pairs past the cap).
    fn close_block(&mut self) {
        // A segment counts in the block where it ends.
        self.fold();
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
        self.stats.count += 1.0;
        self.stats.spacing += spacing;
        self.ring.push(q);
        self.unmerged += 1;
        if self.unmerged == BATCH {
            self.fold();
        }
        for (i, ((plan, since), w)) in self
            .ladder
            .plans
            .iter()
            .zip(&mut self.since)
            .zip(&mut self.stats.welch)
            .enumerate()
        {
            let len = plan.len();
            *since += 1;
            // The first segment as soon as the window fills (then `since` = W), then every W/2.
            if self.ring.len() >= len && *since >= len / 2 {
                *since = 0;
                w.segments += 1.0;
                // A window a pruned ladder keeps no channel at only counts its segments.
                if !w.sums.is_empty() {
                    self.pending.push((i, self.frames));
                }
            }
        }
        if let Some(&(_, first)) = self.pending.first() {
            if self.frames - first >= DEFER {
                self.flush();
            }
        }
    }

    /// The unmerged frames' moments into the run's: the batch's means and co-moment (upper
    /// triangle) from its centred values, then Chan's merge.
    fn fold(&mut self) {
        let b = std::mem::take(&mut self.unmerged);
        if b == 0 {
            return;
        }
        let (s, ring) = (&mut self.stats, &self.ring);
        let m = s.mean.len();
        let (nb, n) = (b as f64, s.count);
        let na = n - nb;
        self.batch_mean.clear();
        self.centred.clear();
        for c in 0..m {
            // Shifted by the batch's first value: a coordinate that does not move stays exactly
            // still (its mean exact, its co-moment zero), as the running update kept it.
            let x = ring.last(c, b);
            let from = self.centred.len();
            self.centred.extend(x.iter().map(|v| v - x[0]));
            let shifted = &mut self.centred[from..];
            let mu = lanes_sum(shifted) / nb;
            shifted.iter_mut().for_each(|v| *v -= mu);
            self.batch_mean.push(x[0] + mu);
        }
        let centred = |c: usize| &self.centred[c * b..(c + 1) * b];
        // The upper triangle only: the run's matrix is made whole when its stats leave it.
        let w = na * nb / n;
        for i in 0..m {
            let di = self.batch_mean[i] - s.mean[i];
            for j in i..m {
                let dj = self.batch_mean[j] - s.mean[j];
                s.comoment[i][j] += lanes_dot(centred(i), centred(j)) + w * di * dj;
            }
        }
        for (mu, b) in s.mean.iter_mut().zip(&self.batch_mean) {
            *mu = if na == 0.0 {
                *b
            } else {
                *mu + (b - *mu) * nb / n
            };
        }
    }

    /// Transform the pending segments, window by window, each window's in the order they came
    /// due: the sums are those of transforming each segment as it came due. All on this
    /// thread: a helper thread taking half the windows made the 10⁶-frame bench 10 % slower
    /// once the workers read their own chunks (both cores parse; the pass waited on the helper).
    fn flush(&mut self) {
        let (frames, ring, pending) = (self.frames, &self.ring, &self.pending);
        for (i, (plan, w)) in self
            .ladder
            .plans
            .iter()
            .zip(&mut self.stats.welch)
            .enumerate()
        {
            for &(_, due) in pending.iter().filter(|p| p.0 == i) {
                plan.add_ending(ring, frames - due, &mut w.sums, &mut self.work);
            }
        }
        self.pending.clear();
    }

    /// The run's statistics, keeping its frames when it never filled the shortest window, and
    /// its blocks (empty unless asked for).
    pub(super) fn finish(mut self) -> (Stats, Vec<Stats>) {
        self.fold();
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
