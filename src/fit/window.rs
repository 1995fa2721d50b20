//! Each mode's spectrum fitted at one Welch window, and that window chosen from the data: the
//! ladder's shortest window in which the lowest mode lies [`AUTO_BINS`] bins above zero.

use super::spectrum::{fit_mode, Taper};
use super::stats::Spectra;
use super::verdict::{FittedBy, ModeSpectralFit, WindowChoice};
use super::welch::LEAD;
use crate::recording::Projector;
use crate::report::fixed;

/// The Welch window: the given one, or the shortest of the ladder in which the lowest mode's
/// frequency lies [`AUTO_BINS`] bins above zero with at least 4 segments; failing that, the
/// longest with 4 segments (or the longest there is), its low modes marked unresolved.
pub(super) fn choose_window(
    mut spectra: Vec<Spectra>,
    given: bool,
    lowest: impl Fn(&Spectra) -> Option<f64>,
    fs: f64,
) -> (Spectra, WindowChoice) {
    let count = spectra.len();
    let reference = reference(&spectra);
    if given || count == 1 {
        let s = spectra.swap_remove(reference.min(count - 1));
        let choice = WindowChoice {
            frames: s.window,
            segments: s.segments,
            how: if given { "given" } else { "chosen" },
            why: if given {
                "--window".into()
            } else {
                "the only window the runs fill".into()
            },
        };
        return (s, choice);
    }
    let (f, pick) = rule(&spectra, reference, lowest, fs);
    let wanted = f.map(|f| wanted_frames(f, fs));
    let why = match (pick, wanted) {
        (Some(_), Some(w)) => format!(
            "the shortest window with ≥ 4 segments in which the lowest mode (f ≈ {}) lies ≥ {AUTO_BINS} bins above zero (needs ≥ {} frames)",
            fixed(f.unwrap_or(0.0), 4),
            w.ceil()
        ),
        (None, Some(w)) => format!(
            "the lowest mode (f ≈ {}) needs ≥ {} frames for {AUTO_BINS} bins, but the runs allow at most {} frames with ≥ 4 segments: that window, so low modes may be unresolved",
            fixed(f.unwrap_or(0.0), 4),
            w.ceil(),
            spectra[reference].window
        ),
        _ => "the lowest mode's frequency could not be measured; the longest window with ≥ 4 segments".into(),
    };
    let s = spectra.swap_remove(pick.unwrap_or(reference));
    let choice = WindowChoice {
        frames: s.window,
        segments: s.segments,
        how: "chosen",
        why,
    };
    (s, choice)
}

/// The ladder's reference window: the longest with at least 4 segments, else the longest.
fn reference(spectra: &[Spectra]) -> usize {
    (spectra.iter().rposition(|s| s.segments >= 4)).unwrap_or(spectra.len() - 1)
}

/// The rule at `reference`: the lowest mode's frequency there, and the shortest window with at
/// least 4 segments in which it lies [`AUTO_BINS`] bins above zero.
fn rule(
    spectra: &[Spectra],
    reference: usize,
    lowest: impl Fn(&Spectra) -> Option<f64>,
    fs: f64,
) -> (Option<f64>, Option<usize>) {
    let f = lowest(&spectra[reference]);
    let pick = f.and_then(|f| {
        let wanted = wanted_frames(f, fs);
        (spectra.iter()).position(|s| s.segments >= 4 && s.window as f64 >= wanted)
    });
    (f, pick)
}

/// The frames a window needs for a mode of frequency `f` to lie [`AUTO_BINS`] bins above zero.
fn wanted_frames(f: f64, fs: f64) -> f64 {
    AUTO_BINS * fs / f
}

/// The windows a pass over a whole recording should keep for every mode, from a pilot's
/// spectra (its first frames, every window of the ladder): the one [`choose_window`] takes
/// there, and its neighbour when the lowest mode's frequency lies within a fifth of switching
/// to it. `None` when the choice would not come from that frequency (a window given, too few
/// segments, no frequency measured): the pass then keeps every window.
pub(super) fn likely_windows(
    spectra: &[Spectra],
    lowest: impl Fn(&Spectra) -> Option<f64>,
    fs: f64,
) -> Option<Vec<usize>> {
    let reference = spectra.iter().rposition(|s| s.segments >= 4)?;
    let (f, pick) = rule(spectra, reference, lowest, fs);
    let (wanted, pick) = (wanted_frames(f?, fs), spectra[pick?].window);
    let mut full = vec![pick];
    if wanted > 0.8 * pick as f64 {
        full.push(2 * pick);
    }
    if wanted < 0.6 * pick as f64 {
        full.push(pick / 2);
    }
    Some(full)
}

/// The lowest mode's frequency (cycles per time unit) at the window of `s`: its own spectral
/// fit when that resolves it, else its spectral peak.
pub(super) fn lowest_frequency(
    proj: &Projector,
    cov: &[Vec<f64>],
    s: &Spectra,
    fs: f64,
) -> Option<f64> {
    // A window a pilot's ladder keeps without its lead modes measures nothing.
    if s.psd.len() < LEAD.min(cov.len()) {
        return None;
    }
    let first = fit_modes_spectra(proj, cov, s, fs, (1, None))
        .into_iter()
        .next()?;
    let f = if first.resolved {
        first.omega / (2.0 * std::f64::consts::PI)
    } else {
        spectral_peak_and_centroid(&s.frequencies, &s.psd[0]).0
    };
    (f > 0.0).then_some(f)
}

/// Mode j's fitting band (cycles per time unit) from the spectral peaks of all the modes: from
/// the geometric mean of its peak and the one below to that of its peak and the one above (zero
/// below the first, Nyquist above the last); a neighbour that does not lie on its side (a
/// driven rhythm puts every peak at one frequency) leaves a factor 2 on that side.
fn band(peaks: &[(f64, f64)], j: usize, fs: f64) -> (f64, f64) {
    let f = peaks[j].0;
    let lo = match j.checked_sub(1).map(|i| peaks[i].0) {
        None => 0.0,
        Some(below) if below < 0.8 * f => (below * f).sqrt(),
        Some(_) => 0.5 * f,
    };
    let hi = match peaks.get(j + 1).map(|p| p.0) {
        None => 0.5 * fs,
        Some(above) if above > 1.25 * f => (above * f).sqrt(),
        Some(_) => 2.0 * f,
    };
    (lo, hi)
}

/// Frequency bins above zero the lowest mode should reach in a window chosen from the data.
const AUTO_BINS: f64 = 16.0;

/// Each mode's spectrum fitted at the chosen window (see [`super::spectrum`]), classified.
/// Each mode's spectrum fitted at the chosen window (see [`super::spectrum`]), classified: the
/// first `count`, each from its `warm` fit alone when given (a resample near the pooled fit),
/// else from three starts; the others left unfitted.
pub(super) fn fit_modes_spectra(
    proj: &Projector,
    cov: &[Vec<f64>],
    spec: &Spectra,
    fs: f64,
    (count, warm): (usize, Option<&[ModeSpectralFit]>),
) -> Vec<ModeSpectralFit> {
    let taper = Taper::hann(spec.window);
    let df = fs / spec.window as f64;
    let peaks: Vec<(f64, f64)> = (spec.psd.iter())
        .map(|p| spectral_peak_and_centroid(&spec.frequencies, p))
        .collect();
    let one = |j: usize| {
        let (peak, centroid) = peaks[j];
        let band = band(&peaks, j, fs);
        let tau = 2.0 * std::f64::consts::PI;
        let starts = match warm.and_then(|w| w.get(j)).filter(|w| w.omega > 0.0) {
            Some(w) => vec![(w.omega, w.zeta)],
            // One start for an animal alone (its own fit is a summary beside the pool's),
            // three for the pool.
            None if count < cov.len() => vec![(tau * peak, 0.2)],
            None => vec![(tau * peak, 0.1), (tau * peak, 0.5), (tau * centroid, 0.3)],
        };
        let index = proj.first_mode + j;
        let lambda = proj.eigenvalues[j];
        let fit = |starts: &[(f64, f64)], band| {
            fit_mode(
                &taper,
                (fs, spec.segments as f64),
                &spec.psd[j],
                starts,
                cov[j][j],
                band,
            )
        };
        // A line wider than its band cannot be told from the white level there: fitted
        // again over ±3 half-widths around it, or over an octave each side when the band
        // left it mostly white.
        let fitted = (j < count).then(|| fit(&starts, band)).flatten().map(|s| {
            let (f, half) = (s.omega / tau, s.zeta * s.omega / tau);
            let wide = if s.noise > 3.0 * s.variance {
                (0.5 * f, 2.0 * f)
            } else {
                (f - 3.0 * half, f + 3.0 * half)
            };
            let wide = (wide.0.max(0.0), wide.1.min(0.5 * fs));
            if s.converged && s.zeta < 1.0 && (wide.0 < band.0 || wide.1 > band.1) {
                let union = (wide.0.min(band.0), wide.1.max(band.1));
                fit(&[(s.omega, s.zeta)], union).unwrap_or(s)
            } else {
                s
            }
        });
        match fitted {
            Some(s) => ModeSpectralFit::of(index, lambda, &s, (df, fs), FittedBy::Whittle),
            None => ModeSpectralFit {
                mode: index,
                lambda,
                omega: 0.0,
                omega_error: None,
                zeta: 0.0,
                zeta_error: None,
                variance: cov[j][j],
                variance_error: None,
                noise: 0.0,
                relaxation_rate: None,
                resolved: false,
                votes: false,
                bins: 0.0,
                note: Some(if j < count {
                    super::ModeNote::Unfittable
                } else {
                    super::ModeNote::NotFitted
                }),
                exact: None,
            },
        }
    };
    // The pooled fit (every mode, three starts) spreads its modes over the cores (rayon keeps
    // their order); an animal's own fit runs where it is called (on a worker already).
    let modes = spec.psd.len().min(cov.len());
    if count < modes {
        return (0..modes).map(one).collect();
    }
    on_cores(modes, one)
}

/// `one(j)` for j = 0 … count − 1 on rayon's pool, in order.
pub(super) fn on_cores<T: Send>(count: usize, one: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    use rayon::prelude::*;
    (0..count).into_par_iter().map(one).collect()
}

/// Peak (with parabolic refinement) and centroid of a one-sided spectrum, above zero frequency.
pub fn spectral_peak_and_centroid(freqs: &[f64], psd: &[f64]) -> (f64, f64) {
    let df = if freqs.len() > 1 {
        freqs[1] - freqs[0]
    } else {
        0.0
    };
    let k = (1..psd.len())
        .max_by(|&a, &b| psd[a].total_cmp(&psd[b]))
        .unwrap_or(0);
    let mut peak = freqs.get(k).copied().unwrap_or(0.0);
    if k >= 1 && k + 1 < psd.len() {
        // The vertex of the parabola through the log powers: a Hann-windowed peak is close to a
        // Gaussian there, so this is nearly unbiased where the plain parabola is off by up to a
        // tenth of a bin.
        let (a, b, c) = (psd[k - 1].ln(), psd[k].ln(), psd[k + 1].ln());
        let den = a - 2.0 * b + c;
        // Refine only a true local maximum; the vertex then lies within half a bin.
        if b >= a && b >= c && den < 0.0 && den.is_finite() {
            peak += (0.5 * (a - c) / den).clamp(-0.5, 0.5) * df;
        }
    }
    let (num, den) = freqs
        .iter()
        .zip(psd)
        .skip(1)
        .fold((0.0, 0.0), |(n, d), (f, p)| (n + f * p, d + p));
    (peak, if den > 0.0 { num / den } else { 0.0 })
}
