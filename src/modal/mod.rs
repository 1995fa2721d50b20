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

use std::f64::consts::PI;

use faer::Mat;

mod report;
mod trace;
pub use report::ModesReport;
pub use trace::trace_polynomial;

use crate::banded::{BandedR, BandedSym};
use crate::discretise::{boundary_name, min_points, size, stencil_rows};
use crate::generated::operators::OPERATORS;
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

/// Number of structural zero modes of a k-th difference operator with this boundary: the
/// polynomials of degree < k that vanish on the held points (constants around a ring).
pub fn nullity(k: u32, boundary: Boundary) -> usize {
    match boundary {
        Boundary::Periodic => 1,
        Boundary::Ends { .. } => {
            let (tail, head) = boundary.held(k);
            (k as usize).saturating_sub(tail + head)
        }
    }
}

/// An orthonormal basis of the null space on the unknowns of a non-periodic operator:
/// `Π_h (j − h) · jᵐ` over the held points h, m = 0…nullity − 1, in a centred, scaled variable.
pub fn null_basis(k: u32, boundary: Boundary, points: usize) -> Vec<Vec<f64>> {
    let count = nullity(k, boundary);
    let (tail, head) = boundary.held(k);
    let n = size(k, boundary, points);
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
        return Err(ModalError::Solver(
            "a periodic operator is not banded".into(),
        ));
    }
    let name = boundary_name(boundary);
    let generated = OPERATORS
        .iter()
        .find(|o| o.k == k && o.boundary == name)
        .and_then(|o| o.banded);
    if let Some(build) = generated {
        let b = build(points).map_err(|_| ModalError::TooFewPoints {
            points,
            min: min_points(boundary, k),
        })?;
        return Ok(BandedSym {
            n: b.size,
            bands: b.bands,
        });
    }
    let rows = stencil_rows(k, boundary, points).map_err(|_| ModalError::TooFewPoints {
        points,
        min: min_points(boundary, k),
    })?;
    let n = size(k, boundary, points);
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
    let n = size(k, boundary, points);
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

/// The wave operator (k = 1) with one or both ends held: the sine series of the string.
/// Fixed–fixed: n = N − 2, λᵢ = 4 sin²(πi/(2(N−1))), vᵢ(d) = sin(πi·d/(N−1)); fixed–free:
/// n = N − 1, λᵢ = 4 sin²(π(2i−1)/(2(2N−1))), vᵢ(d) = sin(π(2i−1)·d/(2N−1)), d the distance
/// (in points) from the held end.
fn held_second_difference(
    points: usize,
    tail: usize,
    head: usize,
    count: usize,
    want_shapes: bool,
) -> Spectrum {
    let n = points - tail - head;
    // Mode i has angle π·wave(i)/period per point.
    let (period, wave): (f64, fn(usize) -> f64) = if tail + head == 2 {
        (points as f64 - 1.0, |i| i as f64 + 1.0)
    } else {
        (2.0 * points as f64 - 1.0, |i| 2.0 * i as f64 + 1.0)
    };
    let lam = |i: usize| (2.0 * (PI * wave(i) / (2.0 * period)).sin()).powi(2);
    let eigenvalues: Vec<f64> = (0..count).map(lam).collect();
    let inverse_trace = (0..n).map(|i| 1.0 / lam(i)).sum();
    let mut s = closed_form(n, eigenvalues, inverse_trace, want_shapes, |i, u| {
        let d = if tail == 1 { u + 1 } else { n - u };
        (PI * wave(i) * d as f64 / period).sin()
    });
    s.nullity = 0;
    s
}

fn periodic(k: u32, n: usize, count: usize, want_shapes: bool) -> Spectrum {
    // Ascending: m = 0, then (cos, sin) pairs m = 1, 2, …, and the alternating mode if n is even.
    // 4 sin²(x/2) rather than 2 − 2cos x: no cancellation for the small, physically important modes.
    let lam = |m: usize| (2.0 * (PI * m as f64 / n as f64).sin()).powi(2 * k as i32);
    let mut order: Vec<(usize, bool)> = vec![(0, false)];
    for m in 1..=n / 2 {
        if order.len() >= count {
            break;
        }
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
    closed_form(n, eigenvalues, inverse_trace, want_shapes, |c, j| {
        let (m, sine) = order[c];
        let a = 2.0 * PI * (m * j % n) as f64 / n as f64;
        if sine {
            a.sin()
        } else {
            a.cos()
        }
    })
}

/// A closed-form spectrum with one structural zero mode; `shape(c, j)` is component j of mode c
/// before normalisation.
fn closed_form(
    n: usize,
    eigenvalues: Vec<f64>,
    inverse_trace: f64,
    want_shapes: bool,
    shape: impl Fn(usize, usize) -> f64,
) -> Spectrum {
    let shapes = want_shapes.then(|| {
        let cols: Vec<Vec<f64>> = (0..eigenvalues.len())
            .map(|c| {
                let mut v: Vec<f64> = (0..n).map(|j| shape(c, j)).collect();
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
        held: (0, 0),
    }
}

fn free_second_difference(n: usize, count: usize, want_shapes: bool) -> Spectrum {
    let lam = |i: usize| (2.0 * (PI * i as f64 / (2.0 * n as f64)).sin()).powi(2);
    let eigenvalues: Vec<f64> = (0..count)
        .map(|i| if i == 0 { 0.0 } else { lam(i) })
        .collect();
    let inverse_trace = (1..n).map(|i| 1.0 / lam(i)).sum();
    closed_form(n, eigenvalues, inverse_trace, want_shapes, |i, j| {
        (PI * i as f64 * (j as f64 + 0.5) / n as f64).cos()
    })
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
    // (θ, symmetric?) of each root, found in increasing θ; the grid is 8 times finer than the
    // spacing of either family's roots, so no sign change is missed.
    let mut roots: Vec<(f64, bool)> = Vec::with_capacity(needed);
    let start = 0.5 * step;
    let mut prev = [start, start].map(|t| (t, 0.0));
    prev[0].1 = d4_characteristic(start, n, true);
    prev[1].1 = d4_characteristic(start, n, false);
    let mut theta = start;
    while roots.len() < needed && theta < PI {
        theta = (theta + step).min(PI);
        let mut found: Vec<(f64, bool)> = Vec::new();
        for (fam, sym) in [(0, true), (1, false)] {
            let f = d4_characteristic(theta, n, sym);
            let (ta, fa) = prev[fam];
            if f == 0.0 {
                found.push((theta, sym));
            } else if fa != 0.0 && (f < 0.0) != (fa < 0.0) {
                found.push((refine(|t| d4_characteristic(t, n, sym), ta, theta), sym));
            }
            prev[fam] = (theta, f);
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        roots.extend(found);
    }
    roots.truncate(needed);
    // The non-zero modes of the centrosymmetric D4 alternate symmetric, antisymmetric, …
    // (checked against the dense solver in the tests); a missed root would break that.
    let alternates = roots
        .iter()
        .enumerate()
        .all(|(i, &(_, sym))| sym == (i % 2 == 0));
    let increasing = roots.windows(2).all(|w| w[0].0 < w[1].0);
    if roots.len() != needed || !alternates || !increasing {
        return None;
    }
    let lam = |t: f64| (2.0 * (t / 2.0).sin()).powi(4);
    let mut eigenvalues = vec![0.0; count.min(2)];
    eigenvalues.extend(roots.iter().map(|&(t, _)| lam(t)));
    // The band (3N numbers) only when the inertia check or the shapes need it.
    let top = eigenvalues.last().copied().filter(|&t| t > 1e-6);
    let band = if top.is_some() || want_shapes {
        Some(banded_operator(2, Boundary::FREE, points).ok()?)
    } else {
        None
    };
    // Where it is well conditioned (λ not tiny), Sylvester's inertia confirms the count.
    if let (Some(top), Some(band)) = (top, &band) {
        // A quarter of the top spacing (the top eigenvalues crowd as N grows), at most 1e-9·top.
        let below = eigenvalues.len().checked_sub(2).map(|i| eigenvalues[i]);
        let gap = match below {
            Some(p) if top > p => (0.25 * (top - p)).min(1e-9 * top),
            _ => 1e-9 * top,
        };
        if band.count_below(top + gap) != count || band.count_below(top - gap) != count - 1 {
            return None;
        }
    }
    let inverse_trace = d4_inverse_trace(points);
    let shapes = band.filter(|_| want_shapes).map(|band| {
        let mut cols = null_basis(2, Boundary::FREE, points);
        cols.truncate(count.min(2));
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
        held: (0, 0),
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
    let factor = band.shifted(shift);
    for _ in 0..3 {
        v = factor.solve(&v);
        normalise(&mut v);
    }
    v
}

/// Operators with no closed form or characteristic equation: the structured subspace method
/// for a few modes of a long body, faer's dense solver otherwise.
fn general(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let n = size(k, boundary, points);
    let wanted = count.saturating_sub(nullity(k, boundary));
    let block = subspace_block(wanted);
    if boundary != Boundary::Periodic && n > 400 && block * 3 <= n {
        return subspace_on_unknowns(k, boundary, points, count, want_shapes);
    }
    if n > MAX_DENSE {
        return Err(ModalError::TooManyPoints {
            points,
            why: format!(
                "{count} modes of a {} operator of order {k} need the dense solver, which takes at most {MAX_DENSE} unknowns; ask for at most {} modes",
                boundary_name(boundary),
                (n / 6).saturating_sub(2).max(1)
            ),
        });
    }
    dense(k, boundary, points, count, want_shapes)
}

/// `Σ_rows (w·v)²`: vᵀDv from the stencil rows, without D. For a smooth unit v this keeps
/// the relative accuracy of a small eigenvalue that vᵀ(Dv) would lose to cancellation.
fn stencil_energy(rows: &[Vec<(usize, i64)>], v: &[f64]) -> f64 {
    rows.iter()
        .map(|row| {
            let d: f64 = row.iter().map(|&(i, w)| w as f64 * v[i]).sum();
            d * d
        })
        .sum()
}

fn dense(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let n = size(k, boundary, points);
    // The generated dense builder when the crate has this operator, else the exact matrix.
    let name = boundary_name(boundary);
    let generated = OPERATORS.iter().find(|o| o.k == k && o.boundary == name);
    let rows: Vec<Vec<f64>> = match generated {
        Some(o) => (o.dense)(points).map_err(|e| ModalError::Solver(e.to_string()))?,
        None => crate::discretise::operator_matrix(k, boundary, points)
            .map_err(|e| ModalError::Solver(e.to_string()))?
            .into_iter()
            .map(|r| r.into_iter().map(|v| v as f64).collect())
            .collect(),
    };
    let stencil =
        stencil_rows(k, boundary, points).map_err(|e| ModalError::Solver(e.to_string()))?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| rows[i][j]);
    let evd = m
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| ModalError::Solver(format!("{e:?}")))?;
    let null = nullity(k, boundary);
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
fn subspace_block(wanted: usize) -> usize {
    2 * wanted + 6
}

fn orthonormalise(cols: &mut [Vec<f64>], against: &[Vec<f64>]) {
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
fn regularised_factor(
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
        Err(ModalError::Solver(
            "the regularised operator is singular".into(),
        ))
    }
}

/// One Rayleigh–Ritz step on the orthonormal block `q`: the eigenvectors of H = (SQ)ᵀ(SQ)
/// rotate the block, ascending.
fn rayleigh_ritz(
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
        .map_err(|e| ModalError::Solver(format!("{e:?}")))?;
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

fn subspace_on_unknowns(
    k: u32,
    boundary: Boundary,
    points: usize,
    count: usize,
    want_shapes: bool,
) -> Result<Spectrum, ModalError> {
    let min = min_points(boundary, k);
    if points < min {
        return Err(ModalError::TooFewPoints { points, min });
    }
    if boundary == Boundary::Periodic {
        return Err(ModalError::Solver(
            "a periodic operator is not banded".into(),
        ));
    }
    let n = size(k, boundary, points);
    let rows = stencil_rows(k, boundary, points).map_err(|e| ModalError::Solver(e.to_string()))?;
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
        return Err(ModalError::Solver(
            "the subspace iteration did not converge".into(),
        ));
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

/// The continuum limit of the i-th non-zero mode (i = 1, 2, …) of a k = 1 (string) or k = 2
/// (Euler–Bernoulli beam) operator with these ends: βᵢL, so that λᵢ → (βᵢL/(N−1))^{2k}.
/// Roots of the textbook characteristic equations: free–free and clamped–clamped beams
/// cos βL·cosh βL = 1, clamped–free cos βL·cosh βL = −1, pinned–pinned sin βL = 0, pinned–free
/// and clamped–pinned tan βL = tanh βL; strings iπ, or (i − ½)π with one end held. `None` for
/// other k and periodic fields.
pub fn continuum_beta(k: u32, boundary: Boundary, i: usize) -> Option<f64> {
    use crate::model::End::{Clamped, Free, Pinned};
    let Boundary::Ends { tail, head } = boundary else {
        return None;
    };
    let x = i as f64;
    let root = |g: &dyn Fn(f64) -> f64, centre: f64| refine(g, centre - 0.4, centre + 0.4);
    match k {
        1 => Some(match boundary.held(1) {
            (1, 0) | (0, 1) => (x - 0.5) * PI,
            _ => x * PI,
        }),
        2 => {
            let mut ends = [tail, head];
            ends.sort();
            Some(match ends {
                [Free, Free] | [Clamped, Clamped] => {
                    root(&|b: f64| b.cos() - 1.0 / b.cosh(), (x + 0.5) * PI)
                }
                [Free, Clamped] => root(&|b: f64| b.cos() + 1.0 / b.cosh(), (x - 0.5) * PI),
                [Pinned, Pinned] => x * PI,
                [Free, Pinned] | [Pinned, Clamped] => {
                    root(&|b: f64| b.sin() - b.cos() * b.tanh(), (x + 0.25) * PI)
                }
                // Sorted, so the reversed pairs never occur.
                _ => return None,
            })
        }
        _ => None,
    }
}

/// The paper's Eq. 17 approximation of D4's i-th non-zero eigenvalue (i = 1, 2, …):
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

/// Frequency and damping scales: `omega_X`, `zeta_X` for each scale suffix X (`s`, `b`, `t`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Params {
    values: std::collections::BTreeMap<String, f64>,
}

/// The documented defaults: ω = 1 (it sets the unit of time) and ζ = 0.1 for every scale.
pub const DEFAULT_OMEGA: f64 = 1.0;
/// Default damping scale.
pub const DEFAULT_ZETA: f64 = 0.1;

/// A bad parameter.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("parameter {name}: {why}")]
pub struct ParamError {
    /// The parameter.
    pub name: String,
    /// What is wrong.
    pub why: String,
}

impl Params {
    /// Set `name` (`omega_s`, `zeta_b`, …) after checking it: finite, ω > 0, ζ ≥ 0.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ParamError> {
        let err = |why: &str| ParamError {
            name: name.to_string(),
            why: why.to_string(),
        };
        let Some((kind, scale)) = name.split_once('_') else {
            return Err(err("expected omega_<scale> or zeta_<scale>, e.g. omega_b"));
        };
        if scale.is_empty() || !matches!(kind, "omega" | "zeta") {
            return Err(err("expected omega_<scale> or zeta_<scale>, e.g. omega_b"));
        }
        if !value.is_finite() {
            return Err(err(&format!("{value} is not a finite number")));
        }
        if kind == "omega" && value <= 0.0 {
            return Err(err(&format!(
                "a frequency scale must be positive, not {value}"
            )));
        }
        if kind == "zeta" && value < 0.0 {
            return Err(err(&format!(
                "a damping scale cannot be negative ({value})"
            )));
        }
        self.values.insert(name.to_string(), value);
        Ok(())
    }

    /// Parse `name=value`.
    pub fn set_assignment(&mut self, text: &str) -> Result<(), ParamError> {
        let (name, value) = text.split_once('=').ok_or_else(|| ParamError {
            name: text.to_string(),
            why: "expected name=value, e.g. omega_b=2.5".into(),
        })?;
        let value: f64 = value.trim().parse().map_err(|_| ParamError {
            name: name.trim().to_string(),
            why: format!("{:?} is not a number", value.trim()),
        })?;
        self.set(name.trim(), value)
    }

    /// Read `name = value` lines from a TOML table of numbers.
    pub fn set_from_toml(&mut self, text: &str) -> Result<(), ParamError> {
        let table: toml::Table = toml::from_str(text).map_err(|e| ParamError {
            name: "file".into(),
            why: e.to_string().replace('\n', " "),
        })?;
        for (name, value) in table {
            let v = value.as_float().or(value.as_integer().map(|i| i as f64));
            let v = v.ok_or_else(|| ParamError {
                name: name.clone(),
                why: "must be a number".into(),
            })?;
            self.set(&name, v)?;
        }
        Ok(())
    }

    /// The value set for `name` (`omega_s`, `zeta_b`, …), if any.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.values.get(name).copied()
    }

    /// ω for a scale suffix.
    pub fn omega(&self, scale: &str) -> f64 {
        *self
            .values
            .get(&format!("omega_{scale}"))
            .unwrap_or(&DEFAULT_OMEGA)
    }

    /// ζ for a scale suffix.
    pub fn zeta(&self, scale: &str) -> f64 {
        *self
            .values
            .get(&format!("zeta_{scale}"))
            .unwrap_or(&DEFAULT_ZETA)
    }

    /// Names set that no field of `scales` uses (probably typos).
    pub fn unused(&self, scales: &[&str]) -> Vec<String> {
        self.values
            .keys()
            .filter(|k| !scales.iter().any(|s| k.ends_with(&format!("_{s}"))))
            .cloned()
            .collect()
    }
}

/// How a damped mode moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// A zero mode: free motion.
    Free,
    /// ζᵢ < 1: oscillates at the damped frequency.
    Underdamped,
    /// ζᵢ = 1 (to 1e-12).
    Critical,
    /// ζᵢ > 1: creeps back without oscillation.
    Overdamped,
}

impl Regime {
    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Free => "zero-mode",
            Regime::Underdamped => "underdamped",
            Regime::Critical => "critical",
            Regime::Overdamped => "overdamped",
        }
    }
}

/// One mode with its physics.
#[derive(Debug, Clone)]
pub struct Mode {
    /// Index in ascending order.
    pub index: usize,
    /// Eigenvalue λᵢ.
    pub eigenvalue: f64,
    /// ωᵢ = ω√λᵢ.
    pub frequency: f64,
    /// ζᵢ = ζ√λᵢ.
    pub damping_ratio: f64,
    /// ωᵢ√(1 − ζᵢ²) when underdamped.
    pub damped_frequency: Option<f64>,
    /// Regime.
    pub regime: Regime,
    /// λᵢ⁻¹ / Σⱼ λⱼ⁻¹ over all non-zero modes; 0 for zero modes.
    pub variance_share: f64,
    /// Running sum of the shares.
    pub cumulative_share: f64,
    /// The zero mode's name, for zero modes.
    pub zero_mode: Option<String>,
}

/// A beam's i-th non-zero eigenvalue beside its continuum limit (and, free–free, the paper's
/// Eq. 17).
#[derive(Debug, Clone)]
pub struct BeamComparison {
    /// Mode index (ascending, zero modes included).
    pub index: usize,
    /// The numerical eigenvalue.
    pub eigenvalue: f64,
    /// 16 sin⁴(πi/(2(N−1))): the paper's Eq. 17, for the free–free beam only.
    pub seed_eq17: Option<f64>,
    /// (βᵢL)⁴/(N−1)⁴.
    pub continuum: f64,
}

/// All the modes of one field.
#[derive(Debug, Clone)]
pub struct FieldModes {
    /// The field.
    pub field: crate::model::Field,
    /// Stencil order of its operator.
    pub k: u32,
    /// The spectrum.
    pub spectrum: Spectrum,
    /// ω of the field.
    pub omega: f64,
    /// ζ of the field.
    pub zeta: f64,
    /// The lowest modes.
    pub modes: Vec<Mode>,
    /// Consecutive degenerate pairs (i, j).
    pub degenerate_pairs: Vec<(usize, usize)>,
    /// An earlier field with the same operator and scales, hence the same frequencies.
    pub same_frequencies_as: Option<String>,
    /// Beams (k = 2, any ends): numerics beside the continuum limit (and Eq. 17 when free).
    pub beam: Vec<BeamComparison>,
}

/// Why the model's modes cannot be computed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ModesError {
    /// The modal solver failed.
    #[error("field {field}: {source}")]
    Modal {
        /// Field id.
        field: String,
        /// The error.
        source: ModalError,
    },
    /// The operators could not be derived.
    #[error(transparent)]
    Discretise(#[from] crate::discretise::DiscretiseError),
    /// A field lacks a potential or damping operator, or they differ.
    #[error("field {field}: {why}")]
    Operator {
        /// Field id.
        field: String,
        /// What is wrong.
        why: String,
    },
}

/// Frequencies, damping ratios, regimes and variance shares of a spectrum at scales ω, ζ.
fn physical_modes(
    spectrum: &Spectrum,
    field: &crate::model::Field,
    omega: f64,
    zeta: f64,
) -> Vec<Mode> {
    let mut cumulative = 0.0;
    spectrum
        .eigenvalues
        .iter()
        .enumerate()
        .map(|(i, &lam)| {
            let zero = i < spectrum.nullity;
            let (frequency, ratio) = (omega * lam.sqrt(), zeta * lam.sqrt());
            let regime = if zero {
                Regime::Free
            } else if (ratio - 1.0).abs() <= 1e-12 {
                Regime::Critical
            } else if ratio < 1.0 {
                Regime::Underdamped
            } else {
                Regime::Overdamped
            };
            let share = if zero {
                0.0
            } else {
                1.0 / lam / spectrum.inverse_trace
            };
            cumulative += share;
            Mode {
                index: i,
                eigenvalue: lam,
                frequency,
                damping_ratio: ratio,
                damped_frequency: (regime == Regime::Underdamped)
                    .then(|| frequency * (1.0 - ratio * ratio).sqrt()),
                regime,
                variance_share: share,
                cumulative_share: cumulative,
                zero_mode: zero.then(|| {
                    field
                        .zero_modes
                        .get(i)
                        .cloned()
                        .unwrap_or_else(|| format!("zero mode {i}"))
                }),
            }
        })
        .collect()
}

impl FieldModes {
    /// The same modes with the damping scale ζ (ζᵢ = ζ√λᵢ), without solving again.
    pub fn with_zeta(&self, zeta: f64) -> FieldModes {
        FieldModes {
            zeta,
            modes: physical_modes(&self.spectrum, &self.field, self.omega, zeta),
            ..self.clone()
        }
    }
}

/// The modes of every field of `model` at `order` on `points` points.
pub fn field_modes(
    model: &crate::model::Model,
    order: u32,
    points: usize,
    params: &Params,
    limit: Option<usize>,
    shapes: bool,
) -> Result<Vec<FieldModes>, ModesError> {
    use crate::model::Density;
    let plan = crate::discretise::plan(model, order)?;
    let mut out: Vec<FieldModes> = Vec::new();
    for field in &model.fields {
        let op = |d: Density| {
            plan.iter()
                .filter(|p| p.field == field.id && p.density == d)
                .collect::<Vec<_>>()
        };
        let (potential, damping) = (op(Density::Lagrangian), op(Density::Rayleigh));
        let operator_error = |why: String| ModesError::Operator {
            field: field.id.clone(),
            why,
        };
        let [stiff] = potential.as_slice() else {
            return Err(operator_error(if potential.is_empty() {
                format!("no potential term survives at order {order}, so there is no stiffness operator (see the notes of `theory-search --order {order}`; raise --order)")
            } else {
                format!("{} potential terms survive at order {order}; modes need exactly one potential operator", potential.len())
            }));
        };
        // Modal damping ζᵢ = ζ√λᵢ needs the Rayleigh operator to be the potential one.
        if let Some(d) = damping.iter().find(|d| d.k != stiff.k) {
            return Err(operator_error(format!(
                "the damping operator (Δ^{}) differs from the stiffness one (Δ^{}): damping is not modal",
                d.k, stiff.k
            )));
        }
        let spectrum =
            spectrum(stiff.k, stiff.boundary, points, limit, shapes).map_err(|source| {
                ModesError::Modal {
                    field: field.id.clone(),
                    source,
                }
            })?;
        let (omega, zeta) = (params.omega(field.scale()), params.zeta(field.scale()));
        let zeta = if damping.is_empty() { 0.0 } else { zeta };
        let modes = physical_modes(&spectrum, field, omega, zeta);
        let same_frequencies_as = out
            .iter()
            .find(|o| {
                o.k == stiff.k
                    && o.field.boundary == field.boundary
                    && o.omega == omega
                    && o.zeta == zeta
            })
            .map(|o| o.field.id.clone());
        let beam = match stiff.boundary {
            Boundary::Ends { .. } if stiff.k == 2 => {
                let l4 = (points as f64 - 1.0).powi(4);
                let free = stiff.boundary == Boundary::FREE;
                spectrum
                    .eigenvalues
                    .iter()
                    .enumerate()
                    .skip(spectrum.nullity)
                    .filter_map(|(i, &lam)| {
                        let order = i - spectrum.nullity + 1;
                        Some(BeamComparison {
                            index: i,
                            eigenvalue: lam,
                            seed_eq17: free.then(|| seed_eq17(order, points)),
                            continuum: continuum_beta(2, stiff.boundary, order)?.powi(4) / l4,
                        })
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        out.push(FieldModes {
            degenerate_pairs: degenerate_pairs(&spectrum.eigenvalues, spectrum.nullity, 1e-9),
            field: field.clone(),
            k: stiff.k,
            spectrum,
            omega,
            zeta,
            modes,
            same_frequencies_as,
            beam,
        });
    }
    Ok(out)
}
