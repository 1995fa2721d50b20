//! The modal coordinates kept in time order, lost frames as gaps, and the modes whose Welch fit
//! cannot be trusted fitted again by their exact time-domain likelihood
//! ([`crate::statespace`]: a Kalman filter on the sampled damped oscillator seen through white
//! noise).
//!
//! **Where.** The Whittle fit of a Welch spectrum stays the estimator of a mode unless
//! * its line reaches near Nyquist (f + 3ζf above [`NEAR_NYQUIST`] of it) and is not broad
//!   (ζ < [`BROAD`]): there the taper's
//!   leakage of the folded line and the aliased tails of the unresolved modes bias Ω and ζ
//!   low by several standard errors (tests/coverage.rs), and the mode used not to vote;
//! * its line is narrower than a frequency bin (ζΩ/2π < df): Whittle's Fisher error assumes a
//!   line spread over many bins and is 1.5–2.3× too small for σ² there (issue 56);
//! * frames were lost and not bridged: Welch's segments stay inside runs and drop the frames
//!   of short ones, while the Kalman filter uses every frame and skips the lost ones;
//! * frames were lost and the window the runs allow leaves the mode under a bin above zero
//!   ([`SHORT_RUNS`]: a tracker's stage moves every 12–25 frames): the Kalman filter is not
//!   bound to a window, so it fits the mode across all runs at once, from three starts
//!   (Ω₀/2, Ω₀, 2Ω₀ of the unresolved Whittle estimate Ω₀, whose likelihood is flat and
//!   multi-modal there), the best ln L kept. Such a fit stands when the longest run holds at
//!   least [`RUN_PERIODS`] of its period 2π/Ω (a run shorter than that sees a trend, not an
//!   oscillation, and Ω is then set by the prior start, not the data).
//!
//! Such a mode (fitted, not over-damped, with a line above the white level) is fitted again
//! from the Whittle estimate, over every animal's series at once (one likelihood, the sum of
//! theirs), and the new fit replaces the Whittle one when both describe the same line
//! ([`agrees`]). The report marks it (`exact`: why). Every scope does this, so that one estimator
//! stands behind every number: the pooled fit, each animal's own fit (on its own series, by
//! the same rule: the same animal in a pool and alone is fitted alike), and each bootstrap
//! resample (on the series of the animals it drew, or of its moving blocks of frames, for the
//! modes the pooled fit refitted, started from its estimate). A recording longer than
//! [`MAX_FRAMES`] frames keeps no series (its memory and the fit's time would grow with it):
//! the Whittle fit then stands alone, as on the 10⁶-frame benchmark; so does a pool whose
//! animals' series together pass [`MAX_POOLED`] values.

use super::alias::{branch_band, UNFOLDED};
use super::note::ModeNote;
use super::spectrum::ModeSpectrum;
use super::verdict::ModeSpectralFit;
use super::window::on_cores;
use crate::statespace::{
    fit_oscillator, fit_oscillator_in, free_parameters, newton_step, score_and_information,
    Oscillator, OscillatorFit,
};
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// The most frames (lost ones included) a recording keeps in time order.
pub(super) const MAX_FRAMES: usize = 100_000;

/// The most values (frames × modes) a pool keeps in time order over all its animals: past it no
/// series is kept (the pooled fit keeps the Whittle fits): 2·10⁷ values are 160 MB, where a
/// directory of 300 animals × 10⁵ frames × 12 modes would hold 2.9 GB.
pub(super) const MAX_POOLED: usize = 20_000_000;

/// The share of Nyquist a line may reach (Ω(1 + 3ζ)) before the exact likelihood fits it.
pub(super) const NEAR_NYQUIST: f64 = 0.6;

/// The damping ratio from which a line keeps its Whittle fit (and its note): so
/// broad a line spreads over the whole band, where the leakage of the unresolved modes into its
/// coordinate is not white, and one oscillator's exact likelihood, blind to that, gives its σ² an
/// error far too small (a clamped–free beam's third mode, ζ = 0.55 at 0.8 × Nyquist: a true
/// equipartition rejected in 9 of 20 recordings).
pub(super) const BROAD: f64 = 0.4;

/// Why a mode the short runs' window cannot resolve is fitted by the exact likelihood.
pub(super) const SHORT_RUNS: &str = "window limited by short runs";

/// The share of its period 2π/Ω the longest run must hold for a [`SHORT_RUNS`] fit to stand.
pub(super) const RUN_PERIODS: f64 = 0.5;

/// One animal's modal coordinates in time order, NaN where a frame was lost; none past
/// [`MAX_FRAMES`].
#[derive(Debug, Clone, Default)]
pub(super) struct Series {
    modes: Vec<Vec<f64>>,
    /// Lost frames left as gaps (not bridged) between usable ones.
    lost: usize,
    /// Past [`MAX_FRAMES`]: nothing kept.
    dropped: bool,
}

impl Series {
    /// One usable frame's coordinates `q`.
    pub(super) fn push(&mut self, q: &[f64]) {
        if self.dropped {
            return;
        }
        if self.modes.is_empty() {
            self.modes = vec![Vec::new(); q.len()];
        }
        if self.modes[0].len() >= MAX_FRAMES || self.modes.len() != q.len() {
            self.dropped = true;
            self.modes = Vec::new();
            return;
        }
        for (s, v) in self.modes.iter_mut().zip(q) {
            s.push(*v);
        }
    }

    /// `n` frames lost between usable ones, left as a gap.
    pub(super) fn gap(&mut self, n: usize) {
        if self.dropped || self.modes.is_empty() {
            return;
        }
        // Saturating: a clock step of absurd length is a gap of usize::MAX frames.
        if self.modes[0].len().saturating_add(n) >= MAX_FRAMES {
            self.dropped = true;
            self.modes = Vec::new();
            return;
        }
        self.lost += n;
        for s in &mut self.modes {
            s.extend(std::iter::repeat_n(f64::NAN, n));
        }
    }

    /// The values it holds.
    pub(super) fn values(&self) -> usize {
        self.modes.iter().map(Vec::len).sum()
    }

    /// Let go of its frames (a pool past [`MAX_POOLED`]).
    pub(super) fn drop_frames(&mut self) {
        (self.modes, self.dropped) = (Vec::new(), true);
    }

    /// Whether it holds the recording.
    pub(super) fn kept(&self) -> bool {
        !self.dropped && !self.modes.is_empty()
    }

    /// All of it.
    pub(super) fn whole(&self) -> Span<'_> {
        Span {
            series: self,
            frames: 0..self.modes.first().map_or(0, Vec::len),
        }
    }

    /// The frames (lost ones included) of consecutive blocks of `counts` usable frames each,
    /// from the first usable frame on; `None` when the blocks hold more frames than it does.
    pub(super) fn blocks(&self, counts: &[usize]) -> Option<Vec<Range<usize>>> {
        let first = self.modes.first()?;
        let mut usable = (first.iter().enumerate()).filter(|(_, v)| !v.is_nan());
        let mut out = Vec::with_capacity(counts.len());
        let mut end = 0;
        for &c in counts {
            let start = if c == 0 { end } else { usable.next()?.0 };
            end = match c {
                0 => end,
                1 => start + 1,
                _ => usable.nth(c - 2)?.0 + 1,
            };
            out.push(start..end);
        }
        Some(out)
    }
}

/// Some consecutive frames of one animal's [`Series`]: what one likelihood term is made of.
#[derive(Debug, Clone)]
pub(super) struct Span<'a> {
    pub(super) series: &'a Series,
    pub(super) frames: Range<usize>,
}

impl Span<'_> {
    /// Coordinate `j` over its frames (NaN where lost), when the series holds it.
    pub(super) fn coordinate(&self, j: usize) -> Option<&[f64]> {
        (self.series.modes.get(j)).map(|m| &m[self.frames.clone()])
    }
}

/// Why a mode is fitted by its exact likelihood, or `None` when its Whittle fit stands.
fn wanted(m: &ModeSpectralFit, df: f64, fs: f64, lost: bool) -> Option<&'static str> {
    let short = lost && matches!(m.note, Some(ModeNote::TooFewBins { .. }));
    let fittable = short
        || matches!(
            m.note,
            None | Some(ModeNote::AboveNyquist)
                | Some(ModeNote::LinePastNyquist)
                | Some(ModeNote::OmegaUncertain)
        );
    if !(fittable && m.omega > 0.0 && m.zeta < BROAD && m.variance > 0.0) {
        return None;
    }
    if short {
        return Some(SHORT_RUNS);
    }
    let f = m.omega / (2.0 * std::f64::consts::PI);
    // Above Nyquist the mode is its alias: it does not vote, and its fit is left as it is.
    if f > 0.5 * fs {
        None
    } else if f * (1.0 + 3.0 * m.zeta) > NEAR_NYQUIST * 0.5 * fs {
        Some("line near Nyquist")
    } else if m.zeta * f < df {
        Some("line narrower than a bin")
    } else if lost {
        Some("lost frames")
    } else {
        None
    }
}

/// Whether the time-domain fit `exact` describes the line the Welch spectrum shows in `whittle`:
/// half-widths ζΩ within a factor [`WIDTH_RATIO`] of each other (both counted as at least a
/// bin, the narrowest a window shows) and Ω within two of those half-widths. A coordinate that
/// is not one oscillator over the whole band (slow drift, a neighbour's leakage) is fitted by
/// the time-domain likelihood as a compromise — the shipped example's sharp mode 2 (ζ = 0.012)
/// came out at ζ = 0.26 and Ω 7 % high — where the Whittle fit, over the line's own band,
/// keeps the line: the Whittle fit then stands.
fn agrees(whittle: &ModeSpectralFit, exact: &ModeSpectrum, df: f64) -> bool {
    let tau = 2.0 * std::f64::consts::PI;
    let half = |omega: f64, zeta: f64| (zeta * omega / tau).max(df);
    let (a, b) = (
        half(whittle.omega, whittle.zeta),
        half(exact.omega, exact.zeta),
    );
    let near = (exact.omega - whittle.omega).abs() / tau <= 2.0 * a.max(b);
    near && b <= WIDTH_RATIO * a && a <= WIDTH_RATIO * b
}

/// How far the two fits' half-widths may differ (see [`agrees`]).
const WIDTH_RATIO: f64 = 2.0;

/// The data a scope's exact likelihood is maximised on.
#[derive(Clone, Copy)]
pub(super) enum Exact<'a> {
    /// These spans' coordinates, fitted afresh.
    Spans(&'a [Span<'a>]),
    /// A bootstrap resample: `times[u]` copies of each unit of the [`OneStep`].
    Resample(&'a OneStep, &'a [usize]),
}

impl<'a> Exact<'a> {
    /// The spans fitted afresh (none for a resample).
    pub(super) fn spans(self) -> &'a [Span<'a>] {
        match self {
            Exact::Spans(s) => s,
            Exact::Resample(..) => &[],
        }
    }
}

/// Makes a mode's entry from its exact fit: its index among the fits, the fit, and why it was
/// fitted so.
pub(super) type Classify<'c> =
    dyn Fn(usize, &ModeSpectrum, &'static str) -> ModeSpectralFit + Sync + 'c;

/// For a bootstrap: each unit's score and observed information at the pooled estimate, for each
/// mode the pooled fit fitted by the exact likelihood. A resample's estimate is one Newton step
/// from the pooled one on the sum of its units' (the linearised, one-step bootstrap: to first
/// order the resample's own maximum, at the cost of one more fit in all instead of one per
/// resample — 200 resamples of 16 animals refitted afresh took minutes).
pub(super) struct OneStep {
    modes: Vec<OneMode>,
}

/// One mode of a [`OneStep`].
struct OneMode {
    j: usize,
    why: &'static str,
    /// The pooled estimate, in frames.
    at: Oscillator,
    free: Vec<usize>,
    /// Each unit's score and information.
    units: Vec<(DVector<f64>, DMatrix<f64>)>,
}

impl OneStep {
    /// Of the pooled fit's modes `pooled` over the bootstrap's `units`, sampled at `fs`.
    pub(super) fn of(pooled: &[ModeSpectralFit], units: &[Span<'_>], fs: f64) -> OneStep {
        let jobs: Vec<(usize, &'static str, Oscillator)> = (pooled.iter().enumerate())
            .filter_map(|(j, m)| {
                let why = m.exact?;
                let at = Oscillator {
                    omega: m.omega / fs,
                    zeta: m.zeta,
                    variance: m.variance,
                    noise: m.noise.max(1e-12 * m.variance),
                };
                let finite = [at.omega, at.zeta, at.variance, at.noise]
                    .iter()
                    .all(|v| v.is_finite() && *v > 0.0);
                (finite && holds(units, j)).then_some((j, why, at))
            })
            .collect();
        let modes = on_cores(jobs.len(), |k| {
            let (j, why, at) = jobs[k];
            let free = free_parameters(&at);
            let units = (units.iter())
                .map(|u| {
                    let data = coordinate(std::slice::from_ref(u), j);
                    score_and_information(&data, 1.0, &at, &free)
                })
                .collect();
            OneMode {
                j,
                why,
                at,
                free,
                units,
            }
        });
        OneStep { modes }
    }

    /// The resample of `times[u]` copies of each unit: each mode's one-step fit, with why.
    fn resample(&self, times: &[usize], fs: f64) -> Vec<(usize, &'static str, ModeSpectrum)> {
        (self.modes.iter())
            .filter_map(|m| {
                let n = m.free.len();
                let (mut g, mut h) = (DVector::zeros(n), DMatrix::zeros(n, n));
                for ((ug, uh), &c) in m.units.iter().zip(times) {
                    g += ug * c as f64;
                    h += uh * c as f64;
                }
                let done = newton_step(&m.at, &m.free, (&g, &h))?;
                Some((m.j, m.why, in_time_unit(&done, fs)))
            })
            .collect()
    }
}

/// Fit again by the exact likelihood each mode of `fits` the module header names (over
/// `exact`'s spans) — or, within a pool (`chosen`: the pooled fit's modes), each mode the
/// pooled fit fitted so, started from its estimate (a resample: by its one step). A fit
/// replaces the Whittle one when both describe the same line ([`agrees`]; an alias unfolded
/// by the λ law has no Whittle line to agree with). Modes are spread over the cores.
pub(super) fn refit(
    fits: &mut [ModeSpectralFit],
    (exact, chosen): (Exact<'_>, Option<&[ModeSpectralFit]>),
    (df, fs): (f64, f64),
    classify: &Classify<'_>,
) {
    let done: Vec<(usize, &'static str, ModeSpectrum)> = match exact {
        Exact::Resample(one, times) => one.resample(times, fs),
        Exact::Spans(spans) => {
            if spans.is_empty() || !spans.iter().all(|s| s.series.kept()) {
                return;
            }
            let lost = spans.iter().any(|s| s.series.lost > 0);
            let jobs: Vec<(usize, &'static str, &ModeSpectralFit)> = match chosen {
                Some(pooled) => (pooled.iter().enumerate())
                    .filter_map(|(j, m)| m.exact.map(|why| (j, why, m)))
                    .collect(),
                None => (fits.iter().enumerate())
                    .filter_map(|(j, m)| wanted(m, df, fs, lost).map(|why| (j, why, m)))
                    .collect(),
            };
            let jobs: Vec<_> = (jobs.into_iter())
                .filter(|&(j, ..)| j < fits.len() && holds(spans, j))
                .collect();
            let longest = longest_run(spans);
            let one = |&(j, why, from): &(usize, &'static str, &ModeSpectralFit)| {
                // Fitted in frames (Δt = 1), Ω back in the recording's time unit.
                let start = Oscillator {
                    omega: from.omega / fs,
                    zeta: from.zeta,
                    variance: from.variance,
                    noise: from.noise.max(1e-6 * from.variance),
                };
                let data = coordinate(spans, j);
                let fit = match why {
                    UNFOLDED => fit_oscillator_in(&data, 1.0, start, branch_band(start.omega)).ok(),
                    SHORT_RUNS => across_runs(&data, start, longest),
                    _ => fit_oscillator(&data, 1.0, start).ok(),
                };
                Some((j, why, in_time_unit(&fit?, fs)))
            };
            on_cores(jobs.len(), |k| one(&jobs[k]))
                .into_iter()
                .flatten()
                .collect()
        }
    };
    for (j, why, spectrum) in done {
        // A short-run fit has no resolved Whittle line to agree with.
        let unresolved = why == UNFOLDED || why == SHORT_RUNS;
        if j < fits.len() && (unresolved || agrees(&fits[j], &spectrum, df)) {
            let mut fit = classify(j, &spectrum, why);
            fit.exact = Some(why);
            fits[j] = fit;
        }
    }
}

/// A [`SHORT_RUNS`] mode's fit across all runs `data` (in frames): the best ln L of three
/// starts, kept when the longest run (`longest` frames) holds [`RUN_PERIODS`] of its period.
fn across_runs(data: &[&[f64]], start: Oscillator, longest: usize) -> Option<OscillatorFit> {
    let zeta = start.zeta.clamp(0.05, 0.3);
    let fits = [0.5, 1.0, 2.0].map(|k| {
        let omega = (start.omega * k).min(0.9 * std::f64::consts::PI);
        fit_oscillator(
            data,
            1.0,
            Oscillator {
                omega,
                zeta,
                ..start
            },
        )
        .ok()
    });
    let best = (fits.into_iter().flatten())
        .filter(|f| f.errors.is_some())
        .max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood))?;
    let period = 2.0 * std::f64::consts::PI / best.estimate.omega;
    (longest as f64 >= RUN_PERIODS * period).then_some(best)
}

/// The most consecutive usable frames in any of `spans`.
fn longest_run(spans: &[Span<'_>]) -> usize {
    let runs = spans.iter().filter_map(|s| s.coordinate(0)).map(|c| {
        let (mut best, mut now) = (0, 0);
        for v in c {
            now = if v.is_nan() { 0 } else { now + 1 };
            best = best.max(now);
        }
        best
    });
    runs.max().unwrap_or(0)
}

/// Mode `j`'s coordinate over each span.
pub(super) fn coordinate<'a>(spans: &'a [Span<'a>], j: usize) -> Vec<&'a [f64]> {
    (spans.iter())
        .map(|s| &s.series.modes[j][s.frames.clone()])
        .collect()
}

/// Whether every span holds mode `j`'s coordinate.
pub(super) fn holds(spans: &[Span<'_>], j: usize) -> bool {
    !spans.is_empty()
        && spans
            .iter()
            .all(|s| s.series.kept() && j < s.series.modes.len())
}

/// A fit made in frames (Δt = 1) as a [`ModeSpectrum`] in the recording's time unit (`fs`
/// frames per unit).
pub(super) fn in_time_unit(done: &OscillatorFit, fs: f64) -> ModeSpectrum {
    let (e, se) = (done.estimate, done.errors);
    let se = se.unwrap_or([f64::INFINITY; 4]);
    ModeSpectrum {
        omega: e.omega * fs,
        omega_error: se[0] * fs,
        zeta: e.zeta,
        zeta_error: se[1],
        variance: e.variance,
        variance_error: se[2],
        noise: e.noise,
        converged: done.errors.is_some(),
    }
}
