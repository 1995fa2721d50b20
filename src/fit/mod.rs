//! Fit the theory to tracked data (paper §2.3.4–2.4, Fig. 2): modal projection, PCA, spectra,
//! and the frequency and temperature scales.
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
//!   its units reported.
//!
//! **Animals.** Several inputs, or several tracks in one, are several animals (`pool`): read in
//! parallel into per-run statistics (`stats`), each animal fitted alone and all pooled; the
//! bootstrap (`bootstrap`) resamples whole animals, or the runs of a single one.
//!
//! Every frame must have the first frame's width and time that increases by whole sampling
//! intervals (the first step, within 1 %). A frame with a missing or non-finite value, or one
//! the time step skips, is lost: it splits the recording into runs (the covariance pools every
//! usable frame, Welch windows stay inside a run) unless `fill_gaps` bridges it linearly.
//! Anything else is an error naming the line. The file is streamed. Memory is O(N² + W·N) for N model points and a Welch window of W frames, whatever
//! the number of frames. A file fitted alone is parsed on every core (`chunks`): its first rows
//! in order, the rest in chunks of whole lines by workers that also project the midlines, taken
//! back in order; plain decimals are read by a fast exact parser (`number`), anything else by
//! the line reader's own code, so every number and every message is the line reader's. A long
//! file alone is foretold (`pilot`): its pass keeps every mode only at the windows its first
//! frames choose, and is made again with every window when the recording chooses another.
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
//! Angles and strains drop translation and rotation (the zero modes), as the paper does. The modal
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
//! **PCA and overlaps.** The PCA is taken of the postures with the zero modes removed, q⊥ = Σ Qᵢvᵢ.
//! That is the angle space measured with the body's own metric (SSᵀ)⁻¹. Its covariance matrix is
//! the covariance of the Qᵢ. Its eigendecomposition is the SVD of the centred data
//! (V and σ²/(n − 1)), accumulated in one pass. `overlap[i][j]` = |cos| between principal component
//! i and mode shape j. In the plain Euclidean angle space, equipartition gives an *isotropic*
//! covariance S D⁺ Sᵀ/β ∝ I, so principal components there are undetermined at equilibrium. The
//! plain angle-space shares are reported beside it (`angle_pca_variance_share`) for comparison
//! with the paper's eigenmaggots.
//!
//! **Spectra and fits.** Welch's method: Hann window of W frames, half overlap, each segment
//! mean-removed, one-sided density. For each mode it reports the peak (parabolic interpolation
//! of the largest bin above zero frequency) and the centroid ∫fP/∫P. The measured angular
//! frequencies mᵢ = 2πfᵢ of the first modes fit the single scale ω of ωᵢ = ω√λᵢ by least squares:
//! ω = Σmᵢ√λᵢ / Σλᵢ. With ω fixed, equipartition Var Qᵢ = 1/(βω²λᵢ) gives β by maximum likelihood
//! over the same modes: β = m / Σᵢ ω²λᵢ Var Qᵢ.

use std::io::BufRead;

mod accumulate;
mod animal;
mod bootstrap;
mod chunks;
mod continuum;
mod error;
mod jitter;
mod note;
mod number;
mod observe;
mod paths;
mod pilot;
mod pool;
mod project;
mod read;
mod report;
mod settings;
mod spectrum;
mod stats;
mod summary;
mod timedomain;
mod uncertainty;
mod verdict;
mod wcon;
mod welch;
mod window;
pub use accumulate::{Each, SinkError};
pub use bootstrap::{Intervals, MAX_REPLICATES};
pub use error::{FitError, LineWhy};
pub use jitter::TrackingNoise;
pub use note::{ModeNote, TestNote};
pub use paths::recordings;
pub use pilot::foretold_windows;
pub use pool::{fit_inputs, Input};
pub use project::{turning_angles, FrameError, Projector};
pub use read::{Frame, LineError, Track, MAX_LINE_BYTES, MAX_WHOLE_FILE};
pub use report::{AnimalFit, Continuum, FitReport, ModeFit, Recording, Subspace};
pub use settings::*;
pub use verdict::{
    ModeSpectralFit, TheoryTest, TheoryTests, Verdict, WindowChoice, RESOLVED_BINS, WIDTH_BINS,
};
pub use window::spectral_peak_and_centroid;

use crate::modal::Params;
use crate::model::Model;

/// Run the fit on the frames in `reader`.
pub fn fit(
    reader: impl BufRead + Send,
    model: &Model,
    params: &Params,
    settings: &FitSettings,
) -> Result<FitReport, FitError> {
    fit_each(reader, model, params, settings, |_, _, _| Ok(()))
}

/// [`fit`], handing the projector, each frame's time and its modal coordinates to `each` as they
/// stream past (an error from `each` ends the fit as an output error).
pub fn fit_each(
    reader: impl BufRead + Send,
    model: &Model,
    params: &Params,
    settings: &FitSettings,
    mut each: impl FnMut(&Projector, f64, &[f64]) -> Result<(), SinkError>,
) -> Result<FitReport, FitError> {
    let input = Input::Reader {
        name: String::new(),
        reader: Box::new(reader),
    };
    fit_inputs(vec![input], model, params, settings, Some(&mut each))
}

/// Fit animals held in memory (each track one animal): one pooled fit and each one's own.
pub fn fit_tracks(
    tracks: Vec<Track>,
    model: &Model,
    params: &Params,
    settings: &FitSettings,
) -> Result<FitReport, FitError> {
    fit_inputs(vec![Input::Tracks(tracks)], model, params, settings, None)
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
