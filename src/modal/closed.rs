//! Closed forms: periodic Fourier spectra, the string (k = 1) for every end, the exact
//! characteristic equation of D4, the continuum beam's roots, and the paper's Eq. 17.

use std::f64::consts::PI;

use super::{banded_operator, columns_to_mat, normalise, null_basis, Method, Spectrum};
use crate::banded::BandedSym;
use crate::model::Boundary;

/// The wave operator (k = 1) with one or both ends held: the sine series of the string.
/// Fixed–fixed: n = N − 2, λᵢ = 4 sin²(πi/(2(N−1))), vᵢ(d) = sin(πi·d/(N−1)); fixed–free:
/// n = N − 1, λᵢ = 4 sin²(π(2i−1)/(2(2N−1))), vᵢ(d) = sin(π(2i−1)·d/(2N−1)), d the distance
/// (in points) from the held end.
pub(super) fn held_second_difference(
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

pub(super) fn periodic(k: u32, n: usize, count: usize, want_shapes: bool) -> Spectrum {
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
pub(super) fn closed_form(
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

pub(super) fn free_second_difference(n: usize, count: usize, want_shapes: bool) -> Spectrum {
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
pub(super) fn refine(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
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

pub(super) fn d4(points: usize, count: usize, want_shapes: bool) -> Option<Spectrum> {
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
pub(super) fn inverse_iteration(band: &BandedSym, lambda: f64) -> Vec<f64> {
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

/// Σ 1/λ over the non-zero modes of D4 on N points: exactly (N⁴ + N² − 20)/420.
///
/// Found by exact rational interpolation of tr((SSᵀ)⁻¹) (S the second difference, D4 = SᵀS) and
/// checked exactly for N = 3…60 (and in the tests); N⁴/420 is the continuum Σ(βᵢL)⁻⁴. A banded
/// inversion would lose ε·cond(D4) ~ ε·N⁴ of relative accuracy, useless at N = 10⁵.
pub fn d4_inverse_trace(points: usize) -> f64 {
    let n = points as f64;
    (n * n * n * n + n * n - 20.0) / 420.0
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

/// The continuum mode shape of the i-th non-zero mode (i = 1, 2, …) of a k = 2 beam or k = 1
/// string with these ends, at s ∈ [0, 1] (the tail at 0), unit mean square: the null vector of
/// the four end conditions on A·e^{−βs} + B·e^{−β(1−s)} + C·cos βs + D·sin βs (the decaying
/// exponentials instead of cosh and sinh, so that high modes lose no digits), or of the two on
/// C·cos βs + D·sin βs for a string. `None` where [`continuum_beta`] has no root.
pub fn continuum_shape(k: u32, boundary: Boundary, i: usize) -> Option<Vec<f64>> {
    use crate::model::End::{Clamped, Free, Pinned};
    let beta = continuum_beta(k, boundary, i)?;
    let Boundary::Ends { tail, head } = boundary else {
        return None;
    };
    // The m-th derivative of each basis function at s, divided by βᵐ.
    let basis = |m: u32, s: f64| -> [f64; 4] {
        let turn = m as f64 * PI / 2.0;
        [
            (-1f64).powi(m as i32) * (-beta * s).exp(),
            (-beta * (1.0 - s)).exp(),
            (beta * s + turn).cos(),
            (beta * s + turn).sin(),
        ]
    };
    let orders = |end| match (k, end) {
        (2, Free) => vec![2, 3],
        (2, Clamped) => vec![0, 1],
        (2, Pinned) => vec![0, 2],
        (_, Free) => vec![1],
        _ => vec![0],
    };
    let mut rows: Vec<[f64; 4]> = Vec::new();
    for (end, s) in [(tail, 0.0), (head, 1.0)] {
        rows.extend(orders(end).into_iter().map(|m| basis(m, s)));
    }
    let width = if k == 2 { 4 } else { 2 };
    let a = nalgebra::DMatrix::from_fn(rows.len(), width, |r, c| rows[r][c + 4 - width]);
    let svd = a.svd(false, true);
    let v_t = svd.v_t?;
    let smallest =
        (0..width).min_by(|&x, &y| svd.singular_values[x].total_cmp(&svd.singular_values[y]))?;
    let coef: Vec<f64> = (0..width).map(|c| v_t[(smallest, c)]).collect();
    let at = |s: f64| -> f64 {
        let b = basis(0, s);
        coef.iter().zip(&b[4 - width..]).map(|(c, b)| c * b).sum()
    };
    let samples = 2001;
    let values: Vec<f64> = (0..samples)
        .map(|p| at(p as f64 / (samples - 1) as f64))
        .collect();
    // Trapezoidal mean square.
    let ms = values
        .windows(2)
        .map(|w| 0.5 * (w[0] * w[0] + w[1] * w[1]))
        .sum::<f64>()
        / (samples - 1) as f64;
    (ms > 0.0).then(|| values.iter().map(|v| v / ms.sqrt()).collect())
}
