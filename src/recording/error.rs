//! Why a recording cannot be read or projected: the file, a line, a setting, the model.

/// Why a recording cannot be read or projected.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
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
        why: LineWhy,
    },
    /// The input holds no frame, or no usable one (a problem of the file, like a bad line).
    #[error("{}", if *.read == 0 { "the input has no frames".to_string() } else { format!("none of the {read} frames is usable: every one has a missing or non-finite value") })]
    NoFrames {
        /// Frames read.
        read: usize,
    },
    /// `--fps` given for a recording that keeps its own clock: only a DeepLabCut export's rows
    /// hold frame indices, which it turns into time.
    #[error("--fps applies to files without a time column; this file has one: {has}")]
    Fps {
        /// Where the recording's time is.
        has: String,
    },
    /// A setting or the data as a whole is unusable.
    #[error("{0}")]
    Invalid(String),
    /// The observed field's modes or operator could not be computed.
    #[error(transparent)]
    Modes(#[from] crate::modal::ModesError),
    /// The observed field's stencil could not be built.
    #[error(transparent)]
    Discretise(#[from] crate::discretise::DiscretiseError),
    /// The model has no field in the role the recording measures.
    #[error(transparent)]
    Role(#[from] crate::model::RoleError),
    /// An error in one of several paths.
    #[error("{name}: {why}")]
    In {
        /// The path.
        name: String,
        /// What is wrong there.
        why: Box<RecordingError>,
    },
}

impl RecordingError {
    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            RecordingError::Open(_)
            | RecordingError::Io(_)
            | RecordingError::Line { .. }
            | RecordingError::NoFrames { .. } => Failure::Input,
            RecordingError::Invalid(_)
            | RecordingError::Fps { .. }
            | RecordingError::Discretise(_)
            | RecordingError::Role(_) => Failure::Usage,
            RecordingError::Modes(e) => e.failure(),
            RecordingError::In { why, .. } => why.failure(),
        }
    }

    /// The error itself, without the path it happened in.
    pub fn innermost(&self) -> &RecordingError {
        match self {
            RecordingError::In { why, .. } => why.innermost(),
            other => other,
        }
    }

    /// The input does not exist (Python's `FileNotFoundError`).
    pub fn is_missing(&self) -> bool {
        matches!(self.innermost(), RecordingError::Open(io) if io.kind() == std::io::ErrorKind::NotFound)
    }
}

/// What is wrong with a line of a recording: a typed cause where one exists.
#[derive(Debug, thiserror::Error)]
pub enum LineWhy {
    /// A problem stated in words (a layout the reader refuses).
    #[error("{0}")]
    Text(String),
    /// The line's bytes or numbers.
    #[error(transparent)]
    Line(#[from] LineError),
    /// The line's time against the frames before it.
    #[error(transparent)]
    Clock(#[from] super::clock::ClockError),
    /// A DeepLabCut row.
    #[error(transparent)]
    Dlc(#[from] super::read::DlcError),
    /// A frame's values (a midline that cannot be projected).
    #[error(transparent)]
    Frame(#[from] super::FrameError),
    /// A track id.
    #[error(transparent)]
    Name(#[from] super::settings::NameError),
    /// A WCON file that is not JSON.
    #[error("not valid WCON JSON: {0}")]
    Json(#[from] serde_json::Error),
}

impl From<String> for LineWhy {
    fn from(why: String) -> LineWhy {
        LineWhy::Text(why)
    }
}

impl From<&str> for LineWhy {
    fn from(why: &str) -> LineWhy {
        LineWhy::Text(why.to_string())
    }
}

/// Why one line of a recording cannot be read (the line number is the caller's).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    /// Longer than [`super::MAX_LINE_BYTES`].
    #[error(
        "longer than {} bytes: not a recording of midlines",
        super::MAX_LINE_BYTES
    )]
    TooLong,
    /// Not UTF-8.
    #[error("is not UTF-8 text")]
    NotUtf8,
    /// Another width than the first frame's.
    #[error("{count} columns where the first frame had {width}")]
    Width {
        /// Cells on this line.
        count: usize,
        /// Cells of the first frame.
        width: usize,
    },
    /// Another width than the header names.
    #[error("{count} columns where the header (line {header}) names {names}{}", points.map_or(String::new(), |(p, q)| format!(": {p} points where it names {q}")))]
    Header {
        /// Cells on this line.
        count: usize,
        /// Cells the header names.
        names: usize,
        /// The header's line.
        header: usize,
        /// Points on this line and in the header, for midlines.
        points: Option<(usize, usize)>,
    },
    /// A time that is not a finite number.
    #[error("column 1: time {0:?} is not a finite number")]
    Time(String),
    /// A value that is not a number.
    #[error("column {column}: {} is not a number", crate::markup::clip(.text))]
    Cell {
        /// Column (1-based, time included).
        column: usize,
        /// The cell.
        text: String,
    },
}
