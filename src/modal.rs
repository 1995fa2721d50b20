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
//! * free, k = 1 (D2,f): closed form λᵢ = 2 − 2cos(πi/N), shapes cos(πi(j+½)/N) (DCT-II);
//! * free, k = 2 (D4): the exact characteristic equation. With λ = s², cos θ = 1 − s/2,
//!   cosh φ = 1 + s/2, symmetric modes satisfy cos(θ(N−1)/2)·cosh(φ(N+1)/2) =
//!   cos(θ(N+1)/2)·cosh(φ(N−1)/2), antisymmetric ones the same with sin and sinh. Roots are
//!   bracketed on a grid finer than their spacing, refined, and the count is checked by
//!   Sylvester inertia; shapes by inverse iteration on the band;
//! * anything else: faer's dense self-adjoint eigensolver, up to [`MAX_DENSE`] points.
//!
//! Σ 1/λ comes from the closed forms (periodic and D2,f: a sum over the closed-form eigenvalues;
//! D4: the exact polynomial of [`d4_inverse_trace`]), or from the dense spectrum.

use std::f64::consts::PI;

use faer::Mat;

use crate::banded::BandedSym;
use crate::discretise::{min_points, size, stencil, stencil_rows};
use crate::model::Boundary;

/// The largest operator the dense fallback will take.
pub const MAX_DENSE: usize = 3000;

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
    /// The eigensolver failed.
    #[error("eigensolver failed: {0}")]
    Solver(String),
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
}

impl Method {
    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::ClosedForm => "closed form",
            Method::Characteristic => "characteristic equation",
            Method::Dense => "dense (faer)",
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
    /// Unit-norm shapes as columns (size × count), when asked for.
    pub shapes: Option<Mat<f64>>,
    /// How it was computed.
    pub method: Method,
}

/// Number of structural zero modes of a k-th difference operator with this boundary.
pub fn nullity(k: u32, boundary: Boundary) -> usize {
    match boundary {
        Boundary::Periodic => 1,
        Boundary::Free => k as usize,
        Boundary::Clamped => 0,
    }
}

/// The operator `Σ_p w_pᵀw_p` in band storage.
pub fn banded_operator(k: u32, boundary: Boundary, points: usize) -> Result<BandedSym, ModalError> {
    let rows = stencil_rows(k, boundary, points).map_err(|_| ModalError::TooFewPoints {
        points,
        min: min_points(boundary, k),
    })?;
    let n = size(boundary, points);
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

/// Σ 1/λ over the non-zero modes of D4 on N points: exactly (N⁴ + N² − 20)/420.
///
/// Found by exact rational interpolation of tr((SSᵀ)⁻¹) (S the second difference, D4 = SᵀS) and
/// checked exactly for N = 3…60 (and in the tests); N⁴/420 is the continuum Σ(βᵢL)⁻⁴. A banded
/// inversion would lose ε·cond(D4) ~ ε·N⁴ of relative accuracy, useless at N = 10⁵.
pub fn d4_inverse_trace(points: usize) -> f64 {
    let n = points as f64;
    (n * n * n * n + n * n - 20.0) / 420.0
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

/// Orthonormal polynomials of degree < `count` on n points (the free null space).
fn null_shapes(count: usize, n: usize) -> Vec<Vec<f64>> {
    let centre = (n as f64 - 1.0) / 2.0;
    let mut out: Vec<Vec<f64>> = Vec::new();
    for deg in 0..count {
        let mut v: Vec<f64> = (0..n)
            .map(|j| (j as f64 - centre).powi(deg as i32))
            .collect();
        for u in &out {
            let dot: f64 = u.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(u).for_each(|(x, y)| *x -= dot * y);
        }
        normalise(&mut v);
        out.push(v);
    }
    out
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
    let min = min_points(boundary, k);
    if points < min {
        return Err(ModalError::TooFewPoints { points, min });
    }
    if points > MAX_POINTS {
        return Err(ModalError::TooManyPoints {
            points,
            why: format!("the modal solver takes at most {MAX_POINTS}"),
        });
    }
    let n = size(boundary, points);
    let count = limit.unwrap_or(n).min(n);
    match (boundary, k) {
        (Boundary::Periodic, _) => Ok(periodic(k, n, count, shapes)),
        (Boundary::Free, 1) => Ok(free_second_difference(n, count, shapes)),
        (Boundary::Free, 2) => match d4(points, count, shapes) {
            Some(s) => Ok(s),
            // The inertia check failed (never seen): fall back to the dense solver.
            None => dense(k, boundary, points, count, shapes),
        },
        _ => dense(k, boundary, points, count, shapes),
    }
}

fn periodic(k: u32, n: usize, count: usize, want_shapes: bool) -> Spectrum {
    // Ascending: m = 0, then (cos, sin) pairs m = 1, 2, …, and the alternating mode if n is even.
    // 4 sin²(x/2) rather than 2 − 2cos x: no cancellation for the small, physically important modes.
    let lam = |m: usize| (2.0 * (PI * m as f64 / n as f64).sin()).powi(2 * k as i32);
    let mut order: Vec<(usize, bool)> = vec![(0, false)];
    for m in 1..=n / 2 {
        order.push((m, false));
        if 2 * m != n {
            order.push((m, true));
        }
    }
    order.truncate(count);
    let eigenvalues: Vec<f64> = order
        .iter()
        .map(|&(m, _)| if m == 0 { 0.0 } else { lam(m) })
        .collect();
    let inverse_trace = (1..n).map(|m| 1.0 / lam(m)).sum();
    let shapes = want_shapes.then(|| {
        let cols: Vec<Vec<f64>> = order
            .iter()
            .map(|&(m, sine)| {
                let mut v: Vec<f64> = (0..n)
                    .map(|j| {
                        let a = 2.0 * PI * (m * j % n) as f64 / n as f64;
                        if sine {
                            a.sin()
                        } else {
                            a.cos()
                        }
                    })
                    .collect();
                normalise(&mut v);
                v
            })
            .collect();
        columns_to_mat(&cols, n)
    });
    Spectrum {
        eigenvalues,
        size: n,
        nullity: 1,
        inverse_trace,
        shapes,
        method: Method::ClosedForm,
    }
}

fn free_second_difference(n: usize, count: usize, want_shapes: bool) -> Spectrum {
    let lam = |i: usize| (2.0 * (PI * i as f64 / (2.0 * n as f64)).sin()).powi(2);
    let eigenvalues: Vec<f64> = (0..count)
        .map(|i| if i == 0 { 0.0 } else { lam(i) })
        .collect();
    let inverse_trace = (1..n).map(|i| 1.0 / lam(i)).sum();
    let shapes = want_shapes.then(|| {
        let cols: Vec<Vec<f64>> = (0..count)
            .map(|i| {
                let mut v: Vec<f64> = (0..n)
                    .map(|j| (PI * i as f64 * (j as f64 + 0.5) / n as f64).cos())
                    .collect();
                normalise(&mut v);
                v
            })
            .collect();
        columns_to_mat(&cols, n)
    });
    Spectrum {
        eigenvalues,
        size: n,
        nullity: 1,
        inverse_trace,
        shapes,
        method: Method::ClosedForm,
    }
}

/// The D4 characteristic function of the symmetric (`sym`) or antisymmetric family at θ ∈ (0, π],
/// divided by cosh(φ(N−1)/2) (or sinh) so that it never overflows.
pub fn d4_characteristic(theta: f64, points: usize, sym: bool) -> f64 {
    // s = 2 − 2cos θ = 4 sin²(θ/2); cosh φ = 1 + s/2 ⇔ sinh(φ/2) = sin(θ/2). Written this way
    // neither loses digits for the small θ of the long-wavelength modes.
    let half = (theta / 2.0).sin();
    let phi = 2.0 * half.asinh();
    let nf = points as f64;
    let a = phi * (nf - 1.0) / 2.0;
    let (ta, tb) = (theta * (nf - 1.0) / 2.0, theta * (nf + 1.0) / 2.0);
    if sym {
        // cosh(a + φ)/cosh(a) = cosh φ + tanh(a) sinh φ
        ta.cos() * (phi.cosh() + a.tanh() * phi.sinh()) - tb.cos()
    } else {
        // sinh(a + φ)/sinh(a) = cosh φ + coth(a) sinh φ
        ta.sin() * (phi.cosh() + phi.sinh() / a.tanh()) - tb.sin()
    }
}

/// A root of `f` in [a, b] with f(a), f(b) of opposite signs (Illinois regula falsi).
fn refine(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let (mut fa, mut fb) = (f(a), f(b));
    let mut side = 0;
    for _ in 0..200 {
        let c = (a * fb - b * fa) / (fb - fa);
        let c = if c.is_finite() && c > a && c < b {
            c
        } else {
            0.5 * (a + b)
        };
        let fc = f(c);
        if fc == 0.0 || (b - a) <= 4.0 * f64::EPSILON * b.abs() {
            return c;
        }
        if (fc < 0.0) == (fa < 0.0) {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (a + b)
}

fn d4(points: usize, count: usize, want_shapes: bool) -> Option<Spectrum> {
    let n = points;
    let needed = count.saturating_sub(2);
    let step = PI / (4.0 * (n as f64 + 1.0));
    let mut roots: Vec<f64> = Vec::with_capacity(needed);
    let mut prev = [
        (step * 0.5, d4_characteristic(step * 0.5, n, true)),
        (step * 0.5, d4_characteristic(step * 0.5, n, false)),
    ];
    let mut theta = step * 0.5;
    while roots.len() < needed && theta < PI {
        theta = (theta + step).min(PI);
        for (fam, sym) in [(0, true), (1, false)] {
            let f = d4_characteristic(theta, n, sym);
            let (ta, fa) = prev[fam];
            if fa == 0.0 {
                roots.push(ta);
            } else if (f < 0.0) != (fa < 0.0) && f != 0.0 {
                roots.push(refine(|t| d4_characteristic(t, n, sym), ta, theta));
            }
            prev[fam] = (theta, f);
        }
        // The last point, θ = π, can itself be a root (λ = 16).
        if theta >= PI {
            for (fam, _) in [(0, true), (1, false)] {
                if prev[fam].1 == 0.0 {
                    roots.push(PI);
                }
            }
        }
    }
    roots.sort_by(f64::total_cmp);
    roots.truncate(needed);
    let lam = |t: f64| (2.0 * (t / 2.0).sin()).powi(4);
    let mut eigenvalues = vec![0.0; count.min(2)];
    eigenvalues.extend(roots.iter().map(|&t| lam(t)));
    if eigenvalues.len() != count {
        return None;
    }
    // Sylvester: exactly `count` eigenvalues lie below just above the largest one found.
    let band = banded_operator(2, Boundary::Free, points).ok()?;
    if let Some(&top) = eigenvalues.last() {
        if top > 0.0 {
            let gap = 1e-9 * top;
            if band.count_below(top + gap) != count || band.count_below(top - gap) != count - 1 {
                return None;
            }
        }
    }
    let inverse_trace = d4_inverse_trace(points);
    let shapes = want_shapes.then(|| {
        let mut cols = null_shapes(count.min(2), n);
        cols.extend(
            eigenvalues
                .iter()
                .skip(2)
                .map(|&l| inverse_iteration(&band, l)),
        );
        columns_to_mat(&cols, n)
    });
    Some(Spectrum {
        eigenvalues,
        size: n,
        nullity: 2,
        inverse_trace,
        shapes,
        method: Method::Characteristic,
    })
}

/// The eigenvector of the simple eigenvalue `lambda` (known to full precision).
fn inverse_iteration(band: &BandedSym, lambda: f64) -> Vec<f64> {
    let n = band.n;
    // A deterministic start with components along every mode.
    let mut v: Vec<f64> = (0..n)
        .map(|j| 1.0 + ((j * 7919) % 101) as f64 / 101.0)
        .collect();
    let shift = lambda * (1.0 - 1e-13) - 1e-300;
    for _ in 0..3 {
        v = band.solve_shifted(shift, &v);
        normalise(&mut v);
    }
    v
}

fn dense(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let n = size(boundary, points);
    if n > MAX_DENSE {
        return Err(ModalError::TooManyPoints {
            points,
            why: format!(
                "no structured solver for a {} operator of order {k}; the dense one takes at most {MAX_DENSE}",
                crate::discretise::boundary_name(boundary)
            ),
        });
    }
    let band = banded_operator(k, boundary, points)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| band.get(i, j));
    let evd = m
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| ModalError::Solver(format!("{e:?}")))?;
    let s = evd.S().column_vector();
    let null = nullity(k, boundary);
    let all: Vec<f64> = (0..n).map(|i| if i < null { 0.0 } else { s[i] }).collect();
    let inverse_trace = all[null..].iter().map(|l| 1.0 / l).sum();
    let shapes = want_shapes.then(|| {
        let u = evd.U();
        let mut cols: Vec<Vec<f64>> = if null > 0 && boundary == Boundary::Free {
            null_shapes(null, n)
        } else {
            Vec::new()
        };
        let start = cols.len();
        for j in start..count {
            let mut v: Vec<f64> = (0..n).map(|i| u[(i, j)]).collect();
            normalise(&mut v);
            cols.push(v);
        }
        cols.truncate(count);
        columns_to_mat(&cols, n)
    });
    Ok(Spectrum {
        eigenvalues: all[..count].to_vec(),
        size: n,
        nullity: null,
        inverse_trace,
        shapes,
        method: Method::Dense,
    })
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

/// The free–free Euler–Bernoulli beam's βᵢL, roots of cos βL · cosh βL = 1 (i = 1, 2, …).
pub fn beam_beta(i: usize) -> f64 {
    // Bracket near (i + ½)π and refine g(β) = cos β − 1/cosh β (same roots, no overflow).
    let g = |b: f64| b.cos() - 1.0 / b.cosh();
    let centre = (i as f64 + 0.5) * PI;
    refine(g, centre - 0.4, centre + 0.4)
}

/// The seed's Eq. 17 approximation of D4's i-th non-zero eigenvalue (i = 1, 2, …):
/// 16 sin⁴(πi/(2(N−1))).
pub fn seed_eq17(i: usize, points: usize) -> f64 {
    16.0 * (PI * i as f64 / (2.0 * (points as f64 - 1.0)))
        .sin()
        .powi(4)
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
