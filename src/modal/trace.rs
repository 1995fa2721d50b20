//! Σ 1/λ over the non-zero modes as the exact polynomial in N it is for the string and the beam
//! with any ends: exact values at small N from integer characteristic polynomials, checked by
//! forward differences that vanish beyond the degree.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};

use crate::model::Boundary;

/// Coefficients c₀ = 1, c₁ … cₙ of det(xI − A) by Berkowitz's division-free algorithm, exact
/// (big integers: the coefficients reach ∏λ ~ 4^{kN}).
fn characteristic_polynomial(a: &[Vec<i64>]) -> Vec<BigInt> {
    let n = a.len();
    let at = |i: usize, j: usize| BigInt::from(a[i][j]);
    let mut v: Vec<BigInt> = vec![BigInt::one(), -at(0, 0)];
    for r in 1..n {
        // Toeplitz column: 1, −a_rr, −R·C, −R·M·C, … with M the leading r×r block.
        let mut t = vec![BigInt::one(), -at(r, r)];
        let mut w: Vec<BigInt> = (0..r).map(|i| at(i, r)).collect();
        for _ in 0..r {
            let rc: BigInt = (0..r).map(|j| at(r, j) * &w[j]).sum();
            t.push(-rc);
            w = (0..r)
                .map(|i| (0..r).map(|j| at(i, j) * &w[j]).sum())
                .collect();
        }
        v = (0..r + 2)
            .map(|i| (0..=i.min(r)).map(|j| &t[i - j] * &v[j]).sum())
            .collect();
    }
    v
}

/// Σ 1/λ over the non-zero eigenvalues of the exact operator: −c_{m−1}/c_m, m its rank.
fn exact_trace_at(k: u32, boundary: Boundary, points: usize) -> Option<BigRational> {
    let m = crate::discretise::operator_matrix(k, boundary, points).ok()?;
    let c = characteristic_polynomial(&m);
    let rank = m.len() - boundary.nullity(k);
    if rank == 0 || c.get(rank)?.is_zero() {
        return None;
    }
    Some(BigRational::new(-c[rank - 1].clone(), c[rank].clone()))
}

fn big_to_f64(x: &BigRational) -> f64 {
    x.to_f64().unwrap_or(f64::NAN)
}

/// Σ 1/λ over the non-zero modes on `points` points as the exact polynomial in N it is for
/// the string and the beam with any ends (and some k ≥ 3 operators; others carry boundary
/// layers that decay geometrically in N, and are refused): exact values at small N by integer
/// characteristic polynomials,
/// forward differences that vanish beyond the degree (checked on two more points), and Newton's
/// form evaluated at N. `None` when the check fails. This is what keeps
/// the variance shares exact at N = 10⁶, where a floating trace of (SᵀS)⁻¹ loses everything to
/// the operator's N^{2k} conditioning.
pub fn trace_polynomial(k: u32, boundary: Boundary, points: usize) -> Option<f64> {
    // Degree at most 2k + 1; the first N's past the smallest body may still be special.
    let degree = 2 * k as usize + 1;
    let start = boundary.min_points(k) + k as usize + 2;
    let values: Vec<BigRational> = (start..start + degree + 3)
        .map(|n| exact_trace_at(k, boundary, n))
        .collect::<Option<_>>()?;
    // Forward differences Δʲt(start), j = 0…degree + 2.
    let mut diffs = Vec::new();
    let mut row = values;
    while !row.is_empty() {
        diffs.push(row[0].clone());
        row = row.windows(2).map(|w| &w[1] - &w[0]).collect();
    }
    if !diffs[degree + 1].is_zero() || !diffs[degree + 2].is_zero() {
        return None;
    }
    if points >= start && points < start + degree + 3 {
        return exact_trace_at(k, boundary, points).map(|t| big_to_f64(&t));
    }
    // Newton: t(N) = Σ Δʲt(start)·C(N − start, j).
    let x = points as f64 - start as f64;
    let mut binom = 1.0;
    let mut total = 0.0;
    for (j, d) in diffs.iter().take(degree + 1).enumerate() {
        total += big_to_f64(d) * binom;
        binom *= (x - j as f64) / (j as f64 + 1.0);
    }
    Some(total)
}
