//! Modes: the eigen-decomposition `D vᵢ = λᵢ vᵢ` of a field's difference operator.
//!
//! Invariants of a [`Spectrum`]:
//! * eigenvalues ascending; the structural zero modes (the operator's null space: constants for
//!   periodic fields, polynomials of degree < k for free ones, none for clamped) come first and
//!   are exactly 0;
//! * shapes are unit-norm columns, orthogonal; sign convention: the first component of magnitude
//!   above 1e-8·max is positive; a degenerate periodic pair is (cos, sin);
//! * `inverse_trace` is Σ 1/λ over *all* non-zero modes (the trace of the pseudo-inverse), exact
//!   to rounding even when only the lowest K modes are computed.
//!
//! Methods, chosen by structure, each O(N) memory:
//! * periodic, any k: closed form λ_m = (2 − 2cos(2πm/n))ᵏ, n = N − 1, Fourier shapes;
//! * k = 1, free–free: closed form λᵢ = 2 − 2cos(πi/N), shapes cos(πi(j+½)/N) (DCT-II); one or
//!   both ends held: the sine series of the string, λᵢ = 2 − 2cos(π(2i−1)/(2N−1)) (fixed–free)
//!   or 2 − 2cos(πi/(N−1)) (fixed–fixed);
//! * k = 2, free–free (D4): the exact characteristic equation. With λ = s², cos θ = 1 − s/2,
//!   cosh φ = 1 + s/2, symmetric modes satisfy cos(θ(N−1)/2)·cosh(φ(N+1)/2) =
//!   cos(θ(N+1)/2)·cosh(φ(N−1)/2), antisymmetric ones the same with sin and sinh. Roots are
//!   bracketed on a grid finer than their spacing, refined, and the count is checked by
//!   Sylvester inertia; shapes by inverse iteration on the band;
//! * any other ends and k, a few modes of a long body: subspace iteration with P·A⁻¹·P = D⁺,
//!   A = SᵀS + GᵀG applied through the Givens QR factor of the stencil rows (see [`subspace`]),
//!   Ritz values as ‖S v‖² so small eigenvalues keep their relative accuracy;
//! * otherwise faer's dense self-adjoint eigensolver, up to [`MAX_DENSE`] unknowns, with each
//!   eigenvalue refined as the stencil energy ‖S v‖² of its eigenvector.
//!
//! Σ 1/λ comes from the closed forms (periodic and k = 1: sums over the closed-form
//! eigenvalues; D4: the exact polynomial of [`d4_inverse_trace`]), from the exact polynomial in N
//! that [`trace_polynomial`] finds and checks (any ends, k = 1 and 2), from Takahashi's
//! recurrence on the QR factor (other k, accurate only at moderate N), or from the dense
//! spectrum.

use faer::Mat;

mod closed;
mod field;
mod report;
mod subspace;
mod trace;
pub use crate::params::{ParamError, Params, DEFAULT_OMEGA, DEFAULT_ZETA};
pub use closed::{
    beam_beta, continuum_beta, continuum_shape, d4_characteristic, d4_inverse_trace, seed_eq17,
};
pub use field::{field_modes, BeamComparison, FieldModes, Mode, ModesError, OperatorIssue, Regime};
pub use report::ModesReport;
pub use subspace::subspace;
pub use trace::trace_polynomial;

use crate::banded::BandedSym;
use crate::discretise::stencil_rows;
use crate::generated::operators::OPERATORS;
use crate::model::Boundary;
use closed::{d4, free_second_difference, held_second_difference, periodic};
use subspace::general;

/// The largest operator the dense fallback will take (about two seconds on one core: the cost
/// grows as N³, so 3000 took nine).
pub const MAX_DENSE: usize = 2000;

/// The most points the modal solver accepts.
pub const MAX_POINTS: usize = 10_000_000;

/// Why modes cannot be computed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ModalError {
    /// Fewer points than the stencil needs.
    #[error("{points} points are too few for this field's operator: need at least {min}")]
    TooFewPoints {
        /// Points asked for.
        points: usize,
        /// The least that works.
        min: usize,
    },
    /// More points than the method can take.
    #[error("{points} points are too many: {why}")]
    TooManyPoints {
        /// Points asked for.
        points: usize,
        /// Which limit.
        why: String,
    },
    /// The stencil could not be built (boxed: the error is large and rare).
    #[error(transparent)]
    Discretise(Box<crate::discretise::DiscretiseError>),
    /// The generated operator refused the size.
    #[error(transparent)]
    Generated(#[from] crate::generated::OperatorError),
    /// A periodic operator wraps around, so it has no band.
    #[error("a periodic operator is not banded")]
    NotBanded,
    /// The regularised operator is singular.
    #[error("eigensolver failed: the regularised operator is singular")]
    Singular,
    /// An eigensolver's iteration did not converge.
    #[error("eigensolver failed: {0} did not converge")]
    NoConvergence(&'static str),
}

impl From<crate::discretise::DiscretiseError> for ModalError {
    fn from(e: crate::discretise::DiscretiseError) -> ModalError {
        ModalError::Discretise(Box::new(e))
    }
}

impl ModalError {
    /// Whether the solver failed on valid input (a numerical failure) rather than being asked
    /// for something it does not take.
    pub fn is_numerical(&self) -> bool {
        matches!(self, ModalError::Singular | ModalError::NoConvergence(_))
    }
}

/// How a spectrum was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Closed-form eigenvalues and shapes.
    ClosedForm,
    /// Roots of the exact characteristic equation (D4).
    Characteristic,
    /// faer's dense self-adjoint eigensolver.
    Dense,
    /// Subspace iteration on the QR factor of the stencil rows (any non-periodic operator).
    Subspace,
}

impl Method {
    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::ClosedForm => "closed form",
            Method::Characteristic => "characteristic equation",
            Method::Dense => "dense (faer)",
            Method::Subspace => "subspace iteration (banded QR)",
        }
    }
}

/// The lowest modes of one operator.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// The lowest `eigenvalues.len()` eigenvalues, ascending.
    pub eigenvalues: Vec<f64>,
    /// Operator size.
    pub size: usize,
    /// Number of structural zero modes (they come first).
    pub nullity: usize,
    /// Σ 1/λ over all non-zero modes.
    pub inverse_trace: f64,
    /// Unit-norm shapes as columns (body points × count), when asked for. Rows are the body's
    /// points (N − 1 around a ring): the unknowns, with zeros at held points.
    pub shapes: Option<Mat<f64>>,
    /// How it was computed.
    pub method: Method,
    /// Held points at (tail, head): the unknowns are rows `held.0 … held.0 + size − 1`.
    pub held: (usize, usize),
}

impl Spectrum {
    /// Shapes from the unknowns onto the body: zero rows for the held points.
    fn embed(mut self, held: (usize, usize)) -> Spectrum {
        self.held = held;
        if held != (0, 0) {
            self.shapes = self.shapes.map(|m| {
                Mat::from_fn(held.0 + m.nrows() + held.1, m.ncols(), |i, j| {
                    if i < held.0 || i >= held.0 + m.nrows() {
                        0.0
                    } else {
                        m[(i - held.0, j)]
                    }
                })
            });
        }
        self
    }
}

/// An orthonormal basis of the null space on the unknowns of a non-periodic operator:
/// `Π_h (j − h) · jᵐ` over the held points h, m = 0…nullity − 1, in a centred, scaled variable.
pub fn null_basis(k: u32, boundary: Boundary, points: usize) -> Vec<Vec<f64>> {
    let count = boundary.nullity(k);
    let (tail, head) = boundary.held(k);
    let n = boundary.unknowns(k, points);
    let centre = (points as f64 - 1.0) / 2.0;
    let scale = centre.max(1.0);
    let t = |q: usize| (q as f64 - centre) / scale;
    let held: Vec<f64> = (0..tail)
        .chain(points.saturating_sub(head)..points)
        .map(t)
        .collect();
    let mut out: Vec<Vec<f64>> = Vec::new();
    for deg in 0..count {
        let mut v: Vec<f64> = (0..n)
            .map(|u| {
                let x = t(u + tail);
                held.iter().map(|h| x - h).product::<f64>() * x.powi(deg as i32)
            })
            .collect();
        // Twice, so the basis is orthonormal to rounding.
        for _ in 0..2 {
            for u in &out {
                let dot: f64 = u.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(u).for_each(|(x, y)| *x -= dot * y);
            }
        }
        normalise(&mut v);
        out.push(v);
    }
    out
}

/// The operator `Σ_p w_pᵀw_p` in band storage: from the generated code when it has this
/// operator (the larva's), otherwise from the stencil. Periodic operators wrap around and are
/// not banded.
pub fn banded_operator(k: u32, boundary: Boundary, points: usize) -> Result<BandedSym, ModalError> {
    if boundary == Boundary::Periodic {
        return Err(ModalError::NotBanded);
    }
    let generated = OPERATORS
        .iter()
        .find(|o| o.k == k && o.boundary == boundary)
        .and_then(|o| o.banded);
    if let Some(build) = generated {
        let b = build(points).map_err(|_| ModalError::TooFewPoints {
            points,
            min: boundary.min_points(k),
        })?;
        return Ok(BandedSym {
            n: b.size,
            bands: b.bands,
        });
    }
    let rows = stencil_rows(k, boundary, points).map_err(|_| ModalError::TooFewPoints {
        points,
        min: boundary.min_points(k),
    })?;
    let n = boundary.unknowns(k, points);
    let p = k as usize;
    let mut bands: Vec<Vec<f64>> = (0..=p).map(|d| vec![0.0; n.saturating_sub(d)]).collect();
    for row in rows {
        for &(i, a) in &row {
            for &(j, b) in &row {
                if j >= i && j - i <= p {
                    bands[j - i][i] += (a * b) as f64;
                }
            }
        }
    }
    Ok(BandedSym { n, bands })
}

fn fix_sign(v: &mut [f64]) {
    let max = v.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    if let Some(first) = v.iter().find(|x| x.abs() > 1e-8 * max) {
        if *first < 0.0 {
            v.iter_mut().for_each(|x| *x = -*x);
        }
    }
}

fn normalise(v: &mut [f64]) {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 {
        v.iter_mut().for_each(|x| *x /= norm);
    }
    fix_sign(v);
}

fn columns_to_mat(cols: &[Vec<f64>], n: usize) -> Mat<f64> {
    Mat::from_fn(n, cols.len(), |i, j| cols[j][i])
}

/// The lowest `limit` (all if `None`) modes of the k-th difference operator with `boundary` on
/// `points` points.
pub fn spectrum(
    k: u32,
    boundary: Boundary,
    points: usize,
    limit: Option<usize>,
    shapes: bool,
) -> Result<Spectrum, ModalError> {
    let min = boundary.min_points(k);
    if points < min {
        return Err(ModalError::TooFewPoints { points, min });
    }
    if points > MAX_POINTS {
        return Err(ModalError::TooManyPoints {
            points,
            why: format!("the modal solver takes at most {MAX_POINTS}"),
        });
    }
    let n = boundary.unknowns(k, points);
    let count = limit.unwrap_or(n).min(n);
    let (tail, head) = boundary.held(k);
    let s = match (boundary, k) {
        (Boundary::Periodic, _) => Ok(periodic(k, n, count, shapes)),
        (_, 1) if tail + head == 0 => Ok(free_second_difference(n, count, shapes)),
        (_, 1) => Ok(held_second_difference(points, tail, head, count, shapes)),
        (Boundary::FREE, 2) => match d4(points, count, shapes) {
            Some(s) => Ok(s),
            // The inertia check failed (never seen): fall back to the general method.
            None => general(k, boundary, points, count, shapes),
        },
        _ => general(k, boundary, points, count, shapes),
    }?;
    Ok(s.embed((tail, head)))
}

/// Pairs (i, j) of consecutive eigenvalues equal to `tol` relative.
pub fn degenerate_pairs(eigenvalues: &[f64], nullity: usize, tol: f64) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    let mut i = nullity;
    while i + 1 < eigenvalues.len() {
        let (a, b) = (eigenvalues[i], eigenvalues[i + 1]);
        if (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-300) {
            pairs.push((i, i + 1));
            i += 2;
        } else {
            i += 1;
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beam_roots_are_the_textbook_ones() {
        for (i, want) in [(1, 4.730040745), (2, 7.853204624), (3, 10.995607838)] {
            assert!((beam_beta(i) - want).abs() < 1e-8, "{i}");
        }
    }

    #[test]
    fn degenerate_pairs_skip_zero_modes() {
        assert_eq!(
            degenerate_pairs(&[0.0, 1.0, 1.0, 3.0, 3.0, 4.0], 1, 1e-10),
            [(1, 2), (3, 4)]
        );
    }
}
