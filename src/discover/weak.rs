//! The weak form in time, projected on the grid's modes.
//!
//! For the field's equation ∂t²u + Σ cₘ ∂t pₘ(∂tu) = Σ cₘ fₘ(u, ∂tu) + ξ on the grid
//! ([`crate::dynamics::Candidate`]), a mode shape vᵢ and a bump ψ(t) = (1 − τ²)⁸,
//! τ = (t − t₀)/H, both derivatives of the inertia and the momenta moved onto ψ:
//!
//! ∫ ψ'' vᵢ·u dt = Σₘ cₘ ∫ (ψ vᵢ·fₘ + ψ' vᵢ·pₘ) dt + ∫ ψ vᵢ·ξ dt,
//!
//! sums over the frames (Δt each), velocities by centred differences. One row per mode and
//! window; windows of one mode do not overlap, so their noise terms are independent for white
//! noise. H is the mode's own time scale, 1/(ωᵢΔt) frames (at least [`MIN_HALF_WIDTH`]), from `fit`'s spectral fit.
//!
//! **Instruments.** Thermal noise ξ inside a window moves u inside it, so the regressors and
//! the noise correlate (a least-squares fit would bias the damping); tracking noise does the
//! same to every regressor. Each row's instruments are its mode's two previous windows (their
//! target and regressors) and the state two frames before the window opens (the mode's
//! coordinate and every candidate's force there, projected): the state before a window does
//! not know the noise inside it, and is correlated with the state in it. The nearby state
//! predicts a nonlinear force's fluctuation, which the earlier windows have forgotten (a cubic
//! term was otherwise not told from the linear stiffness). The estimate is two-stage least
//! squares.
//!
//! **Time in frames.** The rows measure time in the first recording's sampling interval
//! ([`time_unit`]), not in the data's unit: the sums, the instruments, the windows' clock and
//! every tolerance downstream are then the same numbers whatever unit the time column is
//! written in (seconds, milliseconds, or 10¹⁰⁰ of them), and nothing overflows on the way.
//! A coefficient of dimension Tᵖ ([`Candidate::time_power`]) is taken back to the data's
//! unit by the factor Δtᵖ ([`in_data_unit`]).

use super::data::Recording;
use super::DiscoverError;
use crate::dynamics::Candidate;

/// Rows of the weak form of one library.
#[derive(Debug, Clone, Default)]
pub(super) struct Rows {
    /// ∫ψ''vᵢ·u, weighted.
    pub target: Vec<f64>,
    /// One regressor per candidate, weighted.
    pub regressors: Vec<Vec<f64>>,
    /// The instruments (previous windows' target and regressors), in the block of columns
    /// of the row's mode (`slot`).
    pub instruments: Vec<Vec<f64>>,
    /// Which mode's block of instrument columns.
    pub slot: Vec<usize>,
    /// Number of blocks.
    pub slots: usize,
    /// ∫ψ² dt: the noise's share of a row, for the noise level.
    pub norm: Vec<f64>,
    /// The row's weight (1/rms of its mode's targets).
    pub weight: Vec<f64>,
    /// Time of the window's centre, on one line through every recording.
    pub time: Vec<f64>,
    /// Which recording.
    pub animal: Vec<usize>,
}

impl Rows {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.target.len()
    }

    /// Row `r`'s target less the fit (`set`, `beta`), unweighted.
    pub fn residual(&self, r: usize, set: &[usize], beta: &[f64]) -> f64 {
        let fitted: f64 = set
            .iter()
            .zip(beta)
            .map(|(&m, b)| b * self.regressors[m][r])
            .sum();
        self.target[r] - fitted
    }

    /// Weigh each mode's rows by 1/(its residual's rms) under the fit (`set`, `beta`): the
    /// second step of two-step efficient estimation, so that modes the noise dominates count
    /// for less. Instruments are untouched, so the estimate stays consistent.
    pub fn reweight(&mut self, set: &[usize], beta: &[f64]) {
        let mut sum = vec![0.0; self.slots];
        let mut count = vec![0.0; self.slots];
        for r in 0..self.len() {
            let e = self.weight[r] * self.residual(r, set, beta);
            sum[self.slot[r]] += e * e;
            count[self.slot[r]] += 1.0;
        }
        for r in 0..self.len() {
            let s = self.slot[r];
            let rms = (sum[s] / count[s]).sqrt();
            if rms > 0.0 && rms.is_finite() {
                self.weight[r] /= rms;
            }
        }
    }
}

/// Frames per radian a mode needs: sums over frames stand for the weak form's integrals only
/// when the motion is sampled finely (about 19 frames per period).
pub const MIN_FRAMES_PER_RADIAN: f64 = 3.0;

/// The modes a recording's rows use: the lowest non-zero modes whose spectral peak `fit`
/// resolves and that are sampled at [`MIN_FRAMES_PER_RADIAN`], up to the first that is not
/// (a lone peak further up is more likely noise than a mode the damping left visible).
pub(super) fn used(rec: &Recording) -> impl Iterator<Item = &crate::fit::ModeSpectralFit> {
    rec.fit
        .modes_fit
        .iter()
        .take_while(|m| m.resolved && m.omega * rec.dt * MIN_FRAMES_PER_RADIAN <= 1.0)
}

/// ψ, ψ', ψ'' of the bump at τ ∈ [−1, 1] (derivatives in τ).
fn bump(tau: f64) -> (f64, f64, f64) {
    let a = 1.0 - tau * tau;
    let p = BUMP_POWER;
    let pf = f64::from(p);
    (
        a.powi(p),
        -2.0 * pf * tau * a.powi(p - 1),
        -2.0 * pf * a.powi(p - 1) + 4.0 * pf * (pf - 1.0) * tau * tau * a.powi(p - 2),
    )
}

/// The bump's power p in (1 − τ²)ᵖ: its derivatives up to p − 1 vanish at the ends, so the sums
/// over frames converge fast to the integrals.
pub const BUMP_POWER: i32 = 8;

/// The least half-width in frames: the sums over frames must resolve the bump's ψ''.
pub const MIN_HALF_WIDTH: usize = 12;

/// The half-width in frames of mode `mode`'s windows (its angular frequency ω).
pub(super) fn half_width(omega: f64, dt: f64) -> usize {
    ((1.0 / (omega * dt)).round() as usize).max(MIN_HALF_WIDTH)
}

/// Per-frame projections: for each candidate, vᵢ·f and vᵢ·p at each frame of a run.
struct Projected {
    /// target[k] = vᵢ·u_k.
    target: Vec<f64>,
    force: Vec<Vec<f64>>,
    momentum: Vec<Vec<f64>>,
}

fn project(run: &[Vec<f64>], dt: f64, shape: &[f64], library: &[Candidate]) -> Projected {
    let n = run.len();
    let strip = |x: &[f64]| library.first().map_or_else(|| x.to_vec(), |c| c.strip(x));
    let s = strip(shape);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut force = vec![vec![0.0; n]; library.len()];
    let mut momentum = vec![vec![0.0; n]; library.len()];
    let mut target = vec![0.0; n];
    let frames: Vec<Vec<f64>> = run.iter().map(|p| strip(p)).collect();
    for k in 1..n.saturating_sub(1) {
        let u = &frames[k];
        let v: Vec<f64> = frames[k + 1]
            .iter()
            .zip(&frames[k - 1])
            .map(|(a, b)| (a - b) / (2.0 * dt))
            .collect();
        target[k] = dot(&s, u);
        for (m, c) in library.iter().enumerate() {
            if c.kinetic {
                momentum[m][k] = dot(&s, &c.momentum(&v));
            } else {
                force[m][k] = dot(&s, &c.force(u, &v));
            }
        }
    }
    Projected {
        target,
        force,
        momentum,
    }
}

/// The budget of one library's rows: frames × points × modes used × library terms (each
/// term's force at every frame, projected on every used mode); 3·10⁸ is about ten seconds.
pub const MAX_WORK: f64 = 3e8;

/// [`MAX_WORK`] checked for a library of `terms` terms before its rows are summed.
pub(super) fn check_work(recordings: &[Recording], terms: usize) -> Result<(), DiscoverError> {
    let work: f64 = recordings
        .iter()
        .map(|r| r.values() as f64 * used(r).count() as f64 * terms as f64)
        .sum();
    if work > MAX_WORK {
        return Err(DiscoverError::WeakBudget { work, terms });
    }
    Ok(())
}

/// The time unit of the rows, in the data's: the first recording's sampling interval (a frame).
pub(super) fn time_unit(recordings: &[Recording]) -> f64 {
    recordings.first().map_or(1.0, |r| r.dt)
}

/// A quantity of dimension Tᵖ measured in frames ([`time_unit`] `unit`), in the data's time
/// unit: `x`·unitᵖ, one factor at a time so that no power of the unit overflows on its own
/// (non-finite only when the answer is beyond the floats).
pub(super) fn in_data_unit(x: f64, unit: f64, p: i32) -> f64 {
    let step = if p < 0 { unit.recip() } else { unit };
    (0..p.unsigned_abs()).fold(x, |x, _| x * step)
}

/// Every row of `library` over the recordings, on the modes `fit` resolved, time in frames of
/// the first recording ([`time_unit`]).
pub(super) fn rows(recordings: &[Recording], library: &[Candidate]) -> Rows {
    let mut rows = Rows {
        regressors: vec![Vec::new(); library.len()],
        ..Rows::default()
    };
    // Each mode has its own instrument columns: how earlier windows predict the present one
    // differs from mode to mode (a pooled first stage would be weak).
    let mut slots: Vec<usize> = recordings
        .iter()
        .flat_map(|r| used(r).map(|m| m.mode))
        .collect();
    slots.sort_unstable();
    slots.dedup();
    rows.slots = slots.len();
    let mut offset = 0.0;
    let unit = time_unit(recordings);
    for (a, rec) in recordings.iter().enumerate() {
        // 1 for the first recording, whatever its unit.
        let dt = rec.dt / unit;
        for mode in used(rec) {
            let Some(shape) = mode
                .mode
                .checked_sub(rec.first_mode)
                .and_then(|j| rec.shapes.get(j))
            else {
                continue;
            };
            let h = half_width(mode.omega, rec.dt);
            let start = rows.len();
            let mut clock = offset;
            for run in &rec.runs {
                let p = project(run, dt, shape, library);
                // Windows [c − h, c + h] inside frames 1 … n − 2, two frames apart.
                let mut history: Vec<Vec<f64>> = Vec::new();
                let mut c = 1 + h;
                while c + h + 1 < run.len() {
                    let mut y = 0.0;
                    let mut x = vec![0.0; library.len()];
                    let mut norm = 0.0;
                    for k in c - h..=c + h {
                        let tau = (k as f64 - c as f64) / h as f64;
                        let (w0, w1, w2) = bump(tau);
                        let (d1, d2) = (w1 / (h as f64 * dt), w2 / (h as f64 * dt).powi(2));
                        y += d2 * p.target[k] * dt;
                        norm += w0 * w0 * dt;
                        for (m, xm) in x.iter_mut().enumerate() {
                            *xm += (w0 * p.force[m][k] + d1 * p.momentum[m][k]) * dt;
                        }
                    }
                    let mut here = vec![y];
                    here.extend(&x);
                    if history.len() >= 2 {
                        let n = history.len();
                        let mut z = history[n - 1].clone();
                        z.extend(&history[n - 2]);
                        // Frames k0 ± 1 (its velocity) end before the window's first frame.
                        let k0 = c - h - 2;
                        z.push(p.target[k0]);
                        z.extend((0..library.len()).map(|m| p.force[m][k0] + p.momentum[m][k0]));
                        rows.slot.push(slots.binary_search(&mode.mode).unwrap_or(0));
                        rows.target.push(y);
                        for (m, xm) in x.iter().enumerate() {
                            rows.regressors[m].push(*xm);
                        }
                        rows.instruments.push(z);
                        rows.norm.push(norm);
                        rows.time.push(clock + c as f64 * dt);
                        rows.animal.push(a);
                    }
                    history.push(here);
                    c += 2 * h + 3;
                }
                clock += run.len() as f64 * dt;
            }
            // Each mode weighs alike: its rows scaled by 1/rms of its targets.
            let n = rows.len() - start;
            let rms =
                (rows.target[start..].iter().map(|y| y * y).sum::<f64>() / n.max(1) as f64).sqrt();
            let w = if rms > 0.0 { 1.0 / rms } else { 1.0 };
            rows.weight.extend(std::iter::repeat_n(w, n));
        }
        offset += rec.runs.iter().map(Vec::len).sum::<usize>() as f64 * dt;
    }
    rows
}
