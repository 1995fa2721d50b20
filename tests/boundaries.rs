//! Per-end boundaries: every end combination of the string (k = 1) and the beam (k = 2) against
//! faer's dense solver on the exact integer matrix, the continuum limits of the textbook beams
//! and strings, and the structured O(N)-memory method against both.

// Textbook values, typed as printed.
#![allow(clippy::approx_constant)]

use faer::Mat;
use theory_search::discretise::{operator_matrix, stencil_rows};
use theory_search::modal::{continuum_beta, spectrum, subspace, Method};
use theory_search::model::{Boundary, End};

fn all_ends() -> Vec<Boundary> {
    let mut out = vec![];
    for tail in End::ALL {
        for head in End::ALL {
            out.push(Boundary::Ends { tail, head });
        }
    }
    out
}

/// Eigenvalues of the exact integer matrix by faer's dense solver: the independent oracle.
fn dense_oracle(k: u32, b: Boundary, points: usize) -> Vec<f64> {
    let m = operator_matrix(k, b, points).unwrap();
    let n = m.len();
    let a = Mat::<f64>::from_fn(n, n, |i, j| m[i][j] as f64);
    let evd = a.self_adjoint_eigen(faer::Side::Lower).unwrap();
    let s = evd.S().column_vector();
    (0..n).map(|i| s[i]).collect()
}

#[test]
fn every_end_combination_matches_dense_faer() {
    for k in [1u32, 2] {
        for b in all_ends() {
            for points in 5..=60 {
                let s = spectrum(k, b, points, None, true).unwrap();
                let want = dense_oracle(k, b, points);
                assert_eq!(s.eigenvalues.len(), want.len(), "{b} k={k} N={points}");
                for (got, want) in s.eigenvalues.iter().zip(&want) {
                    assert!(
                        (got - want).abs() < 1e-10,
                        "{b} k={k} N={points}: {got} vs {want}"
                    );
                }
                // Zero modes come out of the boundary.
                let zeros = want.iter().filter(|l| l.abs() < 1e-9).count();
                assert_eq!(s.nullity, zeros, "{b} k={k} N={points}");
                assert_eq!(b.nullity(k), zeros);
                // Shapes are eigenvectors: ‖Dv − λv‖ small.
                let shapes = s.shapes.unwrap();
                let m = operator_matrix(k, b, points).unwrap();
                // Shapes live on the body: zero at held points, the unknowns after the tail's.
                let (tail, head) = b.held(k);
                assert_eq!(shapes.nrows(), points);
                for c in 0..shapes.ncols() {
                    for q in (0..tail).chain(points - head..points) {
                        assert_eq!(shapes[(q, c)], 0.0);
                    }
                }
                let shapes = shapes.subrows(tail, m.len());
                for (c, lam) in s.eigenvalues.iter().enumerate() {
                    let res: f64 = (0..m.len())
                        .map(|i| {
                            let dv: f64 =
                                (0..m.len()).map(|j| m[i][j] as f64 * shapes[(j, c)]).sum();
                            (dv - lam * shapes[(i, c)]).powi(2)
                        })
                        .sum();
                    assert!(res.sqrt() < 1e-8, "{b} k={k} N={points} mode {c}: {res}");
                }
            }
        }
    }
}

#[test]
fn a_cantilever_has_no_zero_mode_and_pinned_free_one() {
    let cantilever = Boundary::Ends {
        tail: End::Free,
        head: End::Clamped,
    };
    assert_eq!(cantilever.nullity(2), 0);
    let pinned_free = Boundary::Ends {
        tail: End::Pinned,
        head: End::Free,
    };
    assert_eq!(pinned_free.nullity(2), 1);
    assert_eq!(Boundary::FREE.nullity(2), 2);
    assert_eq!(Boundary::CLAMPED.nullity(1), 0);
    // Held points are not unknowns; every row still has k + 1 points of the body.
    assert_eq!(cantilever.unknowns(2, 20), 18);
    assert_eq!(stencil_rows(2, cantilever, 20).unwrap().len(), 18);
}

/// βᵢL from the i-th non-zero eigenvalue on N points.
fn beta(k: u32, lam: f64, points: usize) -> f64 {
    (points as f64 - 1.0) * lam.powf(1.0 / (2 * k) as f64)
}

#[test]
fn continuum_limits_of_the_textbook_beams() {
    let named = [
        (
            End::Clamped,
            End::Free,
            [1.87510, 4.69409, 7.85476, 10.99554],
        ),
        (
            End::Pinned,
            End::Pinned,
            [3.14159, 6.28319, 9.42478, 12.56637],
        ),
        (
            End::Clamped,
            End::Clamped,
            [4.73004, 7.85320, 10.99561, 14.13717],
        ),
        (
            End::Pinned,
            End::Free,
            [3.92660, 7.06858, 10.21018, 13.35177],
        ),
        (
            End::Clamped,
            End::Pinned,
            [3.92660, 7.06858, 10.21018, 13.35177],
        ),
    ];
    for (tail, head, want) in named {
        for b in [
            Boundary::Ends { tail, head },
            Boundary::Ends {
                tail: head,
                head: tail,
            },
        ] {
            for (i, w) in want.iter().enumerate() {
                let c = continuum_beta(2, b, i + 1).unwrap();
                assert!((c - w).abs() < 1e-5, "{b}: β{} = {c}, textbook {w}", i + 1);
            }
            // Within 0.2 % at N = 2000, the error shrinking as N doubles.
            let mut last = f64::INFINITY;
            for points in [500, 1000, 2000] {
                let s = spectrum(2, b, points, Some(b.nullity(2) + 4), false).unwrap();
                let worst = (0..4)
                    .map(|i| {
                        let lam = s.eigenvalues[s.nullity + i];
                        (beta(2, lam, points) / want[i] - 1.0).abs()
                    })
                    .fold(0.0, f64::max);
                assert!(
                    worst < last,
                    "{b}: error {worst} at N = {points}, {last} before"
                );
                last = worst;
            }
            assert!(last < 2e-3, "{b}: {last} at N = 2000");
        }
    }
}

#[test]
fn string_closed_forms() {
    for points in [5usize, 17, 64] {
        let nf = points as f64;
        // Fixed–fixed: λᵢ = 2 − 2cos(πi/(N−1)).
        let s = spectrum(1, Boundary::CLAMPED, points, None, false).unwrap();
        for (i, lam) in s.eigenvalues.iter().enumerate() {
            let want = 2.0 - 2.0 * (std::f64::consts::PI * (i + 1) as f64 / (nf - 1.0)).cos();
            assert!((lam - want).abs() < 1e-12);
        }
        // Fixed–free: λᵢ = 2 − 2cos(π(2i−1)/(2N−1)).
        for b in [
            Boundary::Ends {
                tail: End::Pinned,
                head: End::Free,
            },
            Boundary::Ends {
                tail: End::Free,
                head: End::Clamped,
            },
        ] {
            let s = spectrum(1, b, points, None, false).unwrap();
            assert_eq!(s.method, Method::ClosedForm);
            for (i, lam) in s.eigenvalues.iter().enumerate() {
                let want = 2.0
                    - 2.0 * (std::f64::consts::PI * (2 * i + 1) as f64 / (2.0 * nf - 1.0)).cos();
                assert!((lam - want).abs() < 1e-12);
            }
        }
    }
    for b in all_ends() {
        let s = spectrum(1, b, 4000, Some(b.nullity(1) + 3), false).unwrap();
        for i in 0..3 {
            let got = beta(1, s.eigenvalues[s.nullity + i], 4000);
            let want = continuum_beta(1, b, i + 1).unwrap();
            assert!((got / want - 1.0).abs() < 1e-3, "{b}: {got} vs {want}");
        }
    }
}

#[test]
fn the_structured_method_agrees_with_dense_and_holds_long_bodies() {
    for k in [1u32, 2, 3] {
        for b in all_ends() {
            for points in [9usize, 30, 61] {
                let want = dense_oracle(k, b, points);
                let count = (b.nullity(k) + 3).min(want.len());
                let s = subspace(k, b, points, count, true).unwrap();
                for (got, w) in s.eigenvalues.iter().zip(&want) {
                    assert!(
                        (got - w).abs() < 1e-10 * w.abs().max(1e-3),
                        "{b} k={k} N={points}: {got} vs {w}"
                    );
                }
                let nonzero: f64 = want
                    .iter()
                    .filter(|l| l.abs() > 1e-9)
                    .map(|l| 1.0 / l)
                    .sum();
                // Takahashi's recurrence loses about ε·cond(S) of relative accuracy.
                let tol = if k == 3 { 1e-6 } else { 1e-8 };
                assert!(
                    (s.inverse_trace / nonzero - 1.0).abs() < tol,
                    "{b} k={k} N={points}: Σ1/λ {} vs {nonzero}",
                    s.inverse_trace
                );
            }
        }
    }
    // A long cantilever: O(N) memory, the continuum limit to 1e-4.
    let cantilever = Boundary::Ends {
        tail: End::Free,
        head: End::Clamped,
    };
    let s = spectrum(2, cantilever, 200_000, Some(3), true).unwrap();
    assert_eq!(s.method, Method::Subspace);
    for i in 0..3 {
        let got = beta(2, s.eigenvalues[i], 200_000);
        let want = continuum_beta(2, cantilever, i + 1).unwrap();
        assert!((got / want - 1.0).abs() < 1e-4, "{got} vs {want}");
    }
}

#[test]
fn the_trace_of_the_pseudo_inverse_is_an_exact_polynomial_in_n() {
    use theory_search::modal::trace_polynomial;
    for k in [1u32, 2, 3] {
        for b in all_ends() {
            for points in [25usize, 47] {
                // k = 1 and 2 always give one; k = 3 with natural conditions at an end carries
                // boundary layers that decay geometrically in N, so none is claimed there.
                let Some(got) = trace_polynomial(k, b, points) else {
                    assert_eq!(k, 3, "{b} k={k}: no polynomial found");
                    continue;
                };
                let want: f64 = dense_oracle(k, b, points)
                    .iter()
                    .filter(|l| l.abs() > 1e-9)
                    .map(|l| 1.0 / l)
                    .sum();
                // The dense sum is itself only good to about ε·cond.
                assert!(
                    (got / want - 1.0).abs() < 1e-7,
                    "{b} k={k} N={points}: {got} vs {want}"
                );
            }
        }
    }
    // The cantilever's is N⁴/12 to leading order: Σ(βᵢL)⁻⁴ = 1/12 for the clamped–free beam.
    let cantilever = Boundary::Ends {
        tail: End::Free,
        head: End::Clamped,
    };
    let n = 1e6;
    let t = trace_polynomial(2, cantilever, 1_000_000).unwrap();
    assert!((t / (n * n * n * n / 12.0) - 1.0).abs() < 1e-5, "{t}");
}
