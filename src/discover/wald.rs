//! The Wald distances of the joint likelihood's estimate from the library's subsets.
//!
//! Every subset S of the library is scored by the Wald distance of the whole
//! library's estimate from the subspace cₘ = 0 (m ∉ S), J(S) = ĉ_Eᵀ (V_EE)⁻¹ ĉ_E, V = I⁻¹ and
//! E the terms left out: the likelihood ratio's quadratic form, χ² on |E| degrees of freedom
//! when the left-out terms are absent. Backward elimination by J(S) + |S| ln n, as the diagonal
//! estimator's. The selected set is then refitted by the exact likelihood. Draws: the one-step
//! bootstrap of the diagonal estimator, on each unit's (block's or animal's) score and OPG.

use nalgebra::{DMatrix, DVector};

use super::exact::Quadratic;

/// The Wald distances of an estimate (the coefficients first, then nuisance parameters) from
/// the library's subsets.
pub(super) struct Wald {
    /// The estimate of every free parameter.
    pub theta: DVector<f64>,
    /// Its covariance.
    pub covariance: DMatrix<f64>,
    /// The library index of each coefficient (positions 0 … k − 1 of θ).
    pub index: Vec<usize>,
}

impl Wald {
    /// From an estimate and its information; `None` when the information is singular.
    pub fn new(theta: DVector<f64>, information: DMatrix<f64>, index: Vec<usize>) -> Option<Wald> {
        Some(Wald {
            theta,
            covariance: information.cholesky()?.inverse(),
            index,
        })
    }
}

impl Quadratic for Wald {
    fn fit(&self, set: &[usize]) -> Option<(Vec<f64>, DMatrix<f64>, f64)> {
        let kept: Vec<usize> = (0..self.index.len())
            .filter(|&p| set.contains(&self.index[p]))
            .collect();
        let out: Vec<usize> = (0..self.index.len())
            .filter(|p| !kept.contains(p))
            .collect();
        let v = &self.covariance;
        let ee = v.select_rows(&out).select_columns(&out);
        let (shift, j, correction) = if out.is_empty() {
            (
                DVector::zeros(kept.len()),
                0.0,
                DMatrix::zeros(kept.len(), kept.len()),
            )
        } else {
            let inv = ee.cholesky()?.inverse();
            let e = DVector::from_iterator(out.len(), out.iter().map(|&p| self.theta[p]));
            let fe = v.select_rows(&kept).select_columns(&out);
            let w = &inv * &e;
            (&fe * &w, e.dot(&w), &fe * &inv * fe.transpose())
        };
        let beta: Vec<f64> = (kept.iter().zip(shift.iter()))
            .map(|(&p, s)| self.theta[p] - s)
            .collect();
        // In the order of `set`.
        let order: Vec<usize> = set
            .iter()
            .filter_map(|i| kept.iter().position(|&p| self.index[p] == *i))
            .collect();
        let cov = v.select_rows(&kept).select_columns(&kept) - correction;
        Some((
            order.iter().map(|&r| beta[r]).collect(),
            cov.select_rows(&order).select_columns(&order),
            j,
        ))
    }
}
