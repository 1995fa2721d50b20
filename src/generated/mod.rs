//! Rust source generated from the engine's operators by `theory-search emit` (templates under
//! `templates/`). The files here other than this one are never edited by hand; a test
//! regenerates them in memory and fails if they differ.

pub mod operators;

/// Why a generated operator cannot be applied or built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OperatorError {
    /// Fewer points than the stencil needs.
    #[error("{points} points are too few for this operator: need at least {min}")]
    TooFewPoints {
        /// Points asked for.
        points: usize,
        /// The least that works.
        min: usize,
    },
    /// A vector of the wrong length.
    #[error("vector length {got} does not match the operator size {expected}")]
    Length {
        /// The operator size.
        expected: usize,
        /// The shorter of the lengths given.
        got: usize,
    },
}

/// A symmetric banded matrix by its upper bands: `bands[d][i] = A[i][i + d]`, `d = 0…k`.
#[derive(Debug, Clone, PartialEq)]
pub struct Banded {
    /// Matrix size.
    pub size: usize,
    /// Diagonal (d = 0) and the k upper bands.
    pub bands: Vec<Vec<f64>>,
}

/// `apply(points, phi, out)`: `out = D·phi`.
pub type ApplyFn = fn(usize, &[f64], &mut [f64]) -> Result<(), OperatorError>;

/// A generated operator with its functions.
#[derive(Debug, Clone, Copy)]
pub struct GeneratedOperator {
    /// Field id.
    pub field: &'static str,
    /// `lagrangian` or `rayleigh`.
    pub density: &'static str,
    /// The surviving term it comes from.
    pub term: &'static str,
    /// Boundary condition.
    pub boundary: &'static str,
    /// Stencil order.
    pub k: u32,
    /// Number of unknowns on N points.
    pub size: fn(usize) -> Result<usize, OperatorError>,
    /// `out = D·phi` in O(N).
    pub apply: ApplyFn,
    /// The dense matrix.
    pub dense: fn(usize) -> Result<Vec<Vec<f64>>, OperatorError>,
    /// The upper bands (not for periodic operators, whose corners wrap).
    pub banded: Option<fn(usize) -> Result<Banded, OperatorError>>,
}
