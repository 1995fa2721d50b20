//! A driven travelling wave: several modal coordinates phase-locked at one frequency with a lag
//! between them (issue 56).
//!
//! **Why a lag.** A passive body's modes are independent, and every coordinate the fit
//! measures is an instantaneous linear map of them and of white tracking noise (the projection,
//! the N-point modes not quite the body's, aliasing in space and time). The cross-spectral
//! matrix of such coordinates is A·diag(Pₖ(f))·Aᵀ: real at every frequency. A leak of one mode
//! into another's coordinate ("showing through") is coherent but in phase. A travelling wave
//! y = A sin(ks − Ωt) is not: its modes oscillate at the one Ω with phases that differ (a
//! free body's even and odd modes in quadrature, where r² ≈ 0 and the "modes move together"
//! check cannot see them). So the test is the imaginary part of the coherency
//! C = Sᵢⱼ/√(Sᵢᵢ Sⱼⱼ) between coordinates, at every frequency bin and pair.
//!
//! **Threshold.** Over K non-overlapping Hann segments of independent Gaussian coordinates the
//! magnitude-squared coherence exceeds c with probability (1 − c)^(K−1), and Im(C)² ≤ |C|²; c
//! is set so that this, over every bin and pair, is [`FALSE_ALARM`]. The segments are the
//! fit's window, halved until there are [`MIN_SEGMENTS`] of them inside the runs; with fewer,
//! or no series kept (past `timedomain::MAX_FRAMES`), there is no test.

use super::timedomain::Span;
use rustfft::num_complex::Complex;

/// The chance, over every bin and pair, that a passive body's coordinates are called a wave.
pub const FALSE_ALARM: f64 = 1e-3;

/// The fewest segments the test is made on.
pub const MIN_SEGMENTS: usize = 8;

/// The shortest segment, in frames.
const MIN_WINDOW: usize = 32;

/// The most modes examined (the lowest: a wave's power is where the body bends most).
const MAX_MODES: usize = 12;

/// Modes phase-locked at one frequency with a lag between them.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct DrivenWave {
    /// The shared frequency (cycles per time unit).
    pub frequency: f64,
    /// The coordinates coherent there (indices from 0, the first non-zero mode).
    pub coordinates: Vec<usize>,
    /// The largest squared imaginary coherency there, and the threshold it passed.
    pub coherence: f64,
    pub threshold: f64,
}

/// The driven wave in the first `modes` coordinates of `spans` at the fit's `window` (frames)
/// and sampling rate `fs`, if there is one.
pub(super) fn driven_wave(
    spans: &[Span<'_>],
    window: usize,
    fs: f64,
    modes: usize,
) -> Option<DrivenWave> {
    let m = modes.min(MAX_MODES);
    if m < 2 {
        return None;
    }
    // Each span's coordinates, and the NaN-free runs of frames in it.
    let mut runs: Vec<(Vec<&[f64]>, std::ops::Range<usize>)> = Vec::new();
    for s in spans {
        let coords: Vec<&[f64]> = (0..m).map(|j| s.coordinate(j)).collect::<Option<_>>()?;
        let mut start = None;
        for t in 0..=coords[0].len() {
            let usable = t < coords[0].len() && coords.iter().all(|c| c[t].is_finite());
            match (usable, start) {
                (true, None) => start = Some(t),
                (false, Some(a)) => {
                    runs.push((coords.clone(), a..t));
                    start = None;
                }
                _ => {}
            }
        }
    }
    let segments = |w: usize| runs.iter().map(|r| r.1.len() / w).sum::<usize>();
    let mut w = window.next_power_of_two().max(MIN_WINDOW);
    while w > MIN_WINDOW && segments(w) < MIN_SEGMENTS {
        w /= 2;
    }
    let k = segments(w);
    if k < MIN_SEGMENTS {
        return None;
    }
    let bins = w / 2;
    let fft = rustfft::FftPlanner::new().plan_fft_forward(w);
    let hann: Vec<f64> = (0..w)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / w as f64).cos())
        .collect();
    // s[i][j][f]: Σ X̂ᵢ X̂ⱼ* over segments, j ≥ i, bins 1 … W/2 − 1.
    let mut s = vec![vec![vec![Complex::new(0.0, 0.0); bins]; m]; m];
    let mut x = vec![vec![Complex::new(0.0, 0.0); w]; m];
    for (coords, range) in &runs {
        for seg in 0..range.len() / w {
            let from = range.start + seg * w;
            for (xj, c) in x.iter_mut().zip(coords) {
                let piece = &c[from..from + w];
                let mean = piece.iter().sum::<f64>() / w as f64;
                for ((z, v), h) in xj.iter_mut().zip(piece).zip(&hann) {
                    *z = Complex::new((v - mean) * h, 0.0);
                }
                fft.process(xj);
            }
            for i in 0..m {
                for j in i..m {
                    for (f, acc) in s[i][j].iter_mut().enumerate().skip(1) {
                        *acc += x[i][f] * x[j][f].conj();
                    }
                }
            }
        }
    }
    let pairs = (m * (m - 1) / 2) as f64;
    let tail = FALSE_ALARM / ((bins - 1) as f64 * pairs);
    let threshold = 1.0 - tail.powf(1.0 / (k - 1) as f64);
    let coherency = |i: usize, j: usize, f: usize| {
        let d = (s[i][i][f].re * s[j][j][f].re).sqrt();
        if d > 0.0 {
            s[i][j][f] / d
        } else {
            Complex::new(0.0, 0.0)
        }
    };
    let mut best: Option<(f64, usize)> = None;
    for f in 1..bins {
        for i in 0..m {
            for j in i + 1..m {
                let im = coherency(i, j, f).im.powi(2);
                if best.is_none_or(|(b, _)| im > b) {
                    best = Some((im, f));
                }
            }
        }
    }
    let (coherence, f) = best.filter(|&(c, _)| c > threshold)?;
    let coordinates: Vec<usize> = (0..m)
        .filter(|&i| {
            (0..m).any(|j| j != i && coherency(i.min(j), i.max(j), f).norm_sqr() > threshold)
        })
        .collect();
    Some(DrivenWave {
        frequency: f as f64 * fs / w as f64,
        coordinates,
        coherence,
        threshold,
    })
}

impl DrivenWave {
    /// Its modes, by index (`first_mode` the first non-zero one's).
    fn modes(&self, first_mode: usize) -> Vec<usize> {
        self.coordinates.iter().map(|j| first_mode + j).collect()
    }

    /// The dispersion `rejected`, whatever the voting modes said: a driven wave puts its modes
    /// at its own frequency, not at the body's. A dispersion the modes already reject keeps its
    /// own reason (the warning says the rest).
    pub(super) fn reject(&self, test: &mut super::TheoryTest, first_mode: usize) {
        if test.verdict == super::Verdict::Rejected {
            return;
        }
        test.verdict = super::Verdict::Rejected;
        test.note = Some(super::TestNote::DrivenWave {
            modes: self.modes(first_mode),
            frequency: self.frequency,
        });
    }

    /// The warning the report gives.
    pub(super) fn warning(&self, first_mode: usize) -> String {
        let list: Vec<String> = self
            .modes(first_mode)
            .iter()
            .map(|m| m.to_string())
            .collect();
        format!(
            "a driven travelling wave: modes {} are phase-locked at f = {} per time unit with a lag between them (squared imaginary coherency {} against {} by chance for a passive body, whose coordinates are instantaneous mixtures of independent modes); the dispersion is rejected and ω, β and κ describe the wave, not the body: fit its driving force with `discover --active`",
            list.join(", "),
            crate::report::number(self.frequency),
            crate::report::fixed(self.coherence, 2),
            crate::report::fixed(self.threshold, 2),
        )
    }
}
