//! The kinds of failure every error of the library falls into. The kind, never the message
//! text, decides the command line's exit code and the Python exception:
//!
//! | kind | exit | Python |
//! |---|---|---|
//! | usage: a bad argument, value, setting or model | 2 | `UsageError` (`ValueError`) |
//! | input: a file that cannot be read or is malformed | 1 | `InputError` (`ValueError`), `MissingFileError` |
//! | numerical: valid input on which a computation failed | 3 | `NumericalError` (`ArithmeticError`) |
//! | output: a result that cannot be written | 1 | `OutputError` (`OSError`) |

/// What kind of failure an error is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// A bad argument, value, setting or model.
    Usage,
    /// A file that cannot be read, or is malformed.
    Input,
    /// Valid input on which a computation failed (no convergence, no equilibrium, overflow).
    Numerical,
    /// A result that cannot be written.
    Output,
}

impl Failure {
    /// The command line's exit code for this kind.
    pub fn exit_code(self) -> u8 {
        match self {
            Failure::Usage => 2,
            Failure::Input | Failure::Output => 1,
            Failure::Numerical => 3,
        }
    }
}
