//! Scenario: the difference operators derived from the survivors are the seed's D2,c, D2,f and
//! D4 (Eq. 3–5) exactly, at every size where the stencil fits; they generalise to k = 3 and to
//! other boundaries; and the generated Rust code agrees with them.

// Matrix code reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use num_rational::Rational64;
use theory_search::discretise::{operator_matrix, operators, stencil};
use theory_search::generated::operators::OPERATORS;
use theory_search::generated::OperatorError;
use theory_search::model::{Boundary, End, Model};

type M = Vec<Vec<i64>>;

/// D2,c as the seed describes it: (N−1)×(N−1), 2 on the diagonal, −1 beside it and in the two
/// corners (entries that coincide add up).
fn seed_d2c(points: usize) -> M {
    let n = points - 1;
    let mut m = vec![vec![0; n]; n];
    for i in 0..n {
        m[i][i] += 2;
        m[i][(i + 1) % n] -= 1;
        m[(i + 1) % n][i] -= 1;
    }
    m
}

/// D2,f: N×N tridiagonal 2, −1 with the two end diagonal entries 1.
fn seed_d2f(n: usize) -> M {
    let mut m = vec![vec![0; n]; n];
    for i in 0..n {
        m[i][i] = if i == 0 || i == n - 1 { 1 } else { 2 };
        if i + 1 < n {
            m[i][i + 1] = -1;
            m[i + 1][i] = -1;
        }
    }
    m
}

/// D4: rows (1 −2 1), (−2 5 −4 1), then (1 −4 6 −4 1), mirrored at the head. N ≥ 4.
fn seed_d4(n: usize) -> M {
    let mut m = vec![vec![0; n]; n];
    for i in 0..n {
        for (off, v) in [(-2i64, 1), (-1, -4), (0, 6), (1, -4), (2, 1)] {
            let j = i as i64 + off;
            if j >= 0 && (j as usize) < n {
                m[i][j as usize] = v;
            }
        }
    }
    let head = [[1, -2, 1], [-2, 5, -4]];
    for (r, row) in head.iter().enumerate() {
        for (c, &v) in row.iter().enumerate() {
            m[r][c] = v;
            m[n - 1 - r][n - 1 - c] = v;
        }
    }
    m
}

#[test]
fn periodic_first_difference_is_d2c_at_every_size() {
    for points in 3..=64 {
        assert_eq!(
            operator_matrix(1, Boundary::Periodic, points).unwrap(),
            seed_d2c(points),
            "N = {points}"
        );
    }
}

#[test]
fn free_first_difference_is_d2f_at_every_size() {
    for points in 2..=64 {
        assert_eq!(
            operator_matrix(1, Boundary::FREE, points).unwrap(),
            seed_d2f(points),
            "N = {points}"
        );
    }
}

#[test]
fn free_second_difference_is_d4_at_every_size() {
    assert_eq!(
        operator_matrix(2, Boundary::FREE, 3).unwrap(),
        [[1, -2, 1], [-2, 4, -2], [1, -2, 1]]
    );
    for points in 4..=64 {
        assert_eq!(
            operator_matrix(2, Boundary::FREE, points).unwrap(),
            seed_d4(points),
            "N = {points}"
        );
    }
}

const D2C_12: &str = "
   2 -1  0  0  0  0  0  0  0  0 -1
  -1  2 -1  0  0  0  0  0  0  0  0
   0 -1  2 -1  0  0  0  0  0  0  0
   0  0 -1  2 -1  0  0  0  0  0  0
   0  0  0 -1  2 -1  0  0  0  0  0
   0  0  0  0 -1  2 -1  0  0  0  0
   0  0  0  0  0 -1  2 -1  0  0  0
   0  0  0  0  0  0 -1  2 -1  0  0
   0  0  0  0  0  0  0 -1  2 -1  0
   0  0  0  0  0  0  0  0 -1  2 -1
  -1  0  0  0  0  0  0  0  0 -1  2";

const D2F_12: &str = "
   1 -1  0  0  0  0  0  0  0  0  0  0
  -1  2 -1  0  0  0  0  0  0  0  0  0
   0 -1  2 -1  0  0  0  0  0  0  0  0
   0  0 -1  2 -1  0  0  0  0  0  0  0
   0  0  0 -1  2 -1  0  0  0  0  0  0
   0  0  0  0 -1  2 -1  0  0  0  0  0
   0  0  0  0  0 -1  2 -1  0  0  0  0
   0  0  0  0  0  0 -1  2 -1  0  0  0
   0  0  0  0  0  0  0 -1  2 -1  0  0
   0  0  0  0  0  0  0  0 -1  2 -1  0
   0  0  0  0  0  0  0  0  0 -1  2 -1
   0  0  0  0  0  0  0  0  0  0 -1  1";

const D4_12: &str = "
   1 -2  1  0  0  0  0  0  0  0  0  0
  -2  5 -4  1  0  0  0  0  0  0  0  0
   1 -4  6 -4  1  0  0  0  0  0  0  0
   0  1 -4  6 -4  1  0  0  0  0  0  0
   0  0  1 -4  6 -4  1  0  0  0  0  0
   0  0  0  1 -4  6 -4  1  0  0  0  0
   0  0  0  0  1 -4  6 -4  1  0  0  0
   0  0  0  0  0  1 -4  6 -4  1  0  0
   0  0  0  0  0  0  1 -4  6 -4  1  0
   0  0  0  0  0  0  0  1 -4  6 -4  1
   0  0  0  0  0  0  0  0  1 -4  5 -2
   0  0  0  0  0  0  0  0  0  1 -2  1";

fn parse(block: &str) -> M {
    block
        .trim()
        .lines()
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn larva_operators_at_12_points_are_the_seeds_mark_for_mark() {
    let ops = operators(&Model::larva(), 4, 12).unwrap();
    let find = |field: &str, density: &str| {
        ops.iter()
            .find(|o| o.field == field && o.density == density)
            .unwrap_or_else(|| panic!("no {field} {density} operator"))
    };
    for density in ["lagrangian", "rayleigh"] {
        assert_eq!(find("x", density).matrix, parse(D2C_12));
        assert_eq!(find("theta", density).matrix, parse(D2F_12));
        assert_eq!(find("y", density).matrix, parse(D4_12));
        assert_eq!(find("z", density).matrix, parse(D4_12));
    }
    assert_eq!(find("x", "lagrangian").term, "(∂s φ)²");
    assert_eq!(find("y", "rayleigh").term, "(∂tss φ)²");
    assert_eq!(find("x", "lagrangian").boundary, "periodic");
}

/// Exact rank by fraction-free Gaussian elimination over the rationals.
fn rank(m: &M) -> usize {
    let mut a: Vec<Vec<Rational64>> = m
        .iter()
        .map(|r| r.iter().map(|&v| Rational64::from_integer(v)).collect())
        .collect();
    let (rows, cols) = (a.len(), a.first().map_or(0, Vec::len));
    let mut rank = 0;
    for c in 0..cols {
        let Some(p) = (rank..rows).find(|&r| a[r][c] != Rational64::from_integer(0)) else {
            continue;
        };
        a.swap(rank, p);
        for r in 0..rows {
            if r != rank && a[r][c] != Rational64::from_integer(0) {
                let f = a[r][c] / a[rank][c];
                for k in c..cols {
                    let v = a[rank][k];
                    a[r][k] -= f * v;
                }
            }
        }
        rank += 1;
    }
    rank
}

fn times(m: &M, v: &[i64]) -> Vec<i64> {
    m.iter()
        .map(|r| r.iter().zip(v).map(|(a, b)| a * b).sum())
        .collect()
}

#[test]
fn operators_are_symmetric_psd_with_the_expected_null_spaces() {
    // (k, boundary, expected nullity, null vectors as polynomials of degree < nullity)
    let cases = [
        (1, Boundary::Periodic, 1),
        (2, Boundary::Periodic, 1),
        (1, Boundary::FREE, 1),
        (2, Boundary::FREE, 2),
        (3, Boundary::FREE, 3),
        (1, Boundary::CLAMPED, 0),
        (2, Boundary::CLAMPED, 0),
        (3, Boundary::CLAMPED, 0),
        (2, Boundary::PINNED, 0),
        (3, Boundary::PINNED, 1),
        (
            2,
            Boundary::Ends {
                tail: End::Pinned,
                head: End::Free,
            },
            1,
        ),
        (
            2,
            Boundary::Ends {
                tail: End::Free,
                head: End::Clamped,
            },
            0,
        ),
        (
            3,
            Boundary::Ends {
                tail: End::Free,
                head: End::Clamped,
            },
            1,
        ),
    ];
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    for (k, boundary, nullity) in cases {
        for points in [boundary.min_points(k), 7, 12, 25] {
            let m = operator_matrix(k, boundary, points).unwrap();
            let n = m.len();
            for i in 0..n {
                for j in 0..n {
                    assert_eq!(m[i][j], m[j][i]);
                }
            }
            assert_eq!(n - rank(&m), nullity, "k = {k}, {boundary:?}, N = {points}");
            // Polynomials of degree < nullity are the null space (free); constants (periodic).
            for deg in 0..nullity as u32 * u32::from(boundary.held(k) == (0, 0)) {
                let p: Vec<i64> = (0..n as i64).map(|i| i.pow(deg)).collect();
                assert!(
                    times(&m, &p).iter().all(|&v| v == 0),
                    "degree {deg} not null"
                );
            }
            // xᵀDx equals Σ(Δᵏx)² computed directly, so it is never negative.
            for _ in 0..5 {
                let x: Vec<i64> = (0..n)
                    .map(|_| {
                        seed ^= seed << 13;
                        seed ^= seed >> 7;
                        seed ^= seed << 17;
                        (seed % 11) as i64 - 5
                    })
                    .collect();
                let quad: i64 = x.iter().zip(times(&m, &x)).map(|(a, b)| a * b).sum();
                let w = stencil(k);
                // The whole body: held points are zeros, the unknowns fill the rest.
                let (tail, head) = boundary.held(k);
                let body: Vec<i64> = match boundary {
                    Boundary::Periodic => x.clone(),
                    _ => (0..points)
                        .map(|q| {
                            if q < tail || q >= points - head {
                                0
                            } else {
                                x[q - tail]
                            }
                        })
                        .collect(),
                };
                let at = |i: i64| -> i64 { body[i.rem_euclid(body.len() as i64) as usize] };
                let positions: Vec<i64> = match boundary {
                    Boundary::Periodic => (0..n as i64).collect(),
                    _ => (0..=(points as i64 - 1 - k as i64)).collect(),
                };
                let direct: i64 = positions
                    .iter()
                    .map(|&p| {
                        let d: i64 = w
                            .iter()
                            .enumerate()
                            .map(|(j, c)| c * at(p + j as i64))
                            .sum();
                        d * d
                    })
                    .sum();
                assert_eq!(quad, direct);
                assert!(quad >= 0);
            }
        }
    }
}

#[test]
fn a_free_axial_field_gives_d2f() {
    let text = Model::larva_toml().replacen("boundary = \"periodic\"", "boundary = \"free\"", 1);
    let model = Model::from_toml(&text).unwrap();
    let ops = operators(&model, 4, 12).unwrap();
    let x = ops.iter().find(|o| o.field == "x").unwrap();
    assert_eq!(x.boundary, "free");
    assert_eq!(x.matrix, parse(D2F_12));
}

#[test]
fn too_few_points_is_a_clear_error() {
    let err = operators(&Model::larva(), 4, 1).unwrap_err().to_string();
    assert!(err.contains("too few"), "{err}");
    assert!(
        operators(&Model::larva(), 4, 2).is_err(),
        "periodic x needs 3 points"
    );
    assert!(operators(&Model::larva(), 4, 3).is_ok());
}

#[test]
fn generated_code_agrees_with_the_engine() {
    let model = Model::larva();
    assert_eq!(OPERATORS.len(), 8);
    let mut seed = 42u64;
    for points in [3usize, 4, 5, 12, 37, 100] {
        let ops = operators(&model, 4, points).unwrap();
        assert_eq!(ops.len(), OPERATORS.len());
        for (op, generated) in ops.iter().zip(OPERATORS) {
            assert_eq!(
                (op.field.as_str(), op.density.as_str(), op.boundary.as_str()),
                (
                    generated.field,
                    generated.density,
                    generated.boundary.name().as_str()
                )
            );
            let n = (generated.size)(points).unwrap();
            assert_eq!(n, op.size);
            let dense = (generated.dense)(points).unwrap();
            let exact: Vec<Vec<f64>> = op
                .matrix
                .iter()
                .map(|r| r.iter().map(|&v| v as f64).collect())
                .collect();
            assert_eq!(dense, exact, "{} {} N = {points}", op.field, op.density);
            if let Some(banded) = generated.banded {
                let b = banded(points).unwrap();
                for (d, band) in b.bands.iter().enumerate() {
                    for (i, v) in band.iter().enumerate() {
                        assert_eq!(*v, exact[i][i + d]);
                    }
                }
            }
            for _ in 0..3 {
                let phi: Vec<f64> = (0..n)
                    .map(|_| {
                        seed = seed
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
                    })
                    .collect();
                let mut out = vec![0.0; n];
                (generated.apply)(points, &phi, &mut out).unwrap();
                for (i, row) in exact.iter().enumerate() {
                    let want: f64 = row.iter().zip(&phi).map(|(a, b)| a * b).sum();
                    assert!(
                        (out[i] - want).abs() <= 1e-12 * (1.0 + want.abs()),
                        "{} row {i}",
                        op.field
                    );
                }
            }
        }
    }
    let gen = &OPERATORS[0];
    assert_eq!(
        (gen.size)(2),
        Err(OperatorError::TooFewPoints { points: 2, min: 3 })
    );
    let mut out = vec![0.0; 3];
    assert!(matches!(
        (gen.apply)(12, &[0.0; 3], &mut out),
        Err(OperatorError::Length { .. })
    ));
}

/// The centred stencils of an active force's factors (`discretise::centred`).
#[test]
fn centred_stencils_are_the_textbook_ones() {
    use theory_search::discretise::centred;
    assert_eq!(centred(0), vec![1.0]);
    assert_eq!(centred(1), vec![-0.5, 0.0, 0.5]);
    assert_eq!(centred(2), vec![1.0, -2.0, 1.0]);
    assert_eq!(centred(3), vec![-0.5, 1.0, 0.0, -1.0, 0.5]);
    assert_eq!(centred(4), vec![1.0, -4.0, 6.0, -4.0, 1.0]);
}
