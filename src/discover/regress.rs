//! Two-stage least squares on the weak-form rows, the selection, its scores and the bootstrap.
//!
//! Every fit of a set S of candidates works from the rows' cross products (ZᵀZ, ZᵀX, Zᵀy, XᵀX,
//! Xᵀy, yᵀy, each row counted by its multiplicity in a bootstrap draw): with M = ZᵀZ and
//! A = M⁻¹ZᵀX_S, β = (X_SᵀZ A)⁻¹ Aᵀ Zᵀy and the residual yᵀy − 2β·X_Sᵀy + βᵀX_SᵀX_Sβ.
//!
//! **Selection** is backward elimination by an information criterion of the moments
//! (Andrews 1999; a BIC for instrumental variables): IC(S) = J(S)/σ² + |S| ln n, where
//! J(S) = gᵀ(ZᵀZ)⁻¹g, g = Zᵀ(y − X_Sβ_S), is Sargan's statistic and σ² the whole library's
//! residual variance. From the whole library, drop the candidate whose removal lowers IC most,
//! until none does. A residual sum of squares would not do: on thermal data the true
//! equation's residual (the noise) correlates with the state, and dropping a true damping term
//! can lower it.

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};

use super::weak::Rows;

/// The factor 1/√v that scales a diagonal entry v of a Gram matrix to 1 (0 for an empty column).
fn unit_diagonal(v: f64) -> f64 {
    if v > 0.0 {
        1.0 / v.sqrt()
    } else {
        0.0
    }
}

/// The rows' cross products, each row counted `count` times.
#[derive(Debug, Clone)]
pub(super) struct Gram {
    zz: DMatrix<f64>,
    zx: DMatrix<f64>,
    zy: DVector<f64>,
    xx: DMatrix<f64>,
    xy: DVector<f64>,
    yy: f64,
    /// Rows counted.
    pub n: f64,
    /// Instruments per slot (ZᵀZ's diagonal blocks).
    block: usize,
    /// The instruments' scales and M⁻¹ in those units (see [`Gram::scaled`]).
    inverse: Option<(Vec<f64>, DMatrix<f64>)>,
}

impl Gram {
    /// The cross products of `rows` with multiplicities `count`.
    pub fn new(rows: &Rows, count: &[f64]) -> Gram {
        let p = rows.regressors.len();
        let q = rows.instruments.first().map_or(0, Vec::len) * rows.slots;
        let mut g = Gram {
            zz: DMatrix::zeros(q, q),
            zx: DMatrix::zeros(q, p),
            zy: DVector::zeros(q),
            xx: DMatrix::zeros(p, p),
            xy: DVector::zeros(p),
            yy: 0.0,
            n: 0.0,
            block: rows.instruments.first().map_or(0, Vec::len),
            inverse: None,
        };
        let mut x = vec![0.0; p];
        for (r, &c) in count.iter().enumerate() {
            if c == 0.0 {
                continue;
            }
            let w = rows.weight[r];
            let y = w * rows.target[r];
            for (m, xm) in x.iter_mut().enumerate() {
                *xm = w * rows.regressors[m][r];
            }
            // A row's instruments fill its mode's block only.
            let z = &rows.instruments[r];
            let at = rows.slot[r] * z.len();
            for (i, zi) in z.iter().enumerate() {
                let zi = c * zi;
                for (j, zj) in z.iter().enumerate() {
                    g.zz[(at + i, at + j)] += zi * zj;
                }
                for (m, xm) in x.iter().enumerate() {
                    g.zx[(at + i, m)] += zi * xm;
                }
                g.zy[at + i] += zi * y;
            }
            for (i, xi) in x.iter().enumerate() {
                for (j, xj) in x.iter().enumerate() {
                    g.xx[(i, j)] += c * xi * xj;
                }
                g.xy[i] += c * xi * y;
            }
            g.yy += c * y * y;
            g.n += c;
        }
        g.inverse = g.finite().then(|| g.scaled()).flatten();
        g
    }

    /// Every cross product is finite (no decomposition may see anything else).
    pub fn finite(&self) -> bool {
        let all = |m: &DMatrix<f64>| m.iter().all(|x| x.is_finite());
        all(&self.zz)
            && all(&self.zx)
            && all(&self.xx)
            && self.zy.iter().chain(self.xy.iter()).all(|x| x.is_finite())
            && self.yy.is_finite()
    }

    /// The instruments scaled to unit diagonal (M's conditioning is then their own), and
    /// M⁻¹ in those units; `None` when the pseudo-inverse fails.
    fn scaled(&self) -> Option<(Vec<f64>, DMatrix<f64>)> {
        let q = self.zz.nrows();
        let d: Vec<f64> = (0..q).map(|i| unit_diagonal(self.zz[(i, i)])).collect();
        // ZᵀZ is block diagonal (a row fills its slot's block only): inverted block by block.
        let b = self.block.max(1);
        let mut inverse = DMatrix::zeros(q, q);
        for at in (0..q).step_by(b) {
            let m = DMatrix::from_fn(b, b, |i, j| {
                self.zz[(at + i, at + j)] * d[at + i] * d[at + j]
            });
            if !m.iter().all(|x| x.is_finite()) {
                return None;
            }
            let pinv = m.svd(true, true).pseudo_inverse(1e-12).ok()?;
            inverse.view_mut((at, at), (b, b)).copy_from(&pinv);
        }
        Some((d, inverse))
    }

    /// β of the candidates `set` and the moment objective J = gᵀM⁻¹g, g = Zᵀ(y − X_Sβ);
    /// `None` when the instruments do not determine them.
    pub fn fit(&self, set: &[usize]) -> Option<(Vec<f64>, f64)> {
        let (d, minv) = self.inverse.as_ref()?;
        let q = d.len();
        let zy = DVector::from_fn(q, |i, _| self.zy[i] * d[i]);
        if set.is_empty() {
            return Some((Vec::new(), zy.dot(&(minv * &zy))));
        }
        let zx = DMatrix::from_fn(q, set.len(), |i, j| self.zx[(i, set[j])] * d[i]);
        let a = minv * &zx;
        let h = zx.transpose() * &a;
        let rhs = a.transpose() * &zy;
        // H scaled to unit diagonal, so that the SVD's cut is relative: a regressor's scale
        // (its unit, its mode's time scale) decides nothing. β = S (SHS)⁺ S rhs.
        let s = DVector::from_fn(set.len(), |i, _| unit_diagonal(h[(i, i)]));
        let scaled = DMatrix::from_fn(set.len(), set.len(), |i, j| h[(i, j)] * s[i] * s[j]);
        let rhs = rhs.component_mul(&s);
        if !(scaled.iter().chain(rhs.iter()).all(|x| x.is_finite())) {
            return None;
        }
        let beta = scaled
            .svd(true, true)
            .solve(&rhs, 1e-14)
            .ok()?
            .component_mul(&s);
        let g = zy - zx * &beta;
        let j = g.dot(&(minv * &g));
        let beta: Vec<f64> = beta.iter().copied().collect();
        (beta.iter().all(|b| b.is_finite()) && j.is_finite()).then_some((beta, j.max(0.0)))
    }

    /// The moment objective of a given `beta` on these rows (held-out rows).
    pub fn objective(&self, set: &[usize], beta: &[f64]) -> Option<f64> {
        let (d, minv) = self.inverse.as_ref()?;
        let q = d.len();
        let g = DVector::from_fn(q, |i, _| {
            let fitted: f64 = set
                .iter()
                .zip(beta)
                .map(|(&m, b)| b * self.zx[(i, m)])
                .sum();
            (self.zy[i] - fitted) * d[i]
        });
        Some(g.dot(&(minv * &g)).max(0.0))
    }

    /// yᵀy: the residual of no term.
    pub fn total(&self) -> f64 {
        self.yy
    }

    /// The residual variance σ² of the set's structural residual, per row.
    pub fn variance(&self, set: &[usize]) -> Option<f64> {
        let (beta, _) = self.fit(set)?;
        Some(self.residual(set, &beta) / self.n.max(1.0))
    }

    /// The criterion J/σ² + |S| ln n (σ² the whole library's residual variance): J/σ² is
    /// Sargan's statistic, χ² with (instruments − |S|) degrees of freedom when S holds every
    /// force present, and it grows with n when a needed force is missing.
    pub fn criterion(&self, set: &[usize], sigma2: f64) -> Option<f64> {
        let (_, j) = self.fit(set)?;
        Some(j / sigma2.max(f64::MIN_POSITIVE) + set.len() as f64 * self.n.max(1.0).ln())
    }

    /// Backward elimination by [`Gram::criterion`] from `all`.
    pub fn select(&self, all: &[usize]) -> Vec<usize> {
        let mut set = all.to_vec();
        let Some(sigma2) = self.variance(all) else {
            return set;
        };
        let Some(mut score) = self.criterion(&set, sigma2) else {
            return set;
        };
        loop {
            let best = (0..set.len())
                .filter_map(|i| {
                    let mut fewer = set.clone();
                    fewer.remove(i);
                    Some((self.criterion(&fewer, sigma2)?, i))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            match best {
                Some((b, i)) if b < score => {
                    set.remove(i);
                    score = b;
                }
                _ => return set,
            }
        }
    }

    /// The residual of `beta` on these rows.
    pub fn residual(&self, set: &[usize], beta: &[f64]) -> f64 {
        let mut r = self.yy;
        for (i, &a) in set.iter().enumerate() {
            r -= 2.0 * beta[i] * self.xy[a];
            for (j, &b) in set.iter().enumerate() {
                r += beta[i] * beta[j] * self.xx[(a, b)];
            }
        }
        r.max(0.0)
    }
}

/// The held-out moment objective per row over `folds` contiguous blocks of time, in units of
/// `sigma2`: β from the other blocks, J on the block's own instruments. Unlike a held-out
/// residual it is not lowered by fitting the noise the state carries (Langevin data).
pub(super) fn cross_validated(
    rows: &Rows,
    set: &[usize],
    folds: usize,
    sigma2: f64,
) -> Option<f64> {
    let (lo, hi) = span(rows);
    let width = (hi - lo) / folds as f64;
    let mut total = 0.0;
    let mut n = 0.0;
    for f in 0..folds {
        let inside = |t: f64| ((t - lo) / width).floor().min(folds as f64 - 1.0) as usize == f;
        let train: Vec<f64> = rows.time.iter().map(|&t| f64::from(!inside(t))).collect();
        let test: Vec<f64> = train.iter().map(|c| 1.0 - c).collect();
        let (beta, _) = Gram::new(rows, &train).fit(set)?;
        let held = Gram::new(rows, &test);
        total += held.objective(set, &beta)?;
        n += held.n;
    }
    (n > 0.0).then(|| total / n / sigma2.max(f64::MIN_POSITIVE))
}

fn span(rows: &Rows) -> (f64, f64) {
    let lo = rows.time.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = rows.time.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi + 1e-9 * (hi - lo).abs().max(1.0))
}

/// Blocks of time drawn in a moving-block bootstrap.
pub const BLOCKS: usize = 25;

/// Multiplicities of one bootstrap draw: whole animals when there are several, else
/// [`BLOCKS`] blocks of time of length (span / BLOCKS), each starting anywhere.
pub(super) fn draw(rows: &Rows, animals: usize, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
    let mut count = vec![0.0; rows.len()];
    if animals > 1 {
        for _ in 0..animals {
            let a = rng.random_range(0..animals);
            for (c, &b) in count.iter_mut().zip(&rows.animal) {
                if b == a {
                    *c += 1.0;
                }
            }
        }
        return count;
    }
    let (lo, hi) = span(rows);
    let length = (hi - lo) / BLOCKS as f64;
    for _ in 0..BLOCKS {
        let start = lo + rng.random::<f64>() * (hi - lo - length);
        for (c, &t) in count.iter_mut().zip(&rows.time) {
            if t >= start && t < start + length {
                *c += 1.0;
            }
        }
    }
    count
}

/// A seeded generator for the bootstrap.
pub(super) fn generator(seed: u64) -> rand_chacha::ChaCha8Rng {
    rand_chacha::ChaCha8Rng::seed_from_u64(seed)
}

/// The 2.5 and 97.5 % percentiles of `draws` (draws of `units` whole animals: the expanded
/// percentiles), each through `convert`.
pub(super) fn percentiles(
    draws: &mut [f64],
    units: usize,
    convert: impl Fn(f64) -> f64,
) -> Option<[f64; 2]> {
    if draws.len() < 20 {
        return None;
    }
    draws.sort_by(f64::total_cmp);
    // Draws of a few whole animals: the expanded percentile interval (as `fit`'s), whose tail
    // is Φ(−√(K/(K−1))·t_{K−1}); five pooled animals covered c′_y in 16 of 20 with 2.5 %.
    let tail = match units {
        0 | 1 => 0.025,
        k => crate::fit::expanded_tail(k),
    };
    let at = |p: f64| draws[((p * (draws.len() - 1) as f64).round() as usize).min(draws.len() - 1)];
    let (a, b) = (convert(at(tail)), convert(at(1.0 - tail)));
    Some([a.min(b), a.max(b)])
}
