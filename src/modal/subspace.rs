//! Subspace iteration on the QR factor of the stencil rows for a few modes of a long body,
//! and faer's dense solver otherwise.

use faer::Mat;

use super::{
    columns_to_mat, normalise, null_basis, trace_polynomial, Method, ModalError, Spectrum,
    MAX_DENSE,
};
use crate::banded::BandedR;
use crate::discretise::stencil_rows;
use crate::generated::operators::OPERATORS;
use crate::model::Boundary;

/// Operators with no closed form or characteristic equation: the structured subspace method
/// for a few modes of a long body, faer's dense solver otherwise.
pub(super) fn general(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let n = boundary.unknowns(k, points);
    let wanted = count.saturating_sub(boundary.nullity(k));
    let block = subspace_block(wanted);
    if boundary != Boundary::Periodic && n > 400 && block * 3 <= n {
        return subspace_on_unknowns(k, boundary, points, count, want_shapes);
    }
    if n > MAX_DENSE {
        return Err(ModalError::TooManyPoints {
            points,
            why: format!(
                "{count} modes of a {} operator of order {k} need the dense solver, which takes at most {MAX_DENSE} unknowns; ask for at most {} modes",
                boundary.name(),
                (n / 6).saturating_sub(2).max(1)
            ),
        });
    }
    dense(k, boundary, points, count, want_shapes)
}

/// `Σ_rows (w·v)²`: vᵀDv from the stencil rows, without D. For a smooth unit v this keeps
/// the relative accuracy of a small eigenvalue that vᵀ(Dv) would lose to cancellation.
pub(super) fn stencil_energy(rows: &[Vec<(usize, i64)>], v: &[f64]) -> f64 {
    rows.iter()
        .map(|row| {
            let d: f64 = row.iter().map(|&(i, w)| w as f64 * v[i]).sum();
            d * d
        })
        .sum()
}

pub(super) fn dense(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let n = boundary.unknowns(k, points);
    // The generated dense builder when the crate has this operator, else the exact matrix.
    let generated = OPERATORS
        .iter()
        .find(|o| o.k == k && o.boundary == boundary);
    let rows: Vec<Vec<f64>> = match generated {
        Some(o) => (o.dense)(points)?,
        None => crate::discretise::operator_matrix(k, boundary, points)?
            .into_iter()
            .map(|r| r.into_iter().map(|v| v as f64).collect())
            .collect(),
    };
    let stencil = stencil_rows(k, boundary, points)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| rows[i][j]);
    let evd = m
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| ModalError::NoConvergence("faer's self-adjoint eigensolver"))?;
    let null = boundary.nullity(k);
    let u = evd.U();
    // Non-zero modes: eigenvalues refined as stencil energies of the eigenvectors, which gives
    // the small ones to relative accuracy (the solver's own are accurate to ε‖D‖ absolute).
    let mut pairs: Vec<(f64, Vec<f64>)> = (null..n)
        .map(|j| {
            let mut v: Vec<f64> = (0..n).map(|i| u[(i, j)]).collect();
            normalise(&mut v);
            (stencil_energy(&stencil, &v), v)
        })
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let inverse_trace = pairs.iter().map(|(l, _)| 1.0 / l).sum();
    let mut eigenvalues = vec![0.0; null];
    eigenvalues.extend(pairs.iter().map(|(l, _)| *l));
    eigenvalues.truncate(count);
    let shapes = want_shapes.then(|| {
        let mut cols = if boundary == Boundary::Periodic {
            vec![vec![1.0 / (n as f64).sqrt(); n]]
        } else {
            null_basis(k, boundary, points)
        };
        cols.extend(pairs.into_iter().map(|(_, v)| v));
        cols.truncate(count);
        columns_to_mat(&cols, n)
    });
    Ok(Spectrum {
        eigenvalues,
        size: n,
        nullity: null,
        inverse_trace,
        shapes,
        method: Method::Dense,
        held: (0, 0),
    })
}

/// Block size of the subspace method for `wanted` non-zero modes: twice as many, plus a margin,
/// so the slowest wanted mode converges at least as (λ_K/λ_2K)^{k} per step.
pub(super) fn subspace_block(wanted: usize) -> usize {
    2 * wanted + 6
}

pub(super) fn orthonormalise(cols: &mut [Vec<f64>], against: &[Vec<f64>]) {
    for c in 0..cols.len() {
        // Twice is enough (Kahan–Parlett).
        for _ in 0..2 {
            let (done, rest) = cols.split_at_mut(c);
            let v = &mut rest[0];
            for u in against.iter().chain(done.iter()) {
                let dot: f64 = u.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(u).for_each(|(x, y)| *x -= dot * y);
            }
        }
        let norm = cols[c].iter().map(|x| x * x).sum::<f64>().sqrt();
        cols[c].iter_mut().for_each(|x| *x /= norm);
    }
}

/// The structured method for any non-periodic operator, O(N·K) memory.
///
/// With S the stencil rows and Z the known null basis, add one row eᵢ per null mode at spread
/// unknowns (G) so that A = SᵀS + GᵀG is regular; then P·A⁻¹·P = D⁺ exactly (P = I − ZZᵀ: a
/// solution x of A x = P b has G x = 0, because ZᵀGᵀG x = ZᵀPb = 0 and GZ is regular). A⁻¹ is
/// applied through R from the Givens QR of [S; G], never through SᵀS, so its accuracy follows
/// S's conditioning. Subspace iteration with P·A⁻¹·P and Rayleigh–Ritz on ‖S·Q‖² gives the
/// lowest modes; tr(D⁺) = tr(A⁻¹) − Σ zᵢᵀA⁻¹zᵢ with tr(A⁻¹) by Takahashi's recurrence.
pub fn subspace(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    subspace_on_unknowns(k, boundary, points, count, want_shapes).map(|s| s.embed(boundary.held(k)))
}

/// R of [S; G]: the stencil rows and one row eᵢ per null mode, at spread unknowns.
pub(super) fn regularised_factor(
    rows: &[Vec<(usize, i64)>],
    z: &[Vec<f64>],
    n: usize,
    k: u32,
) -> Result<BandedR, ModalError> {
    let spread: Vec<usize> = (0..z.len())
        .map(|i| ((i + 1) * n / (z.len() + 1)).min(n - 1))
        .collect();
    let float_rows: Vec<Vec<(usize, f64)>> = rows
        .iter()
        .map(|r| r.iter().map(|&(i, w)| (i, w as f64)).collect())
        .chain(spread.iter().map(|&i| vec![(i, 1.0)]))
        .collect();
    let r = BandedR::from_rows(n, k as usize, float_rows.iter().map(|r| r.as_slice()));
    if r.is_regular() {
        Ok(r)
    } else {
        Err(ModalError::Singular)
    }
}

/// One Rayleigh–Ritz step on the orthonormal block `q`: the eigenvectors of H = (SQ)ᵀ(SQ)
/// rotate the block, ascending.
pub(super) fn rayleigh_ritz(
    rows: &[Vec<(usize, i64)>],
    q: Vec<Vec<f64>>,
    n: usize,
) -> Result<Vec<Vec<f64>>, ModalError> {
    let block = q.len();
    let w: Vec<Vec<f64>> = q
        .iter()
        .map(|v| {
            rows.iter()
                .map(|row| row.iter().map(|&(i, c)| c as f64 * v[i]).sum())
                .collect()
        })
        .collect();
    let h = Mat::<f64>::from_fn(block, block, |a, b| {
        w[a].iter().zip(&w[b]).map(|(x, y)| x * y).sum()
    });
    let evd = h
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| ModalError::NoConvergence("faer's self-adjoint eigensolver"))?;
    let g = evd.U();
    Ok((0..block)
        .map(|c| {
            let mut v = vec![0.0; n];
            for (b, qb) in q.iter().enumerate() {
                let coef = g[(b, c)];
                v.iter_mut().zip(qb).for_each(|(x, y)| *x += coef * y);
            }
            v
        })
        .collect())
}

pub(super) fn subspace_on_unknowns(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let min = boundary.min_points(k);
    if points < min {
        return Err(ModalError::TooFewPoints { points, min });
    }
    if boundary == Boundary::Periodic {
        return Err(ModalError::NotBanded);
    }
    let n = boundary.unknowns(k, points);
    let rows = stencil_rows(k, boundary, points)?;
    let z = null_basis(k, boundary, points);
    let r = regularised_factor(&rows, &z, n, k)?;
    let project = |v: &mut Vec<f64>| {
        for u in &z {
            let dot: f64 = u.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(u).for_each(|(x, y)| *x -= dot * y);
        }
    };
    // The exact polynomial when it is found; Takahashi's recurrence (accurate at modest N) else.
    let inverse_trace = trace_polynomial(k, boundary, points).unwrap_or_else(|| {
        r.inverse_trace()
            - z.iter()
                .map(|u| {
                    let mut y = u.clone();
                    r.solve_normal(&mut y);
                    u.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()
                })
                .sum::<f64>()
    });
    let wanted = count.saturating_sub(z.len());
    let block = subspace_block(wanted).min(n - z.len());
    // A deterministic start with components along every mode.
    let mut q: Vec<Vec<f64>> = (0..block)
        .map(|c| {
            (0..n)
                .map(|j| 1.0 + (((j + 1) * (c + 7919) * 104_729) % 1009) as f64 / 1009.0)
                .collect()
        })
        .collect();
    orthonormalise(&mut q, &z);
    let mut ritz: Vec<f64> = vec![f64::INFINITY; block];
    let mut converged = wanted == 0;
    let mut last_change = f64::INFINITY;
    for _ in 0..1000 {
        if converged {
            break;
        }
        for v in q.iter_mut() {
            project(v);
            r.solve_normal(v);
            project(v);
        }
        orthonormalise(&mut q, &z);
        q = rayleigh_ritz(&rows, q, n)?;
        let values: Vec<f64> = q[..wanted]
            .iter()
            .map(|v| stencil_energy(&rows, v))
            .collect();
        let change = values
            .iter()
            .zip(&ritz)
            .map(|(a, b)| (a - b).abs() / a.abs())
            .fold(0.0, f64::max);
        // Eigenvalues converge at least 16-fold per step (the block is twice the wanted
        // modes); a change that stops falling is rounding noise, reached at large N.
        converged = change <= 1e-13 || (change <= 1e-7 && change > 0.5 * last_change);
        last_change = change;
        ritz[..wanted].copy_from_slice(&values);
    }
    if !converged {
        return Err(ModalError::NoConvergence("the subspace iteration"));
    }
    let mut eigenvalues = vec![0.0; z.len().min(count)];
    eigenvalues.extend_from_slice(&ritz[..wanted]);
    let shapes = want_shapes.then(|| {
        let mut cols: Vec<Vec<f64>> = z.clone();
        cols.extend(q.into_iter().take(wanted).map(|mut v| {
            normalise(&mut v);
            v
        }));
        cols.truncate(count);
        columns_to_mat(&cols, n)
    });
    Ok(Spectrum {
        eigenvalues,
        size: n,
        nullity: z.len(),
        inverse_trace,
        shapes,
        method: Method::Subspace,
        held: (0, 0),
    })
}
