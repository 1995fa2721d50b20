//! Which modes the exact estimators use, and each one's exact fit.
//!
//! From the lowest up (at most [`MAX_MODES`]), until one fails: a mode `fit` resolves (or
//! fitted by its exact likelihood) starts from `fit`'s estimate; a mode `fit` left unresolved
//! for want of a spectral peak (over-damped, flat under its white level, too near zero, too
//! uncertain, or not converged there) is fitted by the exact likelihood from its own starts,
//! kept when its Ω and ζ are determined. Above a resolved mode only an over-damped own fit
//! counts, and only faster than the mode below it. Every fit used is an under-damped line or an
//! over-damped one whose two time scales the frames resolve.

use super::data::Recording;
use super::exact::{fit_mode, mode_data, ModeData, ModeFit, MAX_MODES};
use super::DiscoverError;
use crate::fit::{ModeNote, ModeSpectralFit};
use crate::statespace::Oscillator;

/// The modes used, their fits and data, and which were fitted from their own starts.
pub(super) struct Used {
    /// Indices into the first recording's `modes_fit`.
    pub modes: Vec<usize>,
    /// Each one's exact fit.
    pub fits: Vec<ModeFit>,
    /// Each one's series in blocks.
    pub data: Vec<ModeData>,
    /// The modes (as numbered in reports) fitted from their own starts.
    pub own: Vec<usize>,
}

/// The modes of `recordings` the exact estimators use (`available` continuum or grid
/// coordinates), chosen on the first recording's fit; a refusal when not even the lowest is.
pub(super) fn used(recordings: &[Recording], available: usize) -> Result<Used, DiscoverError> {
    let first = &recordings[0];
    let candidates: Vec<usize> = (0..available.min(first.fit.modes_fit.len()))
        .take(MAX_MODES)
        .collect();
    let mut data = mode_data(recordings, &candidates);
    let mut fits: Vec<ModeFit> = Vec::new();
    // The modes fitted from their own starts, as reported.
    let mut own: Vec<usize> = Vec::new();
    for (d, &j) in data.iter().zip(&candidates) {
        let m = &first.fit.modes_fit[j];
        let gain = first.basis.gain(j);
        let found = if m.resolved || m.exact.is_some() {
            fit_mode(d, from_fit(m, gain, first.dt))
        } else if peakless(m) {
            let below = fits.last().map(|f: &ModeFit| f.fit.estimate.omega);
            // Above a mode fit resolved, only an over-damped line: an under-damped one there is
            // a line fit's spectrum did not see (on both worms, the undulation leaked).
            let after_resolved = own.len() < fits.len();
            own.push(m.mode);
            own_fit(d).filter(|f| {
                below.is_none_or(|w| f.fit.estimate.omega > ABOVE * w)
                    && (!after_resolved || f.fit.estimate.zeta >= 1.0)
            })
        } else {
            None
        };
        let found = found.filter(determined);
        match found {
            Some(f) => fits.push(f),
            None => break,
        }
    }
    if fits.is_empty() {
        return Err(DiscoverError::NoResolvedMode {
            recording: crate::markup::clip(&first.name),
        });
    }
    let modes = candidates[..fits.len()].to_vec();
    data.truncate(fits.len());
    keep_own(first, &modes, &mut own);
    Ok(Used {
        modes,
        fits,
        data,
        own,
    })
}

/// Mode `m`'s start from `fit`'s estimate (its coordinate divided by `gain`; time in frames of
/// `dt`).
fn from_fit(m: &ModeSpectralFit, gain: f64, dt: f64) -> Oscillator {
    let variance = (m.variance / (gain * gain)).max(f64::MIN_POSITIVE);
    Oscillator {
        omega: (m.omega * dt).clamp(1e-6, std::f64::consts::PI * 1.9),
        zeta: m.zeta.clamp(1e-3, 10.0),
        variance,
        noise: (m.noise / (gain * gain)).max(variance * 1e-4),
    }
}

/// `own` (modes as reported) kept to those among `modes` (the fit's mode positions).
pub(super) fn keep_own(first: &Recording, modes: &[usize], own: &mut Vec<usize>) {
    own.retain(|&k| modes.iter().any(|&j| first.fit.modes_fit[j].mode == k));
}

/// How many of the `modes` used (`fits` their exact fits) the diagonal estimator keeps: those
/// below the first that `fit` cannot tell from an alias (near or past Nyquist, not unfolded)
/// and whose fit is not faster than the mode below by [`ABOVE`]. (A free beam at 14 frames a
/// period, no frames lost: modes 5 and 6, truly at 1.3 and 1.9 × Nyquist, fitted at 0.9 ×
/// Nyquist, 1.19 × mode 4, put c_y −29 % and c′_y −61 % off with J = 11 641 on 8 degrees of
/// freedom. The joint likelihood keeps them: its sampled system places each mode's alias
/// itself, and the active beam's c′_y lost 5 % without its mode 5.)
pub(super) fn unaliased(first: &Recording, modes: &[usize], fits: &[ModeFit]) -> usize {
    let ambiguous = |j: usize| {
        matches!(
            first.fit.modes_fit[j].note,
            Some(
                ModeNote::NearAlias
                    | ModeNote::AboveNyquist
                    | ModeNote::LinePastNyquist
                    | ModeNote::BroadAlias { .. }
                    | ModeNote::BroadNearNyquist { .. }
            )
        )
    };
    (1..fits.len())
        .find(|&k| {
            let (w, below) = (fits[k].fit.estimate.omega, fits[k - 1].fit.estimate.omega);
            ambiguous(modes[k]) && w <= ABOVE * below
        })
        .unwrap_or(fits.len())
}

/// Whether `fit` left mode `m` unresolved only for want of a spectral peak (over-damped, flat
/// under its white level, too near zero or too uncertain in Ω for the Welch spectrum, or not
/// converged there): the Kalman likelihood needs no peak. A mode near or past Nyquist is not
/// one: its likelihood has an alias's optimum too.
fn peakless(m: &ModeSpectralFit) -> bool {
    matches!(
        m.note,
        Some(
            ModeNote::NotConverged
                | ModeNote::OverDamped { .. }
                | ModeNote::MostlyFlat
                | ModeNote::OmegaUncertain
                | ModeNote::TooFewBins { .. }
        )
    )
}

/// How much faster than the mode below it a peak-less mode's own fit must be: a beam's modes
/// are ordered (Ωₙ ∝ rₙ², 2.8× from a free beam's first to its second), and a coordinate at a
/// lower mode's frequency is that mode showing through (WormPose's modes 6–9 at Ω ≈ 2.4 with
/// its mode 4 at 2.37: the undulation, leaked).
const ABOVE: f64 = 1.25;

/// Starts of a peak-less mode's own fit: Ω per frame and ζ, from a slow to a fast line and
/// from a sharp to an over-damped one.
const OWN_STARTS: [(f64, f64); 6] = [
    (0.05, 0.3),
    (0.05, 2.0),
    (0.25, 0.3),
    (0.25, 2.0),
    (1.0, 0.3),
    (1.0, 2.0),
];

/// The standard errors of ln Ω and ln ζ under which a peak-less mode's own fit is used: its
/// time scales determined, not a line lost in the noise.
const OWN_ERRORS: [f64; 2] = [0.1, 0.2];

/// The correlation of ln Ω and ln ζ above which a mode's fit is not used: an over-damped mode
/// whose fast rate the frames do not resolve shows only its slow rate, Ω and ζ lie on a ridge
/// and the information understates its length. On a Kelvin beam (ζ₁ = 0.6, 8–30 frames a
/// period) the fits off the truth had 0.93–0.9996, those on it −0.49 to 0.81; with the
/// ridge's modes in, c_y came out −90 % (one such mode `fit` had called resolved).
const RIDGE: f64 = 0.9;

/// The fastest rate per frame, Ω(ζ + √(ζ² − 1)), of an over-damped mode that is used: beyond
/// it the mode's Ω spread twice its standard error over seeds (the same beam's second mode,
/// 3.7 per frame at 14 frames a period) and c_y's interval missed in 2 of 6; at 1.7 (30 frames
/// a period) it held.
const FASTEST: f64 = 2.0;

/// Whether a mode's exact fit is used: an under-damped line always (its peak separates Ω from
/// ζ: a clamped beam's sharp first mode at 1 % tracking noise has them correlated beyond
/// [`RIDGE`] and is right); an over-damped one off the ridge ([`RIDGE`]) with its fast rate
/// resolved ([`FASTEST`]).
fn determined(f: &ModeFit) -> bool {
    let c = &f.covariance;
    let ridge = c[(0, 1)] / (c[(0, 0)] * c[(1, 1)]).sqrt() > RIDGE;
    let p = f.fit.estimate;
    let fast = p.omega * (p.zeta + (p.zeta * p.zeta - 1.0).max(0.0).sqrt());
    p.zeta < 1.0 || (!ridge && fast <= FASTEST)
}

/// A peak-less mode's fit from [`OWN_STARTS`] (the highest likelihood), when its Ω and ζ are
/// determined ([`OWN_ERRORS`]), its line holds more variance than the white noise over it
/// (WormPose's modes 6–9, mostly white, gave lines at the lower modes' frequencies), and an
/// under-damped line lies below
/// [`EXACT_NYQUIST`](crate::fit::EXACT_NYQUIST) × Nyquist.
fn own_fit(d: &ModeData) -> Option<ModeFit> {
    let observed: Vec<f64> = (d.blocks.iter().flatten().copied())
        .filter(|v| v.is_finite())
        .collect();
    let total = observed.iter().map(|v| v * v).sum::<f64>() / observed.len().max(1) as f64;
    let best = (OWN_STARTS.iter())
        .filter_map(|&(omega, zeta)| {
            fit_mode(
                d,
                Oscillator {
                    omega,
                    zeta,
                    variance: 0.9 * total,
                    noise: 0.1 * total,
                },
            )
        })
        .max_by(|a, b| a.fit.log_likelihood.total_cmp(&b.fit.log_likelihood))?;
    let se = |k: usize| best.covariance[(k, k)].max(0.0).sqrt();
    let p = best.fit.estimate;
    let alias = p.zeta < 1.0 && p.omega > crate::fit::EXACT_NYQUIST * std::f64::consts::PI;
    let known = se(0) <= OWN_ERRORS[0] && se(1) <= OWN_ERRORS[1];
    (total > 0.0 && known && !alias && p.variance >= p.noise).then_some(best)
}
