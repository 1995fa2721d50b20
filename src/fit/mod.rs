//! Fit the theory to tracked data (paper §2.3.4–2.4, Fig. 2): modal projection, PCA, spectra,
//! and the frequency and temperature scales.
//!
//! **Input.** Read by the measurement layer ([`crate::recording`]): its formats, lost frames
//! and observation map are described there.
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
mod advice;
mod alias;
mod animal;
mod bootstrap;
mod bridging;
mod error;
mod gist;
mod note;
mod pilot;
mod pool;
mod rates;
mod report;
mod settings;
mod spectrum;
mod spread;
mod stats;
mod summary;
mod timedomain;
mod uncertainty;
mod verdict;
mod wave;
mod welch;
mod window;
pub use accumulate::{Each, SinkError};
pub use advice::{Advice, Step};
pub use animal::AnimalFit;
pub(crate) use bootstrap::expanded_tail;
pub use bootstrap::{Intervals, MAX_REPLICATES};
pub use error::FitError;
pub use note::{ModeNote, TestNote};
pub use pilot::foretold_windows;
pub use pool::{fit_inputs, Input};
pub use rates::{AcrossRates, RateGroup};
pub use report::{Continuum, FitReport, ModeFit, Recording, Subspace};
pub use settings::*;
pub(crate) use spread::spread_of;
pub use spread::Spread;
pub use verdict::{
    ModeSpectralFit, TheoryTest, TheoryTests, Verdict, WindowChoice, EXACT_NYQUIST, RESOLVED_BINS,
    WIDTH_BINS,
};
pub use window::spectral_peak_and_centroid;

use crate::modal::Params;
use crate::model::Model;
use crate::recording::{Projector, Track};

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
