//! Modes above Nyquist. Sampled every Δt, a mode at frequency f shows at its alias
//! f_b = min(f mod f_s, f_s − f mod f_s) ∈ [0, f_s/2]; its true frequency is one of
//! k·f_s ± f_b, and the data tell these branches apart only weakly (the exact likelihood of a
//! damped oscillator differs between them only through the phase of its autocovariance).
//!
//! * [`mark_aliases`]: a resolved mode whose Ω lies below a lower mode's in the upper half of
//!   the band is an alias, and does not vote; checked again after unfolding (a free beam's
//!   sharp sixth mode unfolded to 2.97 rad/frame showed the seventh's 2.33 to be an alias).
//! * [`unfold`]: where the theory's λ law (Ω ∝ √λ, scaled by the highest resolved mode under
//!   [`LAW_NEAR`] × f_s: the law the dispersion test checks) puts a mode that does not vote at
//!   f_law between [`LAW_NEAR`] and [`LAW_FAR`] × f_s, the branch of aliases holding it (the
//!   half-band between the multiples of f_s/2 around f_law, when f_law lies [`TOLERANCE`] of
//!   itself inside it) is taken, and the mode fitted again by the exact likelihood with Ω held
//!   to that branch, started at f_law. It then votes like any mode, marked `exact: "alias
//!   unfolded by the λ law"`. The law only picks the branch: within it Ω is the data's, known
//!   as well as its alias is, so a mode off the law by more than its error still rejects it.
//!   Near a multiple of f_s/2 the branch cannot be told, and the mode is left out of the vote.

use super::note::ModeNote;
use super::timedomain::{coordinate, holds, in_time_unit, Classify, Span, BROAD};
use super::verdict::ModeSpectralFit;
use super::window::on_cores;
use crate::statespace::{fit_oscillator_in, Oscillator};
use std::f64::consts::PI;

/// The share of the sampling rate from which the λ law's frequency is used to unfold a mode
/// (0.4 f_s = 0.8 × Nyquist, where a time-domain fit stops voting on its own).
pub(super) const LAW_NEAR: f64 = 0.4;

/// How far from the edges of its branch (a share of its frequency) the λ law's frequency must
/// lie for the branch to be taken.
pub(super) const TOLERANCE: f64 = 0.05;

/// The highest share of the sampling rate at which the λ law's frequency is used (beyond, the
/// modes are small, broad, and many).
pub(super) const LAW_FAR: f64 = 2.0;

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

/// The half-band of frequencies [m·f_s/2, (m + 1)·f_s/2] (one branch of the aliases) that holds
/// `law` within [`TOLERANCE`], as Ω in radians per frame; none when `law` lies too near a
/// multiple of f_s/2 for the branch to be told.
fn half_band(law: f64, fs: f64) -> Option<(f64, f64)> {
    let m = (law / (0.5 * fs)).floor();
    let (lo, hi) = (m * 0.5 * fs, (m + 1.0) * 0.5 * fs);
    let inside = law * (1.0 - TOLERANCE) >= lo && law * (1.0 + TOLERANCE) <= hi;
    let edge = 1e-3;
    inside.then(|| ((PI * (m + edge)).max(edge), PI * (m + 1.0 - edge)))
}

/// The branch (radians per frame, between the multiples of π) that holds `omega`.
pub(super) fn branch_band(omega: f64) -> (f64, f64) {
    let m = (omega / PI).floor();
    let edge = 1e-3;
    ((PI * (m + edge)).max(edge), PI * (m + 1.0 - edge))
}

/// Fit again within the branch the λ law picks (module header) each mode of `fits` that does
/// not vote and that the law puts between [`LAW_NEAR`] and [`LAW_FAR`] × f_s; `regressor[j]`
/// is the λ the dispersion test regresses mode j on, `classify` makes the fit's entry.
pub(super) fn unfold(
    fits: &mut [ModeSpectralFit],
    spans: &[Span<'_>],
    (regressor, fs): (&[f64], f64),
    classify: &Classify<'_>,
) {
    if spans.is_empty() {
        return;
    }
    // The highest resolved mode below LAW_NEAR × f_s: (f, λ, ζ).
    let mut reference: Option<(f64, f64, f64)> = None;
    // (mode index, the start, the branch).
    let mut jobs = Vec::new();
    for (j, m) in fits.iter().enumerate() {
        let Some(&lambda) = regressor.get(j).filter(|l| **l > 0.0) else {
            continue;
        };
        let f = m.omega / (2.0 * PI);
        if m.resolved && f < LAW_NEAR * fs {
            reference = Some((f, lambda, m.zeta));
            continue;
        }
        let Some((f0, l0, z0)) = reference.filter(|_| !m.resolved && holds(spans, j)) else {
            continue;
        };
        let law = f0 * (lambda / l0).sqrt();
        let Some(band) = half_band(law, fs).filter(|_| (LAW_NEAR..=LAW_FAR).contains(&(law / fs)))
        else {
            continue;
        };
        // Started at the law's frequency and a damping ratio growing as it does (ζ ∝ √λ, the
        // damping test's law), with the coordinate's variance.
        // A line the damping law makes broad (ζ ≥ 0.4) is not unfolded: there the leakage of the
        // modes above is not white (a clamped–free beam's third mode, ζ = 0.53, unfolded at 14
        // frames a period, rejected a true damping law in 4 of 20).
        if z0 * law / f0 >= BROAD {
            continue;
        }
        let data = coordinate(spans, j);
        let (sum2, n) = (data.iter().flat_map(|y| y.iter()).filter(|v| v.is_finite()))
            .fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
        let variance = sum2 / n.max(1) as f64;
        let start = Oscillator {
            omega: (2.0 * PI * law / fs).clamp(band.0, band.1),
            zeta: (z0 * law / f0).clamp(0.01, 0.9),
            variance: 0.9 * variance,
            noise: 0.1 * variance,
        };
        if variance > 0.0 && variance.is_finite() {
            jobs.push((j, start, band));
        }
    }
    let one = |&(j, start, band): &(usize, Oscillator, (f64, f64))| {
        let done = fit_oscillator_in(&coordinate(spans, j), 1.0, start, band).ok()?;
        let mut fit = classify(j, &in_time_unit(&done, fs), UNFOLDED);
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
    use super::half_band;
    use std::f64::consts::PI;

    #[test]
    fn the_law_picks_a_branch_only_away_from_its_edges() {
        // A free beam's third mode at 8 frames per period of the first: 0.675 f_s, the branch
        // from f_s/2 to f_s.
        let (lo, hi) = half_band(0.675, 1.0).unwrap();
        assert!((lo / PI - 1.0).abs() < 0.01 && (hi / PI - 2.0).abs() < 0.01);
        // Its fourth, at 1.117 f_s: from f_s to 3f_s/2.
        let (lo, _) = half_band(1.117, 1.0).unwrap();
        assert!((lo / PI - 2.0).abs() < 0.01);
        // Near Nyquist or near f_s the branch cannot be told.
        assert_eq!(half_band(0.49, 1.0), None);
        assert_eq!(half_band(1.02, 1.0), None);
        // Below Nyquist the law may pick the first branch itself.
        assert!(half_band(0.42, 1.0).is_some());
    }
}
