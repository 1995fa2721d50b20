//! Symmetric banded matrices: `A[i][j]` for `|i − j| ≤ p`, stored as upper bands
//! `bands[d][i] = A[i][i + d]`, `d = 0…p`.
//!
//! What the modal solver needs without forming a dense N×N matrix, each O(N·p²):
//! * [`BandedSym::count_below`]: the number of eigenvalues below σ, by Sylvester's law of inertia
//!   (negative pivots of the LDLᵀ factorisation of A − σI);
//! * [`BandedSym::solve_shifted`]: `(A − σI)x = b`, for inverse iteration.

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
        let Ldlt { l, d } = self.ldlt(sigma);
        let (n, p) = (self.n, self.bandwidth());
        let mut x = b.to_vec();
        for i in 0..n {
            for k in i.saturating_sub(p)..i {
                x[i] -= l[i - k][k] * x[k];
            }
        }
        for i in 0..n {
            x[i] /= d[i];
        }
        for i in (0..n).rev() {
            for k in i + 1..(i + p + 1).min(n) {
                x[i] -= l[k - i][i] * x[k];
            }
        }
        x
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
