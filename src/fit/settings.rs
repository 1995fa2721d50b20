//! What a fit is asked to do beyond reading the recording: the Welch window, the frequency
//! estimator, the modes fitted, ω, the bootstrap; and their limits (checked before any data
//! are read).

use super::FitError;
use crate::recording::{InputKind, RecordingSettings, Setting};

/// The longest Welch window, in frames.
pub const MAX_WINDOW: usize = 1 << 20;

/// How a mode's frequency is read off its spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Estimator {
    /// The strongest peak (rhythmic behaviour).
    Peak,
    /// The spectral centroid (aperiodic behaviour).
    Centroid,
}

impl Estimator {
    /// Its name, as `--estimator` takes it and the report says it.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::Peak => "peak",
            Estimator::Centroid => "centroid",
        }
    }
}

/// Settings of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSettings {
    /// How the recording is read and projected.
    pub recording: RecordingSettings,
    /// Welch window W in frames; `None` chooses it from the data (see `verdict`).
    pub window: Option<usize>,
    /// Frequency estimator.
    pub estimator: Estimator,
    /// Non-zero modes used to fit ω and β.
    pub fit_modes: usize,
    /// Fix ω instead of fitting it.
    pub omega: Option<f64>,
    /// Bootstrap replicates for 95 % intervals (0: none).
    pub bootstrap: usize,
    /// Seed of the bootstrap draws.
    pub seed: u64,
}

impl FitSettings {
    /// Defaults for `kind`: the recording's defaults ([`RecordingSettings::new`]), the window
    /// chosen by the data, the first four modes, the peak estimator.
    pub fn new(kind: InputKind) -> Self {
        FitSettings {
            recording: RecordingSettings::new(kind),
            window: None,
            estimator: Estimator::Peak,
            fit_modes: 4,
            omega: None,
            bootstrap: 0,
            seed: 1,
        }
    }
}

impl FitSettings {
    /// Set the option `name` (Python's keyword; the command line's flag with `_` for `-`) to
    /// `value`, checked; a recording option goes to [`RecordingSettings::set`]. `Ok(false)`:
    /// no such option.
    pub fn set(&mut self, name: &str, value: &Setting) -> Result<bool, FitError> {
        match name {
            "window" => self.window = Some(value.count(name, MAX_WINDOW)?),
            "estimator" => {
                let estimators = [("peak", Estimator::Peak), ("centroid", Estimator::Centroid)];
                self.estimator = value.choice(name, &estimators)?;
            }
            "fit_modes" => self.fit_modes = value.count(name, usize::MAX)?,
            "omega" => self.omega = Some(value.real(name)?),
            "bootstrap" => self.bootstrap = value.count(name, super::MAX_REPLICATES)?,
            "seed" => self.seed = value.count(name, usize::MAX)? as u64,
            _ => return Ok(self.recording.set(name, value)?),
        }
        Ok(true)
    }

    /// The settings from (name, value) pairs, each checked, then the whole: the one
    /// constructor both faces call. A name that is no option is refused.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, Setting)>,
    ) -> Result<FitSettings, FitError> {
        let mut settings = FitSettings::new(InputKind::Midline);
        let unknown = |name| FitError::Invalid(format!("fit has no option {name:?}"));
        crate::recording::apply_pairs(pairs, |n, v| settings.set(n, v), unknown)?;
        check_settings(&settings)?;
        Ok(settings)
    }
}

/// The settings' limits, checked before any data are read.
pub(crate) fn check_settings(settings: &FitSettings) -> Result<(), FitError> {
    settings.recording.check()?;
    let invalid = |s: String| FitError::Invalid(s);
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
    if settings.bootstrap > super::MAX_REPLICATES {
        return Err(invalid(format!(
            "--bootstrap takes at most {} replicates, not {}",
            super::MAX_REPLICATES,
            settings.bootstrap
        )));
    }
    if let Some(w) = settings.omega {
        if !(w.is_finite() && w > 0.0) {
            return Err(invalid(format!("ω must be a positive number, not {w}")));
        }
    }
    Ok(())
}
