//! The measurement layer, below `fit` and `discover`: the recordings a path names, the readers
//! (plain CSV, DeepLabCut CSV, WCON), numbers, a file parsed on every core, the observation map,
//! the projection on the body's modes (continuum where the body has them), and the tracking
//! noise. One [`RecordingSettings`] says how; [`RecordingError`] says why not.
//!
//! **Input.** One frame per line, numbers separated by commas or white space; blank lines, `#`
//! comments and one header line (a first line that does not start with a number) are skipped.
//! * `midline`: `t x₁ y₁ … x_K y_K`, K ≥ 5 points, head first by default (`head_first`);
//! * `lengths`: `t ℓ₁ … ℓ_K`, K ≥ 3 segment lengths around the body (axial data);
//! * with `track_column`, a track id before t: each track is one animal, rows may interleave;
//! * DeepLabCut CSV (recognised by its `scorer`/`bodyparts`/`coords` header rows): the frame
//!   index, then x, y, likelihood per body part; time is index/fps, and a point below the
//!   likelihood threshold makes its frame lost;
//! * WCON (tracker-commons JSON, recognised by its opening `{`; see `wcon`): each id one animal,
//!   its units reported;
//! * HDF5 (recognised by its signature; see `hdf5`): a SLEAP analysis file (each track one
//!   animal) or DeepLabCut's `.h5` (each individual one animal), time the frame index over fps.
//!
//! Every frame must have the first frame's width and time that increases by whole sampling
//! intervals (the first step, within 1 %). A frame with a missing or non-finite value, or one
//! the time step skips, is lost. Anything else is an error naming the line.
//!
//! **Observation map.** A field's operator is D = SᵀS, where S holds its difference stencils
//! ([`crate::discretise::stencil_rows`]). The data observe S·q, not q:
//! * the turning angles between segments of a midline resampled to N points equally spaced in
//!   arc length are, to first order, the second differences of the transverse displacement in
//!   units of the spacing, that is S·y for D4 (free, k = 2);
//! * the segment strains ℓⱼ/h − 1, h the first frame's mean length, are the first differences
//!   S·x: periodic for D2,c (N = K + 1 points, head and tail one point), or of a free chain of
//!   K + 1 points for a model whose axial field has free ends.
//!
//! Angles and strains drop translation and rotation (the zero modes), as the paper does; a field
//! whose ends hold points is held in the lab, so each frame is observed with the held points
//! of its animal's first usable frame (`held`). The modal
//! coordinates are the least-squares solution of S·q = o: Qᵢ = (S vᵢ)·o / λᵢ for each non-zero
//! mode when the observations cover the body, because the S vᵢ are orthogonal with
//! |S vᵢ|² = λᵢ.
//!
//! When only the first K segments of a ring of R were measured (`ring`), the strains observe
//! K of the R rows of S. The lowest whole modes (at most K − 1, never half a degenerate pair)
//! are then fitted by least squares together with a constant for the unknown mean strain; the
//! equipartition shares are renormalised over the fitted modes. Unresolved modes alias into
//! them, so a truncated fit reads a dominant rhythm well and thermal noise poorly.
//!

mod chunks;
mod clock;
mod continuum;
mod error;
mod format;
mod hdf5;
mod held;
mod jitter;
mod number;
mod observe;
mod paths;
mod project;
mod read;
mod settings;
mod wcon;

pub(crate) use chunks::Chunked;
pub use clock::{ClockError, MIN_TIME_STEP};
pub use error::{LineError, LineWhy, RecordingError};
pub use format::FRAME_UNIT;
pub(crate) use format::{frame_units, layout_units, sniff, whole, whole_bytes};
pub(crate) use hdf5::parse as parse_hdf5;
pub use held::{Movement, MOVING_SHARE};
pub(crate) use jitter::Jitter;
pub use jitter::TrackingNoise;
pub use paths::recordings;
pub(crate) use project::Work;
pub use project::{turning_angles, FrameError, Projector};
pub(crate) use read::{read_tracks, FrameReader, Source, TrackSource};
pub use read::{Frame, Track, MAX_LINE_BYTES, MAX_WHOLE_FILE};
pub use settings::*;
pub(crate) use wcon::parse as parse_wcon;

/// Chan's merge of (mean, co-moment, count) b, taken `times` times, into a: returns the count.
pub(crate) fn merge_moments(
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

/// A seeded xorshift stream: the tests' random inputs, the same on every run.
#[cfg(test)]
pub(crate) fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}
