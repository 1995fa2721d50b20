//! Welch's estimate of the modal coordinates' spectra: each segment of W frames mean-removed,
//! Hann-tapered and transformed, |X̂(f)|² summed over segments at half overlap, the density
//! Σ|X̂|²·(2 off the ends)/(fs·Σw²·segments). A pass keeps the sums at every window of a
//! [`Ladder`] (the user's window, or powers of two to choose from); a ladder a pilot prunes
//! keeps only the lead channels at its longest window (their spectra choose, never fit) and no
//! channel at the other windows it does not expect to be chosen (their segments still count).

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
    pub(super) fn add_ending(
        &self,
        ring: &Ring,
        back: usize,
        acc: &mut [Vec<f64>],
        work: &mut FftWork,
    ) {
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
            partial: false,
            window: len,
            segments: segments.round() as usize,
            frequencies,
            psd,
        }
    }
}

/// r(τ) = Σₙ wₙwₙ₊τ for τ = 0 … W − 1, each sum taken in order of n. Eight lags at once: their
/// sums are independent chains, which a processor runs side by side (one lag after the other
/// waits on each addition in turn: W²/2 of them, 10 ms at W = 4096).
pub(super) fn lag_products(window: &[f64]) -> Vec<f64> {
    const AT_ONCE: usize = 8;
    let len = window.len();
    let mut lags = Vec::with_capacity(len);
    for first in (0..len).step_by(AT_ONCE) {
        let lanes = AT_ONCE.min(len - first);
        let mut sums = [0.0; AT_ONCE];
        // Every lane's terms while all have them, then each lane's own remainder, in order.
        let common = len - (first + lanes - 1);
        for n in 0..common {
            let w = window[n];
            let ahead = &window[n + first..n + first + lanes];
            for (s, v) in sums.iter_mut().zip(ahead) {
                *s += w * v;
            }
        }
        for (j, s) in sums.iter_mut().enumerate().take(lanes) {
            let t = first + j;
            for n in common..len - t {
                *s += window[n] * window[n + t];
            }
        }
        lags.extend_from_slice(&sums[..lanes]);
    }
    lags
}

/// Σ x in eight independent lanes: the compiler vectorises it (a plain fold is one serial
/// chain of additions, which was half the time of a segment).
pub(super) fn lanes_sum(x: &[f64]) -> f64 {
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

/// Σ xᵢyᵢ in eight independent lanes, as [`lanes_sum`].
pub(super) fn lanes_dot(x: &[f64], y: &[f64]) -> f64 {
    let mut lanes = [0.0; 8];
    let (cx, cy) = (x.chunks_exact(8), y.chunks_exact(8));
    let tail: f64 = (cx.remainder().iter().zip(cy.remainder()))
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in cx.zip(cy) {
        for ((l, u), v) in lanes.iter_mut().zip(a).zip(b) {
            *l += u * v;
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
    /// The densities of the channels kept at this window (every one, unless it is partial).
    pub(super) psd: Vec<Vec<f64>>,
    /// Only the lead channels (or none) were kept here: enough to choose the window, not to fit
    /// at it.
    pub(super) partial: bool,
}

/// The Welch windows accumulated in one pass: the user's one, or a ladder of powers of two
/// for the fit to choose from once the modes' frequencies are known.
#[derive(Clone)]
pub(super) struct Ladder {
    pub(super) plans: Vec<Plan>,
    /// Channels kept at each window: every one (`None`), or the first few.
    kept: Vec<Option<usize>>,
}

/// The channels a pruned ladder keeps at its longest window: the lowest mode, whose frequency
/// there chooses the window, and its neighbour, whose peak bounds its fitting band (one complex
/// transform for the two).
pub(super) const LEAD: usize = 2;

/// The windows tried when none is given: 16, 32, … 4096 frames.
pub(super) const LADDER: std::ops::RangeInclusive<u32> = 4..=12;

impl Ladder {
    /// One window `W`, or the ladder.
    pub(super) fn new(window: Option<usize>) -> Ladder {
        let plans = match window {
            Some(w) => vec![Plan::new(w)],
            None => LADDER.map(|k| Plan::new(1 << k)).collect(),
        };
        let kept = vec![None; plans.len()];
        Ladder { plans, kept }
    }

    /// This ladder keeping every channel only at the windows `full`, the [`LEAD`] channels at
    /// the longest (where a long recording's choice measures the lowest mode), none at the
    /// others: their segments are still counted, which is all the choice reads of them. A
    /// recording whose runs are too short for the longest window measures at a shorter one,
    /// which then holds no channel: the pass is made again with the whole ladder.
    pub(super) fn pruned(&self, full: &[usize]) -> Ladder {
        let longest = self.longest();
        let kept = (self.plans.iter())
            .map(|p| match p.len() {
                w if full.contains(&w) => None,
                w if w == longest => Some(LEAD),
                _ => Some(0),
            })
            .collect();
        Ladder {
            plans: self.plans.clone(),
            kept,
        }
    }

    /// The channels of `m` kept at window `i`.
    pub(super) fn channels(&self, i: usize, m: usize) -> usize {
        self.kept[i].map_or(m, |k| k.min(m))
    }

    pub(super) fn longest(&self) -> usize {
        self.plans.iter().map(Plan::len).max().unwrap_or(0)
    }
}

/// Raw Welch sums at one window: Σ|X̂(f)|² per channel and frequency, and the segments.
#[derive(Clone, Debug, Default)]
pub(super) struct WelchSums {
    pub(super) sums: Vec<Vec<f64>>,
    pub(super) segments: f64,
}

/// The last frames of a run, channel by channel, each channel in a space of twice the capacity:
/// a frame is written once, after the last, and when the space is full the frames held move
/// to its start (one bulk copy per capacity's frames), so the last W ≤ cap frames of a channel
/// are always one contiguous slice and a Welch segment reads them without a copy. (Writing
/// every value twice, at i and i + cap, kept twice the store streams open: measurably slower.)
/// The capacity doubles as the run grows, up to the ladder's longest window (a run of a few
/// frames holds a few).
pub(super) struct Ring {
    channels: usize,
    longest: usize,
    cap: usize,
    data: Vec<f64>,
    /// Where the next frame goes in each channel's space, and how many frames are held (the
    /// `held` before `pos`).
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
            // The frames held, oldest first, at the start of each channel's larger space.
            let cap = (2 * self.cap).max(16).min(self.longest);
            let mut data = vec![0.0; 2 * cap * self.channels];
            for c in 0..self.channels {
                let held = self.last(c, self.held);
                data[2 * cap * c..][..held.len()].copy_from_slice(held);
            }
            (self.data, self.cap, self.pos) = (data, cap, self.held);
        }
        let (cap, held) = (self.cap, self.held);
        if self.pos == 2 * cap {
            for c in 0..self.channels {
                let base = 2 * cap * c;
                self.data
                    .copy_within(base + 2 * cap - held..base + 2 * cap, base);
            }
            self.pos = held;
        }
        for (c, x) in q.iter().enumerate().take(self.channels) {
            self.data[2 * cap * c + self.pos] = *x;
        }
        self.pos += 1;
        self.held = (held + 1).min(cap);
    }

    /// The last `w` frames of channel `c` (w ≤ the frames held).
    pub(super) fn last(&self, c: usize, w: usize) -> &[f64] {
        self.ending(c, w, 0)
    }

    /// The `w` frames of channel `c` that end `back` frames before the newest
    /// (w + back ≤ the frames held).
    pub(super) fn ending(&self, c: usize, w: usize, back: usize) -> &[f64] {
        let end = 2 * self.cap * c + self.pos - back;
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

    pub(super) fn of(frames: &[Vec<f64>]) -> Ring {
        let channels = frames.first().map_or(0, Vec::len);
        let mut ring = Ring::new(channels, frames.len());
        for f in frames {
            ring.push(f);
        }
        ring
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ring lends the frames pushed last, through growth and every move to the start.
    #[test]
    fn the_ring_holds_the_last_frames() {
        for longest in [1, 5, 16, 40, 100] {
            let mut ring = Ring::new(3, longest);
            let mut all: Vec<Vec<f64>> = Vec::new();
            for n in 0..1000 {
                let frame: Vec<f64> = (0..3).map(|c| (n * 10 + c) as f64).collect();
                ring.push(&frame);
                all.push(frame);
                let held = ring.len();
                assert_eq!(
                    held,
                    all.len().min(ring.cap),
                    "longest {longest}, frame {n}"
                );
                for c in 0..3 {
                    for back in [0, 1, held / 3] {
                        let w = held - back;
                        let want: Vec<f64> = all[all.len() - back - w..all.len() - back]
                            .iter()
                            .map(|f| f[c])
                            .collect();
                        assert_eq!(ring.ending(c, w, back), want.as_slice());
                    }
                }
            }
            assert_eq!(
                ring.cap, longest,
                "the capacity grows to the longest window"
            );
            assert_eq!(ring.frames(), all[all.len() - ring.len()..].to_vec());
        }
    }

    /// The lag products side by side are the plain sums, bit for bit.
    #[test]
    fn lag_products_are_the_sums_in_order() {
        for len in (1..40).chain([255, 256, 1000, 4096]) {
            let w = Plan::new(len).window;
            let plain: Vec<f64> = (0..len)
                .map(|t| (0..len - t).map(|n| w[n] * w[n + t]).sum())
                .collect();
            let fast = lag_products(&w);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&plain), "W = {len}");
        }
    }
}
