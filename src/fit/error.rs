//! Why a fit cannot be made.

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
