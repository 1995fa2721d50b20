//! Forward and backward peristalsis split by a gyroscopic force, by simulation (the paper's
//! App. C and Fig. 11).
//!
//! App. C posits c(X₁Ẋ₂ − X₂Ẋ₁)X₁ on the first axial pair, whose frequencies on a circular
//! orbit of amplitude A then solve ω_s² + cA²ω_s − ω² = 0 (the seed prints cA: `asymmetry`): a
//! wave running one way is faster than one running the other, 1 : 2 at |c|A²/ω = √2/2. That force is nonlocal (docs/derivation.md). The local force with the same
//! linear effect is the axial field's lowest gyroscopic force g∂t∂s x, which an `[active]`
//! section without PAR allows: on a wave e^{i(ks − ωt)} it gives ω² + gkω − c²k² = 0, App. C's
//! relation with cA² ↔ gk, on circular travelling waves only (App. C's force is cubic, does
//! work off circular orbits and keeps a standing wave standing; g∂t∂s x drives it into a
//! travelling one). On the grid (centred differences) k becomes sin k and ck the pair's
//! own frequency ω₁, so with the coupling G = −g sin k/ω₁ the forward (towards the head, +s)
//! and backward frequencies are ω₁(√(G² + 4) ± G)/2 and the ratio is 1 : 2 at G = 1/√2 on any
//! grid.
//!
//! **Measured, not assumed**: for each G the ring is started as a standing wave of the first
//! pair (both directions equally) and integrated by the discretised body's implicit step (no
//! damping: the frequencies are the undamped ones; 100 steps per period, 10 periods); its
//! Fourier amplitude A(t) = Σⱼ xⱼe^{−ikj} is a sum of two exponentials e^{−iω_f t} and
//! e^{+iω_b t}, read off by Prony's method (A_{n+2} = pA_{n+1} + qA_n by least squares, the
//! roots of z² − pz − q). The implicit midpoint step turns a mode of frequency ω by exactly
//! 2 arctan(ωh/2) per step (its Cayley transform), which is inverted: the frequencies are the
//! discretised body's own, free of the step's error. The 1 : 2 coupling is located by bisection
//! on such runs.

use nalgebra::Complex;

use super::BehaviourError;
use crate::boundary::Boundary;
use crate::dynamics::nonlinear::NonlinearBody;
use crate::model::{Density, Role};
use crate::theory::Theory;

/// App. C's coupling at the 1 : 2 ratio, |c|A/ω = √2/2 (with A = ω = 1).
pub const PAPER_COUPLING: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// One coupling's simulated frequencies, in units of the pair's own ω₁.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Split {
    /// G = −g sin k/ω₁.
    pub coupling: f64,
    /// The wave running towards the head (+s).
    pub forward: f64,
    /// The wave running towards the tail.
    pub backward: f64,
}

/// The sweep over couplings and the simulated 1 : 2 point.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ForwardBackward {
    /// The axial field.
    pub field: String,
    /// The gyroscopic force's coefficient (`g_x`).
    pub coefficient: String,
    /// ω₁, the first axial pair's frequency without the force.
    pub omega: f64,
    /// Per coupling.
    pub sweep: Vec<Split>,
    /// The coupling where backward : forward = 1 : 2, from simulations.
    pub half: f64,
}

/// A failure of the discretised body, typed (a step that does not converge is numerical).
fn dynamics(e: crate::dynamics::nonlinear::NonlinearError) -> BehaviourError {
    BehaviourError::Dynamics(e.into())
}

/// (forward, backward) / ω₁ from the dispersion relation at coupling G.
pub fn analytic(coupling: f64) -> (f64, f64) {
    let s = (coupling * coupling + 4.0).sqrt();
    ((s + coupling) / 2.0, (s - coupling) / 2.0)
}

/// The axial field's ring, its gyroscopic coefficient and the coefficients at rest.
struct Ring {
    model: crate::model::Model,
    order: u32,
    points: usize,
    field: usize,
    coefficient: String,
    values: std::collections::BTreeMap<String, f64>,
}

impl Ring {
    fn of(theory: &Theory) -> Result<Ring, BehaviourError> {
        let model = &theory.model;
        let field = model.role_index(Role::Axial, "figures forward_backward")?;
        let f = &model.fields[field];
        if f.boundary != Boundary::Periodic {
            return Err(BehaviourError::Body(format!(
                "forward and backward waves need a periodic axial field (a ring): {} is {}",
                f.id,
                f.boundary.name()
            )));
        }
        let forces = crate::active::active_forces(model, theory.order)?;
        let linear = |x: &&crate::active::Force| matches!(x.shape.factors(), [g] if g.power == 1 && g.deriv.t == 1 && g.deriv.s == 1);
        let coefficient = forces
            .as_ref()
            .and_then(|all| all[field].gyroscopic.iter().find(linear))
            .and_then(|x| x.coefficient.clone())
            .ok_or_else(|| {
                BehaviourError::Body(format!(
                    "the {} model gives {} no gyroscopic force ∂t∂s {} (an [active] section without PAR does): App. C's splitting has no term to come from",
                    crate::markup::clip(&model.name),
                    f.id,
                    f.symbol
                ))
            })?;
        let mut values = crate::dynamics::default_coefficients(model, theory.order, &theory.params)
            .map_err(dynamics)?;
        // Undamped: the frequencies are App. C's.
        let r = crate::reduce::analyse(model, Density::Rayleigh, theory.order)
            .map_err(|e| dynamics(e.into()))?;
        for p in r
            .fields
            .iter()
            .flat_map(|f| &f.density)
            .filter_map(|d| d.parameter.as_ref())
        {
            values.insert(p.clone(), 0.0);
        }
        Ok(Ring {
            model: model.clone(),
            order: theory.order,
            points: theory.points,
            field,
            coefficient,
            values,
        })
    }

    fn body(&self, g: f64) -> Result<NonlinearBody, BehaviourError> {
        let mut values = self.values.clone();
        values.insert(self.coefficient.clone(), g);
        NonlinearBody::new(&self.model, self.order, self.points, &values).map_err(dynamics)
    }

    /// Which of the body's systems is the axial field.
    fn system(&self, body: &NonlinearBody) -> Result<usize, BehaviourError> {
        let id = &self.model.fields[self.field].id;
        body.fields
            .iter()
            .position(|f| &f.id == id)
            .ok_or_else(|| BehaviourError::Body(format!("field {id} has no kinetic term")))
    }

    /// ω₁ and the (forward, backward) frequencies at gyroscopic coefficient g.
    fn frequencies(&self, g: f64, omega: f64) -> Result<(f64, f64), BehaviourError> {
        let body = self.body(g)?;
        let at = self.system(&body)?;
        let n = body.fields[at].unknowns;
        let k = 2.0 * std::f64::consts::PI / n as f64;
        let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
            .fields
            .iter()
            .map(|f| (vec![0.0; f.unknowns], vec![0.0; f.unknowns]))
            .collect();
        state[at].0 = (0..n).map(|j| (k * j as f64).cos()).collect();
        let h = 2.0 * std::f64::consts::PI / omega / 100.0;
        let amplitude = |x: &[f64]| -> Complex<f64> {
            x.iter()
                .enumerate()
                .map(|(j, v)| v * Complex::from_polar(1.0, -k * j as f64))
                .sum()
        };
        let mut series = vec![amplitude(&state[at].0)];
        let mut integrator = body.integrator(h);
        for step in 0..1000 {
            integrator
                .step(&mut state, step as f64 * h)
                .map_err(dynamics)?;
            series.push(amplitude(&state[at].0));
        }
        let [a, b] = prony(&series).ok_or_else(|| {
            BehaviourError::Invalid("the ring's amplitude is not two waves".into())
        })?;
        // e^{−iω_f h} turns clockwise, e^{+iω_b h} anticlockwise; the midpoint step turns a
        // frequency ω by 2 arctan(ωh/2) per step (its Cayley transform), inverted here.
        let omega_of = |z: Complex<f64>| 2.0 / h * (-z.arg() / 2.0).tan();
        let (f, b) = (omega_of(a), omega_of(b));
        Ok((f.max(b), -f.min(b)))
    }
}

/// The two roots z of A_{n+2} = pA_{n+1} + qA_n fitted by least squares.
fn prony(a: &[Complex<f64>]) -> Option<[Complex<f64>; 2]> {
    let (mut m, mut r) = (
        [[Complex::new(0.0, 0.0); 2]; 2],
        [Complex::new(0.0, 0.0); 2],
    );
    for w in a.windows(3) {
        let row = [w[1], w[0]];
        for i in 0..2 {
            for j in 0..2 {
                m[i][j] += row[i].conj() * row[j];
            }
            r[i] += row[i].conj() * w[2];
        }
    }
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if det.norm() == 0.0 {
        return None;
    }
    let p = (r[0] * m[1][1] - m[0][1] * r[1]) / det;
    let q = (m[0][0] * r[1] - m[1][0] * r[0]) / det;
    let d = (p * p + 4.0 * q).sqrt();
    let roots = [(p + d) / 2.0, (p - d) / 2.0];
    roots.iter().all(|z| z.norm().is_finite()).then_some(roots)
}

/// Simulate the axial ring of `theory` at each coupling G of `couplings` (G = −g sin k/ω₁) and
/// locate backward : forward = 1 : 2 by bisection on G ∈ [0, 2].
pub fn forward_backward(
    theory: &Theory,
    couplings: &[f64],
) -> Result<ForwardBackward, BehaviourError> {
    if couplings.iter().any(|g| !g.is_finite() || g.abs() > 100.0) {
        return Err(BehaviourError::Invalid(
            "couplings must be finite numbers within ±100".into(),
        ));
    }
    let ring = Ring::of(theory)?;
    let passive = ring.body(0.0)?;
    let at = ring.system(&passive)?;
    let lin = passive.fields[at].undamped(false).map_err(dynamics)?;
    let omega = lin
        .frequencies
        .iter()
        .flatten()
        .copied()
        .find(|w| *w > 1e-9)
        .ok_or_else(|| BehaviourError::Body("the axial field has no oscillating pair".into()))?;
    let n = passive.fields[at].unknowns;
    if n < 3 {
        return Err(BehaviourError::Body(format!(
            "a ring of {n} distinct points carries no travelling wave (its pair is k = π, where ∂t∂s vanishes): use at least 4 points"
        )));
    }
    let sin_k = (2.0 * std::f64::consts::PI / n as f64).sin();
    let split = |coupling: f64| -> Result<Split, BehaviourError> {
        let (f, b) = ring.frequencies(-coupling * omega / sin_k, omega)?;
        Ok(Split {
            coupling,
            forward: f / omega,
            backward: b / omega,
        })
    };
    let sweep = couplings
        .iter()
        .map(|&c| split(c))
        .collect::<Result<Vec<_>, _>>()?;
    let (mut lo, mut hi) = (0.0, 2.0);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        let s = split(mid)?;
        if s.backward / s.forward > 0.5 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(ForwardBackward {
        field: theory.model.fields[ring.field].id.clone(),
        coefficient: ring.coefficient,
        omega,
        sweep,
        half: 0.5 * (lo + hi),
    })
}
