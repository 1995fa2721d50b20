//! The candidate forces of one field, each on its own: what `discover` regresses on.
//!
//! Every coefficient the equations name (`c_y`, `c'_y`, `a_y`, …) multiplies one force of the
//! discretised body. A candidate is the body with that coefficient 1 and every other 0, so
//! its force is exactly the one `simulate` integrates:
//! f(u, v) = −∇V(u) − ∇R(v) + f_active(u, v), and for a kinetic term beyond ½|v|² the momentum
//! p(v) = ∇T(v) whose time derivative enters as −∂t p.
//!
//! **Units.** The grid's are the point spacing h = 1/(N − 1) body lengths for lengths and
//! positions. A term (∂tᵃ∂sᵇφ)ⁿ of a density has c = c_grid·h^(2 + n(b − 1)) in body lengths;
//! an active force a·Π(∂tᵃⁱ∂sᵇⁱφ) has a = a_grid·h^(1 − Σ(1 − bᵢ)) (dimensions of ∂t²φ = force
//! per unit mass, φ = h·u). [`Candidate::to_body_lengths`] is that power of h.

use std::collections::BTreeMap;

use super::nonlinear::{entering_terms, plan_names, FieldSystem, NonlinearBody};
use super::NonlinearError;
use crate::discretise::force_plan;
use crate::equations::ForceKind;
use crate::model::{Density, Model};

/// One coefficient's force on one field's unknowns.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The coefficient as the equations print it.
    pub name: String,
    /// Conservative (from L, gyroscopic included), dissipative (from R) or active.
    pub kind: ForceKind,
    /// A kinetic term: it enters through its momentum, not as a force.
    pub kinetic: bool,
    /// The power of the spacing h that turns the grid's coefficient into body lengths.
    pub spacing_power: i32,
    /// The power p of the time unit in the coefficient's dimension (T^p): −2 for a force of
    /// the positions alone, −2 + k for one of degree k in the velocities (−1 for c′ of
    /// (∂t∂s²φ)²), so the coefficient in time unit τ₀ is the one in the unit τ₁ times
    /// (τ₀/τ₁)^p.
    pub time_power: i32,
    /// A force of the `[active]` section (active or gyroscopic), not of the densities.
    pub entering: bool,
    system: FieldSystem,
}

impl Candidate {
    /// The force f(u, v) of the coefficient set to 1 (zero for a kinetic term).
    pub fn force(&self, u: &[f64], v: &[f64]) -> Vec<f64> {
        let mut f = self.system.active_force(u, v);
        for p in &self.system.potential {
            p.gradient(u, -1.0, &mut f);
        }
        for p in &self.system.dissipation {
            p.gradient(v, -1.0, &mut f);
        }
        f
    }

    /// The momentum ∇T(v) of a kinetic term beyond ½|v|² (zero otherwise).
    pub fn momentum(&self, v: &[f64]) -> Vec<f64> {
        let mut p = vec![0.0; self.system.unknowns];
        for k in &self.system.kinetic {
            k.gradient(v, 1.0, &mut p);
        }
        p
    }

    /// Unknowns of the field.
    pub fn unknowns(&self) -> usize {
        self.system.unknowns
    }

    /// A vector on the body's points as the field's unknowns.
    pub fn strip(&self, points: &[f64]) -> Vec<f64> {
        self.system.strip(points)
    }

    /// The factor h^p that turns the grid's coefficient into body lengths on `points` points.
    pub fn to_body_lengths(&self, points: usize) -> f64 {
        let h = 1.0 / (points as f64 - 1.0);
        h.powi(self.spacing_power)
    }
}

/// Every coefficient of field `field` of `model` at `order`, as a force on `points` points, in
/// the equations' order.
pub fn library(
    model: &Model,
    order: u32,
    points: usize,
    field: &str,
) -> Result<Vec<Candidate>, NonlinearError> {
    // The plan and the `[active]` forces are derived once: each is a whole enumeration, and a
    // body per coefficient re-deriving them cost names × derivations (13 s at order 8).
    let plan = force_plan(model, order)?;
    let index = model.fields.iter().position(|f| f.id == field);
    let forces = crate::active::active_forces(model, order)
        .map_err(NonlinearError::Active)?
        .unwrap_or_default();
    let active = entering_terms(&forces);
    let gyroscopic: Vec<String> = forces
        .into_iter()
        .flat_map(|f| f.gyroscopic.into_iter().filter_map(|g| g.coefficient))
        .collect();
    let names = plan_names(&plan, &active);
    let mut out = Vec::new();
    for name in &names {
        let values: BTreeMap<String, f64> = names
            .iter()
            .map(|n| (n.clone(), if n == name { 1.0 } else { 0.0 }))
            .collect();
        let body = NonlinearBody::planned(model, &plan, &active, points, &values)?;
        let Some(system) = body.fields.into_iter().find(|f| f.id == field) else {
            continue;
        };
        let term = plan
            .iter()
            .filter(|f| f.field.id == field)
            .flat_map(|f| &f.terms)
            .find(|t| t.parameter.as_deref() == Some(name.as_str()));
        let entering = index
            .and_then(|i| active.get(i))
            .into_iter()
            .flatten()
            .find(|(_, n)| n == name);
        let (kind, kinetic, spacing_power, time_power) = match (term, entering) {
            // ∂R/∂v of (∂t∂sᵇφ)ⁿ has degree n − 1 in the velocities, V's gradient none; a
            // kinetic term's momentum, of degree n − 1, enters as ∂t p(v) beside ∂t²φ.
            (Some(t), _) => (
                match t.density {
                    Density::Lagrangian => ForceKind::Conservative,
                    Density::Rayleigh => ForceKind::Dissipative,
                },
                t.kinetic,
                2 + t.power as i32 * (t.b as i32 - 1),
                match (t.density, t.kinetic) {
                    (Density::Lagrangian, false) => -2,
                    (Density::Lagrangian, true) => t.power as i32 - 2,
                    (Density::Rayleigh, _) => t.power as i32 - 3,
                },
            ),
            (None, Some((term, _))) => {
                let lost: i32 = term
                    .factors()
                    .iter()
                    .map(|f| f.power as i32 * (1 - f.deriv.s as i32))
                    .sum();
                let kind = if gyroscopic.contains(name) {
                    ForceKind::Conservative
                } else {
                    ForceKind::Active
                };
                let velocities: i32 = term
                    .factors()
                    .iter()
                    .map(|f| (f.power * f.deriv.t) as i32)
                    .sum();
                (kind, false, 1 - lost, velocities - 2)
            }
            // Another field's coefficient.
            (None, None) => continue,
        };
        out.push(Candidate {
            entering: entering.is_some(),
            name: name.clone(),
            kind,
            kinetic,
            spacing_power,
            time_power,
            system,
        });
    }
    Ok(out)
}
