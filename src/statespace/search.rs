//! The search of [`super::fit_oscillator`]: Nelder–Mead within bounds, and central differences
//! for the Newton steps and the observed information.

use nalgebra::DMatrix;

use super::{BUDGET, STEP};

/// Step of the numeric gradient in ln θ.
const GRADIENT_STEP: f64 = 1e-5;

/// The gradient and Hessian of `f` at `t` over the parameters `idx`, by central differences.
pub(super) fn derivatives(
    f: &dyn Fn(&[f64; 4]) -> f64,
    t: &[f64; 4],
    idx: &[usize],
) -> (nalgebra::DVector<f64>, DMatrix<f64>) {
    let n = idx.len();
    let at = |moves: &[(usize, f64)]| {
        let mut x = *t;
        for &(i, d) in moves {
            x[i] += d;
        }
        f(&x)
    };
    let centre = f(t);
    let mut g = nalgebra::DVector::zeros(n);
    let mut h = DMatrix::zeros(n, n);
    for (r, &i) in idx.iter().enumerate() {
        let (plus, minus) = (at(&[(i, STEP)]), at(&[(i, -STEP)]));
        // The gradient at a finer step: the Newton steps' fixed point is its zero.
        g[r] = (at(&[(i, GRADIENT_STEP)]) - at(&[(i, -GRADIENT_STEP)])) / (2.0 * GRADIENT_STEP);
        h[(r, r)] = (plus - 2.0 * centre + minus) / (STEP * STEP);
        for (c, &j) in idx.iter().enumerate().take(r) {
            let pp = at(&[(i, STEP), (j, STEP)]);
            let pm = at(&[(i, STEP), (j, -STEP)]);
            let mp = at(&[(i, -STEP), (j, STEP)]);
            let mm = at(&[(i, -STEP), (j, -STEP)]);
            let v = (pp - pm - mp + mm) / (4.0 * STEP * STEP);
            h[(r, c)] = v;
            h[(c, r)] = v;
        }
    }
    (g, h)
}

/// Nelder–Mead on `f` from `start` with initial steps `steps`, each vertex held within the
/// bounds by `clamp`, for at most [`BUDGET`] evaluations: the best point and its value.
pub(super) fn nelder_mead(
    f: &dyn Fn(&[f64; 4]) -> f64,
    clamp: &dyn Fn([f64; 4]) -> [f64; 4],
    start: [f64; 4],
    steps: [f64; 4],
) -> ([f64; 4], f64) {
    let mut simplex: Vec<([f64; 4], f64)> = (0..5)
        .map(|k| {
            let mut x = start;
            if k > 0 {
                x[k - 1] += steps[k - 1];
                // A vertex pushed onto a bound goes the other way.
                if clamp(x)[k - 1] == start[k - 1] {
                    x[k - 1] -= 2.0 * steps[k - 1];
                }
            }
            let x = clamp(x);
            (x, f(&x))
        })
        .collect();
    let mut spent = 5;
    let point = |a: &[f64; 4], b: &[f64; 4], s: f64| {
        clamp(std::array::from_fn(|i| a[i] + s * (b[i] - a[i])))
    };
    while spent < BUDGET {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[4].1);
        let size = (1..5)
            .flat_map(|k| (0..4).map(move |i| (k, i)))
            .map(|(k, i)| (simplex[k].0[i] - simplex[0].0[i]).abs())
            .fold(0.0, f64::max);
        if (worst - best).abs() < 1e-8 && size < 1e-5 {
            break;
        }
        let centroid: [f64; 4] =
            std::array::from_fn(|i| simplex[..4].iter().map(|v| v.0[i]).sum::<f64>() / 4.0);
        let reflected = point(&centroid, &simplex[4].0, -1.0);
        let fr = f(&reflected);
        spent += 1;
        if fr < simplex[0].1 {
            let expanded = point(&centroid, &simplex[4].0, -2.0);
            let fe = f(&expanded);
            spent += 1;
            simplex[4] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[3].1 {
            simplex[4] = (reflected, fr);
        } else {
            let (towards, ft) = if fr < simplex[4].1 {
                (reflected, fr)
            } else {
                (simplex[4].0, simplex[4].1)
            };
            let contracted = point(&centroid, &towards, 0.5);
            let fc = f(&contracted);
            spent += 1;
            if fc < ft {
                simplex[4] = (contracted, fc);
            } else {
                let best = simplex[0].0;
                for v in simplex.iter_mut().skip(1) {
                    v.0 = point(&best, &v.0, 0.5);
                    v.1 = f(&v.0);
                }
                spent += 4;
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0]
}
