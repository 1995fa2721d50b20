//! Scenario: the independent continuum-beam generator of the `discover` studies
//! (tests/common/continuum.rs) checked against analytic values: its modal quadrature (the modes
//! orthonormal, ∫φᵢφⱼ⁗ = λⱼδᵢⱼ, the boundary conditions, the active matrix by parts), the
//! passive beam's stationary variances T/(cλₙ) and lag-1 autocorrelations of damped
//! oscillators, the active beam's stationary covariance solving the continuous Lyapunov
//! equation and its probability current (none without the active force), an unstable beam
//! refused, the CSV's lost frames, the tracked points at equal arc length on the bent body,
//! and `fit` reading κ = √c off a passive free–free recording.

mod common;

use common::beam::{fitted, root, shape};
use common::continuum::{
    derivative, discretise, kept, midline, overlap, positions, record, shapes, states, Beam, C,
};
use nalgebra::DVector;

/// Frames of the statistical checks, cut into batches for their errors (batch means).
const FRAMES: usize = 200_000;
const BATCHES: usize = 20;

/// The mean over each batch of `f(frame)` and the error of their mean: (mean, standard error).
fn batched(n: usize, f: impl Fn(usize) -> f64) -> (f64, f64) {
    let len = n / BATCHES;
    let means: Vec<f64> = (0..BATCHES)
        .map(|b| (b * len..(b + 1) * len).map(&f).sum::<f64>() / len as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / BATCHES as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (BATCHES - 1) as f64;
    (mean, (var / BATCHES as f64).sqrt())
}

/// The ratio of the sums of `f` and `g` over the frames, and its error from the batches'.
fn ratio(n: usize, f: impl Fn(usize) -> f64, g: impl Fn(usize) -> f64) -> (f64, f64) {
    let len = n / BATCHES;
    let sum = |h: &dyn Fn(usize) -> f64, b: usize| (b * len..(b + 1) * len).map(h).sum::<f64>();
    let each: Vec<f64> = (0..BATCHES).map(|b| sum(&f, b) / sum(&g, b)).collect();
    let all = (0..BATCHES).map(|b| sum(&f, b)).sum::<f64>()
        / (0..BATCHES).map(|b| sum(&g, b)).sum::<f64>();
    let mean = each.iter().sum::<f64>() / BATCHES as f64;
    let var = each.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (BATCHES - 1) as f64;
    (all, (var / BATCHES as f64).sqrt())
}

#[test]
fn modal_quadrature() {
    for clamped in [false, true] {
        let m = 12;
        let lambda: Vec<f64> = (1..=m).map(|n| root(clamped, n).powi(4)).collect();
        let scale =
            |i: usize, j: usize, p: i32| (root(clamped, i + 1) * root(clamped, j + 1)).powi(p);
        let gram = overlap(clamped, m, 0, 0);
        let stiff = overlap(clamped, m, 0, 4);
        // By parts twice (the boundary terms vanish at free and clamped ends alike).
        let bend = overlap(clamped, m, 2, 2);
        // ∫φᵢφⱼ‴ = −∫φᵢ′φⱼ″ (φᵢφⱼ″ vanishes at both ends).
        let active = overlap(clamped, m, 0, 3);
        let by_parts = overlap(clamped, m, 1, 2);
        for i in 0..m {
            for j in 0..m {
                let delta = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (gram[(i, j)] - delta).abs() < 1e-8,
                    "∫φ{i}φ{j} = {}",
                    gram[(i, j)]
                );
                let target = lambda[j] * delta;
                for (name, v) in [("φ⁗", stiff[(i, j)]), ("φ″φ″", bend[(i, j)])] {
                    assert!(
                        (v - target).abs() < 1e-8 * scale(i, j, 2),
                        "clamped {clamped}: ∫{name} ({i}, {j}) = {v} against {target}"
                    );
                }
                let (a, b) = (active[(i, j)], -by_parts[(i, j)]);
                assert!(
                    (a - b).abs() < 1e-8 * scale(i, j, 2),
                    "clamped {clamped}: ∫φ{i}φ{j}‴ = {a} against −∫φ′φ″ = {b}"
                );
            }
        }
        // The active matrix is not zero, nor symmetric (a non-conservative force).
        assert!(active[(0, 1)].abs() > 1.0 && (active[(0, 1)] + active[(1, 0)]).abs() > 1.0);
        // The boundary conditions, and each derivative the difference quotient of the one below.
        for n in 1..=m {
            let r = root(clamped, n);
            let at = |s: f64, d: u32| derivative(clamped, r, s, d) / r.powi(d as i32);
            let zero = if clamped {
                [at(0.0, 0), at(0.0, 1), at(1.0, 2), at(1.0, 3)]
            } else {
                [at(0.0, 2), at(0.0, 3), at(1.0, 2), at(1.0, 3)]
            };
            assert!(zero.iter().all(|z| z.abs() < 1e-9), "mode {n}: {zero:?}");
            let h = 1e-6;
            for s in [0.1, 0.37, 0.5, 0.93] {
                for d in 1..=4 {
                    let fd = (at(s + h, d - 1) - at(s - h, d - 1)) / (2.0 * h * r);
                    assert!((fd - at(s, d)).abs() < 1e-6, "mode {n} d{d} at {s}");
                }
                // beam::shape's form, to its cancellation: it subtracts terms of size cosh rs.
                let diff = shape(clamped, r, s) - at(s, 0);
                let tolerance = 1e-13 * (r * s).cosh() + 1e-12;
                assert!(
                    diff.abs() < tolerance,
                    "clamped {clamped} mode {n} at {s}: {diff:e}"
                );
            }
        }
    }
}

#[test]
fn tracked_points_lie_at_equal_arc_length_on_the_bent_body() {
    // Bent sixteen times the studies' passive temperature (tangent angles of a few tenths of
    // a radian), so the body's own geometry shows: each segment's chord is the integral of
    // (cos ψ, sin ψ) over one 24th of arc length (a fine midpoint sum here), and the lateral
    // positions differ from y(s) at second order.
    let beam = Beam {
        temperature: Beam::passive(false).temperature * 16.0,
        frames: 50,
        ..Beam::passive(false)
    };
    let states = states(&beam, 4);
    let (points, ys) = (positions(&beam, &states), midline(&beam, &states));
    let h = 1.0 / (beam.points - 1) as f64;
    let roots = beam.roots();
    let (mut worst, mut bent, mut turned) = (0.0f64, 0.0f64, 0.0f64);
    for ((p, y), x) in points.iter().zip(&ys).zip(&states) {
        for k in 0..beam.points - 1 {
            let (dx, dy) = (p[2 * k + 2] - p[2 * k], p[2 * k + 3] - p[2 * k + 1]);
            let (mut c, mut s) = (0.0, 0.0);
            for q in 0..400 {
                let at = h * (k as f64 + (q as f64 + 0.5) / 400.0);
                let psi: f64 = (0..beam.modes)
                    .map(|j| x[j] * derivative(false, roots[j], at, 1))
                    .sum();
                turned = turned.max(psi.abs());
                (c, s) = (c + psi.cos() / 400.0, s + psi.sin() / 400.0);
            }
            worst = worst.max((dx - h * c).hypot(dy - h * s) / h);
        }
        bent = bent.max(
            (0..beam.points)
                .map(|k| (p[2 * k + 1] - y[k]).abs())
                .fold(0.0, f64::max),
        );
    }
    assert!(
        turned > 0.2,
        "tangent angles up to {turned} rad only: no geometry tested"
    );
    // Simpson's error; the studies' tracking noise is 2·10⁻³ of a segment.
    assert!(
        worst < 1e-5,
        "a chord off the arc's by {worst:e} of a segment"
    );
    assert!(
        bent > 1e-4,
        "y(s) moved only {bent:e} off the midline: no geometry tested"
    );
}

/// The modal coordinates fitted back by least squares of the noiseless midline on φⱼ(sₖ).
fn coordinates(beam: &Beam, seed: u64) -> Vec<DVector<f64>> {
    let phi = shapes(beam);
    let svd = phi.clone().svd(true, true);
    midline(beam, &states(beam, seed))
        .iter()
        .map(|y| svd.solve(y, 1e-12).expect("solves"))
        .collect()
}

#[test]
fn passive_variances_and_autocorrelation() {
    for clamped in [false, true] {
        let beam = Beam {
            frames: FRAMES,
            ..Beam::passive(clamped)
        };
        let d = discretise(&beam);
        let m = beam.modes;
        // The stationary covariance is equipartition: diag(T/(cλ), T).
        for i in 0..2 * m {
            for j in 0..2 * m {
                let truth = match (i == j, i < m) {
                    (false, _) => 0.0,
                    (true, true) => beam.temperature / (beam.c * d.lambda[i]),
                    (true, false) => beam.temperature,
                };
                let scale = (d.stationary[(i, i)] * d.stationary[(j, j)]).sqrt();
                assert!((d.stationary[(i, j)] - truth).abs() < 1e-8 * scale);
            }
        }
        let q = coordinates(&beam, 7 + u64::from(clamped));
        for n in 0..m {
            let truth = beam.temperature / (beam.c * d.lambda[n]);
            let (var, err) = batched(q.len(), |t| q[t][n] * q[t][n]);
            println!(
                "clamped {clamped} mode {}: variance / T/(cλ) = {:.4} ± {:.4}",
                n + 1,
                var / truth,
                err / truth
            );
            assert!((var - truth).abs() < 4.0 * err && (var / truth - 1.0).abs() < 0.08);
        }
        for n in 1..=3 {
            let (omega, zeta, dt) = (beam.omega(n), beam.zeta(n), beam.dt());
            let wd = omega * (1.0 - zeta * zeta).sqrt();
            let truth = (-zeta * omega * dt).exp()
                * ((wd * dt).cos() + zeta * omega / wd * (wd * dt).sin());
            let (rho, err) = ratio(
                q.len() - 1,
                |t| q[t][n - 1] * q[t + 1][n - 1],
                |t| q[t][n - 1] * q[t][n - 1],
            );
            println!("clamped {clamped} mode {n}: lag-1 ρ {rho:.4} ± {err:.4} against {truth:.4}");
            // The exact step's own: E[qₜ₊₁qₜ] = Φ_qq P_qq with P diagonal.
            let exact = d.phi[(n - 1, n - 1)];
            assert!(
                (exact - truth).abs() < 1e-9,
                "mode {n}: Φ {exact} against {truth}"
            );
            assert!(
                (rho - truth).abs() < 4.0 * err + 1e-3,
                "mode {n}: {rho} {truth}"
            );
        }
    }
}

/// The sample covariance of the states against the stationary covariance, and the probability
/// current Jᵢⱼ = E[qᵢq̇ⱼ] − E[qⱼq̇ᵢ] normalised by √(E[qᵢ²]E[q̇ⱼ²]): (sample, error, P's value).
fn current(beam: &Beam, seed: u64, i: usize, j: usize) -> (f64, f64, f64) {
    let d = discretise(beam);
    let m = beam.modes;
    let x = states(beam, seed);
    let p = &d.stationary;
    let (qi, vj, qj, vi) = (i, m + j, j, m + i);
    let norm = (p[(qi, qi)] * p[(vj, vj)]).sqrt();
    // The sample covariance of q₁…q₃, q̇₁…q̇₃ against P.
    let idx = [0, 1, 2, m, m + 1, m + 2];
    for &k in &idx {
        for &l in &idx {
            let (s, err) = batched(x.len(), |t| x[t][k] * x[t][l]);
            let scale = (p[(k, k)] * p[(l, l)]).sqrt();
            assert!(
                (s - p[(k, l)]).abs() < 4.0 * err + 1e-3 * scale,
                "a = {}: covariance ({k}, {l}) {s:e} ± {err:e} against P's {:e}",
                beam.a,
                p[(k, l)]
            );
        }
    }
    let (j_sample, err) = batched(x.len(), |t| {
        (x[t][qi] * x[t][vj] - x[t][qj] * x[t][vi]) / norm
    });
    (j_sample, err, (p[(qi, vj)] - p[(qj, vi)]) / norm)
}

#[test]
fn active_current() {
    for clamped in [false, true] {
        let active = Beam {
            frames: FRAMES,
            ..Beam::active(clamped)
        };
        let d = discretise(&active);
        println!(
            "clamped {clamped}: a = {}, margin {:.4e}, Δt {:.4}, slowest {:.4?}",
            active.a,
            d.margin(),
            d.dt,
            {
                let mut e = d.eigenvalues.clone();
                e.sort_by(|x, y| y.0.total_cmp(&x.0));
                e.into_iter()
                    .filter(|z| z.1 >= 0.0)
                    .take(3)
                    .collect::<Vec<_>>()
            }
        );
        // P solves the continuous Lyapunov equation F P + P Fᵀ + G Gᵀ = 0: Φ and Q are the
        // exact discretisation.
        let f = &d.drift;
        let residual = f * &d.stationary + &d.stationary * f.transpose() + &d.diffusion;
        assert!(
            residual.amax() < 1e-9 * d.diffusion.amax(),
            "{:e}",
            residual.amax()
        );
        // Not equipartition: the first mode's variance off T/(cλ₁).
        let equipartition = active.temperature / (active.c * d.lambda[0]);
        assert!((d.stationary[(0, 0)] / equipartition - 1.0).abs() > 0.1);
        let passive = Beam { a: 0.0, ..active };
        for (i, j) in [(0, 1), (1, 2)] {
            let (s, err, truth) = current(&active, 11, i, j);
            println!(
                "clamped {clamped} J{}{}: {s:.4} ± {err:.4}, P's {truth:.4}",
                i + 1,
                j + 1
            );
            assert!(
                (s - truth).abs() < 4.0 * err,
                "J = {s} ± {err} against {truth}"
            );
            if (i, j) == (1, 2) {
                assert!(
                    s.abs() > 8.0 * err && truth.abs() > 0.05,
                    "no current: {s} ± {err}"
                );
            }
            let (s, err, truth) = current(&passive, 11, i, j);
            assert!(
                truth.abs() < 1e-9 && s.abs() < 4.0 * err,
                "a = 0: J = {s} ± {err}"
            );
        }
    }
}

#[test]
#[should_panic(expected = "an unstable beam")]
fn unstable_refused() {
    discretise(&Beam {
        a: 40.0 * C,
        ..Beam::active(false)
    });
}

#[test]
fn lost_frames_in_bursts() {
    let beam = Beam {
        frames: 2000,
        ..Beam::active(true)
    };
    let text = record(&beam, 3);
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("t,x1,y1,x2,y2") && header.ends_with(",x25,y25"));
    let times: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.len(), 1900);
    let dt = beam.dt();
    let mut bursts = 0;
    for w in times.windows(2) {
        let step = (w[1] - w[0]) / dt;
        assert!((step - step.round()).abs() < 1e-6 && step.round() >= 1.0);
        assert!(step.round() <= 31.0, "a gap of {step} frames");
        bursts += usize::from(step.round() > 1.0);
    }
    assert!(bursts >= 10, "{bursts} gaps");
    assert_eq!(kept(&beam, 3).iter().filter(|k| !**k).count(), 100);
    // The loss changes nothing else: the kept frames are the lossless recording's.
    let whole = record(&Beam { lost: 0.0, ..beam }, 3);
    let all: std::collections::HashSet<&str> = whole.lines().collect();
    assert!(text.lines().all(|l| all.contains(l)));
}

#[test]
fn fit_reads_kappa() {
    let beam = Beam {
        noise: 0.01 * common::continuum::AMPLITUDE,
        ..Beam::passive(false)
    };
    let report = fitted(&record(&beam, 5), false, 12, None);
    let c = report.continuum.expect("a continuum constant");
    println!("κ {} {:?} truth {}", c.constant, c.interval, beam.kappa());
    assert!(
        (c.constant / beam.kappa() - 1.0).abs() < 0.03,
        "κ = {}",
        c.constant
    );
}
