//! Running a body of [`super::nonlinear`]: which bodies go this way (not all terms squares), the
//! coefficients a run does not set, the initial state (uniform, or along a mode of the
//! linearisation about rest) and the reports, in the modal run's layout.

use std::collections::BTreeMap;

use super::nonlinear::{NonlinearBody, NonlinearError};
use crate::model::{Density, Model};
use crate::reduce::{analyse, DensityTerm};

/// Whether every surviving term is one the linear operators take (the kinetic term, squares
/// (∂sᵏφ)² and (∂t∂sᵏφ)²): then the exact modal propagators apply instead.
pub fn is_quadratic(model: &Model, order: u32) -> Result<bool, NonlinearError> {
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a =
            analyse(model, density, order).map_err(|e| NonlinearError::Engine(e.to_string()))?;
        let square = |d: &DensityTerm| matches!(d.term.factors(), [f] if f.power == 2);
        if !a.fields.iter().all(|f| f.density.iter().all(square)) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The coefficient of each term a run does not set: a leading-order square takes what the
/// linear commands give it (c = ω², c′ = ζω of its field's scale, so that `--param omega_s`
/// means the same), every other term 0 (off until set).
pub fn default_coefficients(
    model: &Model,
    order: u32,
    params: &crate::modal::Params,
) -> Result<BTreeMap<String, f64>, NonlinearError> {
    let engine = |e: crate::reduce::OrderError| NonlinearError::Engine(e.to_string());
    let mut leading = model.clone();
    leading.lagrangian.beyond_leading = 0;
    leading.rayleigh.beyond_leading = 0;
    let mut out = BTreeMap::new();
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a = analyse(model, density, order).map_err(engine)?;
        let first = analyse(&leading, density, order).map_err(engine)?;
        for (f, lead) in a.fields.iter().zip(&first.fields) {
            let scale = f.field.scale().to_string();
            let (omega, zeta) = (params.omega(&scale), params.zeta(&scale));
            for d in &f.density {
                let Some(name) = &d.parameter else { continue };
                let square = matches!(d.term.factors(), [x] if x.power == 2);
                let value = match density {
                    _ if !(square && lead.survivors.contains(&d.term)) => 0.0,
                    Density::Lagrangian => omega * omega,
                    Density::Rayleigh => zeta * omega,
                };
                out.insert(name.clone(), value);
            }
        }
    }
    Ok(out)
}

/// The most work a nonlinear run may take, in units of about two nanoseconds (measured: 10⁴
/// steps of the larva at the next order on 100 points are 5.4·10⁸ units, 1.5 s; 10⁵ steps of
/// the tethered filament on 200 points 4.2·10⁹, 5.8 s): a step costs about 30 units per term
/// and unknown of each field, plus a dense factorisation U³/3 for a ring too small for its band.
/// Refused before it starts.
pub const MAX_NONLINEAR_WORK: f64 = 5e9;

/// The work of one step of `body` in the units of [`MAX_NONLINEAR_WORK`].
fn work_per_step(body: &NonlinearBody) -> f64 {
    body.fields
        .iter()
        .map(|f| {
            let u = f.unknowns as f64;
            let terms = (1 + f.potential.len() + f.dissipation.len()) as f64;
            30.0 * u * terms
                + if f.periodic && u < 40.0 {
                    u * u * u / 3.0
                } else {
                    0.0
                }
        })
        .sum()
}

impl NonlinearBody {
    /// Run `config` (time step, steps, reporting) from each field displaced uniformly by
    /// `uniform` (field id, Q, V; others at rest), reporting every `config.every` steps like
    /// the modal run (positions at every point; no modal coordinates).
    pub fn run(
        &self,
        config: &super::Config,
        uniform: &[(String, f64, f64)],
        mut sink: impl FnMut(&super::Sample) -> Result<(), super::Halt>,
    ) -> Result<(), super::DynamicsError> {
        use super::{DynamicsError, Halt};
        super::check_config(config)?;
        let invalid = |s: String| Err(DynamicsError::Invalid(s));
        if !config.forcing.is_empty() {
            return invalid(
                "--force and --drive act on modes, which a nonlinear body does not have yet".into(),
            );
        }
        if config.temperature > 0.0 {
            return invalid("Langevin noise on a nonlinear body is not integrated yet: run it at --temperature 0".into());
        }
        let work = config.steps as f64 * work_per_step(self);
        if work > MAX_NONLINEAR_WORK {
            return invalid(format!(
                "{} steps of this body on {} points are about {:.0} s of work, more than the {:.0} s a run may take: fewer steps or points",
                config.steps,
                config.points,
                work * 2e-9,
                MAX_NONLINEAR_WORK * 2e-9
            ));
        }
        let mut state: Vec<(Vec<f64>, Vec<f64>)> = self
            .fields
            .iter()
            .map(|f| (vec![0.0; f.unknowns], vec![0.0; f.unknowns]))
            .collect();
        for (id, q, v) in uniform {
            let Some(k) = self.fields.iter().position(|f| &f.id == id) else {
                let ids: Vec<&str> = self.fields.iter().map(|f| f.id.as_str()).collect();
                return invalid(format!("unknown field {id:?} (fields: {})", ids.join(", ")));
            };
            if !(q.is_finite() && v.is_finite()) {
                return invalid(format!("initial state of {id} is not finite"));
            }
            state[k].0.fill(*q);
            state[k].1.fill(*v);
        }
        for i in &config.initial {
            let Some(k) = self.fields.iter().position(|f| f.id == i.field) else {
                let ids: Vec<&str> = self.fields.iter().map(|f| f.id.as_str()).collect();
                return invalid(format!(
                    "unknown field {:?} (fields: {})",
                    i.field,
                    ids.join(", ")
                ));
            };
            let lin = self.fields[k]
                .linearise(true)
                .map_err(|e| DynamicsError::Invalid(e.to_string()))?;
            let shapes = lin.shapes.unwrap_or_default();
            let Some(shape) = shapes.get(i.mode) else {
                return invalid(format!(
                    "field {} has modes 0…{}, not {}",
                    i.field,
                    shapes.len() - 1,
                    i.mode
                ));
            };
            // About the equilibrium: u = u* + Q·shape.
            if state[k].0.iter().all(|x| *x == 0.0) {
                state[k].0.copy_from_slice(&lin.equilibrium);
            }
            for (j, s) in shape.iter().enumerate() {
                state[k].0[j] += i.displacement * s;
                state[k].1[j] += i.velocity * s;
            }
        }
        let sample = |t: f64, state: &[(Vec<f64>, Vec<f64>)]| super::Sample {
            t,
            energy: self.energy(state),
            positions: self
                .fields
                .iter()
                .zip(state)
                .map(|(f, (u, _))| {
                    // Around a ring the head is the tail: every point written, as the modal run.
                    let mut p = u.clone();
                    if f.periodic {
                        p.push(u[0]);
                    }
                    p
                })
                .collect(),
            modal: Vec::new(),
            velocity: state.iter().map(|(_, v)| v.clone()).collect(),
        };
        let report =
            |s: &super::Sample, sink: &mut dyn FnMut(&super::Sample) -> Result<(), Halt>| match sink(
                s,
            ) {
                Ok(()) => Ok(true),
                Err(Halt::Stop) => Ok(false),
                Err(Halt::Io(e)) => Err(DynamicsError::Output(e.kind(), e.to_string())),
                Err(Halt::Fail(m)) => Err(DynamicsError::Invalid(m)),
            };
        if !report(&sample(0.0, &state), &mut sink)? {
            return Ok(());
        }
        for step in 1..=config.steps {
            let t = (step - 1) as f64 * config.dt;
            self.step(&mut state, config.dt, t)
                .map_err(|e| DynamicsError::Invalid(e.to_string()))?;
            if step % config.every == 0
                && !report(&sample(step as f64 * config.dt, &state), &mut sink)?
            {
                return Ok(());
            }
        }
        Ok(())
    }
}
