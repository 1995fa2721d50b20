//! Rust source generated from the engine's operators by `theory-search emit` (templates under
//! `templates/`). The files here other than this one are never edited by hand; a test
//! regenerates them in memory and fails if they differ.

pub mod forces;
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
    pub boundary: crate::boundary::Boundary,
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

/// What a generated stencil supplies: its weights, how many positions it takes on n unknowns,
/// and where weight j of position p lands (None: outside the body).
#[derive(Clone, Copy)]
pub(crate) struct Stencil {
    /// The k-th difference weights.
    pub weights: &'static [f64],
    /// Number of stencil positions on n unknowns.
    pub positions: fn(usize) -> usize,
    /// Index of weight j at position p on n unknowns.
    pub index: fn(usize, usize, usize) -> Option<usize>,
}

impl Stencil {
    /// `out = D·phi`, D = Σ_p w_pᵀw_p, in O(N·k).
    pub(crate) fn apply(
        &self,
        n: usize,
        phi: &[f64],
        out: &mut [f64],
    ) -> Result<(), OperatorError> {
        if phi.len() != n || out.len() != n {
            return Err(OperatorError::Length {
                expected: n,
                got: phi.len().min(out.len()),
            });
        }
        out.fill(0.0);
        for p in 0..(self.positions)(n) {
            let at = |j: usize| (self.index)(n, p, j);
            let d: f64 = self
                .weights
                .iter()
                .enumerate()
                .filter_map(|(j, w)| at(j).map(|i| w * phi[i]))
                .sum();
            for (j, w) in self.weights.iter().enumerate() {
                if let Some(i) = at(j) {
                    out[i] += w * d;
                }
            }
        }
        Ok(())
    }

    /// Every (i, j, w_a·w_b) product the positions contribute to D.
    fn products(&self, n: usize, mut add: impl FnMut(usize, usize, f64)) {
        for p in 0..(self.positions)(n) {
            for (a, wa) in self.weights.iter().enumerate() {
                for (b, wb) in self.weights.iter().enumerate() {
                    if let (Some(i), Some(j)) = ((self.index)(n, p, a), (self.index)(n, p, b)) {
                        add(i, j, wa * wb);
                    }
                }
            }
        }
    }

    /// The dense matrix D.
    pub(crate) fn dense(&self, n: usize) -> Vec<Vec<f64>> {
        let mut m = vec![vec![0.0; n]; n];
        self.products(n, |i, j, v| m[i][j] += v);
        m
    }

    /// The upper bands of D (non-periodic stencils only).
    pub(crate) fn banded(&self, n: usize) -> Banded {
        let k = self.weights.len() - 1;
        let mut bands: Vec<Vec<f64>> = (0..=k).map(|d| vec![0.0; n.saturating_sub(d)]).collect();
        self.products(n, |i, j, v| {
            if j >= i {
                bands[j - i][i] += v;
            }
        });
        Banded { size: n, bands }
    }
}
