//! Why a fit cannot be made: the recording (its own error), the per-frame sink, a setting,
//! a pruned pass.

use crate::recording::RecordingError;

/// Why a fit cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// The recording cannot be read or projected.
    #[error(transparent)]
    Recording(#[from] RecordingError),
    /// The per-frame sink of [`super::fit_each`] failed.
    #[error("{0}")]
    Output(#[source] Box<dyn std::error::Error + Send + Sync>),
    /// Too few frames, or no run long enough, for variances and spectra: a problem of the
    /// recording, as a recording with no frames is (one frame and nine exit alike).
    #[error("{0}")]
    TooShort(String),
    /// A fit setting or the data as a whole is unusable.
    #[error("{0}")]
    Invalid(String),
    /// The window chosen (by the recording, or by a bootstrap resample) is one a pass pruned by
    /// a pilot kept only for the choice (the pilot guessed another); [`super::fit_inputs`] then
    /// reads the file again with every channel at every window, so a caller never sees it.
    #[error("window {window} was chosen, but the pass kept only its lead modes there")]
    Pruned {
        /// The window chosen.
        window: usize,
    },
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
    /// An error reading input `name`, named (unless the input has no name).
    pub(super) fn named(self, name: &str) -> FitError {
        let e = self;
        match e {
            FitError::Recording(
                RecordingError::Io(_)
                | RecordingError::Open(_)
                | RecordingError::Line { .. }
                | RecordingError::NoFrames { .. }
                | RecordingError::Fps { .. },
            ) if !name.is_empty() => FitError::In {
                name: name.to_string(),
                why: Box::new(e),
            },
            other => other,
        }
    }

    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            FitError::Recording(e) => e.failure(),
            FitError::TooShort(_) => Failure::Input,
            FitError::Output(_) => Failure::Output,
            FitError::Invalid(_) | FitError::Pruned { .. } => Failure::Usage,
            FitError::In { why, .. } => why.failure(),
        }
    }

    /// The error itself, without the input it happened in.
    pub fn innermost(&self) -> &FitError {
        match self {
            FitError::In { why, .. } => why.innermost(),
            other => other,
        }
    }

    /// The input does not exist (Python's `FileNotFoundError`).
    pub fn is_missing(&self) -> bool {
        matches!(self.innermost(), FitError::Recording(r) if r.is_missing())
    }
}
