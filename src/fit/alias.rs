//! Modes above Nyquist. Sampled every Δt, a mode at frequency f shows at its alias
//! f_b = min(f mod f_s, f_s − f mod f_s) ∈ [0, f_s/2]; its true frequency is one of
//! k·f_s ± f_b, and the data tell these branches apart only weakly (the exact likelihood of a
//! damped oscillator differs between them only through the phase of its autocovariance).
//!
//! * [`mark_aliases`]: a resolved mode whose Ω lies below a lower mode's in the upper half of
//!   the band is an alias, and does not vote.
//! * [`unfold`]: where the theory's λ law (Ω ∝ √λ, scaled by the resolved mode below it: the
//!   law the dispersion test checks) puts a mode at f_law ≥ [`LAW_NEAR`] × f_s, the branch
//!   k·f_s ± f_b nearest f_law is taken when it is unambiguous — within [`TOLERANCE`] × f_law
//!   of it, every other branch beyond twice that — and the mode is fitted again by the exact
//!   likelihood with Ω held to that branch (between the multiples of f_s/2 around it). It then
//!   votes like any mode, marked `exact: "alias unfolded by the λ law"`. The law only picks
//!   the branch: within it Ω is the data's, known as well as its alias, so a mode off the law
//!   by more than its error still rejects it (a branch a random frequency would land near the law's
//!   by chance is off it by several per cent, far beyond such errors). Where no branch is
//!   unambiguous (an alias near 0 or f_s/2) the mode is left as it was, out of the vote.

use super::note::ModeNote;
use super::timedomain::{coordinate, holds, in_time_unit, Classify, Span};
use super::verdict::ModeSpectralFit;
use super::window::on_cores;
use crate::statespace::{fit_oscillator_in, Oscillator};
use std::f64::consts::PI;

/// The share of the sampling rate from which the λ law's frequency is used to unfold a mode
/// (0.4 f_s = 0.8 × Nyquist, where a time-domain fit stops voting on its own).
pub(super) const LAW_NEAR: f64 = 0.4;

/// How far from the λ law's frequency (a share of it) the chosen branch may lie.
pub(super) const TOLERANCE: f64 = 0.12;

/// What a mode unfolded by the λ law is marked with.
pub(super) const UNFOLDED: &str = "alias unfolded by the λ law";

/// Take the vote from a resolved mode whose Ω lies below a lower resolved mode's in the upper
/// half of the band (f above a quarter of the sampling rate): a passive body's frequencies rise
/// with λ, so it is the alias of a mode above Nyquist (a free beam's third mode at 8 frames per
/// period of its first voted at its alias and rejected the true dispersion in 15 of 20).
pub(super) fn mark_aliases(fits: &mut [ModeSpectralFit], fs: f64) {
    let mut highest: Option<(usize, f64)> = None;
    for m in fits.iter_mut() {
        if !m.resolved {
            continue;
        }
        match highest {
            Some((below, omega)) if m.omega < omega && m.omega > 0.25 * 2.0 * PI * fs => {
                m.resolved = false;
                m.votes = false;
                m.note = Some(ModeNote::Alias { below });
            }
            Some((_, omega)) if m.omega <= omega => {}
            _ => highest = Some((m.mode, m.omega)),
        }
    }
}

/// The branch k·f_s ± f_b of alias `fb` nearest `law`, when unambiguous (module header).
fn branch(fb: f64, law: f64, fs: f64) -> Option<f64> {
    let k = (law / fs).round();
    let mut candidates: Vec<f64> = [k - 1.0, k, k + 1.0]
        .iter()
        .flat_map(|&k| [k * fs - fb, k * fs + fb])
        .filter(|&f| f > 0.0)
        .collect();
    candidates.sort_by(|a, b| (a - law).abs().total_cmp(&(b - law).abs()));
    let (best, next) = (*candidates.first()?, *candidates.get(1)?);
    let tol = TOLERANCE * law;
    ((best - law).abs() <= tol && (next - law).abs() > 2.0 * tol).then_some(best)
}

/// The band of Ω (radians per frame) between the multiples of π around `omega`: one branch.
pub(super) fn branch_band(omega: f64) -> (f64, f64) {
    let half = (omega / PI).floor();
    let edge = 1e-3;
    ((PI * (half + edge)).max(edge), PI * (half + 1.0 - edge))
}

/// Fit again on the branch the λ law picks (module header) each mode of `fits` that is fitted
/// but does not vote and that the law puts near or above Nyquist; `regressor[j]` is the λ the
/// dispersion test regresses mode j on, `classify` makes the fit's entry from its spectrum.
pub(super) fn unfold(
    fits: &mut [ModeSpectralFit],
    spans: &[Span<'_>],
    (regressor, fs): (&[f64], f64),
    classify: &Classify<'_>,
) {
    if spans.is_empty() {
        return;
    }
    // (mode index, the branch's frequency) to fit.
    let mut jobs = Vec::new();
    let mut reference: Option<(f64, f64)> = None;
    for (j, m) in fits.iter().enumerate() {
        let Some(&lambda) = regressor.get(j).filter(|l| **l > 0.0) else {
            continue;
        };
        let f = m.omega / (2.0 * PI);
        let law = reference.map(|(f0, l0)| f0 * (lambda / l0).sqrt());
        match law {
            Some(law) if law >= LAW_NEAR * fs && !m.resolved => {
                let fitted = m.omega > 0.0 && m.variance > 0.0 && m.zeta < 1.0;
                let fb = (f % fs).min(fs - f % fs);
                if let Some(fc) = branch(fb, law, fs).filter(|_| fitted && holds(spans, j)) {
                    jobs.push((j, fc, fb));
                    reference = Some((fc, lambda));
                }
            }
            _ if m.resolved && f < LAW_NEAR * fs => reference = Some((f, lambda)),
            _ => {}
        }
    }
    let one = |&(j, fc, fb): &(usize, f64, f64)| -> Option<(usize, ModeSpectralFit)> {
        let m = &fits[j];
        let omega = 2.0 * PI * fc / fs;
        let band = branch_band(omega);
        let start = Oscillator {
            omega: omega.clamp(band.0, band.1),
            // The same decay rate ζΩ as the alias's.
            zeta: (m.zeta * fb / fc).clamp(1e-3, 0.9),
            variance: m.variance,
            noise: m.noise.max(1e-6 * m.variance),
        };
        let done = fit_oscillator_in(&coordinate(spans, j), 1.0, start, band).ok()?;
        let spectrum = in_time_unit(&done, fs);
        let mut fit = classify(j, &spectrum, UNFOLDED);
        fit.exact = Some(UNFOLDED);
        Some((j, fit))
    };
    let done = on_cores(jobs.len(), |k| one(&jobs[k]));
    for (j, fit) in done.into_iter().flatten() {
        fits[j] = fit;
    }
}

#[cfg(test)]
mod tests {
    use super::branch;

    #[test]
    fn the_law_picks_a_branch_only_when_it_is_unambiguous() {
        // A free beam's third mode at 8 frames per period of the first: 0.675 f_s, seen at 0.325.
        assert_eq!(branch(0.325, 0.66, 1.0), Some(0.675));
        // Its fourth, at 1.117 f_s, seen at 0.117.
        assert_eq!(branch(0.117, 1.1, 1.0), Some(1.117));
        // An alias near Nyquist: 0.48 and 0.52 are both near the law.
        assert_eq!(branch(0.48, 0.5, 1.0), None);
        // Far from the law: no branch.
        assert_eq!(branch(0.3, 0.5, 1.0), None);
        // Below Nyquist the law may pick the alias itself.
        assert_eq!(branch(0.41, 0.42, 1.0), Some(0.41));
    }
}
