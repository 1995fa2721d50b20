//! What a fit is asked to do: input kinds and formats, units, the settings and their limits
//! (checked before any data are read).

use super::FitError;
use crate::markup::clip;
use crate::report::number;

/// The highest frame rate `--fps` takes: frames a nanosecond apart. Faster rates make sampling
/// intervals whose frequencies and ω cannot be printed and read back.
pub const MAX_FPS: f64 = 1e9;

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

/// Lost frames bridged linearly by default (`--fill-gaps`): single lost frames and pairs, the
/// dropped frames of a tracker, cost a run split otherwise.
pub const DEFAULT_FILL_GAPS: usize = 2;

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

/// A name from a recording or an argument that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NameError {
    /// Not a track id.
    #[error("{} is not a track id (1 to 64 printable characters)", clip(.0))]
    TrackId(String),
    /// Not a unit name.
    #[error("{} is not a unit (at most 32 printable characters)", clip(.0))]
    Unit(String),
}

/// Printable: no control or invisible formatting character.
fn printable(c: char) -> bool {
    !c.is_control() && !crate::model::is_invisible(c)
}

/// A name from a recording (a track id): printable, at most 64 characters.
pub fn checked_name(text: &str) -> Result<String, NameError> {
    let ok = !text.is_empty() && text.chars().count() <= 64 && text.chars().all(printable);
    ok.then(|| text.to_string())
        .ok_or_else(|| NameError::TrackId(text.to_string()))
}

/// A unit name: printable, without quotes, at most 32 characters.
pub fn checked_unit(text: &str) -> Result<String, NameError> {
    let ok = text.chars().count() <= 32
        && text
            .chars()
            .all(|c| printable(c) && !matches!(c, '"' | '\\' | '<' | '>' | '&'));
    ok.then(|| text.to_string())
        .ok_or_else(|| NameError::Unit(text.to_string()))
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
    /// Welch window W in frames; `None` chooses it from the data (see `verdict`).
    pub window: Option<usize>,
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
    /// By default [`DEFAULT_FILL_GAPS`]: 1 % of frames lost at random splits a recording into
    /// runs of about 100 frames, too short for the windows its modes need.
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
            window: None,
            estimator: Estimator::Peak,
            fit_modes: 4,
            omega: None,
            ring: None,
            fill_gaps: DEFAULT_FILL_GAPS,
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

/// The settings' limits, checked before any data are read.
pub(super) fn check_settings(settings: &FitSettings) -> Result<(), FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    if let Some(f) = settings.fps {
        if !(f.is_finite() && f > 0.0 && f <= MAX_FPS) {
            return Err(invalid(format!(
                "--fps must be a positive number up to {} (a nanosecond between frames), not {}",
                number(MAX_FPS),
                number(f)
            )));
        }
    }
    // Units are written into reports, CSV and figures: both faces' values are checked here.
    for unit in [&settings.time_unit, &settings.length_unit]
        .into_iter()
        .flatten()
    {
        checked_unit(unit).map_err(|e| invalid(e.to_string()))?;
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
    match settings.window {
        Some(w) if w > MAX_WINDOW => {
            return Err(invalid(format!(
                "the Welch window can be at most {MAX_WINDOW} frames, not {w}"
            )))
        }
        Some(w) if w < 8 => {
            return Err(invalid(format!(
                "the Welch window must be at least 8 frames, not {w}"
            )))
        }
        _ => {}
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
