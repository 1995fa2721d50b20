//! Scenario: the modes of the larva's operators. Every structured method (closed forms, the D4
//! characteristic equation, banded shapes, Σ1/λ by selected inversion) against faer's dense
//! self-adjoint eigensolver on the exact operator.

use faer::Mat;
use theory_search::discretise::operator_matrix;
use theory_search::modal::{spectrum, Method, Spectrum};
use theory_search::model::Boundary;

/// All eigenvalues and vectors of the exact operator, densely.
fn dense_reference(
    k: u32,
    boundary: Boundary,
    points: usize,
) -> (Vec<f64>, Mat<f64>, Vec<Vec<i64>>) {
    let m = operator_matrix(k, boundary, points).unwrap();
    let n = m.len();
    let a = Mat::<f64>::from_fn(n, n, |i, j| m[i][j] as f64);
    let evd = a.self_adjoint_eigen(faer::Side::Lower).unwrap();
    let s = evd.S().column_vector();
    ((0..n).map(|i| s[i]).collect(), evd.U().to_owned(), m)
}

/// Every computed eigenpair satisfies D v = λ v to `tol`, shapes are orthonormal, eigenvalues
/// match the dense ones.
fn check(k: u32, boundary: Boundary, points: usize, s: &Spectrum, tol: f64) {
    let (reference, _, m) = dense_reference(k, boundary, points);
    let scale = reference.last().copied().unwrap_or(1.0).max(1.0);
    assert!(
        !s.eigenvalues.is_empty(),
        "k={k} {boundary:?} N={points}: no eigenvalue"
    );
    assert!(
        s.eigenvalues.len() <= reference.len(),
        "k={k} {boundary:?} N={points}: more eigenvalues than unknowns"
    );
    for (i, (got, want)) in s.eigenvalues.iter().zip(&reference).enumerate() {
        assert!(
            (got - want).abs() <= tol * scale,
            "k={k} {boundary:?} N={points} λ{i}: {got} vs {want}"
        );
    }
    // Dense small eigenvalues carry an absolute error ~ ε·λmax, so Σ1/λ is only known from them
    // to about ε·λmax/λmin relative.
    let dense_trace: f64 = reference[s.nullity..].iter().map(|l| 1.0 / l).sum();
    let dense_tol = 1e-13 * scale / reference.get(s.nullity).copied().unwrap_or(1.0);
    assert!(
        (s.inverse_trace - dense_trace).abs() <= dense_tol.max(1e-12) * dense_trace,
        "Σ1/λ {} vs {dense_trace}",
        s.inverse_trace
    );
    if s.eigenvalues.len() == reference.len() {
        let own: f64 = s.eigenvalues[s.nullity..].iter().map(|l| 1.0 / l).sum();
        assert!(
            (own - s.inverse_trace).abs() <= 1e-11 * own,
            "Σ1/λ of own eigenvalues {own} vs {}",
            s.inverse_trace
        );
    }
    if let Some(body) = &s.shapes {
        // Shapes live on the body; the operator acts on the unknowns after the held tail.
        let n = m.len();
        let v = body.subrows(s.held.0, n);
        for c in 0..v.ncols() {
            let lam = s.eigenvalues[c];
            for i in 0..n {
                let dv: f64 = (0..n).map(|j| m[i][j] as f64 * v[(j, c)]).sum();
                assert!(
                    (dv - lam * v[(i, c)]).abs() <= tol * scale,
                    "residual of mode {c} at N={points}"
                );
            }
            for d in 0..=c {
                let dot: f64 = (0..n).map(|i| v[(i, c)] * v[(i, d)]).sum();
                let want = if c == d { 1.0 } else { 0.0 };
                assert!(
                    (dot - want).abs() < 1e-9,
                    "orthonormality {c},{d} at N={points}"
                );
            }
            let first = (0..n).map(|i| v[(i, c)]).find(|x| x.abs() > 1e-6).unwrap();
            assert!(first > 0.0, "sign convention");
        }
    }
}

#[test]
fn closed_forms_agree_with_dense_at_every_size() {
    for points in 3..=80 {
        let s = spectrum(1, Boundary::Periodic, points, None, true).unwrap();
        assert_eq!(s.method, Method::ClosedForm);
        check(1, Boundary::Periodic, points, &s, 1e-12);
        let s = spectrum(1, Boundary::FREE, points, None, true).unwrap();
        assert_eq!(s.method, Method::ClosedForm);
        check(1, Boundary::FREE, points, &s, 1e-12);
    }
}

#[test]
fn d4_characteristic_equation_agrees_with_dense() {
    for points in (3..=60).chain([101, 150, 201]) {
        let s = spectrum(2, Boundary::FREE, points, None, points <= 60).unwrap();
        assert_eq!(s.method, Method::Characteristic, "N = {points}");
        assert_eq!(s.eigenvalues.len(), points);
        check(2, Boundary::FREE, points, &s, 1e-12);
    }
}

#[test]
fn lowest_modes_only() {
    let all = spectrum(2, Boundary::FREE, 300, None, false).unwrap();
    let few = spectrum(2, Boundary::FREE, 300, Some(7), true).unwrap();
    assert_eq!(few.eigenvalues.len(), 7);
    assert_eq!(&all.eigenvalues[..7], &few.eigenvalues[..]);
    assert_eq!(all.inverse_trace, few.inverse_trace);
    check(2, Boundary::FREE, 300, &few, 1e-11);
}

/// Above N ≈ 121 600 the top two beam eigenvalues are closer than the inertia check's old fixed
/// gap (1e-9·λ_top), which sent every mode to the dense solver and failed; the gap now follows
/// the spacing. Every mode at N = 121 700 and N = 150 000, against the lowest-K path.
#[test]
fn every_beam_mode_just_above_the_old_limit() {
    for points in [121_700, 150_000] {
        let all = spectrum(2, Boundary::FREE, points, None, false)
            .unwrap_or_else(|e| panic!("N = {points}: {e}"));
        assert_eq!(all.eigenvalues.len(), points);
        assert_eq!(all.method, Method::Characteristic);
        let few = spectrum(2, Boundary::FREE, points, Some(12), false).unwrap();
        assert_eq!(few.eigenvalues.len(), 12);
        for (i, (a, b)) in all.eigenvalues.iter().zip(&few.eigenvalues).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1e-300),
                "N = {points}, λ{i}: {a} vs {b}"
            );
        }
        assert!(
            all.eigenvalues.windows(2).all(|w| w[0] <= w[1]),
            "ascending"
        );
        // The top of the spectrum approaches 16 (the stencil's symbol at the Nyquist wave).
        let top = all.eigenvalues[points - 1];
        assert!(top < 16.0 && top > 15.999, "N = {points}: λ_top = {top}");
    }
}

#[test]
fn other_operators_use_the_dense_solver() {
    for (k, boundary) in [
        (3, Boundary::FREE),
        (2, Boundary::CLAMPED),
        (2, Boundary::Periodic),
    ] {
        for points in [6, 13, 40] {
            let s = spectrum(k, boundary, points, None, true).unwrap();
            check(k, boundary, points, &s, 1e-10);
        }
    }
}

#[test]
fn sums_of_inverse_eigenvalues_match_closed_forms() {
    // Σ over non-zero modes: (n²−1)/12 for D2,c (n = N−1), (N²−1)/6 for D2,f.
    for points in [3usize, 12, 1000, 100_000] {
        let n = (points - 1) as f64;
        let s = spectrum(1, Boundary::Periodic, points, Some(3), false).unwrap();
        assert!((s.inverse_trace - (n * n - 1.0) / 12.0).abs() < 1e-9 * n * n);
        let nf = points as f64;
        let s = spectrum(1, Boundary::FREE, points, Some(3), false).unwrap();
        assert!((s.inverse_trace - (nf * nf - 1.0) / 6.0).abs() < 1e-9 * nf * nf);
    }
}

#[test]
fn too_few_points_is_an_error() {
    assert!(spectrum(1, Boundary::Periodic, 2, None, false).is_err());
    assert!(spectrum(2, Boundary::FREE, 2, None, false).is_err());
    assert!(spectrum(1, Boundary::FREE, 1, None, false).is_err());
}

/// tr((SSᵀ)⁻¹) by exact Gauss–Jordan elimination over the rationals.
fn exact_d4_inverse_trace(points: usize) -> num_rational::Ratio<i128> {
    use num_rational::Ratio;
    let m = points - 2;
    let mut a: Vec<Vec<Ratio<i128>>> = (0..m)
        .map(|i| {
            (0..m)
                .map(|j| {
                    let v = match i.abs_diff(j) {
                        0 => 6,
                        1 => -4,
                        2 => 1,
                        _ => 0,
                    };
                    Ratio::from_integer(v)
                })
                .collect()
        })
        .collect();
    let mut inv: Vec<Vec<Ratio<i128>>> = (0..m)
        .map(|i| {
            (0..m)
                .map(|j| Ratio::from_integer((i == j) as i128))
                .collect()
        })
        .collect();
    for c in 0..m {
        let p = (c..m).find(|&r| a[r][c] != Ratio::from_integer(0)).unwrap();
        a.swap(c, p);
        inv.swap(c, p);
        let piv = a[c][c];
        for j in 0..m {
            a[c][j] /= piv;
            inv[c][j] /= piv;
        }
        for r in 0..m {
            if r != c && a[r][c] != Ratio::from_integer(0) {
                let f = a[r][c];
                for j in 0..m {
                    let (x, y) = (a[c][j], inv[c][j]);
                    a[r][j] -= f * x;
                    inv[r][j] -= f * y;
                }
            }
        }
    }
    (0..m).map(|i| inv[i][i]).sum()
}

#[test]
fn d4_inverse_trace_polynomial_is_exact() {
    use num_rational::Ratio;
    for points in 3..=24usize {
        let n = points as i128;
        let poly = Ratio::new(n.pow(4) + n * n - 20, 420);
        assert_eq!(exact_d4_inverse_trace(points), poly, "N = {points}");
    }
    // At large N it agrees with the sum over the characteristic-equation eigenvalues.
    for points in [500usize, 2000] {
        let s = spectrum(2, Boundary::FREE, points, None, false).unwrap();
        let own: f64 = s.eigenvalues[2..].iter().map(|l| 1.0 / l).sum();
        assert!(
            (own - s.inverse_trace).abs() <= 1e-10 * own,
            "N = {points}: {own} vs {}",
            s.inverse_trace
        );
    }
}

use theory_search::modal::{field_modes, Params, Regime};
use theory_search::model::Model;

#[test]
fn larva_at_12_points_has_the_operators_equipartition_shares() {
    let modes = field_modes(&Model::larva(), 4, 12, &Params::default(), None, false).unwrap();
    let x = &modes[0];
    // First four axial modes (two cos/sin pairs) over all non-zero modes: 80.10 %.
    assert!(
        (x.modes[4].cumulative_share - 0.8010).abs() < 5e-5,
        "{}",
        x.modes[4].cumulative_share
    );
    assert_eq!(
        x.degenerate_pairs,
        [(1, 2), (3, 4), (5, 6), (7, 8), (9, 10)]
    );
    assert_eq!(x.modes[0].zero_mode.as_deref(), Some("axial translation"));
    assert_eq!(x.modes[0].variance_share, 0.0);
    let y = &modes[2];
    // First four transverse non-zero modes: 98.33 %.
    assert!(
        (y.modes[5].cumulative_share - 0.9833).abs() < 5e-5,
        "{}",
        y.modes[5].cumulative_share
    );
    assert_eq!(
        y.modes[1].zero_mode.as_deref(),
        Some("mediolateral rotation")
    );
    assert!(y.degenerate_pairs.is_empty());
    assert_eq!(modes[3].same_frequencies_as.as_deref(), Some("y"));
    assert_eq!(
        modes[1].modes[0].zero_mode.as_deref(),
        Some("rotation about the axis")
    );
    for f in &modes {
        let total: f64 = f.modes.iter().map(|m| m.variance_share).sum();
        assert!((total - 1.0).abs() < 1e-12);
        assert!(f
            .modes
            .windows(2)
            .all(|w| w[0].eigenvalue <= w[1].eigenvalue));
    }
}

#[test]
fn frequencies_and_damping_scale_with_the_parameters() {
    let mut p = Params::default();
    p.set("omega_b", 3.0).unwrap();
    p.set("zeta_b", 0.5).unwrap();
    let modes = field_modes(&Model::larva(), 4, 20, &p, Some(6), false).unwrap();
    let y = &modes[2];
    for m in &y.modes {
        assert!((m.frequency - 3.0 * m.eigenvalue.sqrt()).abs() < 1e-15);
        assert!((m.damping_ratio - 0.5 * m.eigenvalue.sqrt()).abs() < 1e-15);
        if let Some(wd) = m.damped_frequency {
            assert!((wd - m.frequency * (1.0 - m.damping_ratio.powi(2)).sqrt()).abs() < 1e-15);
        }
    }
    // Critical damping of the first bending mode, overdamping above it.
    let lam = y.modes[2].eigenvalue;
    let mut p = Params::default();
    p.set("zeta_b", 1.0 / lam.sqrt()).unwrap();
    let y = &field_modes(&Model::larva(), 4, 20, &p, Some(6), false).unwrap()[2];
    assert_eq!(y.modes[2].regime, Regime::Critical);
    assert_eq!(y.modes[3].regime, Regime::Overdamped);
    assert_eq!(y.modes[0].regime, Regime::Free);
    assert!(y.modes[3].damped_frequency.is_none());
}

#[test]
fn bad_parameters_are_rejected() {
    let mut p = Params::default();
    for (name, value) in [
        ("omega_b", f64::NAN),
        ("omega_b", -1.0),
        ("omega_b", 0.0),
        ("zeta_s", -0.1),
        ("zeta_t", f64::INFINITY),
        ("omegab", 1.0),
        ("kappa_b", 1.0),
    ] {
        assert!(p.set(name, value).is_err(), "{name} = {value}");
    }
    assert!(p.set_assignment("omega_b").is_err());
    assert!(p.set_assignment("omega_b=fast").is_err());
    assert!(p.set_from_toml("omega_b = \"x\"").is_err());
    assert!(p.set_from_toml("omega_b = 2\nzeta_b = 0.25").is_ok());
    assert_eq!((p.omega("b"), p.zeta("b")), (2.0, 0.25));
}

#[test]
fn d4_converges_to_the_beam_not_to_eq_17() {
    let first = |points: usize| {
        let modes = field_modes(
            &Model::larva(),
            4,
            points,
            &Params::default(),
            Some(3),
            false,
        )
        .unwrap();
        let b = modes[2].beam[0].clone();
        (
            (b.continuum - b.eigenvalue) / b.eigenvalue,
            (b.seed_eq17.unwrap() - b.eigenvalue) / b.eigenvalue,
        )
    };
    let (beam_small, _) = first(12);
    let (beam_large, eq17_large) = first(100_000);
    assert!(beam_small.abs() > 0.1);
    assert!(beam_large.abs() < 1e-4, "{beam_large}");
    // Eq. 17 stays off by 1 − (π/β₁L)⁴ ≈ 80.5 %.
    assert!((eq17_large + 0.8054).abs() < 1e-3, "{eq17_large}");
}
