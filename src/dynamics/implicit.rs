//! The implicit step of a [`FieldSystem`], made cheap enough to run next to the exact modal
//! propagators.
//!
//! **The scheme.** Average vector field with the dissipation at the mean velocity:
//! q₁ = q₀ + h v̄, v₁ = v₀ − h ∫₀¹ ∇V(q₀ + ξΔ) dξ − h ∇R(v̄) + h f(t + h/2) + η, Δ = q₁ − q₀,
//! v̄ = Δ/h. Without noise and forces it keeps the discrete energy balance exactly,
//! E₁ − E₀ = −h v̄·∇R(v̄). Each step solves r(Δ) = 2Δ/h − 2v₀ + h∫∇V + h∇R(Δ/h) − h f − η = 0 for Δ.
//!
//! **Why it is cheap.** The squares of V and R have constant Hessians K and C: their part of
//! ∫∇V is K(q₀ + Δ/2) exactly (no quadrature), their part of the Newton matrix
//! J = 2/h + hK/2 + C + h∫ξ∇²V_nl + ∇²R_nl is constant. So J is factorised once and kept while
//! it still contracts Newton's iteration fast (its changes are O(h) against the 2/h that
//! dominates it), refactorised when the contraction slows; a field without a nonlinear term
//! keeps one factorisation for the whole run and takes one solve per step, exact.
//!
//! **Noise.** With quadratic dissipation R = Σ c (w·v)², fluctuation–dissipation at temperature
//! kT gives the velocity kick η = Σ_rows √(4 c kT h) ξ_r w_r (covariance 2kT h ∇²R, the modal
//! run's ⟨ξξ⟩ = 4γkT per mode). On a linear body the midpoint rule with this kick leaves the
//! exact Gibbs distribution invariant; on a nonlinear one it is first order in h.

use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::jacobian::{Factored, Jacobian};
use super::nonlinear::{FieldSystem, NonlinearError, Power};

/// A symmetric matrix by rows of (column, value), flat (compressed rows).
struct Sparse {
    entries: Vec<(usize, f64)>,
    starts: Vec<usize>,
}

impl Sparse {
    /// The (constant) Hessian of the squares among `powers` on n unknowns.
    fn hessian_of<'a>(powers: impl Iterator<Item = &'a Power>, n: usize) -> Sparse {
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        let zero = vec![0.0; n];
        for p in powers {
            p.hessian(
                &zero,
                1.0,
                &mut |i, j, x| match rows[i].iter_mut().find(|e| e.0 == j) {
                    Some(e) => e.1 += x,
                    None => rows[i].push((j, x)),
                },
            );
        }
        let mut starts = vec![0];
        let mut entries = Vec::new();
        for r in rows {
            entries.extend(r);
            starts.push(entries.len());
        }
        Sparse { entries, starts }
    }

    fn rows(&self) -> impl Iterator<Item = &[(usize, f64)]> {
        self.starts.windows(2).map(|w| &self.entries[w[0]..w[1]])
    }

    /// out += scale · A x.
    fn mul_add(&self, x: &[f64], scale: f64, out: &mut [f64]) {
        if self.entries.is_empty() {
            return;
        }
        for (o, row) in out.iter_mut().zip(self.rows()) {
            *o += scale * row.iter().map(|&(j, a)| a * x[j]).sum::<f64>();
        }
    }

    /// J += scale · A.
    fn add_to(&self, scale: f64, jac: &mut Jacobian) {
        for (i, row) in self.rows().enumerate() {
            for &(j, a) in row {
                jac.add(i, j, scale * a);
            }
        }
    }
}

/// One field's stepping state over a run: the split of its terms, the kept factorisation and
/// scratch vectors (no allocation per step).
pub(super) struct FieldStepper<'a> {
    system: &'a FieldSystem,
    stiffness: Sparse,
    friction: Sparse,
    /// The squares of the kinetic energy beyond ½|v|², as a matrix (the mass is I + this).
    mass: Sparse,
    potential: Vec<&'a Power>,
    kinetic: Vec<&'a Power>,
    dissipation: Vec<&'a Power>,
    nodes: Vec<(f64, f64)>,
    bandwidth: usize,
    /// Noise rows: (row, √(4c·kT·h)).
    noise: Vec<(&'a [(usize, f64)], f64)>,
    factor: Option<Factored>,
    /// The last step's acceleration, without its kick.
    accel: Vec<f64>,
    /// Scratch: Δ, the residual, a quadrature point.
    delta: Vec<f64>,
    r: Vec<f64>,
    at: Vec<f64>,
    /// ∇T_nl(v₀) of the step, for the momentum change.
    p0: Vec<f64>,
    /// Scratch for the active forces: v̄ and f(ū, v̄).
    mid: Vec<f64>,
    force: Vec<f64>,
    /// The work done so far: (dissipated, injected by the active forces); kept only for a
    /// field with active forces (the dissipated part is otherwise not needed).
    work: (f64, f64),
}

/// The contraction above which the kept Newton matrix is refreshed.
const REFRESH: f64 = 0.03;

/// How many Newton iterations a step may take.
const MAX_ITERATIONS: usize = 60;

impl<'a> FieldStepper<'a> {
    /// The stepper of `system`, without noise.
    pub(super) fn new(system: &'a FieldSystem) -> FieldStepper<'a> {
        let square = |p: &&Power| p.power() == 2;
        let n = system.unknowns;
        FieldStepper {
            stiffness: Sparse::hessian_of(system.potential.iter().filter(square), n),
            friction: Sparse::hessian_of(system.dissipation.iter().filter(square), n),
            mass: Sparse::hessian_of(system.kinetic.iter().filter(square), n),
            potential: system.potential.iter().filter(|p| !square(p)).collect(),
            kinetic: system.kinetic.iter().filter(|p| !square(p)).collect(),
            dissipation: system.dissipation.iter().filter(|p| !square(p)).collect(),
            nodes: system.quadrature(),
            bandwidth: system.bandwidth(),
            noise: Vec::new(),
            factor: None,
            accel: vec![0.0; n],
            delta: vec![0.0; n],
            r: vec![0.0; n],
            at: vec![0.0; n],
            p0: vec![0.0; n],
            mid: vec![0.0; n],
            force: vec![0.0; n],
            work: (0.0, 0.0),
            system,
        }
    }

    /// Noise at temperature kT for steps of h, through the quadratic dissipation only.
    fn with_noise(mut self, h: f64, kt: f64) -> Result<FieldStepper<'a>, NonlinearError> {
        if !self.kinetic.is_empty() {
            return Err(NonlinearError::Noise {
                field: self.system.id.clone(),
                why: "a kinetic energy quadratic in the velocity",
            });
        }
        for p in &self.system.dissipation {
            if p.power() != 2 || p.coefficient < 0.0 {
                return Err(NonlinearError::Noise {
                    field: self.system.id.clone(),
                    why: "a dissipation that is a sum of squares with non-negative coefficients",
                });
            }
            let amplitude = (4.0 * p.coefficient * kt * h).sqrt();
            self.noise.extend(p.rows().map(|r| (r, amplitude)));
        }
        Ok(self)
    }

    fn linear(&self) -> bool {
        self.system.is_linear()
    }

    /// The Newton matrix at the current Δ from (u, v), factorised.
    fn factorise(&mut self, u: &[f64], v: &[f64], h: f64) {
        let n = self.system.unknowns;
        let mut jac = Jacobian::new(n, self.system.periodic, self.bandwidth);
        for i in 0..n {
            jac.add(i, i, 2.0 / h);
        }
        self.mass.add_to(2.0 / h, &mut jac);
        // ∂/∂Δ of ∇T(v₁), v₁ = 2Δ/h − v₀.
        for (a, (d, x)) in self.at.iter_mut().zip(self.delta.iter().zip(v)) {
            *a = 2.0 * d / h - x;
        }
        for p in &self.kinetic {
            p.hessian(&self.at, 2.0 / h, &mut |i, j, x| jac.add(i, j, x));
        }
        self.stiffness.add_to(0.5 * h, &mut jac);
        self.friction.add_to(1.0, &mut jac);
        for &(xi, w) in &self.nodes {
            for (a, (ui, di)) in self.at.iter_mut().zip(u.iter().zip(&self.delta)) {
                *a = ui + xi * di;
            }
            for p in &self.potential {
                p.hessian(&self.at, h * w * xi, &mut |i, j, x| jac.add(i, j, x));
            }
        }
        for (a, d) in self.at.iter_mut().zip(&self.delta) {
            *a = d / h;
        }
        for p in &self.dissipation {
            p.hessian(&self.at, 1.0, &mut |i, j, x| jac.add(i, j, x));
        }
        self.factor = Some(jac.factor());
    }

    /// r(Δ) into `self.r`, with `push` = h f + η already summed (or empty).
    fn residual(&mut self, u: &[f64], v: &[f64], h: f64, push: &[f64]) {
        let Self { r, delta, at, .. } = self;
        for i in 0..r.len() {
            r[i] = 2.0 * delta[i] / h - 2.0 * v[i];
            at[i] = u[i] + 0.5 * delta[i];
        }
        for (ri, p) in r.iter_mut().zip(push) {
            *ri -= p;
        }
        // The momentum change beyond v₁ − v₀: M_q(v₁ − v₀) + ∇T_nl(v₁) − ∇T_nl(v₀).
        if !self.mass.entries.is_empty() || !self.kinetic.is_empty() {
            for i in 0..r.len() {
                at[i] = 2.0 * delta[i] / h - 2.0 * v[i];
            }
            self.mass.mul_add(at, 1.0, r);
            for (a, (d, x)) in at.iter_mut().zip(delta.iter().zip(v)) {
                *a = 2.0 * d / h - x;
            }
            for p in &self.kinetic {
                p.gradient(at, 1.0, r);
            }
            for (ri, p) in r.iter_mut().zip(&self.p0) {
                *ri -= p;
            }
            for i in 0..r.len() {
                at[i] = u[i] + 0.5 * delta[i];
            }
        }
        self.stiffness.mul_add(at, h, r);
        self.friction.mul_add(delta, 1.0, r);
        for &(xi, w) in &self.nodes {
            for (a, (ui, di)) in at.iter_mut().zip(u.iter().zip(delta.iter())) {
                *a = ui + xi * di;
            }
            for p in &self.potential {
                p.gradient(at, h * w, r);
            }
        }
        for (a, d) in at.iter_mut().zip(delta.iter()) {
            *a = d / h;
        }
        for p in &self.dissipation {
            p.gradient(at, h, r);
        }
        if !self.system.active.is_empty() {
            self.active_at_mid(u, h);
            for (ri, f) in self.r.iter_mut().zip(&self.force) {
                *ri -= h * f;
            }
        }
    }

    /// f(ū, v̄) into `self.force` at the current Δ (ū = u₀ + Δ/2, v̄ = Δ/h; `self.at` holds ū).
    fn active_at_mid(&mut self, u: &[f64], h: f64) {
        for (((a, m), d), x) in self
            .at
            .iter_mut()
            .zip(&mut self.mid)
            .zip(&self.delta)
            .zip(u)
        {
            *a = x + 0.5 * d;
            *m = d / h;
        }
        self.force.fill(0.0);
        for a in &self.system.active {
            a.add(&self.at, &self.mid, 1.0, &mut self.force);
        }
    }

    /// The step's dissipated and injected work, h v̄·∇R(v̄) and h v̄·f(ū, v̄), added to
    /// `self.work` (at the converged Δ, before u moves).
    fn account(&mut self, u: &[f64], h: f64) {
        self.active_at_mid(u, h);
        let friction = self.system.dissipation_gradient(&self.mid);
        let dot = |a: &[f64]| h * a.iter().zip(&self.mid).map(|(x, y)| x * y).sum::<f64>();
        self.work.0 += dot(&friction);
        self.work.1 += dot(&self.force);
    }

    /// The noise kick η of one step into `out` (added).
    pub(super) fn kick(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        for &(row, amplitude) in &self.noise {
            let z: f64 = StandardNormal.sample(rng);
            for &(j, w) in row {
                out[j] += amplitude * z * w;
            }
        }
    }

    /// A linear field's step: r(Δ) = JΔ − (2v₀ − hK u₀ − h∇V_lin + push) is linear in Δ and J is
    /// constant, so Δ is one solve with the factorisation kept for the whole run.
    fn linear_step(
        &mut self,
        u: &mut [f64],
        v: &mut [f64],
        h: f64,
        t: f64,
        push: &[f64],
    ) -> Result<(), NonlinearError> {
        if self.factor.is_none() {
            self.delta.fill(0.0);
            self.factorise(u, v, h);
        }
        let Self { r, delta, .. } = self;
        for (i, ri) in r.iter_mut().enumerate() {
            *ri = 2.0 * v[i] + push.get(i).copied().unwrap_or(0.0);
        }
        self.mass.mul_add(v, 2.0, r);
        self.stiffness.mul_add(u, -h, r);
        // Power-1 terms: a constant force.
        for p in &self.potential {
            p.gradient(u, -h, r);
        }
        if let Some(factor) = &self.factor {
            factor.solve(r);
        }
        delta.copy_from_slice(r);
        self.finish(u, v, h, t, push)
    }

    /// q₁ = q₀ + Δ, v₁ = 2Δ/h − v₀; the acceleration kept for the next guess.
    fn finish(
        &mut self,
        u: &mut [f64],
        v: &mut [f64],
        h: f64,
        t: f64,
        push: &[f64],
    ) -> Result<(), NonlinearError> {
        if !self.system.active.is_empty() {
            self.account(u, h);
        }
        for i in 0..u.len() {
            let v1 = 2.0 * self.delta[i] / h - v[i];
            let kick = push.get(i).copied().unwrap_or(0.0);
            self.accel[i] = (v1 - v[i] - kick) / h;
            u[i] += self.delta[i];
            v[i] = v1;
        }
        if u.iter().chain(v.iter()).all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(NonlinearError::Diverged { t: t + h })
        }
    }

    /// One step of length h from (u, v) at time t, in place; `push` = h f + η (or empty).
    pub(super) fn step(
        &mut self,
        u: &mut [f64],
        v: &mut [f64],
        h: f64,
        t: f64,
        push: &[f64],
    ) -> Result<(), NonlinearError> {
        if self.linear() {
            return self.linear_step(u, v, h, t, push);
        }
        // The guess: Δ = h v₀ + h·push/2 + h²a/2 with the last step's acceleration a (without its
        // kick), so Newton starts O(h³) from the answer.
        for (i, d) in self.delta.iter_mut().enumerate() {
            let kick = push.get(i).copied().unwrap_or(0.0);
            *d = h * (v[i] + 0.5 * kick + 0.5 * h * self.accel[i]);
        }
        self.p0.fill(0.0);
        for p in &self.kinetic {
            p.gradient(v, 1.0, &mut self.p0);
        }
        let mut last = f64::INFINITY;
        let mut converged = false;
        let mut rounding = false;
        // At rest about an equilibrium u* ≠ 0 (Δ ≈ 0, v ≈ 0) the rounding of ∇V(u) is the
        // floor, not Δ's own size: a change below an ulp of u cannot change u + Δ.
        let magnitude = |x: &[f64]| x.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for _ in 0..MAX_ITERATIONS {
            self.residual(u, v, h, push);
            if self.factor.is_none() {
                self.factorise(u, v, h);
            }
            let Some(factor) = &self.factor else { break };
            factor.solve(&mut self.r);
            let size = self.delta.iter().map(|d| d.abs()).fold(0.0, f64::max);
            let change = self.r.iter().map(|d| d.abs()).fold(0.0, f64::max);
            for (d, s) in self.delta.iter_mut().zip(&self.r) {
                *d -= s;
            }
            if !change.is_finite() {
                break;
            }
            // Converged at the rounding floor: the error left after this iteration, θ/(1 − θ)
            // times its change for the contraction θ measured from the second iteration on, is
            // an ulp or so of Δ (or of h·v₀ when Δ is near zero); or it stopped shrinking once
            // already tiny.
            let theta = change / last;
            let left = if !last.is_finite() {
                f64::INFINITY
            } else if theta < 0.5 {
                theta / (1.0 - theta) * change
            } else {
                change
            };
            let scale = size.max(h * magnitude(v));
            let floor = left <= 4e-15 * scale || change == 0.0;
            let stalled = change >= last && change <= 1e-11 * scale;
            if floor || stalled {
                converged = true;
                break;
            }
            // A kept matrix that contracts slowly is refreshed at the current Δ.
            if theta > REFRESH {
                self.factor = None;
            }
            last = change;
            rounding = change <= 4.0 * f64::EPSILON * magnitude(u);
        }
        // Out of iterations with every change below a few ulps of u: nothing Newton could add
        // would change u + Δ.
        converged |= rounding;
        if !converged {
            self.factor = None;
            return Err(NonlinearError::NoConvergence { t });
        }
        self.finish(u, v, h, t, push)
    }
}

/// A body's fields stepped together at a fixed step h, keeping each field's factorisation.
pub struct Integrator<'a> {
    fields: Vec<FieldStepper<'a>>,
    h: f64,
}

impl super::nonlinear::NonlinearBody {
    /// An integrator of step h without noise.
    pub fn integrator(&self, h: f64) -> Integrator<'_> {
        Integrator {
            fields: self.fields.iter().map(FieldStepper::new).collect(),
            h,
        }
    }

    /// An integrator of step h at temperature kT > 0.
    pub(super) fn noisy_integrator(
        &self,
        h: f64,
        kt: f64,
    ) -> Result<Integrator<'_>, NonlinearError> {
        Ok(Integrator {
            fields: self
                .fields
                .iter()
                .map(|f| FieldStepper::new(f).with_noise(h, kt))
                .collect::<Result<_, _>>()?,
            h,
        })
    }
}

impl Integrator<'_> {
    /// Advance every field one step from time t, without noise or forces.
    pub fn step(
        &mut self,
        state: &mut [(Vec<f64>, Vec<f64>)],
        t: f64,
    ) -> Result<(), NonlinearError> {
        let h = self.h;
        for (f, (u, v)) in self.fields.iter_mut().zip(state.iter_mut()) {
            f.step(u, v, h, t, &[])?;
        }
        Ok(())
    }

    /// The same with each field's velocity kick h f + η in `push` (empty: none).
    pub(super) fn step_pushed(
        &mut self,
        state: &mut [(Vec<f64>, Vec<f64>)],
        t: f64,
        push: &[Vec<f64>],
    ) -> Result<(), NonlinearError> {
        let h = self.h;
        for ((f, (u, v)), p) in self.fields.iter_mut().zip(state.iter_mut()).zip(push) {
            f.step(u, v, h, t, p)?;
        }
        Ok(())
    }

    /// The work done since the start, summed over the fields: (dissipated, injected by the
    /// active forces); both zero for a body without active forces (only then is it kept).
    pub fn work(&self) -> (f64, f64) {
        self.fields
            .iter()
            .fold((0.0, 0.0), |(d, i), f| (d + f.work.0, i + f.work.1))
    }

    /// Add one step's noise kicks into `push`.
    pub(super) fn kicks(&self, rng: &mut ChaCha8Rng, push: &mut [Vec<f64>]) {
        for (f, p) in self.fields.iter().zip(push) {
            f.kick(rng, p);
        }
    }
}
