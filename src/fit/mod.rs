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
//! the number of frames.
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

mod bootstrap;
mod pool;
mod read;
mod stats;
mod wcon;
pub use bootstrap::{Intervals, MAX_REPLICATES};
pub use pool::{fit_inputs, Each, Input};
pub use read::{Frame, Track, MAX_LINE_BYTES, MAX_WHOLE_FILE};

use crate::modal::{field_modes, Params};
use crate::model::Model;
use crate::report::{check_finite, csv_numbers, to_json, NonFinite, Report};

/// The most model points a fit takes (every mode shape is kept).
/// Each frame's projection costs about N² (modes × observations), so model points stay at most
/// 500 (a quarter of a million operations a frame).
pub const MAX_POINTS: usize = 500;

/// The longest Welch window, in frames.
pub const MAX_WINDOW: usize = 1 << 20;

/// What the columns after time hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum InputKind {
    /// `x₁ y₁ … x_K y_K`: midline points, tail to head.
    Midline,
    /// `ℓ₁ … ℓ_K`: segment lengths around the body.
    Lengths,
}

/// How a mode's frequency is read off its spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Estimator {
    /// The strongest peak (rhythmic behaviour).
    Peak,
    /// The spectral centroid (aperiodic behaviour).
    Centroid,
}

/// How an input is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputFormat {
    /// From the content: `{` opens WCON, DeepLabCut's header rows mark its CSV, else plain.
    Auto,
    /// Plain CSV or white space, one frame per line (DeepLabCut's header rows recognised).
    Csv,
    /// WCON (tracker-commons JSON).
    Wcon,
}

/// Units of the recording's time and length columns, as the file or the user names them.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct Units {
    /// Time unit (ω is in radians per this unit).
    pub time: Option<String>,
    /// Length unit of the coordinates.
    pub length: Option<String>,
}

impl std::fmt::Display for Units {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "time in {}, lengths in {}",
            self.time.as_deref().unwrap_or("the time column's unit"),
            self.length.as_deref().unwrap_or("the coordinates' unit")
        )
    }
}

/// A name from a recording (a track id): printable, at most 64 characters.
pub fn checked_name(text: &str) -> Result<String, String> {
    let ok =
        !text.is_empty() && text.chars().count() <= 64 && text.chars().all(|c| !c.is_control());
    ok.then(|| text.to_string())
        .ok_or_else(|| format!("{text:.40?} is not a track id (1 to 64 printable characters)"))
}

/// A unit name: printable, without quotes, at most 32 characters.
pub fn checked_unit(text: &str) -> Result<String, String> {
    let ok = text.chars().count() <= 32
        && text
            .chars()
            .all(|c| !c.is_control() && !matches!(c, '"' | '\\' | '<' | '>' | '&'));
    ok.then(|| text.to_string())
        .ok_or_else(|| format!("{text:.40?} is not a unit (at most 32 printable characters)"))
}

/// Settings of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSettings {
    /// Input columns.
    pub kind: InputKind,
    /// Field of the model the data observe; `None`: the lateral field for midlines, the axial
    /// one for lengths (by role).
    pub field: Option<String>,
    /// Order of the theory whose operator the data are projected on.
    pub order: u32,
    /// Model points N for midlines (lengths use K + 1).
    pub points: usize,
    /// Welch window W in frames.
    pub window: usize,
    /// Frequency estimator.
    pub estimator: Estimator,
    /// Non-zero modes used to fit ω and β.
    pub fit_modes: usize,
    /// Fix ω instead of fitting it.
    pub omega: Option<f64>,
    /// Lengths only: the segments around the whole body when only the first K were measured
    /// (the paper's seven abdominal segments); `None` when the K segments close the ring.
    pub ring: Option<usize>,
    /// Gaps of at most this many lost frames are bridged linearly; longer ones split the runs.
    pub fill_gaps: usize,
    /// The data list the head first (most trackers); the model's head is its last point.
    pub head_first: bool,
    /// Frames per second of a DeepLabCut file (its rows carry frame indices, not time).
    pub fps: Option<f64>,
    /// DeepLabCut points tracked below this likelihood count as lost.
    pub min_likelihood: f64,
    /// Layout of the inputs.
    pub format: InputFormat,
    /// The first column of a CSV is a track id: each track is one animal.
    pub track_column: bool,
    /// Bootstrap replicates for 95 % intervals (0: none).
    pub bootstrap: usize,
    /// Seed of the bootstrap draws.
    pub seed: u64,
    /// Time unit of the recordings (overrides a WCON file's).
    pub time_unit: Option<String>,
    /// Length unit of the recordings (overrides a WCON file's).
    pub length_unit: Option<String>,
}

impl FitSettings {
    /// Defaults for `kind`: the lateral field on 12 points (midline) or the axial one (lengths),
    /// order 4, W = 256, the first four modes, the peak estimator.
    pub fn new(kind: InputKind) -> Self {
        FitSettings {
            kind,
            field: None,
            order: crate::model::DEFAULT_ORDER,
            points: 12,
            window: 256,
            estimator: Estimator::Peak,
            fit_modes: 4,
            omega: None,
            ring: None,
            fill_gaps: 0,
            head_first: true,
            fps: None,
            min_likelihood: 0.6,
            format: InputFormat::Auto,
            track_column: false,
            bootstrap: 0,
            seed: 1,
            time_unit: None,
            length_unit: None,
        }
    }
}

/// Why a fit cannot be made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FitError {
    /// The input could not be read.
    #[error("cannot read the input: {0}")]
    Io(String),
    /// A line is malformed.
    #[error("line {line}: {why}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
    },
    /// The per-frame sink of [`fit_each`] failed.
    #[error("{0}")]
    Output(String),
    /// A setting or the data as a whole is unusable.
    #[error("{0}")]
    Invalid(String),
    /// An error in one of several inputs or animals.
    #[error("{name}: {why}")]
    In {
        /// The input or animal.
        name: String,
        /// What is wrong there.
        why: Box<FitError>,
    },
}

impl FitError {
    /// The error itself, without the input it happened in.
    pub fn innermost(&self) -> &FitError {
        match self {
            FitError::In { why, .. } => why.innermost(),
            other => other,
        }
    }
}

/// How complete a recording was.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Recording {
    /// Recordings (animals) pooled.
    pub recordings: usize,
    /// Rows read (frames, lost or not).
    pub frames_read: usize,
    /// Frames the tracker lost (rows with a missing value, and frames the time steps skip).
    pub frames_lost: usize,
    /// Lost frames bridged linearly (`--fill-gaps`).
    pub frames_filled: usize,
    /// Gaps that split the recording.
    pub gaps: usize,
    /// Runs of consecutive frames between gaps.
    pub runs: usize,
    /// The longest run, in frames.
    pub longest_run: usize,
}

/// One mode's fit.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModeFit {
    /// Mode index (zero modes included).
    pub index: usize,
    /// λᵢ.
    pub eigenvalue: f64,
    /// Variance of Qᵢ.
    pub variance: f64,
    /// Peak frequency (cycles per time unit).
    pub peak_frequency: f64,
    /// Spectral centroid (cycles per time unit).
    pub centroid_frequency: f64,
    /// Measured angular frequency used in the fit, 2π × the chosen estimate.
    pub angular_frequency: f64,
    /// The fitted theory's ω√λᵢ.
    pub theory_angular_frequency: f64,
}

/// The result of a fit. The JSON contract's keys come first.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FitReport {
    /// Frames used (read and usable, plus any bridged).
    pub frames: usize,
    /// Points (midline) or segments (lengths) per frame in the input.
    pub points: usize,
    /// PCA variance shares, descending, over the non-zero modes.
    pub pca_variance_share: Vec<f64>,
    /// Equipartition shares λᵢ⁻¹/Σλⱼ⁻¹, ascending λ.
    pub theory_variance_share: Vec<f64>,
    /// |cos| between principal component i and non-zero mode shape j.
    pub overlap: Vec<Vec<f64>>,
    /// The fitted (or fixed) frequency scale.
    pub omega: f64,
    /// The fitted inverse temperature, lengths in units of the spacing.
    pub beta: f64,
    /// Input kind.
    pub kind: InputKind,
    /// Observed field.
    pub field: String,
    /// The observed field's scale suffix (its `omega_<scale>` parameter).
    pub scale: String,
    /// Model points N.
    pub model_points: usize,
    /// Sampling interval.
    pub sample_interval: f64,
    /// Welch window used (frames) and segments averaged.
    pub welch: (usize, usize),
    /// For principal component k: the length of its projection onto the eigenspace of mode k
    /// (the whole degenerate pair when λₖ is shared, so a rotated cos/sin pair still scores 1).
    pub mode_overlap: Vec<f64>,
    /// Variance shares of the PCA of the plain angles (or strains).
    pub angle_pca_variance_share: Vec<f64>,
    /// Per non-zero mode.
    pub modes: Vec<ModeFit>,
    /// Modes used for ω and β.
    pub fitted_modes: usize,
    /// Frequencies of the spectra (cycles per time unit).
    #[serde(skip)]
    pub frequencies: Vec<f64>,
    /// Welch PSD of each non-zero modal coordinate.
    #[serde(skip)]
    pub psd: Vec<Vec<f64>>,
    /// Principal components as columns over the mode shapes: `components[i][j]` = component of
    /// PC i along mode j.
    #[serde(skip)]
    pub components: Vec<Vec<f64>>,
    /// The non-zero mode shapes on the model's points, `shapes[j][p]`.
    #[serde(skip)]
    pub shapes: Vec<Vec<f64>>,
    /// What the recording held: frames read, lost, bridged; gaps and runs.
    pub recording: Recording,
    /// Cautions about what the numbers can mean for this input.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// With several animals: each one's own fit, beside the pooled one above.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub animals: Vec<AnimalFit>,
    /// Units of the recording's columns.
    pub units: Units,
    /// The mean model point spacing h = (body length)/(N − 1) (midlines) or rest segment
    /// length (lengths), in the coordinates' unit: modal amplitudes are in units of h.
    pub spacing: f64,
    /// The first k principal components against the first k modes, k = 1, 2, ….
    pub subspace: Vec<Subspace>,
    /// 95 % bootstrap intervals (`--bootstrap`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals: Option<Intervals>,
    /// The arguments that make `simulate` use the fitted scales (see [`FitReport::onward`]).
    pub onward: Vec<String>,
}

/// The first k principal components against the first k theory modes.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Subspace {
    /// k.
    pub k: usize,
    /// The smallest cosine of the principal angles between the two k-dimensional subspaces
    /// (1: the same subspace).
    pub cosine: f64,
    /// Variance share the first k theory modes capture.
    pub modes_capture: f64,
    /// Variance share the first k principal components capture (the most any k directions can).
    pub components_capture: f64,
}

/// One animal's own fit, in a pooled fit of several.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AnimalFit {
    /// The animal's name (file, and track id within it).
    pub recording: String,
    /// Frames used.
    pub frames: usize,
    /// Frames lost.
    pub frames_lost: usize,
    /// Its ω (`None` when it cannot be fitted alone).
    pub omega: Option<f64>,
    /// Its β.
    pub beta: Option<f64>,
    /// Its first principal component's variance share.
    pub first_share: Option<f64>,
    /// Its PCA variance shares, descending.
    pub pca_variance_share: Vec<f64>,
    /// Its components' overlaps with their modes.
    pub mode_overlap: Vec<f64>,
    /// Why it could not be fitted alone (it still counts in the pool).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

impl AnimalFit {
    /// The summary of `report`, the fit of animal `name` alone.
    pub fn of(name: &str, counts: &Recording, report: &FitReport) -> AnimalFit {
        AnimalFit {
            recording: name.to_string(),
            frames: report.frames,
            frames_lost: counts.frames_lost,
            omega: Some(report.omega),
            beta: Some(report.beta),
            first_share: report.pca_variance_share.first().copied(),
            pca_variance_share: report.pca_variance_share.clone(),
            mode_overlap: report.mode_overlap.clone(),
            note: None,
        }
    }

    fn failed(animal: &pool::Animal, why: &str) -> AnimalFit {
        AnimalFit {
            recording: animal.name.clone(),
            frames: animal.stats.count as usize,
            frames_lost: animal.counts.frames_lost,
            omega: None,
            beta: None,
            first_share: None,
            pca_variance_share: Vec::new(),
            mode_overlap: Vec::new(),
            note: Some(why.to_string()),
        }
    }
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

/// Resample a polyline to `n` points equally spaced in arc length.
fn resample(points: &[(f64, f64)], n: usize) -> Result<Vec<(f64, f64)>, String> {
    let mut cum = vec![0.0];
    for w in points.windows(2) {
        let d = ((w[1].0 - w[0].0).powi(2) + (w[1].1 - w[0].1).powi(2)).sqrt();
        cum.push(cum.last().unwrap_or(&0.0) + d);
    }
    let total = *cum.last().unwrap_or(&0.0);
    if total <= 0.0 {
        return Err("the midline has zero length".into());
    }
    let mut out = Vec::with_capacity(n);
    let mut seg = 0;
    for i in 0..n {
        let s = total * i as f64 / (n - 1) as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let len = cum[seg + 1] - cum[seg];
        let u = if len > 0.0 {
            ((s - cum[seg]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (points[seg], points[seg + 1]);
        out.push((a.0 + u * (b.0 - a.0), a.1 + u * (b.1 - a.1)));
    }
    Ok(out)
}

/// Turning angles between consecutive segments of a polyline (radians, in (−π, π]).
pub fn turning_angles(points: &[(f64, f64)]) -> Result<Vec<f64>, String> {
    let seg: Vec<(f64, f64)> = points
        .windows(2)
        .map(|w| (w[1].0 - w[0].0, w[1].1 - w[0].1))
        .collect();
    if seg.iter().any(|s| s.0 == 0.0 && s.1 == 0.0) {
        return Err("two consecutive midline points coincide".into());
    }
    Ok(seg
        .windows(2)
        .map(|w| {
            let cross = w[0].0 * w[1].1 - w[0].1 * w[1].0;
            let dot = w[0].0 * w[1].0 + w[0].1 * w[1].1;
            cross.atan2(dot)
        })
        .collect())
}

/// The observation o of one frame: turning angles (midline) or strains (lengths).
fn observe(
    kind: InputKind,
    values: &[f64],
    n: usize,
    reference: Option<f64>,
) -> Result<Vec<f64>, String> {
    match kind {
        InputKind::Midline => {
            let pts: Vec<(f64, f64)> = values.chunks(2).map(|c| (c[0], c[1])).collect();
            let pts = if pts.len() == n {
                pts
            } else {
                resample(&pts, n)?
            };
            turning_angles(&pts)
        }
        InputKind::Lengths => {
            if values.iter().any(|&l| l <= 0.0) {
                return Err("segment lengths must be positive".into());
            }
            let h = reference.unwrap_or_else(|| values.iter().sum::<f64>() / values.len() as f64);
            Ok(values.iter().map(|l| l / h - 1.0).collect())
        }
    }
}

/// The map from one frame's values to the modal coordinates of the observed field's non-zero
/// modes: Qⱼ = (S vⱼ)·o/λⱼ (see the module header).
#[derive(Debug, Clone)]
pub struct Projector {
    /// Input kind.
    pub kind: InputKind,
    /// Points (midline) or segments (lengths) per input frame.
    pub input_points: usize,
    /// Model points N.
    pub points: usize,
    /// The observed field's id.
    pub field: String,
    /// The observed field's scale suffix.
    pub scale: String,
    /// Index of the first non-zero mode.
    pub first_mode: usize,
    /// λⱼ of the non-zero modes.
    pub eigenvalues: Vec<f64>,
    /// The row of the least-squares solve for each fitted mode, over the observations:
    /// (S vⱼ)/λⱼ when the observations cover the body.
    pub rows: Vec<Vec<f64>>,
    /// (S vⱼ) over the observations, for each fitted mode.
    pub design: Vec<Vec<f64>>,
    /// The non-zero mode shapes on the model's points.
    pub shapes: Vec<Vec<f64>>,
    /// Lengths: the rest length strains are measured against (`fit` takes the first frame's
    /// mean). `None` divides each frame by its own mean, which is exact on a closed ring but
    /// hides the total stretch of a free chain.
    pub reference_length: Option<f64>,
}

impl Projector {
    /// The projector for frames of `width` values after time.
    pub fn new(
        model: &Model,
        params: &Params,
        settings: &FitSettings,
        width: usize,
    ) -> Result<Projector, FitError> {
        let invalid = |s: String| FitError::Invalid(s);
        let (k_in, n) = dimensions(settings, width)?;
        let field_index = observed_field(model, settings)?;
        // Only the observed field's modes: another field's limits must not refuse this fit.
        let all = field_modes(
            &model.only(field_index),
            settings.order,
            n,
            params,
            None,
            true,
        )
        .map_err(|e| invalid(e.to_string()))?;
        let fm = &all[0];
        let shapes = fm
            .spectrum
            .shapes
            .as_ref()
            .ok_or_else(|| invalid("no mode shapes".into()))?;
        let rows = crate::discretise::stencil_rows(fm.k, fm.field.boundary, n)
            .map_err(|e| invalid(e.to_string()))?;
        let expected = match settings.kind {
            InputKind::Midline => n - 2,
            InputKind::Lengths => n - 1,
        };
        if rows.len() != expected {
            return Err(invalid(format!(
            "field {} ({:?}, k = {}) has {} difference rows on {n} points, but the {} give {expected} observations",
            fm.field.id,
            fm.field.boundary,
            fm.k,
            rows.len(),
            match settings.kind {
                InputKind::Midline => "turning angles",
                InputKind::Lengths => "segment strains",
            }
        )));
        }
        let first_mode = fm.spectrum.nullity;
        // Stencil rows index the unknowns; shapes are on the body, after the held tail points.
        let held = fm.spectrum.held.0;
        let size = shapes.nrows();
        let m = fm.spectrum.size - first_mode;
        if m == 0 {
            return Err(invalid("the field has no non-zero modes".into()));
        }
        let all_lambdas: Vec<f64> = fm.spectrum.eigenvalues[first_mode..].to_vec();
        // The observed rows of S: all of them, or the first K segments of a longer ring.
        let observed = match settings.kind {
            InputKind::Midline => rows.len(),
            InputKind::Lengths => k_in,
        };
        let partial = observed < rows.len();
        // A partial ring fits at most K − 1 modes (the constant takes one more unknown), never
        // half of a degenerate pair.
        let mut fitted = m;
        if partial {
            fitted = m.min(observed - 1);
            let same = |i: usize, j: usize| {
                (all_lambdas[i] - all_lambdas[j]).abs() <= 1e-9 * all_lambdas[i]
            };
            if fitted < m && fitted > 0 && same(fitted - 1, fitted) {
                fitted -= 1;
            }
            if fitted == 0 {
                return Err(invalid(format!(
                    "{observed} measured segments of a ring of {} resolve no whole mode",
                    rows.len()
                )));
            }
        }
        let lambdas: Vec<f64> = all_lambdas[..fitted].to_vec();
        // design[j][i] = (S vⱼ)ᵢ over the observed rows.
        let design: Vec<Vec<f64>> = (0..fitted)
            .map(|j| {
                rows[..observed]
                    .iter()
                    .map(|r| {
                        r.iter()
                            .map(|&(i, w)| w as f64 * shapes[(i + held, first_mode + j)])
                            .sum::<f64>()
                    })
                    .collect()
            })
            .collect();
        let projector: Vec<Vec<f64>> = if partial {
            least_squares_rows(&design)?
        } else {
            // The S vⱼ are orthogonal with |S vⱼ|² = λⱼ: Qⱼ = (S vⱼ)·o/λⱼ.
            design
                .iter()
                .zip(&lambdas)
                .map(|(d, l)| d.iter().map(|x| x / l).collect())
                .collect()
        };
        Ok(Projector {
            kind: settings.kind,
            input_points: k_in,
            points: n,
            field: fm.field.id.clone(),
            scale: fm.field.scale().to_string(),
            first_mode,
            rows: projector,
            design,
            shapes: (0..fitted)
                .map(|j| (0..size).map(|p| shapes[(p, first_mode + j)]).collect())
                .collect(),
            eigenvalues: lambdas,
            reference_length: None,
        })
    }

    /// The modal coordinates of one frame's values.
    pub fn modal(&self, values: &[f64]) -> Result<Vec<f64>, String> {
        let o = observe(self.kind, values, self.points, self.reference_length)?;
        Ok(self
            .rows
            .iter()
            .map(|p| p.iter().zip(&o).map(|(a, b)| a * b).sum())
            .collect())
    }

    /// The model point spacing of one frame in the data's length unit: arc length over N − 1
    /// (midlines), the rest segment length (lengths).
    pub fn spacing(&self, values: &[f64]) -> f64 {
        match self.kind {
            InputKind::Midline => {
                let length: f64 = values
                    .chunks(2)
                    .collect::<Vec<_>>()
                    .windows(2)
                    .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                    .sum();
                length / (self.points - 1) as f64
            }
            InputKind::Lengths => self
                .reference_length
                .unwrap_or_else(|| values.iter().sum::<f64>() / values.len() as f64),
        }
    }
}

/// Values per frame → (measured points or segments K, model points N), checked.
fn dimensions(settings: &FitSettings, width: usize) -> Result<(usize, usize), FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    let line = |why: String| FitError::Line { line: 0, why };
    let (k_in, n) = match settings.kind {
        InputKind::Midline => {
            if width % 2 != 0 {
                return Err(line(format!(
                    "a midline frame is t then x y pairs: {width} values after t is odd"
                )));
            }
            if settings.points < 3 {
                return Err(invalid(format!(
                    "a midline needs at least 3 model points for one turning angle, not {}",
                    settings.points
                )));
            }
            (width / 2, settings.points)
        }
        InputKind::Lengths => {
            let ring = settings.ring.unwrap_or(width);
            if ring < width {
                return Err(invalid(format!(
                    "the ring of {ring} segments cannot hold the {width} measured ones"
                )));
            }
            (width, ring.saturating_add(1))
        }
    };
    if n > MAX_POINTS {
        return Err(invalid(format!(
            "{k_in} segments make a ring of {n} points; at most {MAX_POINTS}"
        )));
    }
    let min_k = if settings.kind == InputKind::Midline {
        5
    } else {
        3
    };
    if k_in < min_k {
        return Err(line(format!(
            "{k_in} points per frame; at least {min_k} are needed"
        )));
    }
    Ok((k_in, n))
}

/// The model field the data observe: `--field`, or the role the input kind implies.
fn observed_field(model: &Model, settings: &FitSettings) -> Result<usize, FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    Ok(match &settings.field {
        Some(id) => model
            .fields
            .iter()
            .position(|f| &f.id == id)
            .ok_or_else(|| invalid(format!("the model has no field {id:?}")))?,
        None => {
            let behaviour = match settings.kind {
                InputKind::Midline => "fit (midlines)",
                InputKind::Lengths => "fit (lengths)",
            };
            crate::behaviour::role_fields(model, behaviour).map_err(|e| invalid(e.to_string()))?[0]
        }
    })
}

/// The rows of (BᵀB)⁻¹Bᵀ for B = [design | 1], the constant absorbing the unknown mean strain of
/// a partial ring; the constant's own row is dropped.
fn least_squares_rows(design: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, FitError> {
    let (m, k) = (design.len(), design[0].len());
    let b = nalgebra::DMatrix::from_fn(k, m + 1, |i, j| if j < m { design[j][i] } else { 1.0 });
    let normal = b.transpose() * &b;
    let chol = nalgebra::Cholesky::new(normal).ok_or_else(|| {
        FitError::Invalid("the measured segments do not separate the fitted modes".into())
    })?;
    let solved = chol.solve(&b.transpose());
    Ok((0..m)
        .map(|j| solved.row(j).iter().cloned().collect())
        .collect())
}

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
    mut each: impl FnMut(&Projector, f64, &[f64]) -> Result<(), String>,
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

/// The settings' limits, checked before any data are read.
fn check_settings(settings: &FitSettings) -> Result<(), FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    if let Some(f) = settings.fps {
        if !(f.is_finite() && f > 0.0) {
            return Err(invalid(format!("--fps must be a positive number, not {f}")));
        }
    }
    if !(0.0..=1.0).contains(&settings.min_likelihood) {
        return Err(invalid(format!(
            "--min-likelihood must be between 0 and 1, not {}",
            settings.min_likelihood
        )));
    }
    if settings.points > MAX_POINTS {
        return Err(invalid(format!(
            "at most {MAX_POINTS} model points, not {}",
            settings.points
        )));
    }
    if settings.window > MAX_WINDOW {
        return Err(invalid(format!(
            "the Welch window can be at most {MAX_WINDOW} frames, not {}",
            settings.window
        )));
    }
    if settings.window < 8 {
        return Err(invalid(format!(
            "the Welch window must be at least 8 frames, not {}",
            settings.window
        )));
    }
    if settings.fit_modes == 0 {
        return Err(invalid("fit at least one mode".into()));
    }
    if let Some(w) = settings.omega {
        if !(w.is_finite() && w > 0.0) {
            return Err(invalid(format!("ω must be a positive number, not {w}")));
        }
    }
    Ok(())
}

/// PCA, overlaps, shares, frequencies and the ω and β fits from the accumulated moments.
fn summarise(
    proj: &Projector,
    settings: &FitSettings,
    cov: Vec<Vec<f64>>,
    interval: f64,
    spectra: stats::Spectra,
) -> Result<FitReport, FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    let stats::Spectra {
        window: used_window,
        segments,
        frequencies,
        psd,
    } = spectra;
    let lambdas = &proj.eigenvalues;
    let (m, first_mode) = (lambdas.len(), proj.first_mode);

    // PCA in the body metric: eigen of cov(Q), descending.
    let (pca_share, components) = descending_eigen(&cov);
    let (angle_share, _) = descending_eigen(&angle_covariance(&proj.design, &cov));
    let inv: f64 = lambdas.iter().map(|l| 1.0 / l).sum();
    let theory_share: Vec<f64> = lambdas.iter().map(|l| 1.0 / l / inv).collect();
    let overlap: Vec<Vec<f64>> = components
        .iter()
        .map(|c| c.iter().map(|x| x.abs()).collect())
        .collect();
    let mode_overlap = pair_overlaps(lambdas, &components);
    let subspace = subspaces(&cov, &pca_share, &components);
    let mut modes: Vec<ModeFit> = (0..m)
        .map(|j| {
            let (peak, centroid) = spectral_peak_and_centroid(&frequencies, &psd[j]);
            let f = match settings.estimator {
                Estimator::Peak => peak,
                Estimator::Centroid => centroid,
            };
            ModeFit {
                index: first_mode + j,
                eigenvalue: lambdas[j],
                variance: cov[j][j],
                peak_frequency: peak,
                centroid_frequency: centroid,
                angular_frequency: 2.0 * std::f64::consts::PI * f,
                theory_angular_frequency: 0.0,
            }
        })
        .collect();
    let used = settings.fit_modes.min(m);
    let fitted = &modes[..used];
    let omega = settings.omega.unwrap_or_else(|| {
        fitted
            .iter()
            .map(|x| x.angular_frequency * x.eigenvalue.sqrt())
            .sum::<f64>()
            / fitted.iter().map(|x| x.eigenvalue).sum::<f64>()
    });
    if !(omega.is_finite() && omega > 0.0) {
        return Err(invalid(
            "no frequency could be measured (flat spectra): give --omega".into(),
        ));
    }
    let spread: f64 = fitted
        .iter()
        .map(|x| omega * omega * x.eigenvalue * x.variance)
        .sum();
    if spread <= 0.0 {
        return Err(invalid(
            "the postures do not vary: no temperature can be fitted".into(),
        ));
    }
    let beta = used as f64 / spread;
    for x in &mut modes {
        x.theory_angular_frequency = omega * x.eigenvalue.sqrt();
    }
    Ok(FitReport {
        frames: 0,
        recording: Recording::default(),
        warnings: Vec::new(),
        animals: Vec::new(),
        units: Units::default(),
        spacing: 0.0,
        subspace,
        intervals: None,
        onward: Vec::new(),
        points: proj.input_points,
        pca_variance_share: pca_share,
        theory_variance_share: theory_share,
        overlap,
        omega,
        beta,
        kind: settings.kind,
        field: proj.field.clone(),
        scale: proj.scale.clone(),
        model_points: proj.points,
        sample_interval: interval,
        welch: (used_window, segments),
        mode_overlap,
        angle_pca_variance_share: angle_share,
        modes,
        fitted_modes: used,
        frequencies,
        psd,
        components,
        shapes: proj.shapes.clone(),
    })
}

/// Plain angle-space covariance (S V) cov(Q) (S V)ᵀ over the observations, `design[i]` = S vᵢ.
fn angle_covariance(design: &[Vec<f64>], cov: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let m = design.len();
    let obs = design[0].len();
    (0..obs)
        .map(|a| {
            (0..obs)
                .map(|b| {
                    let mut s = 0.0;
                    for i in 0..m {
                        for j in 0..m {
                            s += design[i][a] * cov[i][j] * design[j][b];
                        }
                    }
                    s
                })
                .collect()
        })
        .collect()
}

/// The first k principal components against the first k modes, for k up to 6: the smallest
/// singular value of the k × k block of components over modes is the cosine of the largest
/// principal angle; the captured variances are the modes' variances and the components'
/// shares, summed.
fn subspaces(cov: &[Vec<f64>], pca_share: &[f64], components: &[Vec<f64>]) -> Vec<Subspace> {
    let m = cov.len();
    let trace: f64 = (0..m).map(|j| cov[j][j]).sum();
    (1..=m.min(6))
        .map(|k| {
            let block = nalgebra::DMatrix::from_fn(k, k, |i, j| components[i][j]);
            let cosine = block
                .singular_values()
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .clamp(0.0, 1.0);
            let modes: f64 = (0..k).map(|j| cov[j][j]).sum();
            Subspace {
                k,
                cosine,
                modes_capture: if trace > 0.0 { modes / trace } else { 0.0 },
                components_capture: pca_share[..k].iter().sum(),
            }
        })
        .collect()
}

/// Each principal component's overlap with its mode, or with the plane of its degenerate pair.
fn pair_overlaps(lambdas: &[f64], components: &[Vec<f64>]) -> Vec<f64> {
    let m = lambdas.len();
    let degenerate = |i: usize, j: usize| (lambdas[i] - lambdas[j]).abs() <= 1e-9 * lambdas[i];
    components
        .iter()
        .enumerate()
        .map(|(k, c)| {
            (0..m)
                .filter(|&j| degenerate(k, j))
                .map(|j| c[j] * c[j])
                .sum::<f64>()
                .sqrt()
        })
        .collect()
}

/// Eigenvalue shares (descending) and eigenvectors (rows, same order) of a symmetric matrix.
fn descending_eigen(a: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let (values, vectors) = crate::behaviour::principal_components(a)
        .unwrap_or_else(|_| (vec![0.0; a.len()], vec![vec![0.0; a.len()]; a.len()]));
    let total: f64 = values.iter().map(|v| v.max(0.0)).sum();
    let shares = values
        .iter()
        .map(|v| if total > 0.0 { v.max(0.0) / total } else { 0.0 })
        .collect();
    (shares, vectors)
}

impl Report for FitReport {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        let r = self;
        Some(csv_numbers(
            &[
                "mode",
                "eigenvalue",
                "pca_share",
                "theory_share",
                "overlap",
                "variance",
                "peak_frequency",
                "centroid_frequency",
                "angular_frequency",
                "theory_angular_frequency",
            ],
            r.modes.iter().enumerate().map(|(k, m)| {
                vec![
                    m.index as f64,
                    m.eigenvalue,
                    r.pca_variance_share[k],
                    r.theory_variance_share[k],
                    r.overlap[k][k],
                    m.variance,
                    m.peak_frequency,
                    m.centroid_frequency,
                    m.angular_frequency,
                    m.theory_angular_frequency,
                ]
            }),
        ))
    }

    fn text(&self) -> String {
        let r = self;
        let what = match r.kind {
            InputKind::Midline => format!("{}-point midlines", r.points),
            InputKind::Lengths => format!("{} segment lengths", r.points),
        };
        let time = r.units.time.as_deref().unwrap_or("time unit");
        let length = r.units.length.as_deref().unwrap_or("length unit");
        let mut t = format!(
            "Fit of {} frames of {what} (sampling interval {} {time}) to field {} on N = {}\n\
             \x20 ω = {:.6} rad/{time} (least squares over modes {}–{}), β = {:.6} {time}² (amplitudes in point spacings h = {:.6} {length}; β/h² = {:.6} {time}²/{length}²)\n",
            r.frames,
            (r.sample_interval * 1e9).round() / 1e9,
            r.field,
            r.model_points,
            r.omega,
            r.modes[0].index,
            r.modes[r.fitted_modes - 1].index,
            r.beta,
            r.spacing,
            r.beta / (r.spacing * r.spacing),
        );
        if let Some(i) = &r.intervals {
            t += &format!(
                "  95 % intervals ({} replicates over {} {}, {} fitted): ω [{:.6}, {:.6}], β [{:.6}, {:.6}]\n",
                i.replicates, i.units, i.resampled, i.fitted, i.omega[0], i.omega[1], i.beta[0], i.beta[1]
            );
        }
        let rec = &r.recording;
        t += &format!(
            "  recording: {} animal(s), {} frames read, {} lost ({} bridged), {} gaps, {} runs, longest {} frames\n",
            rec.recordings, rec.frames_read, rec.frames_lost, rec.frames_filled, rec.gaps, rec.runs, rec.longest_run
        );
        t += &format!(
            "  Welch: window {} frames, {} segments\n  mode        λ   PCA share  equipartition  overlap with mode   peak f  centroid f   measured ω  theory ω√λ\n",
            r.welch.0, r.welch.1
        );
        for (k, m) in r.modes.iter().enumerate() {
            t += &format!(
                "  {:>4} {:>8.5} {:>9.3} % {:>12.3} % {:>18.5} {:>8.5} {:>11.5} {:>12.5} {:>11.5}\n",
                m.index,
                m.eigenvalue,
                100.0 * r.pca_variance_share[k],
                100.0 * r.theory_variance_share[k],
                r.mode_overlap[k],
                m.peak_frequency,
                m.centroid_frequency,
                m.angular_frequency,
                m.theory_angular_frequency,
            );
        }
        t += "  overlap: |cos(PCₖ, vₖ)|, or the projection onto the pair's plane when λₖ is degenerate\n";
        t += &subspace_text(r);
        for w in &r.warnings {
            t += &format!("  warning: {w}\n");
        }
        t += &animals_text(&r.animals);
        let shares: Vec<String> = r
            .angle_pca_variance_share
            .iter()
            .map(|s| format!("{:.1}", 100.0 * s))
            .collect();
        t += &format!(
            "  PCA of the plain angles (%, the paper's eigenmaggots; equipartition makes them equal): {}\n",
            shares.join(" ")
        );
        t += &format!(
            "  onward (times in {time}, lengths in point spacings): theory-search simulate --points {} {}\n",
            r.model_points,
            r.onward.join(" ")
        );
        t
    }
}

impl FitReport {
    /// The per-animal table as CSV (the `csv` crate's writer): animal, frames, lost, ω, β, then
    /// each component's share and overlap; empty cells for an animal not fitted alone.
    pub fn animals_csv(&self) -> String {
        let m = self.modes.len();
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header: Vec<String> = ["animal", "frames", "frames_lost", "omega", "beta", "note"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        header.extend((1..=m).map(|k| format!("pca_share_{k}")));
        header.extend((1..=m).map(|k| format!("overlap_{k}")));
        let opt = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
        let mut rows = vec![header];
        for a in &self.animals {
            let mut row = vec![
                a.recording.clone(),
                a.frames.to_string(),
                a.frames_lost.to_string(),
                opt(a.omega),
                opt(a.beta),
                a.note.clone().unwrap_or_default(),
            ];
            for list in [&a.pca_variance_share, &a.mode_overlap] {
                row.extend((0..m).map(|k| opt(list.get(k).copied())));
            }
            rows.push(row);
        }
        for r in rows {
            // Writing to memory cannot fail.
            w.write_record(&r).ok();
        }
        String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
    }

    /// The arguments that make `simulate` (and, without `--temperature`, `behave` and `modes`)
    /// use the fitted scales: `--param omega_<scale>=ω --temperature 1/β`.
    pub fn onward_arguments(&self) -> Vec<String> {
        vec![
            "--param".into(),
            format!("omega_{}={}", self.scale, self.omega),
            "--temperature".into(),
            format!("{}", 1.0 / self.beta),
        ]
    }
}

/// The subspace agreement lines: first k components against first k modes.
fn subspace_text(r: &FitReport) -> String {
    let row = |f: &dyn Fn(&Subspace) -> String| -> String {
        r.subspace.iter().map(f).collect::<Vec<_>>().join(" ")
    };
    let mut t = format!(
        "  first k = 1…{}: cos of the widest principal angle between components and modes: {}\n",
        r.subspace.len(),
        row(&|s| format!("{:.4}", s.cosine))
    );
    t += &format!(
        "    variance captured by the first k modes: {} %; by the first k components: {} %\n",
        row(&|s| format!("{:.1}", 100.0 * s.modes_capture)),
        row(&|s| format!("{:.1}", 100.0 * s.components_capture))
    );
    if let Some(i) = &r.intervals {
        let span = |v: &[[f64; 2]], scale: f64| -> String {
            v.iter()
                .map(|[a, b]| format!("[{:.3}, {:.3}]", scale * a, scale * b))
                .collect::<Vec<_>>()
                .join(" ")
        };
        t += &format!(
            "    95 %: PCA shares (%) {}\n    95 %: overlaps {}\n    95 %: subspace cosines {}\n",
            span(&i.pca_variance_share, 100.0),
            span(&i.mode_overlap, 1.0),
            span(&i.subspace_cosine, 1.0)
        );
    }
    t
}

/// Each animal's own fit, one line each.
fn animals_text(animals: &[AnimalFit]) -> String {
    if animals.is_empty() {
        return String::new();
    }
    let mut t = format!(
        "  each animal alone ({} pooled above):\n  {:<40} {:>7} {:>6} {:>10} {:>12} {:>9}\n",
        animals.len(),
        "animal",
        "frames",
        "lost",
        "ω",
        "β",
        "PC 1"
    );
    for a in animals {
        match (a.omega, a.beta, a.first_share) {
            (Some(w), Some(b), Some(p)) => {
                t += &format!(
                    "  {:<40} {:>7} {:>6} {:>10.5} {:>12.5} {:>7.2} %\n",
                    a.recording,
                    a.frames,
                    a.frames_lost,
                    w,
                    b,
                    100.0 * p
                )
            }
            _ => {
                t += &format!(
                    "  {:<40} {:>7} {:>6}  not fitted alone: {}\n",
                    a.recording,
                    a.frames,
                    a.frames_lost,
                    a.note.as_deref().unwrap_or("")
                )
            }
        }
    }
    t
}
