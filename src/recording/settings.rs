//! What reading a recording is asked to do: input kinds and formats, units, the body's points
//! and field, lost frames, and their limits (checked before any data are read). One value,
//! [`RecordingSettings`], built by one constructor from (name, value) pairs
//! ([`RecordingSettings::set`]) that the command line and Python both call.

use super::RecordingError;
use crate::markup::clip;
use crate::report::number;

/// The highest frame rate `--fps` takes: frames a nanosecond apart. Faster rates make sampling
/// intervals whose frequencies and ω cannot be printed and read back.
pub const MAX_FPS: f64 = 1e9;

/// The most model points a fit takes (every mode shape is kept).
/// Each frame's projection costs about N² (modes × observations), so model points stay at most
/// 500 (a quarter of a million operations a frame).
pub const MAX_POINTS: usize = 500;

/// What the columns after time hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum InputKind {
    /// `x₁ y₁ … x_K y_K`: midline points, tail to head.
    Midline,
    /// `ℓ₁ … ℓ_K`: segment lengths around the body.
    Lengths,
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
    /// HDF5: a SLEAP analysis file or DeepLabCut's `.h5`.
    Hdf5,
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

/// How a recording is read and projected on the body's modes.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordingSettings {
    /// Input columns.
    pub kind: InputKind,
    /// Field of the model the data observe; `None`: the lateral field for midlines, the axial
    /// one for lengths (by role).
    pub field: Option<String>,
    /// Order of the theory whose operator the data are projected on.
    pub order: u32,
    /// Model points N for midlines (lengths use K + 1).
    pub points: usize,
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
    /// Time unit of the recordings (overrides a WCON file's).
    pub time_unit: Option<String>,
    /// Length unit of the recordings (overrides a WCON file's).
    pub length_unit: Option<String>,
}

impl RecordingSettings {
    /// Defaults for `kind`: the lateral field on 12 points (midline) or the axial one
    /// (lengths), order 4, gaps of two frames bridged, head first.
    pub fn new(kind: InputKind) -> Self {
        RecordingSettings {
            kind,
            field: None,
            order: crate::model::DEFAULT_ORDER,
            points: 12,
            ring: None,
            fill_gaps: DEFAULT_FILL_GAPS,
            head_first: true,
            fps: None,
            min_likelihood: 0.6,
            format: InputFormat::Auto,
            track_column: false,
            time_unit: None,
            length_unit: None,
        }
    }

    /// The settings' limits, checked before any data are read.
    pub fn check(&self) -> Result<(), RecordingError> {
        let invalid = |s: String| RecordingError::Invalid(s);
        if let Some(f) = self.fps {
            if !(f.is_finite() && f > 0.0 && f <= MAX_FPS) {
                return Err(invalid(format!(
                    "--fps must be a positive number up to {} (a nanosecond between frames), not {}",
                    number(MAX_FPS),
                    number(f)
                )));
            }
        }
        // Units are written into reports, CSV and figures: both faces' values are checked here.
        for unit in [&self.time_unit, &self.length_unit].into_iter().flatten() {
            checked_unit(unit).map_err(|e| invalid(e.to_string()))?;
        }
        if !(0.0..=1.0).contains(&self.min_likelihood) {
            return Err(invalid(format!(
                "--min-likelihood must be between 0 and 1, not {}",
                self.min_likelihood
            )));
        }
        if self.points > MAX_POINTS {
            return Err(invalid(format!(
                "at most {MAX_POINTS} model points, not {}",
                self.points
            )));
        }
        if self.ring.is_some() && self.kind != InputKind::Lengths {
            return Err(invalid("--ring applies to --kind lengths only".into()));
        }
        Ok(())
    }
}

/// One setting's value as a face gives it: the command line's parsed argument, or a Python
/// keyword argument. The library checks its type and range, so both faces refuse the same
/// values in the same words.
#[derive(Debug, Clone, PartialEq)]
pub enum Setting {
    /// Text (a name, a unit, a choice such as `midline`).
    Text(String),
    /// A whole number (negative ones are refused where a count is meant).
    Int(i128),
    /// A real number.
    Float(f64),
    /// A switch.
    Bool(bool),
}

impl std::fmt::Display for Setting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Setting::Text(t) => write!(f, "{:?}", clip(t)),
            // A whole number of many digits in short form, as every number in a message.
            Setting::Int(i) if i.unsigned_abs() < 1u128 << 64 => write!(f, "{i}"),
            Setting::Int(i) => write!(f, "{}", number(*i as f64)),
            Setting::Float(x) => write!(f, "{}", number(*x)),
            Setting::Bool(b) => write!(f, "{b}"),
        }
    }
}

/// Why a setting's value cannot be used, in the words both faces print.
fn wrong(name: &str, wanted: &str, value: &Setting) -> RecordingError {
    RecordingError::Invalid(format!("{name} must be {wanted}, not {value}"))
}

impl Setting {
    /// A whole number from 0 up to `max`.
    pub fn count(&self, name: &str, max: usize) -> Result<usize, RecordingError> {
        match self {
            Setting::Int(i) if (0..=max as i128).contains(i) => Ok(*i as usize),
            Setting::Int(i) if *i > 0 => Err(RecordingError::Invalid(format!(
                "{name} takes at most {max}, not {self}"
            ))),
            _ if max == usize::MAX => Err(wrong(name, "a whole number, 0 or more", self)),
            _ => Err(wrong(
                name,
                &format!("a whole number from 0 to {max}"),
                self,
            )),
        }
    }

    /// A real number (a whole number is one too); its range is the settings' check's, which
    /// says what the number is for.
    pub fn real(&self, name: &str) -> Result<f64, RecordingError> {
        match self {
            Setting::Float(x) => Ok(*x),
            Setting::Int(i) => Ok(*i as f64),
            _ => Err(wrong(name, "a number", self)),
        }
    }

    /// Text.
    pub fn text(&self, name: &str) -> Result<&str, RecordingError> {
        match self {
            Setting::Text(t) => Ok(t),
            _ => Err(wrong(name, "text", self)),
        }
    }

    /// One of `choices`, by name.
    pub fn choice<T: Copy>(&self, name: &str, choices: &[(&str, T)]) -> Result<T, RecordingError> {
        let names: Vec<String> = choices.iter().map(|(n, _)| format!("{n:?}")).collect();
        let text = self.text(name).ok();
        choices
            .iter()
            .find(|(n, _)| Some(*n) == text)
            .map(|(_, v)| *v)
            .ok_or_else(|| wrong(name, &format!("one of {}", names.join(", ")), self))
    }

    /// A switch.
    pub fn switch(&self, name: &str) -> Result<bool, RecordingError> {
        match self {
            Setting::Bool(b) => Ok(*b),
            _ => Err(wrong(name, "true or false", self)),
        }
    }
}

impl RecordingSettings {
    /// Set the option `name` (as Python's keyword names it; the command line's flag with `-`
    /// for `_`) to `value`, checked. `Ok(false)`: not a recording option (the caller's own,
    /// or unknown).
    pub fn set(&mut self, name: &str, value: &Setting) -> Result<bool, RecordingError> {
        match name {
            "kind" => {
                let kinds = [
                    ("midline", InputKind::Midline),
                    ("lengths", InputKind::Lengths),
                ];
                self.kind = value.choice(name, &kinds)?;
            }
            "field" => self.field = Some(value.text(name)?.to_string()),
            "order" => self.order = value.count(name, u32::MAX as usize)? as u32,
            "points" => self.points = value.count(name, MAX_POINTS)?,
            "ring" => self.ring = Some(value.count(name, MAX_POINTS)?),
            "fill_gaps" => self.fill_gaps = value.count(name, usize::MAX)?,
            "head" => self.head_first = value.choice(name, &[("first", true), ("last", false)])?,
            "fps" => self.fps = Some(value.real(name)?),
            "min_likelihood" => self.min_likelihood = value.real(name)?,
            "input_format" => {
                let formats = [
                    ("auto", InputFormat::Auto),
                    ("csv", InputFormat::Csv),
                    ("wcon", InputFormat::Wcon),
                    ("hdf5", InputFormat::Hdf5),
                ];
                self.format = value.choice(name, &formats)?;
            }
            "track_column" => self.track_column = value.switch(name)?,
            "time_unit" => self.time_unit = Some(value.text(name)?.to_string()),
            "length_unit" => self.length_unit = Some(value.text(name)?.to_string()),
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Apply (name, value) pairs with `set` (a settings value's own setter); a name `set` does
/// not know is `unknown`'s error, its name clipped.
pub fn apply_pairs<'a, E>(
    pairs: impl IntoIterator<Item = (&'a str, Setting)>,
    mut set: impl FnMut(&str, &Setting) -> Result<bool, E>,
    unknown: impl Fn(String) -> E,
) -> Result<(), E> {
    for (name, value) in pairs {
        if !set(name, &value)? {
            return Err(unknown(clip(name)));
        }
    }
    Ok(())
}
