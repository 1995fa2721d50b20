//! Why a fit cannot be made.

/// Why a fit cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// The input could not be opened.
    #[error("cannot read the input: cannot open it ({0})")]
    Open(#[source] std::io::Error),
    /// The input could not be read.
    #[error("cannot read the input: {0}")]
    Io(#[source] std::io::Error),
    /// A line is malformed.
    #[error("line {line}: {why}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
    },
    /// The per-frame sink of [`super::fit_each`] failed.
    #[error("{0}")]
    Output(#[source] Box<dyn std::error::Error + Send + Sync>),
    /// The input holds no frame, or no usable one (a problem of the file, like a bad line).
    #[error("{}", if *.read == 0 { "the input has no frames".to_string() } else { format!("none of the {read} frames is usable: every one has a missing or non-finite value") })]
    NoFrames {
        /// Frames read.
        read: usize,
    },
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
