//! Running a body of [`super::nonlinear`]: which bodies go this way (not all terms squares), the
//! coefficients a run does not set, the initial state (uniform, or along a mode of the
//! linearisation about rest) and the reports, in the modal run's layout.

use std::collections::BTreeMap;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::checked;
use super::nonlinear::{NonlinearBody, NonlinearError};
use crate::model::{Density, Model};
use crate::reduce::{analyse, DensityTerm};

/// Whether every surviving term is one the linear operators take (the kinetic term, squares
/// (∂sᵏφ)² and (∂t∂sᵏφ)²): then the exact modal propagators apply instead.
pub fn is_quadratic(model: &Model, order: u32) -> Result<bool, NonlinearError> {
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a = analyse(model, density, order)?;
        let square = |d: &DensityTerm| matches!(d.term.factors(), [f] if f.power == 2);
        if !a.fields.iter().all(|f| f.density.iter().all(square)) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The coefficient of each term a run does not set: a leading-order square takes what the
/// linear commands give it (c = ω², c′ = ζω of its field's scale, so that `--param omega_s`
/// means the same), every other term and every active force 0 (off until set).
pub fn default_coefficients(
    model: &Model,
    order: u32,
    params: &crate::modal::Params,
) -> Result<BTreeMap<String, f64>, NonlinearError> {
    let mut leading = model.clone();
    leading.lagrangian.beyond_leading = 0;
    leading.rayleigh.beyond_leading = 0;
    let mut out = BTreeMap::new();
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a = analyse(model, density, order)?;
        let first = analyse(&leading, density, order)?;
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
    // An active force is off until set.
    for (_, name) in super::nonlinear::active_terms(model, order)?
        .into_iter()
        .flatten()
    {
        out.insert(name, 0.0);
    }
    Ok(out)
}

/// The most work a nonlinear run may take, in units of about four nanoseconds (measured on
/// 10⁵ steps at N = 200: the larva at the next order with c2_x = 1 and noise, 5.4·10⁸ units in
/// 2.4 s; the tethered filament, 3·10⁸ units in 1.3 s): about ten seconds. Refused before it
/// starts.
pub const MAX_NONLINEAR_WORK: f64 = 2.5e9;

/// The work of one step of `body` in the units of [`MAX_NONLINEAR_WORK`]: per field, its
/// unknowns × (terms + 2), three times over for a nonlinear field (its Newton iterations), plus
/// a dense solve for a ring too small for its band; and `values` numbers written per report.
fn work_per_step(body: &NonlinearBody) -> f64 {
    body.fields
        .iter()
        .map(|f| {
            let u = f.unknowns as f64;
            let terms = (f.potential.len() + f.dissipation.len()) as f64;
            let iterations = if f.is_linear() { 1.0 } else { 3.0 };
            iterations * (u * (terms + 2.0) + if f.periodic && u < 40.0 { u * u } else { 0.0 })
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
        // Each number written costs about a dozen units.
        let values: usize = self.fields.iter().map(|f| 2 * f.unknowns).sum();
        let work = config.steps as f64 * work_per_step(self)
            + (config.steps / config.every) as f64 * 12.0 * values as f64;
        if work > MAX_NONLINEAR_WORK {
            return invalid(format!(
                "{} steps of this body on {} points are about {:.0} s of work, more than the {:.0} s a run may take: fewer steps or points",
                config.steps,
                config.points,
                work * 4e-9,
                MAX_NONLINEAR_WORK * 4e-9
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
        // Modes of the linearisation, computed once per field that an initial state or a force
        // names.
        let mut linearised: BTreeMap<usize, super::LinearisedField> = BTreeMap::new();
        let mut shape_of =
            |field: &str, mode: usize| -> Result<(usize, Vec<f64>, Vec<f64>), DynamicsError> {
                let Some(k) = self.fields.iter().position(|f| f.id == field) else {
                    let ids: Vec<&str> = self.fields.iter().map(|f| f.id.as_str()).collect();
                    return Err(DynamicsError::Invalid(format!(
                        "unknown field {field:?} (fields: {})",
                        ids.join(", ")
                    )));
                };
                let lin = match linearised.entry(k) {
                    std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
                    std::collections::btree_map::Entry::Vacant(e) => {
                        e.insert(self.fields[k].undamped(true)?)
                    }
                };
                let shapes = lin.shapes.as_deref().unwrap_or_default();
                let Some(shape) = shapes.get(mode) else {
                    return Err(DynamicsError::Invalid(format!(
                        "field {field} has modes 0…{}, not {mode}",
                        shapes.len().saturating_sub(1)
                    )));
                };
                let field = &self.fields[k];
                Ok((k, field.strip(shape), field.strip(&lin.equilibrium)))
            };
        for i in &config.initial {
            let (k, shape, equilibrium) = shape_of(&i.field, i.mode)?;
            // About the equilibrium: u = u* + Q·shape.
            if state[k].0.iter().all(|x| *x == 0.0) {
                state[k].0.copy_from_slice(&equilibrium);
            }
            for (j, s) in shape.iter().enumerate() {
                state[k].0[j] += i.displacement * s;
                state[k].1[j] += i.velocity * s;
            }
        }
        // A force on a mode of the linearisation acts along its (unit) shape.
        let mut forces: Vec<(usize, Vec<f64>, &super::Forcing)> = Vec::new();
        for f in &config.forcing {
            let (k, shape, _) = shape_of(&f.field, f.mode)?;
            forces.push((k, shape, f));
        }
        let driven = self.fields.iter().any(|f| !f.active.is_empty());
        let sample = |t: f64, state: &[(Vec<f64>, Vec<f64>)], injected: f64| super::Sample {
            t,
            injected: driven.then_some(injected),
            energy: self.energy(state),
            // The points, as the modal run writes them (zeros where held; around a ring the
            // unknowns, the head being the tail).
            positions: self
                .fields
                .iter()
                .zip(state)
                .map(|(f, (u, _))| f.embed(u))
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
            };
        if !report(&checked(sample(0.0, &state, 0.0))?, &mut sink)? {
            return Ok(());
        }
        let h = config.dt;
        let mut integrator = if config.temperature > 0.0 {
            self.noisy_integrator(h, config.temperature)?
        } else {
            self.integrator(h)
        };
        let pushed = config.temperature > 0.0 || !forces.is_empty();
        let mut push: Vec<Vec<f64>> = if pushed {
            self.fields.iter().map(|f| vec![0.0; f.unknowns]).collect()
        } else {
            Vec::new()
        };
        let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
        for step in 1..=config.steps {
            let t = (step - 1) as f64 * h;
            let stepped = if pushed {
                push.iter_mut().for_each(|p| p.fill(0.0));
                integrator.kicks(&mut rng, &mut push);
                // The force at the step's midpoint, as the scheme's mean velocity.
                let mid = t + 0.5 * h;
                for (k, shape, f) in &forces {
                    let force = f.constant + f.amplitude * (f.frequency * mid + f.phase).cos();
                    for (p, s) in push[*k].iter_mut().zip(shape) {
                        *p += h * force * s;
                    }
                }
                integrator.step_pushed(&mut state, t, &push)
            } else {
                integrator.step(&mut state, t)
            };
            stepped?;
            if step % config.every == 0
                && !report(
                    &checked(sample(step as f64 * h, &state, integrator.work().1))?,
                    &mut sink,
                )?
            {
                return Ok(());
            }
        }
        Ok(())
    }
}
