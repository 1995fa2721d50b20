//! The module's own checks.

use super::*;

#[test]
fn the_closed_form_transition_is_van_loans() {
    for (omega, zeta, dt) in [
        (1.3, 0.05, 0.7),
        (2.9, 0.4, 1.0),
        (0.5, 3.0, 0.3),
        (1.0, 1.0, 0.5),
    ] {
        let p = Oscillator {
            omega,
            zeta,
            variance: 2.0,
            noise: 0.1,
        };
        let (phi, q) = p.transition(dt);
        let (phi2, q2) = discretise(&p.drift(), &p.diffusion(), dt).expect("discretised");
        for i in 0..2 {
            for j in 0..2 {
                assert!(
                    (phi[(i, j)] - phi2[(i, j)]).abs() < 1e-10,
                    "Φ {omega} {zeta}"
                );
                assert!(
                    (q[(i, j)] - q2[(i, j)]).abs() < 1e-9 * (1.0 + q2[(i, j)].abs()),
                    "Q {omega} {zeta}: {q} {q2}"
                );
            }
        }
    }
}

#[test]
fn the_filter_equals_the_gaussian_density_of_a_short_series() {
    // The exact −2 ln L of y ~ N(0, C + νI), C the sampled autocovariance, against the filter.
    let p = Oscillator {
        omega: 1.1,
        zeta: 0.2,
        variance: 1.5,
        noise: 0.3,
    };
    let y = [0.3, -1.2, f64::NAN, 0.8, 1.9, -0.4, f64::NAN, f64::NAN, 0.1];
    let exact = dense_log_likelihood(&p, &y);
    let (filtered, seen) = log_likelihood(&p, &[&y], 1.0);
    assert_eq!(seen, y.iter().filter(|v| v.is_finite()).count());
    assert!((filtered - exact).abs() < 1e-10, "{filtered} {exact}");
}

#[test]
fn bad_input_is_refused() {
    let p = Oscillator {
        omega: 1.0,
        zeta: 0.1,
        variance: 1.0,
        noise: 0.1,
    };
    assert!(matches!(
        fit_oscillator(&[&[1.0; 40]], 0.0, p),
        Err(StateSpaceError::Interval(_))
    ));
    assert!(matches!(
        fit_oscillator(&[&[1.0; 10]], 1.0, p),
        Err(StateSpaceError::TooFewFrames(10))
    ));
    let bad = Oscillator {
        zeta: f64::NAN,
        ..p
    };
    assert!(fit_oscillator(&[&[1.0; 40]], 1.0, bad).is_err());
    let f = DMatrix::zeros(2, 3);
    assert!(discretise(&f, &DMatrix::zeros(2, 2), 1.0).is_err());
}

/// ln L of the observed frames of `y` (Δt = 1) as one Gaussian vector: N(0, C + νI), C the
/// sampled autocovariance, by a dense Cholesky factor (the filter's independent oracle).
fn dense_log_likelihood(p: &Oscillator, y: &[f64]) -> f64 {
    let kept: Vec<usize> = (0..y.len()).filter(|&i| y[i].is_finite()).collect();
    let (phi, _) = p.transition(1.0);
    let mut power: Matrix2<f64> = Matrix2::identity();
    let mut lags = Vec::new();
    for _ in 0..y.len() {
        lags.push((power * p.stationary())[(0, 0)]);
        power *= phi;
    }
    let n = kept.len();
    let cov = DMatrix::from_fn(n, n, |a, b| {
        lags[kept[a].abs_diff(kept[b])] + if a == b { p.noise } else { 0.0 }
    });
    let v = nalgebra::DVector::from_iterator(n, kept.iter().map(|&i| y[i]));
    let chol = cov.cholesky().expect("positive");
    let logdet: f64 = 2.0 * chol.l().diagonal().iter().map(|d| d.ln()).sum::<f64>();
    -0.5 * (n as f64 * (2.0 * std::f64::consts::PI).ln() + logdet + v.dot(&chol.solve(&v)))
}

#[test]
fn the_steady_filter_across_irregular_gaps_equals_the_gaussian_density() {
    // 400 frames of a sharp line (the steady gain is reached between gaps), beginning with a lost
    // frame and losing more at irregular places: the steady-state shortcut and its reset are
    // exact. (A series beginning lost once froze the stationary gain: ln L off by 2×.)
    let p = Oscillator {
        omega: 0.45,
        zeta: 0.05,
        variance: 1.5,
        noise: 0.02,
    };
    let y: Vec<f64> = (0..400)
        .map(|i| {
            let t = i as f64;
            let lost = (t * 0.61).sin() > 0.93 || (t * 0.137).cos() > 0.97;
            if lost {
                f64::NAN
            } else {
                (0.45 * t).sin() + 0.3 * (1.7 * t).cos()
            }
        })
        .collect();
    let gaps = y.iter().filter(|v| v.is_nan()).count();
    assert!((20..100).contains(&gaps), "{gaps} lost frames");
    let (filtered, _) = log_likelihood(&p, &[&y], 1.0);
    let exact = dense_log_likelihood(&p, &y);
    assert!(
        (filtered - exact).abs() < 1e-8 * exact.abs(),
        "{filtered} {exact}"
    );
}
