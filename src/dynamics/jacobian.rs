//! The Newton matrix of an implicit step: symmetric, banded for a field with ends (O(N·p²) to
//! factorise), banded plus corners for a field around a ring, whose wrapped stencils couple the
//! first and last p unknowns. The corners are a correction of rank ≤ 2p, solved by the
//! Sherman–Morrison–Woodbury identity J⁻¹r = B⁻¹r − B⁻¹E(I + Ĉ EᵀB⁻¹E)⁻¹Ĉ EᵀB⁻¹r, with B the
//! band, E the 2p unit columns of the corner indices and Ĉ the corners among them; no inverse
//! of Ĉ is needed. A ring too small for its band to leave the corners apart is solved densely.

use crate::banded::{BandedSym, ShiftedFactor};

/// A Newton matrix being assembled.
pub(super) enum Jacobian {
    /// Band only.
    Banded(BandedSym),
    /// Band plus the corner entries (i, j, value), both orientations.
    Cyclic(BandedSym, Vec<(usize, usize, f64)>),
    /// Everything (a small ring).
    Dense(nalgebra::DMatrix<f64>),
}

impl Jacobian {
    /// An n×n zero matrix of half bandwidth p, with corners when `periodic`.
    pub(super) fn new(n: usize, periodic: bool, p: usize) -> Jacobian {
        let band = || BandedSym {
            n,
            bands: (0..=p.min(n.saturating_sub(1)))
                .map(|d| vec![0.0; n - d])
                .collect(),
        };
        match periodic {
            true if n < 4 * p + 2 => Jacobian::Dense(nalgebra::DMatrix::zeros(n, n)),
            true => Jacobian::Cyclic(band(), Vec::new()),
            false => Jacobian::Banded(band()),
        }
    }

    /// Add x at (i, j) (the callers add both (i, j) and (j, i) of a symmetric term).
    pub(super) fn add(&mut self, i: usize, j: usize, x: f64) {
        match self {
            Jacobian::Dense(m) => m[(i, j)] += x,
            Jacobian::Banded(b) | Jacobian::Cyclic(b, _) if i.abs_diff(j) <= b.bandwidth() => {
                // Symmetric: the upper band holds each pair once.
                if i <= j {
                    b.bands[j - i][i] += x;
                }
            }
            Jacobian::Cyclic(_, corners) => corners.push((i, j, x)),
            Jacobian::Banded(_) => {}
        }
    }

    /// J⁻¹r (factorises, solves once).
    #[cfg(test)]
    pub(super) fn solve(self, r: &[f64]) -> Vec<f64> {
        let mut x = r.to_vec();
        self.factor().solve(&mut x);
        x
    }

    /// The factorisation, to solve for many right-hand sides: an implicit run keeps it over
    /// Newton iterations and steps while it still makes them converge.
    pub(super) fn factor(self) -> Factored {
        match self {
            // A ring whose stencils never wrap (a body with no stiffness, friction or mass
            // term: only forces) has no corners, and nalgebra's LU of the empty capacitance
            // matrix panics on its first solve: the band is the whole matrix.
            Jacobian::Banded(b) => Factored::Banded(b.shifted(0.0)),
            Jacobian::Cyclic(b, corners) if corners.is_empty() => Factored::Banded(b.shifted(0.0)),
            Jacobian::Cyclic(b, corners) => {
                let band = b.shifted(0.0);
                let mut index: Vec<usize> = corners.iter().flat_map(|c| [c.0, c.1]).collect();
                index.sort_unstable();
                index.dedup();
                let m = index.len();
                let at = |k: usize| index.binary_search(&k).unwrap_or(0);
                let mut c = nalgebra::DMatrix::<f64>::zeros(m, m);
                for &(i, j, x) in &corners {
                    c[(at(i), at(j))] += x;
                }
                // Z = B⁻¹E, one solve per corner index.
                let z: Vec<Vec<f64>> = index
                    .iter()
                    .map(|&k| {
                        let mut e = vec![0.0; b.n];
                        e[k] = 1.0;
                        band.solve(&e)
                    })
                    .collect();
                let etz = nalgebra::DMatrix::from_fn(m, m, |a, b| z[b][index[a]]);
                let s = (nalgebra::DMatrix::identity(m, m) + &c * etz).lu();
                Factored::Cyclic {
                    band,
                    index,
                    c,
                    z,
                    s,
                }
            }
            Jacobian::Dense(m) => Factored::Dense(m.lu()),
        }
    }
}

/// A factorised Newton matrix.
pub(super) enum Factored {
    /// LDLᵀ of the band.
    Banded(ShiftedFactor),
    /// LDLᵀ of the band, and the Woodbury correction's pieces: the corner indices, Ĉ, B⁻¹E
    /// and the LU of I + Ĉ EᵀB⁻¹E.
    Cyclic {
        /// The band's factor.
        band: ShiftedFactor,
        /// Corner indices.
        index: Vec<usize>,
        /// The corners among them.
        c: nalgebra::DMatrix<f64>,
        /// B⁻¹E by columns.
        z: Vec<Vec<f64>>,
        /// LU of the capacitance matrix.
        s: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    },
    /// LU of the whole matrix.
    Dense(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
}

impl Factored {
    /// x ← J⁻¹x (NaN everywhere if J is singular).
    pub(super) fn solve(&self, x: &mut [f64]) {
        match self {
            Factored::Banded(f) => f.solve_in_place(x),
            Factored::Cyclic {
                band,
                index,
                c,
                z,
                s,
            } => {
                band.solve_in_place(x);
                let m = index.len();
                let rhs = c * nalgebra::DVector::from_iterator(m, index.iter().map(|&k| x[k]));
                let Some(y) = s.solve(&rhs) else {
                    return x.fill(f64::NAN);
                };
                for (zb, yb) in z.iter().zip(y.iter()) {
                    for (xi, zi) in x.iter_mut().zip(zb) {
                        *xi -= zi * yb;
                    }
                }
            }
            Factored::Dense(lu) => match lu.solve(&nalgebra::DVector::from_column_slice(x)) {
                Some(y) => x.copy_from_slice(y.as_slice()),
                None => x.fill(f64::NAN),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring's Newton matrix (band plus wrapped corners) solved by the Woodbury identity is
    /// the dense solve of the same matrix.
    #[test]
    fn a_cyclic_solve_is_the_dense_one() {
        for (n, p) in [(12, 1), (15, 2), (40, 3)] {
            let mut state = 0x853c_49e6_748f_ea9bu64 ^ n as u64;
            let mut draw = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state % 1000) as f64 / 1000.0 - 0.5
            };
            let (mut cyclic, mut dense) = (
                Jacobian::new(n, true, p),
                nalgebra::DMatrix::<f64>::zeros(n, n),
            );
            for i in 0..n {
                let x = 5.0 + draw();
                cyclic.add(i, i, x);
                dense[(i, i)] += x;
                for d in 1..=p {
                    let j = (i + d) % n;
                    let x = draw();
                    for (a, b) in [(i, j), (j, i)] {
                        cyclic.add(a, b, x);
                        dense[(a, b)] += x;
                    }
                }
            }
            let r: Vec<f64> = (0..n).map(|_| draw()).collect();
            let want = dense
                .lu()
                .solve(&nalgebra::DVector::from_column_slice(&r))
                .unwrap();
            let got = cyclic.solve(&r);
            for (a, b) in got.iter().zip(want.iter()) {
                assert!((a - b).abs() < 1e-12, "n = {n}, p = {p}: {a} against {b}");
            }
        }
    }
}
