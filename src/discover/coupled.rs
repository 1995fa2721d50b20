//! The exact estimator of a linear library whose forces couple the modes (an active ∂s³ force
//! or a gyroscopic ∂t∂s one on a free body): the modes' joint exact likelihood.
//!
//! **Model.** On the M used modes q (continuum shapes, `galerkin`) the library's forces give
//! q̈ = −K(c) q − D(c) q̇ + η, K(c) = −Σₘ cₘ Pₘ and D(c) = −Σₘ cₘ Vₘ (Pₘ = ⟨φᵢ, Lₘφⱼ⟩ and
//! Vₘ = ⟨φᵢ, L′ₘφⱼ⟩, neither symmetric in general). The [`CONDENSED`] continuum modes above
//! the used ones are condensed into them (`condense`: they follow the slow modes
//! quasi-statically), so K and D are the whole body's on the slow modes, not a truncation's
//! (truncated, a free beam at a = 5c has its used modes' damping 1.3 % off). η is white with a
//! full covariance S C S (one force noise nⱼ per mode and their correlations: the condensed
//! modes' own noise reaches every slow mode through one coupling; with η independent between
//! modes, that correlation went into a_y, +0.7 … +1.7 % on the continuum beam; no
//! fluctuation–dissipation assumed, which an active body need not obey). Sampled every frame
//! it is exactly a linear Gaussian state-space model (Van Loan, `statespace::System`),
//! observed through the tracking noise: the projection's covariance R₀ of white noise on the
//! tracked points times σ², σ as the measurement layer measures it on the recording's points
//! (`recording::TrackingNoise`; estimated here only where that is a bound). Each mode's own
//! white noise instead left the slow modes' ν at their own fits' zero and put c′_y 1.2 % high
//! at 30 frames a period.
//!
//! **Estimate.** θ = (c, ln n, ln σ², the correlations) maximises the exact likelihood (the
//! Kalman filter's prediction-error decomposition −ln L = Σₙ ℓₙ(θ), lost frames predictions
//! without update, each run between lost frames a series from the stationary state) by BHHH:
//! the step (Σₙ gₙgₙᵀ)⁻¹ Σₙ gₙ with gₙ = ∂ℓₙ/∂θ by central differences, halved until −ln L
//! falls, until the decrement Gᵀ I⁻¹ G is under 10⁻⁸. Each noise has a floor 10⁻⁸ of its
//! start, where it is held when the likelihood pushes it lower or its information vanishes.
//! At the true θ the gₙ are martingale differences, so I = Σₙ gₙgₙᵀ is the information and
//! its inverse the covariance. Where the projection gives no R₀ (lengths), each mode has its
//! own tracking noise νⱼ, held at its own fit's where that fit found none.
//!
//! **Evidence.** On the independent continuum beam (tests/discover_rates.rs, a = 5c, 12
//! points, 8, 14 and 30 frames a period, 5 % of the frames lost) the exact set in 60 of 60
//! recordings, each coefficient's median within 1.1 % of the body's, covered in 15–20 of 20
//! (docs/discover.md; c_y at 30 frames a period the least). There is no misfit test yet.
//!
//! **Selection** by the Wald distance from the whole library ([`super::wald`]).

use nalgebra::{DMatrix, DVector};

use super::exact::ModeData;
use super::galerkin::ModalForce;
use crate::statespace::System;

/// The estimator's line in the report.
pub(super) const COUPLED: &str = "the modes' joint exact likelihood (one linear system coupled by the library's forces, the modes above the used ones condensed into them, a Kalman filter over the frames, lost frames skipped, the tracking noise the recording's points measure as observation noise), maximised over the coefficients and the modes' correlated force noise; terms by the Wald distance from the whole library";

/// The continuum modes above the used ones condensed into them (quasi-static, to first order
/// in their frequency ratio): with eight, a free beam at a = 5c has its lowest three used
/// modes' rates within 4·10⁻⁴ of the whole beam's (truncated: 1.3 %), the fourth's 0.7 %.
pub(super) const CONDENSED: usize = 8;

/// Relative step of the numeric scores.
const STEP: f64 = 1e-4;
/// Most BHHH iterations.
const ITERATIONS: usize = 40;

/// The joint problem: the frames of every used mode, the library's modal forces and each
/// mode's tracking noise (time in frames).
pub(super) struct Joint {
    /// Each series: frames × M values (NaN when lost).
    series: Vec<Vec<Vec<f64>>>,
    /// The bootstrap unit of each series.
    unit: Vec<usize>,
    units: usize,
    /// (position, velocity) matrices of the candidates estimated, in order.
    forces: Vec<(DMatrix<f64>, DMatrix<f64>)>,
    /// Modes.
    modes: usize,
    /// Each parameter's scale for its numeric derivative.
    scale: Vec<f64>,
    /// Each parameter's floor: the noises' (ln) at 10⁻⁸ of their start, none for coefficients.
    floor: Vec<f64>,
    /// Where each parameter sits in θ.
    layout: Layout,
    /// The tracking noise's covariance for a unit ln σ² = 0, when the projection gives it.
    shape: Option<DMatrix<f64>>,
}

/// Where each parameter sits in θ: the k coefficients, the M modes' ln force noises, the
/// tracking noise's parameters (one ln σ² of a known covariance shape σ²·R₀, or each mode's
/// ln νⱼ), then the force noise's correlations ([`correlations`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Layout {
    pub k: usize,
    pub m: usize,
    tracking: usize,
}

impl Layout {
    /// k coefficients on m modes, the tracking noise `shaped` or one variance per mode.
    pub fn new(k: usize, m: usize, shaped: bool) -> Layout {
        let tracking = if shaped { 1 } else { m };
        Layout { k, m, tracking }
    }

    pub fn forces(&self) -> std::ops::Range<usize> {
        self.k..self.k + self.m
    }

    pub fn tracking(&self) -> std::ops::Range<usize> {
        let start = self.k + self.m;
        start..start + self.tracking
    }

    pub fn correlations(&self) -> std::ops::Range<usize> {
        let start = self.tracking().end;
        start..start + correlations(self.m)
    }

    pub fn len(&self) -> usize {
        self.correlations().end
    }
}

/// One bootstrap unit's summed score and OPG.
type Unit = (DVector<f64>, DMatrix<f64>);

/// An exact fit: θ, −ln L, and each unit's score and OPG over the free parameters.
pub(super) struct JointFit {
    pub theta: DVector<f64>,
    pub free: Vec<usize>,
    pub information: DMatrix<f64>,
    pub units: Vec<(DVector<f64>, DMatrix<f64>)>,
}

impl Joint {
    /// The problem of `data` (one entry per used mode, identical runs), `forces` of the
    /// candidates to estimate, on `modes` modes; `rates` = (a typical Ω², a
    /// typical 2ζΩ) to scale the coefficients' steps; `start` the parameters' start (the
    /// noises' floors below it, laid out as [`Layout`] with `shape`); `shape` the tracking
    /// noise's covariance between the modes up to its scale (none: one variance per mode,
    /// independent). `None` when the modes' runs differ.
    pub fn new(
        data: &[ModeData],
        forces: &[&ModalForce],
        rates: [f64; 2],
        start: &DVector<f64>,
        shape: Option<&DMatrix<f64>>,
    ) -> Option<Joint> {
        let first = data.first()?;
        let m = data.len();
        let shape = shape.filter(|c| c.nrows() == m && c.ncols() == m).cloned();
        let layout = Layout::new(forces.len(), m, shape.is_some());
        if start.len() != layout.len() {
            return None;
        }
        let mut series = Vec::with_capacity(first.blocks.len());
        for (b, block) in first.blocks.iter().enumerate() {
            if data
                .iter()
                .any(|d| d.blocks.get(b).map(Vec::len) != Some(block.len()))
            {
                return None;
            }
            series.push(
                (0..block.len())
                    .map(|t| (0..m).map(|j| data[j].blocks[b][t]).collect())
                    .collect(),
            );
        }
        let units = first.unit.iter().max().map_or(1, |u| u + 1);
        let biggest = |a: &DMatrix<f64>| a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let scale = forces
            .iter()
            .map(|f| f.block(m))
            .map(|f| {
                let (p, v) = (biggest(&f.position), biggest(&f.velocity));
                // The coefficient that moves the rates by their own size.
                let s =
                    (rates[0] / p.max(f64::MIN_POSITIVE)).min(rates[1] / v.max(f64::MIN_POSITIVE));
                if s.is_finite() && s > 0.0 {
                    s
                } else {
                    1.0
                }
            })
            .chain(std::iter::repeat_n(1.0, layout.len() - forces.len()))
            .collect();
        Some(Joint {
            series,
            unit: first.unit.clone(),
            units,
            forces: forces
                .iter()
                .map(|f| (f.position.clone(), f.velocity.clone()))
                .collect(),
            modes: m,
            scale,
            floor: (0..start.len())
                .map(|i| {
                    if !layout.forces().contains(&i) && !layout.tracking().contains(&i) {
                        f64::NEG_INFINITY
                    } else {
                        start[i] - 8.0 * std::f64::consts::LN_10
                    }
                })
                .collect(),
            layout,
            shape,
        })
    }

    /// Every observed frame's term of −ln L at θ, in series order; `None` when the system is
    /// not stable there.
    fn terms(&self, theta: &DVector<f64>) -> Option<Vec<f64>> {
        let m = self.modes;
        let n = self.forces.first().map_or(m, |f| f.0.nrows());
        let mut stiffness = DMatrix::zeros(n, n);
        let mut damping = DMatrix::zeros(n, n);
        for (c, (p, v)) in theta.iter().zip(&self.forces) {
            stiffness -= p * *c;
            damping -= v * *c;
        }
        let (stiffness, damping) = condense(&stiffness, &damping, m)?;
        let force = force_covariance(theta.as_slice(), self.layout);
        let t = self.layout.tracking();
        let tracking = match &self.shape {
            Some(shape) => shape * theta[t.start].exp(),
            None => DMatrix::from_diagonal(&DVector::from_iterator(m, t.map(|i| theta[i].exp()))),
        };
        let system = System::new(&stiffness, &damping, &force, tracking, 1.0).ok()?;
        let refs: Vec<&[Vec<f64>]> = self.series.iter().map(Vec::as_slice).collect();
        Some(system.frame_terms(&refs)?.into_iter().flatten().collect())
    }

    /// −ln L at θ (infinite where the system is not stable).
    pub fn value(&self, theta: &DVector<f64>) -> f64 {
        self.terms(theta)
            .map_or(f64::INFINITY, |t| t.iter().sum::<f64>())
    }

    /// Each frame's score over `free` at θ, by central differences.
    fn scores(&self, theta: &DVector<f64>, free: &[usize]) -> Option<Vec<DVector<f64>>> {
        let mut columns = Vec::with_capacity(free.len());
        for &i in free {
            let h = STEP * (theta[i].abs() + self.scale[i]).max(self.scale[i]);
            let mut up = theta.clone();
            up[i] += h;
            let mut down = theta.clone();
            down[i] -= h;
            let (u, d) = (self.terms(&up)?, self.terms(&down)?);
            columns.push(
                u.iter()
                    .zip(&d)
                    .map(|(a, b)| (a - b) / (2.0 * h))
                    .collect::<Vec<f64>>(),
            );
        }
        let frames = columns.first().map_or(0, Vec::len);
        Some(
            (0..frames)
                .map(|n| DVector::from_iterator(free.len(), columns.iter().map(|c| c[n])))
                .collect(),
        )
    }

    /// Each unit's summed score and OPG.
    fn by_unit(&self, scores: &[DVector<f64>], free: usize) -> Vec<(DVector<f64>, DMatrix<f64>)> {
        let mut units = vec![(DVector::zeros(free), DMatrix::zeros(free, free)); self.units];
        let mut frame = 0;
        for (s, &u) in self.series.iter().zip(&self.unit) {
            let observed = s.iter().filter(|y| y.iter().all(|v| v.is_finite())).count();
            for g in &scores[frame..frame + observed] {
                units[u].0 += g;
                units[u].1.ger(1.0, g, g, 1.0);
            }
            frame += observed;
        }
        units
    }

    /// The units' scores and OPGs over the parameters `moving` (positions in `scores`); where
    /// their information is singular, without the noises within a hundredth of their floor
    /// (the likelihood is flat there: no noise of that size to see).
    fn moving_units(
        &self,
        theta: &DVector<f64>,
        scores: &[DVector<f64>],
        moving: Vec<usize>,
        free: &[usize],
    ) -> (Vec<usize>, Vec<Unit>) {
        let units_of = |rows: &[usize]| {
            let s: Vec<DVector<f64>> = scores.iter().map(|g| g.select_rows(rows)).collect();
            self.by_unit(&s, rows.len())
        };
        let units = units_of(&moving);
        if total(&units).1.cholesky().is_some() {
            return (moving, units);
        }
        let near = |i: usize| theta[i] < self.floor[i] + 2.0 * std::f64::consts::LN_10;
        let kept: Vec<usize> = moving.into_iter().filter(|&r| !near(free[r])).collect();
        let units = units_of(&kept);
        (kept, units)
    }

    /// The exact fit over `free` (the rest held at `start`), by BHHH; `None` when the start
    /// is not stable or the information is singular.
    pub fn fit(&self, start: DVector<f64>, free: &[usize]) -> Option<JointFit> {
        let mut theta = start;
        let mut value = self.value(&theta);
        if !value.is_finite() {
            return None;
        }
        for _ in 0..ITERATIONS {
            // A noise at its floor that the likelihood pushes further down is held there.
            let scores = self.scores(&theta, free)?;
            let g = (scores.iter()).fold(DVector::zeros(free.len()), |g, s| g + s);
            let moving: Vec<usize> = (0..free.len())
                .filter(|&r| !(theta[free[r]] <= self.floor[free[r]] && g[r] > 0.0))
                .collect();
            let (moving, units) = self.moving_units(&theta, &scores, moving, free);
            let (g, info) = total(&units);
            let step = info.clone().cholesky()?.solve(&g);
            let decrement = g.dot(&step);
            if decrement < 1e-8 {
                return Some(JointFit {
                    theta,
                    free: moving.iter().map(|&r| free[r]).collect(),
                    information: info,
                    units,
                });
            }
            let mut moved = false;
            let mut t = 1.0;
            for _ in 0..16 {
                let mut trial = theta.clone();
                for (r, i) in moving.iter().map(|&r| free[r]).enumerate() {
                    trial[i] = (trial[i] - t * step[r]).max(self.floor[i]);
                }
                let v = self.value(&trial);
                if v < value {
                    (theta, value, moved) = (trial, v, true);
                    break;
                }
                t *= 0.5;
            }
            if !moved {
                break;
            }
        }
        // Out of iterations or stuck: the information where it stopped.
        let moving: Vec<usize> = free
            .iter()
            .copied()
            .filter(|&i| theta[i] > self.floor[i])
            .collect();
        let scores = self.scores(&theta, &moving)?;
        let units = self.by_unit(&scores, moving.len());
        let information = total(&units).1;
        Some(JointFit {
            theta,
            free: moving,
            information,
            units,
        })
    }
}

/// The system on the first `m` modes with the rest condensed quasi-statically: the fast modes
/// q_f follow the slow q_s, q_f ≈ −X q_s − (Y − Z) q̇_s with X = K₂₂⁻¹K₂₁, Y = K₂₂⁻¹D₂₁ and
/// Z = K₂₂⁻¹D₂₂X (their inertia left out: second order in the frequency ratio), so
/// K = K₁₁ − K₁₂X and D = D₁₁ − K₁₂Y − D₁₂X + K₁₂Z. `None` when K₂₂ is singular.
fn condense(k: &DMatrix<f64>, d: &DMatrix<f64>, m: usize) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let f = k.nrows() - m;
    if f == 0 {
        return Some((k.clone(), d.clone()));
    }
    let lu = k.view((m, m), (f, f)).into_owned().lu();
    let x = lu.solve(&k.view((m, 0), (f, m)).into_owned())?;
    let y = lu.solve(&d.view((m, 0), (f, m)).into_owned())?;
    let z = lu.solve(&(d.view((m, m), (f, f)) * &x))?;
    let (k12, d12) = (k.view((0, m), (m, f)), d.view((0, m), (m, f)));
    let stiffness = k.view((0, 0), (m, m)) - k12 * &x;
    let damping = d.view((0, 0), (m, m)) - k12 * &y - d12 * &x + k12 * &z;
    (stiffness
        .iter()
        .chain(damping.iter())
        .all(|v| v.is_finite()))
    .then_some((stiffness, damping))
}

/// The parameters of the force noise's correlations between M modes: L's entries below the
/// diagonal.
pub(super) fn correlations(m: usize) -> usize {
    m * m.saturating_sub(1) / 2
}

/// The force noise's covariance S C S at θ: S = diag(√nⱼ) from θ's ln nⱼ, C = L Lᵀ scaled to
/// a unit diagonal, L unit lower triangular with θ's correlation entries (row by row):
/// positive definite for every θ, diagonal at L = I.
fn force_covariance(theta: &[f64], layout: Layout) -> DMatrix<f64> {
    let (k, m) = (layout.k, layout.m);
    let mut l = DMatrix::identity(m, m);
    let mut next = theta.iter().skip(layout.correlations().start);
    for i in 1..m {
        for j in 0..i {
            l[(i, j)] = next.next().copied().unwrap_or(0.0);
        }
    }
    let c = &l * l.transpose();
    let s: Vec<f64> = (0..m)
        .map(|i| (theta[k + i].exp() / c[(i, i)]).sqrt())
        .collect();
    DMatrix::from_fn(m, m, |i, j| s[i] * c[(i, j)] * s[j])
}

/// Σ over units of the score and the OPG.
fn total(units: &[(DVector<f64>, DMatrix<f64>)]) -> (DVector<f64>, DMatrix<f64>) {
    let n = units.first().map_or(0, |u| u.0.len());
    units
        .iter()
        .fold((DVector::zeros(n), DMatrix::zeros(n, n)), |(g, h), u| {
            (g + &u.0, h + &u.1)
        })
}

impl JointFit {
    /// The one-step estimate of the free parameters on a draw (`count[u]` times unit u) and
    /// its information; `None` when singular.
    pub fn drawn(&self, count: &[usize]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let n = self.free.len();
        let (mut g, mut h) = (DVector::zeros(n), DMatrix::zeros(n, n));
        for ((ug, uh), &c) in self.units.iter().zip(count) {
            g += ug * c as f64;
            h += uh * c as f64;
        }
        let step = h.clone().cholesky()?.solve(&g);
        let theta = DVector::from_iterator(n, self.free.iter().map(|&i| self.theta[i])) - step;
        Some((theta, h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discover::exact::ModeData;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};

    /// The drift's eigenvalues of q̈ = −Kq − Dq̇ (upper half plane), slowest first.
    fn rates(k: &DMatrix<f64>, d: &DMatrix<f64>) -> Vec<nalgebra::Complex<f64>> {
        let m = k.nrows();
        let mut f = DMatrix::zeros(2 * m, 2 * m);
        f.view_mut((0, m), (m, m)).fill_with_identity();
        f.view_mut((m, 0), (m, m)).copy_from(&-k);
        f.view_mut((m, m), (m, m)).copy_from(&-d);
        let mut z: Vec<_> = f.complex_eigenvalues().iter().copied().collect();
        z.retain(|z| z.im >= 0.0);
        z.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
        z
    }

    #[test]
    fn condensed_modes_keep_the_slow_modes_rates() {
        // A stiff six-mode system coupled both ways (not symmetric), lightly damped: its two
        // slowest rates against those of its first two modes condensed and truncated.
        let lambda = [1.0, 16.0, 81.0, 256.0, 625.0, 1296.0];
        let k = DMatrix::from_fn(6, 6, |i, j| match (i, j) {
            _ if i == j => lambda[i],
            _ if i < j => 2.0 * (i + j) as f64,
            _ => -0.5 * (i + j) as f64,
        });
        let d = DMatrix::from_fn(6, 6, |i, j| if i == j { 0.02 * lambda[i] } else { 0.0 });
        let whole = rates(&k, &d);
        let (kc, dc) = condense(&k, &d, 2).expect("K₂₂ regular");
        let condensed = rates(&kc, &dc);
        let truncated = rates(
            &k.view((0, 0), (2, 2)).into(),
            &d.view((0, 0), (2, 2)).into(),
        );
        for j in 0..2 {
            let off = (condensed[j] - whole[j]).norm() / whole[j].norm();
            let cut = (truncated[j] - whole[j]).norm() / whole[j].norm();
            assert!(
                off < 0.2 * cut && off < 2e-3,
                "rate {j}: {off:e} condensed, {cut:e} cut"
            );
        }
    }

    /// The optimiser and its information on a system sampled by `System`'s own Φ and Q (the
    /// independent generator's study is tests/discover_rates.rs): the three coefficients of
    /// a strongly coupled beam (a = 5c), each within 3 of its standard errors.
    #[test]
    fn a_coupled_systems_coefficients_are_recovered() {
        // K = c Λ − a A, D = 2c′ Λ, A the active matrix ⟨φᵢ, φⱼ‴⟩ of a free beam's first four modes.
        let lambda = [500.56, 3803.5, 14617.3, 39943.8];
        let a_mat = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 336.5, 0.0, 532.3, -44.28, 0.0, 934.5, 0.0, 0.0, -243.2, 0.0, 1961.3, -6.67,
                0.0, -717.7, 0.0,
            ],
        );
        let dt: f64 = 0.18722;
        let (c, cp, a) = (2.5e-3 * dt * dt, 1.117e-4 * dt, 0.0125 * dt * dt);
        let lam = DMatrix::from_diagonal(&DVector::from_row_slice(&lambda));
        let k = &lam * c - &a_mat * a;
        let d = &lam * (2.0 * cp);
        let t = 1e-4 * c * 500.56;
        let noise = &d * (2.0 * t);
        let sys = System::new(&k, &d, &noise, DMatrix::identity(4, 4) * 1e-10, 1.0).unwrap();
        let p0 = sys.stationary().unwrap();
        let chol_q = sys.q.clone().cholesky().unwrap().l();
        let mut x = p0.cholesky().unwrap().l() * DVector::from_fn(8, |_, _| 0.0);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut frames: Vec<Vec<f64>> = Vec::new();
        for _ in 0..20000 {
            let w = DVector::from_fn(8, |_, _| -> f64 { StandardNormal.sample(&mut rng) });
            x = &sys.phi * x + &chol_q * w;
            frames.push(
                (0..4)
                    .map(|j| {
                        let e: f64 = StandardNormal.sample(&mut rng);
                        x[j] + 1e-5 * e
                    })
                    .collect::<Vec<f64>>(),
            );
        }
        let data: Vec<ModeData> = (0..4)
            .map(|j| ModeData {
                blocks: frames
                    .chunks(800)
                    .map(|b| b.iter().map(|f| f[j]).collect())
                    .collect(),
                unit: (0..25).collect(),
            })
            .collect();
        let pos = |m: DMatrix<f64>| ModalForce {
            position: m,
            velocity: DMatrix::zeros(4, 4),
        };
        let fc = pos(-lam.clone());
        let fa = pos(DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 336.97, 0.0, 537.10, -44.234, 0.0, 936.36, 0.0, 0.0, -242.82, 0.0, 1966.48,
                -6.6228, 0.0, -716.61, 0.0,
            ],
        ));
        let fd = ModalForce {
            position: DMatrix::zeros(4, 4),
            velocity: -&lam * 2.0,
        };
        let layout = Layout::new(3, 4, false);
        let mut start = DVector::from_element(layout.len(), (1e-10f64).ln());
        layout.correlations().for_each(|i| start[i] = 0.0);
        start[0] = c * 1.1;
        start[1] = cp * 0.9;
        start[2] = 0.0;
        for j in 0..4 {
            start[3 + j] = (2.0 * t * d[(j, j)]).ln();
        }
        let joint = Joint::new(&data, &[&fc, &fd, &fa], [c * 500.0, 0.1], &start, None).unwrap();
        let fit = joint.fit(start, &(0..7).collect::<Vec<_>>()).unwrap();
        let cov = fit.information.clone().cholesky().unwrap().inverse();
        for (i, truth) in [c, cp, a].into_iter().enumerate() {
            let se = cov[(i, i)].sqrt();
            assert!(
                (fit.theta[i] - truth).abs() < 3.0 * se && se < 0.02 * truth,
                "parameter {i}: {} ± {se} for {truth}",
                fit.theta[i]
            );
        }
    }
}
