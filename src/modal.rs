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

/// The operator `Σ_p w_pᵀw_p` in band storage: from the generated code when it has this
/// operator (the larva's), otherwise from the stencil. Periodic operators wrap around and are
/// not banded.
pub fn banded_operator(k: u32, boundary: Boundary, points: usize) -> Result<BandedSym, ModalError> {
    if boundary == Boundary::Periodic {
        return Err(ModalError::Solver(
            "a periodic operator is not banded".into(),
        ));
    }
    let generated = OPERATORS
        .iter()
        .find(|o| o.k == k && o.boundary == boundary_name(boundary))
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
        Some(banded_operator(2, Boundary::Free, points).ok()?)
    } else {
        None
    };
    // Where it is well conditioned (λ not tiny), Sylvester's inertia confirms the count.
    if let (Some(top), Some(band)) = (top, &band) {
        let gap = 1e-9 * top;
        if band.count_below(top + gap) != count || band.count_below(top - gap) != count - 1 {
            return None;
        }
    }
    let inverse_trace = d4_inverse_trace(points);
    let shapes = band.filter(|_| want_shapes).map(|band| {
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
                boundary_name(boundary)
            ),
        });
    }
    // The generated dense builder when the crate has this operator, else the exact matrix.
    let generated = OPERATORS
        .iter()
        .find(|o| o.k == k && o.boundary == boundary_name(boundary));
    let rows: Vec<Vec<f64>> = match generated {
        Some(o) => (o.dense)(points).map_err(|e| ModalError::Solver(e.to_string()))?,
        None => crate::discretise::operator_matrix(k, boundary, points)
            .map_err(|e| ModalError::Solver(e.to_string()))?
            .into_iter()
            .map(|r| r.into_iter().map(|v| v as f64).collect())
            .collect(),
    };
    let m = Mat::<f64>::from_fn(n, n, |i, j| rows[i][j]);
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
            Regime::Free => "free",
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

/// D4's i-th non-zero eigenvalue beside the seed's Eq. 17 and the continuum beam limit.
#[derive(Debug, Clone)]
pub struct BeamComparison {
    /// Mode index (ascending, zero modes included).
    pub index: usize,
    /// The numerical eigenvalue.
    pub eigenvalue: f64,
    /// 16 sin⁴(πi/(2(N−1))).
    pub seed_eq17: f64,
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
    /// D4 only: numerics beside Eq. 17 and the continuum limit.
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
        let mut cumulative = 0.0;
        let modes = spectrum
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
                            .unwrap_or_else(|| format!("null mode of degree {i}"))
                    }),
                }
            })
            .collect();
        let same_frequencies_as = out
            .iter()
            .find(|o| {
                o.k == stiff.k
                    && o.field.boundary == field.boundary
                    && o.omega == omega
                    && o.zeta == zeta
            })
            .map(|o| o.field.id.clone());
        let beam = if stiff.k == 2 && stiff.boundary == Boundary::Free {
            let l4 = (points as f64 - 1.0).powi(4);
            spectrum
                .eigenvalues
                .iter()
                .enumerate()
                .skip(2)
                .map(|(i, &lam)| BeamComparison {
                    index: i,
                    eigenvalue: lam,
                    seed_eq17: seed_eq17(i - 1, points),
                    continuum: beam_beta(i - 1).powi(4) / l4,
                })
                .collect()
        } else {
            Vec::new()
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
