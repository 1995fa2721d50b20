//! Symmetric banded matrices: `A[i][j]` for `|i − j| ≤ p`, stored as upper bands
//! `bands[d][i] = A[i][i + d]`, `d = 0…p`.
//!
//! What the modal solver needs without forming a dense N×N matrix, each O(N·p²):
//! * [`BandedSym::count_below`]: the number of eigenvalues below σ, by Sylvester's law of inertia
//!   (negative pivots of the LDLᵀ factorisation of A − σI);
//! * [`BandedSym::shifted`]: `A − σI = LDLᵀ` once, then `(A − σI)x = b` for each b (inverse
//!   iteration);
//! * [`BandedR`]: the upper triangular factor R of a tall banded matrix S = QR, built by Givens
//!   row updates without forming SᵀS, so `(SᵀS)⁻¹` is applied with the conditioning of S, not
//!   its square (what keeps the small eigenvalues of a beam accurate at large N); and the trace
//!   of `(SᵀS)⁻¹` from the Takahashi recurrence on R, O(N·p²).

/// A symmetric band matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct BandedSym {
    /// Size.
    pub n: usize,
    /// Upper bands: `bands[d][i] = A[i][i + d]`, `bands[d].len() = n − d`.
    pub bands: Vec<Vec<f64>>,
}

/// The unit lower factor L (by bands below the diagonal) and the pivots D of `A − σI = LDLᵀ`.
struct Ldlt {
    /// `l[d][i] = L[i + d][i]`, d = 1…p.
    l: Vec<Vec<f64>>,
    d: Vec<f64>,
}

impl BandedSym {
    /// Half bandwidth p.
    pub fn bandwidth(&self) -> usize {
        self.bands.len().saturating_sub(1)
    }

    /// `A[i][j]` (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        self.bands.get(j - i).map_or(0.0, |b| b[i])
    }

    /// `A − σI = LDLᵀ` without pivoting. A pivot that comes out exactly zero is nudged by a
    /// relative 1e-300-scale amount so the factorisation goes on (σ then sits on an eigenvalue,
    /// and the count is right on either side).
    fn ldlt(&self, sigma: f64) -> Ldlt {
        let (n, p) = (self.n, self.bandwidth());
        let mut l: Vec<Vec<f64>> = (0..=p).map(|d| vec![0.0; n.saturating_sub(d)]).collect();
        let mut d = vec![0.0; n];
        for j in 0..n {
            // d_j = a_jj − σ − Σ_{k<j} L_jk² d_k
            let mut dj = self.get(j, j) - sigma;
            for k in j.saturating_sub(p)..j {
                let ljk = l[j - k][k];
                dj -= ljk * ljk * d[k];
            }
            if dj == 0.0 {
                dj = f64::MIN_POSITIVE.sqrt();
            }
            d[j] = dj;
            // L_ij = (a_ij − Σ_{k<j} L_ik L_jk d_k) / d_j for i = j+1 … j+p
            for i in j + 1..(j + p + 1).min(n) {
                let mut v = self.get(i, j);
                for k in i.saturating_sub(p)..j {
                    v -= l[i - k][k] * l[j - k][k] * d[k];
                }
                l[i - j][j] = v / dj;
            }
        }
        Ldlt { l, d }
    }

    /// How many eigenvalues of A lie below σ.
    pub fn count_below(&self, sigma: f64) -> usize {
        self.ldlt(sigma).d.iter().filter(|&&v| v < 0.0).count()
    }

    /// Solve `(A − σI)x = b`.
    pub fn solve_shifted(&self, sigma: f64, b: &[f64]) -> Vec<f64> {
        self.shifted(sigma).solve(b)
    }

    /// The factorisation of `A − σI`, to solve with many right-hand sides (inverse iteration
    /// factors once per shift).
    pub fn shifted(&self, sigma: f64) -> ShiftedFactor {
        ShiftedFactor::new(self.ldlt(sigma), self.bandwidth())
    }
}

/// `A − σI = LDLᵀ` of a [`BandedSym`], from [`BandedSym::shifted`]; L kept flat by rows and by
/// columns so each substitution reads memory in order.
pub struct ShiftedFactor {
    /// `below[i·p + d − 1] = L[i][i − d]` (zero where i < d).
    below: Vec<f64>,
    /// `after[i·p + d − 1] = L[i + d][i]` (zero past the end).
    after: Vec<f64>,
    d: Vec<f64>,
    p: usize,
}

impl ShiftedFactor {
    fn new(ldlt: Ldlt, p: usize) -> ShiftedFactor {
        let n = ldlt.d.len();
        let (mut below, mut after) = (vec![0.0; n * p], vec![0.0; n * p]);
        for dd in 1..=p {
            for (i, &x) in ldlt.l[dd].iter().enumerate() {
                // l[d][i] = L[i + d][i]
                after[i * p + dd - 1] = x;
                below[(i + dd) * p + dd - 1] = x;
            }
        }
        ShiftedFactor {
            below,
            after,
            d: ldlt.d,
            p,
        }
    }

    /// Solve `(A − σI)x = b`: forward substitution, the pivots, back substitution.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x);
        x
    }

    /// [`ShiftedFactor::solve_in_place`] for p ≤ 2 (zeros stand in for a missing band).
    fn solve_narrow(&self, x: &mut [f64]) {
        let p = self.p;
        let at = |v: &[f64], i: usize, d: usize| if d <= p { v[i * p + d - 1] } else { 0.0 };
        let (mut x1, mut x2) = (0.0, 0.0);
        for (i, xi) in x.iter_mut().enumerate() {
            // L[i][i−d] is zero where i < d (stored so), so the zeros before x₀ are harmless.
            let value = *xi - at(&self.below, i, 2) * x2 - at(&self.below, i, 1) * x1;
            (x2, x1) = (x1, value);
            *xi = value / self.d[i];
        }
        let (mut x1, mut x2) = (0.0, 0.0);
        for (i, xi) in x.iter_mut().enumerate().rev() {
            let value = *xi - at(&self.after, i, 2) * x2 - at(&self.after, i, 1) * x1;
            (x2, x1) = (x1, value);
            *xi = value;
        }
    }

    /// The same, overwriting `x` (which holds b) with the solution: no allocation.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let (n, p) = (self.d.len(), self.p);
        match p {
            0 => {
                x.iter_mut().zip(&self.d).for_each(|(xi, di)| *xi /= di);
                return;
            }
            // The common bands, with the last unknowns carried in registers: the substitution
            // is a chain of dependent operations, and a trip through memory lengthens it.
            1 | 2 => return self.solve_narrow(x),
            _ => {}
        }
        // Rows past the first p read a full window of the p unknowns before them.
        for i in 0..n {
            let row = &self.below[i * p..(i + 1) * p];
            let mut acc = x[i];
            if i >= p {
                let before = &x[i - p..i];
                for (l, xb) in row.iter().zip(before.iter().rev()) {
                    acc -= l * xb;
                }
            } else {
                for (dd, l) in row.iter().enumerate().take(i) {
                    acc -= l * x[i - dd - 1];
                }
            }
            x[i] = acc;
        }
        for (xi, di) in x.iter_mut().zip(&self.d) {
            *xi /= di;
        }
        for i in (0..n).rev() {
            let col = &self.after[i * p..(i + 1) * p];
            let mut acc = x[i];
            if i + p < n {
                let next = &x[i + 1..i + 1 + p];
                for (l, xa) in col.iter().zip(next) {
                    acc -= l * xa;
                }
            } else {
                for (dd, l) in col.iter().enumerate().take(n - 1 - i) {
                    acc -= l * x[i + dd + 1];
                }
            }
            x[i] = acc;
        }
    }
}

/// The upper triangular factor R (bandwidth p) of a tall matrix S with rows of width ≤ p + 1:
/// `SᵀS = RᵀR`. Stored by bands, `r[d][i] = R[i][i + d]`.
#[derive(Debug, Clone)]
pub struct BandedR {
    r: Vec<Vec<f64>>,
}

impl BandedR {
    /// R of the rows given as (column, value) pairs, each row spanning at most p + 1 consecutive
    /// columns of n. Givens rotations merge one row at a time: O(rows · p²).
    // j indexes every band of R at once, not one slice.
    #[allow(clippy::needless_range_loop)]
    pub fn from_rows<'a>(
        n: usize,
        p: usize,
        rows: impl IntoIterator<Item = &'a [(usize, f64)]>,
    ) -> BandedR {
        let mut r: Vec<Vec<f64>> = (0..=p).map(|d| vec![0.0; n.saturating_sub(d)]).collect();
        let mut a = vec![0.0; p + 1];
        for row in rows {
            let Some(start) = row.iter().map(|&(c, _)| c).min() else {
                continue;
            };
            a.iter_mut().for_each(|v| *v = 0.0);
            for &(c, v) in row {
                a[c - start] += v;
            }
            // Window a[d] = row entry at column j + d; R's row j spans j…j+p.
            for j in start..n {
                if a.iter().all(|&v| v == 0.0) {
                    break;
                }
                if a[0] != 0.0 {
                    let rjj = r[0][j];
                    let h = rjj.hypot(a[0]);
                    let (c, s) = (rjj / h, a[0] / h);
                    for d in 0..=p.min(n - 1 - j) {
                        let (x, y) = (r[d][j], a[d]);
                        r[d][j] = c * x + s * y;
                        a[d] = -s * x + c * y;
                    }
                }
                a.rotate_left(1);
                a[p] = 0.0;
            }
        }
        BandedR { r }
    }

    fn n(&self) -> usize {
        self.r[0].len()
    }

    fn p(&self) -> usize {
        self.r.len() - 1
    }

    /// Whether R is nonsingular (every diagonal entry non-zero).
    pub fn is_regular(&self) -> bool {
        self.r[0].iter().all(|&v| v != 0.0 && v.is_finite())
    }

    /// Solve `RᵀR x = b` in place: O(N·p).
    pub fn solve_normal(&self, x: &mut [f64]) {
        let (n, p) = (self.n(), self.p());
        // Rᵀ y = b (forward).
        for i in 0..n {
            let mut v = x[i];
            for d in 1..=p.min(i) {
                v -= self.r[d][i - d] * x[i - d];
            }
            x[i] = v / self.r[0][i];
        }
        // R x = y (backward).
        for i in (0..n).rev() {
            let mut v = x[i];
            for d in 1..=p.min(n - 1 - i) {
                v -= self.r[d][i] * x[i + d];
            }
            x[i] = v / self.r[0][i];
        }
    }

    /// `tr((RᵀR)⁻¹)` by the Takahashi recurrence: Z = (RᵀR)⁻¹ satisfies RZ = R⁻ᵀ (lower
    /// triangular, diagonal 1/rᵢᵢ), which gives Z's band from the bottom row up without the rest.
    pub fn inverse_trace(&self) -> f64 {
        let (n, p) = (self.n(), self.p());
        // z[d][i] = Z[i][i + d]
        let mut z: Vec<Vec<f64>> = (0..=p).map(|d| vec![0.0; n.saturating_sub(d)]).collect();
        let get = |z: &Vec<Vec<f64>>, i: usize, j: usize| {
            let (i, j) = if i <= j { (i, j) } else { (j, i) };
            z[j - i][i]
        };
        let mut trace = 0.0;
        for i in (0..n).rev() {
            let reach = p.min(n - 1 - i);
            let rii = self.r[0][i];
            for j in (i + 1..=i + reach).rev() {
                let s: f64 = (1..=reach).map(|d| self.r[d][i] * get(&z, i + d, j)).sum();
                z[j - i][i] = -s / rii;
            }
            let s: f64 = (1..=reach).map(|d| self.r[d][i] * z[d][i]).sum();
            z[0][i] = (1.0 / rii - s) / rii;
            trace += z[0][i];
        }
        trace
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tridiag(n: usize) -> BandedSym {
        BandedSym {
            n,
            bands: vec![vec![2.0; n], vec![-1.0; n - 1]],
        }
    }

    #[test]
    fn counts_dirichlet_eigenvalues() {
        // Eigenvalues 2 − 2cos(πj/(n+1)), j = 1…n.
        let n = 50;
        let a = tridiag(n);
        for j in 1..=n {
            let lam = 2.0 - 2.0 * (std::f64::consts::PI * j as f64 / (n + 1) as f64).cos();
            assert_eq!(a.count_below(lam - 1e-9), j - 1);
            assert_eq!(a.count_below(lam + 1e-9), j);
        }
    }

    #[test]
    fn qr_factor_solves_and_traces() {
        // S: the free second difference on 7 points plus a row holding the last point.
        let n = 7;
        let mut rows: Vec<Vec<(usize, f64)>> = (0..n - 2)
            .map(|p| vec![(p, 1.0), (p + 1, -2.0), (p + 2, 1.0)])
            .collect();
        rows.push(vec![(n - 1, 1.0)]);
        rows.push(vec![(n - 2, 1.0)]);
        let r = BandedR::from_rows(n, 2, rows.iter().map(|r| r.as_slice()));
        let mut a = vec![vec![0.0; n]; n];
        for row in &rows {
            for &(i, x) in row {
                for &(j, y) in row {
                    a[i][j] += x * y;
                }
            }
        }
        // Columns of A⁻¹ by solves; their diagonal sums to the Takahashi trace.
        let mut trace = 0.0;
        for c in 0..n {
            let mut e = vec![0.0; n];
            e[c] = 1.0;
            r.solve_normal(&mut e);
            for (i, ai) in a.iter().enumerate() {
                let ax: f64 = (0..n).map(|j| ai[j] * e[j]).sum();
                assert!((ax - if i == c { 1.0 } else { 0.0 }).abs() < 1e-9);
            }
            trace += e[c];
        }
        assert!((r.inverse_trace() - trace).abs() < 1e-9 * trace);
    }

    #[test]
    fn shifted_solve_inverts() {
        let a = BandedSym {
            n: 6,
            bands: vec![vec![6.0; 6], vec![-4.0; 5], vec![1.0; 4]],
        };
        let b: Vec<f64> = (0..6).map(|i| i as f64 - 2.5).collect();
        let x = a.solve_shifted(0.5, &b);
        for (i, bi) in b.iter().enumerate() {
            let ax: f64 = (0..6)
                .map(|j| (a.get(i, j) - if i == j { 0.5 } else { 0.0 }) * x[j])
                .sum();
            assert!((ax - bi).abs() < 1e-12);
        }
    }
}
