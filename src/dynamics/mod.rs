//! Time evolution of the dissipative Hamilton's equations (paper Eq. 6) in modal coordinates.
//!
//! With `q = Σ Qᵢ vᵢ` over the unit-norm modes of a field, every mode is a damped oscillator
//! `Q̈ᵢ + 2γᵢQ̇ᵢ + ωᵢ²Qᵢ = Fᵢ(t) + ξᵢ(t)`, `ωᵢ = ω√λᵢ`, `γᵢ = ζᵢωᵢ = ζωλᵢ`. Nothing is integrated
//! numerically:
//! * the homogeneous flow is `e^{At} = e^{−γt}[C·I + S·(A + γI)]`, `A = [[0, 1], [−ω², −2γ]]`,
//!   `ν² = γ² − ω²`, `C = cosh νt`, `S = sinh(νt)/ν` (cos and sin for ν² < 0; series near 0);
//! * a constant force `c` and a drive `F₀cos(Ωt + φ)` enter through their particular solutions
//!   (`c/ω²`; `Re[F₀e^{i(Ωt+φ)}/(ω² − Ω² + 2iγΩ)]`), a constant force on a zero mode kinematically;
//! * without noise the state at every output time is the closed form
//!   `x(t) = e^{At}(x₀ − x_p(0)) + x_p(t)`, so no error accumulates over any number of steps;
//! * with thermal noise at temperature `kT` (fluctuation–dissipation: `⟨ξξ⟩ = 4γkT δ`) each step
//!   is the exact Ornstein–Uhlenbeck transition: mean as above, covariance
//!   `Σ∞ − e^{Ah}Σ∞e^{Aᵀh}`, `Σ∞ = diag(kT/ωᵢ², kT)`. Zero modes feel no friction, hence no noise.
//!   The random stream is ChaCha8 from `seed`: the same seed gives the same run.
//!
//! The energy reported is `H = Σ ½(Pᵢ² + ωᵢ²Qᵢ²)`, the paper's Eq. 1 in modal coordinates.

mod active;
mod implicit;
mod jacobian;
mod library;
mod linearise;
mod linearised_operators;
pub mod nonlinear;
mod nonlinear_run;
mod sample;
pub use active::ActiveForce;
pub use implicit::Integrator;
pub use library::{library, Candidate};
pub use linearise::{check_growth, DampedMode, GrowthCheck, LinearisedField, LinearisedReport};
pub use linearised_operators::{LinearisedOperator, LinearisedOperatorsReport};
pub use nonlinear_run::{default_coefficients, is_quadratic, MAX_NONLINEAR_WORK};
pub use sample::{checked, sample_header, sample_row, sample_values, Sample};

use nalgebra::{Matrix2, Vector2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::modal::{field_modes, FieldModes, ModesError, Params};
use crate::model::Model;
use nonlinear::NonlinearError;

/// The most points `simulate` takes (it keeps all N shapes of every field).
pub const MAX_SIM_POINTS: usize = 2000;

/// The most work a run may take, in mode-steps (each step advances every mode; each report also
/// writes every field at every point): 10⁹, about ten seconds. Refused before it starts.
pub const MAX_WORK: f64 = 1e9;

/// A force on one mode: `constant + amplitude·cos(frequency·t + phase)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing {
    /// Field id.
    pub field: String,
    /// Mode index.
    pub mode: usize,
    /// Constant part.
    pub constant: f64,
    /// Amplitude of the sinusoidal part.
    pub amplitude: f64,
    /// Angular frequency of the sinusoidal part.
    pub frequency: f64,
    /// Phase of the sinusoidal part.
    pub phase: f64,
}

/// Initial displacement and velocity of one mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Initial {
    /// Field id.
    pub field: String,
    /// Mode index.
    pub mode: usize,
    /// Qᵢ(0).
    pub displacement: f64,
    /// Q̇ᵢ(0).
    pub velocity: f64,
}

/// What to simulate.
#[derive(Debug, Clone)]
pub struct Config {
    /// Points along the body.
    pub points: usize,
    /// Order of the theory.
    pub order: u32,
    /// Time step h.
    pub dt: f64,
    /// Number of steps.
    pub steps: u64,
    /// Report every this many steps (the initial state is always reported).
    pub every: u64,
    /// Thermal energy kT (0: no noise).
    pub temperature: f64,
    /// Seed of the noise.
    pub seed: u64,
    /// Initial modal state (all others start at rest at 0).
    pub initial: Vec<Initial>,
    /// Modal forces.
    pub forcing: Vec<Forcing>,
}

/// Why a simulation cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// The modes could not be computed.
    #[error(transparent)]
    Modes(#[from] ModesError),
    /// A setting is out of range, or the sink failed.
    #[error("{0}")]
    Invalid(String),
    /// The sink's output failed (its kind tells a closed pipe).
    #[error("cannot write: {1}")]
    Output(std::io::ErrorKind, String),
    /// A nonlinear body's discretisation, equilibrium or step failed.
    #[error(transparent)]
    Nonlinear(#[from] NonlinearError),
    /// The state, its energy or the time left the finite numbers (nothing of it is written).
    #[error("the state overflowed f64 at t = {} (energy {energy:.3e}): use smaller amplitudes, coefficients, forces, temperature or time step", crate::report::number(*t))]
    Overflow {
        /// The time of the sample.
        t: f64,
        /// Its energy.
        energy: f64,
    },
}

impl DynamicsError {
    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            DynamicsError::Modes(e) => e.failure(),
            DynamicsError::Invalid(_) => Failure::Usage,
            DynamicsError::Output(..) => Failure::Output,
            DynamicsError::Nonlinear(e) => e.failure(),
            DynamicsError::Overflow { .. } => Failure::Numerical,
        }
    }
}

/// One damped oscillator with its forcing.
#[derive(Debug, Clone)]
struct Oscillator {
    omega: f64,
    gamma: f64,
    constant: f64,
    /// (F₀, Ω, φ) drives.
    drives: Vec<(f64, f64, f64)>,
}

/// `x·e^{−γt}` style products without overflow: returns (e^{−γt}C, e^{−γt}S).
fn damped_cs(gamma: f64, omega: f64, t: f64) -> (f64, f64) {
    let nu2 = gamma * gamma - omega * omega;
    let q = nu2 * t * t;
    if q.abs() < 1e-6 {
        // Series of cosh√q and sinh(√q)/√q: exact to rounding here.
        let decay = (-gamma * t).exp();
        (
            decay * (1.0 + q / 2.0 + q * q / 24.0),
            decay * t * (1.0 + q / 6.0 + q * q / 120.0),
        )
    } else if q < 0.0 {
        let w = (-nu2).sqrt();
        let decay = (-gamma * t).exp();
        (decay * (w * t).cos(), decay * (w * t).sin() / w)
    } else {
        let nu = nu2.sqrt();
        // e^{−γt}cosh νt = ½(e^{(ν−γ)t} + e^{−(ν+γ)t}); ν ≤ γ here (ω ≥ 0), so no overflow.
        let (a, b) = (((nu - gamma) * t).exp(), (-(nu + gamma) * t).exp());
        (0.5 * (a + b), 0.5 * (a - b) / nu)
    }
}

/// One mode's propagator over a fixed step h: e^{Ah} and the constant force's push.
struct Stepper {
    h: f64,
    flow: Matrix2<f64>,
    push: Vector2<f64>,
}

impl Stepper {
    /// The state at t + h from `x` at t: e^{Ah}(x − x_p(t)) + x_p(t + h) + push.
    fn advance(&self, osc: &Oscillator, x: Vector2<f64>, t: f64) -> Vector2<f64> {
        if osc.drives.is_empty() {
            // The particular solution is constant: no trigonometry per step.
            let p = osc.particular(t);
            return self.flow * (x - p) + p + self.push;
        }
        self.flow * (x - osc.particular(t)) + osc.particular(t + self.h) + self.push
    }
}

impl Oscillator {
    /// e^{At}.
    fn flow(&self, t: f64) -> Matrix2<f64> {
        let (c, s) = damped_cs(self.gamma, self.omega, t);
        let a_plus = Matrix2::new(self.gamma, 1.0, -self.omega * self.omega, -self.gamma);
        Matrix2::identity() * c + a_plus * s
    }

    /// The particular solution (Q_p, P_p) at t of the constant force (ω > 0) and the drives.
    fn particular(&self, t: f64) -> Vector2<f64> {
        let mut x = Vector2::zeros();
        if self.omega > 0.0 {
            x[0] += self.constant / (self.omega * self.omega);
        }
        for &(f0, w, phase) in &self.drives {
            // Z = F₀e^{iφ}/(ω² − Ω² + 2iγΩ); Q_p = Re(Z e^{iΩt}), P_p = Re(iΩ Z e^{iΩt}).
            let (dr, di) = (self.omega * self.omega - w * w, 2.0 * self.gamma * w);
            let den = dr * dr + di * di;
            let (nr, ni) = (f0 * phase.cos(), f0 * phase.sin());
            let (zr, zi) = ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den);
            let (c, s) = ((w * t).cos(), (w * t).sin());
            let (er, ei) = (zr * c - zi * s, zr * s + zi * c);
            x[0] += er;
            x[1] += -w * ei;
        }
        x
    }

    /// Kinematic contribution over time t of a constant force on a zero mode.
    fn free_push(&self, t: f64) -> Vector2<f64> {
        if self.omega > 0.0 {
            Vector2::zeros()
        } else {
            Vector2::new(0.5 * self.constant * t * t, self.constant * t)
        }
    }

    /// The state at time t + h from the state `x` at t, without noise.
    fn advance(&self, x: Vector2<f64>, t: f64, h: f64) -> Vector2<f64> {
        self.stepper(h).advance(self, x, t)
    }

    /// The parts of [`Oscillator::advance`] over a fixed step h that do not depend on t,
    /// computed once per mode (the flow costs an exponential and a sine and cosine).
    fn stepper(&self, h: f64) -> Stepper {
        Stepper {
            h,
            flow: self.flow(h),
            push: self.free_push(h),
        }
    }

    /// A lower Cholesky factor of the OU step covariance Σ∞ − e^{Ah}Σ∞e^{Aᵀh}.
    fn noise_factor(&self, h: f64, kt: f64) -> Matrix2<f64> {
        if kt == 0.0 || self.gamma == 0.0 || self.omega == 0.0 {
            return Matrix2::zeros();
        }
        let inf = Matrix2::new(kt / (self.omega * self.omega), 0.0, 0.0, kt);
        let m = self.flow(h);
        let s = inf - m * inf * m.transpose();
        let l11 = s[(0, 0)].max(0.0).sqrt();
        let l21 = if l11 > 0.0 { s[(1, 0)] / l11 } else { 0.0 };
        let l22 = (s[(1, 1)] - l21 * l21).max(0.0).sqrt();
        Matrix2::new(l11, 0.0, l21, l22)
    }
}

/// The free damped oscillator `Q̈ + 2γQ̇ + ω²Q = 0` carried from (Q, Q̇) over time `t`: the exact
/// flow [`simulate`] uses, for models that assemble their own modes.
pub fn propagate(omega: f64, gamma: f64, q: f64, p: f64, t: f64) -> (f64, f64) {
    let osc = Oscillator {
        omega,
        gamma,
        constant: 0.0,
        drives: Vec::new(),
    };
    let x = osc.flow(t) * Vector2::new(q, p);
    (x[0], x[1])
}

/// The smallest time step: increments h·v of states of order 1 stay normal numbers.
pub const MIN_DT: f64 = 1e-100;

pub(crate) fn check_config(c: &Config) -> Result<(), DynamicsError> {
    let bad = |s: String| Err(DynamicsError::Invalid(s));
    if !(c.dt.is_finite() && c.dt > 0.0) {
        return bad(format!(
            "the time step must be a positive number, not {}",
            crate::report::number(c.dt)
        ));
    }
    // The implicit step divides by h (v₁ = 2Δ/h − v₀): below this, Δ ≈ h·v underflows.
    if c.dt < MIN_DT {
        return bad(format!(
            "the time step {} is below {MIN_DT:e}: the step's increments would underflow f64",
            crate::report::number(c.dt)
        ));
    }
    // The last time must be a number: steps × h finite.
    if !(c.dt * c.steps as f64).is_finite() {
        return bad(format!(
            "{} steps of {} end beyond the largest f64",
            c.steps,
            crate::report::number(c.dt)
        ));
    }
    if !(c.temperature.is_finite() && c.temperature >= 0.0) {
        return bad(format!(
            "the temperature must be a non-negative number, not {}",
            crate::report::number(c.temperature)
        ));
    }
    if c.every == 0 {
        return bad("--every must be at least 1".into());
    }
    if c.points > MAX_SIM_POINTS {
        return bad(format!(
            "simulate takes at most {MAX_SIM_POINTS} points, not {}",
            c.points
        ));
    }
    for i in &c.initial {
        if !(i.displacement.is_finite() && i.velocity.is_finite()) {
            return bad(format!(
                "initial state of {}:{} is not finite",
                i.field, i.mode
            ));
        }
    }
    for f in &c.forcing {
        if ![f.constant, f.amplitude, f.frequency, f.phase]
            .iter()
            .all(|v| v.is_finite())
            || f.frequency < 0.0
        {
            return bad(format!(
                "force on {}:{} must be finite with a non-negative frequency",
                f.field, f.mode
            ));
        }
    }
    Ok(())
}

/// Why a sink ends a run early.
#[derive(Debug)]
pub enum Halt {
    /// Enough: the run ends here, successfully.
    Stop,
    /// The sink's output failed (a closed pipe among them).
    Io(std::io::Error),
}

impl From<std::io::Error> for Halt {
    fn from(e: std::io::Error) -> Halt {
        Halt::Io(e)
    }
}

/// Run `config` on `model` with `params`, calling `sink` at every reported instant (a sink
/// returning `Err(Halt::Stop)` ends the run there, successfully). Computes the modes; a caller
/// that has them already calls [`run`].
pub fn simulate(
    model: &Model,
    params: &Params,
    config: &Config,
    sink: impl FnMut(&Sample) -> Result<(), Halt>,
) -> Result<(), DynamicsError> {
    check_config(config)?;
    let fields = field_modes(model, config.order, config.points, params, None, true)?;
    run(&fields, config, sink)
}

/// The damped, forced oscillator of every mode and its initial state, from `config`.
#[allow(clippy::type_complexity)]
fn oscillators(
    fields: &[FieldModes],
    config: &Config,
) -> Result<(Vec<Vec<Oscillator>>, Vec<Vec<Vector2<f64>>>), DynamicsError> {
    let locate = |field: &str, mode: usize| -> Result<(usize, usize), DynamicsError> {
        let f = fields
            .iter()
            .position(|f| f.field.id == field)
            .ok_or_else(|| {
                DynamicsError::Invalid(format!("unknown field {field:?} (fields: {})", ids(fields)))
            })?;
        if mode >= fields[f].modes.len() {
            return Err(DynamicsError::Invalid(format!(
                "field {field} has modes 0…{}, not {mode}",
                fields[f].modes.len() - 1
            )));
        }
        Ok((f, mode))
    };
    let mut oscillators: Vec<Vec<Oscillator>> = fields
        .iter()
        .map(|f| {
            f.modes
                .iter()
                .map(|m| Oscillator {
                    omega: m.frequency,
                    gamma: m.damping_ratio * m.frequency,
                    constant: 0.0,
                    drives: Vec::new(),
                })
                .collect()
        })
        .collect();
    for force in &config.forcing {
        let (f, m) = locate(&force.field, force.mode)?;
        let osc = &mut oscillators[f][m];
        osc.constant += force.constant;
        if force.amplitude != 0.0 {
            if force.frequency == 0.0 {
                osc.constant += force.amplitude * force.phase.cos();
            } else if osc.gamma == 0.0 && (osc.omega - force.frequency).abs() <= 1e-12 * osc.omega {
                return Err(DynamicsError::Invalid(format!(
                    "the drive on {}:{} is at the undamped mode's own frequency {}: resonance has no bounded solution",
                    force.field, force.mode, osc.omega
                )));
            } else {
                osc.drives
                    .push((force.amplitude, force.frequency, force.phase));
            }
        }
    }
    let mut start: Vec<Vec<Vector2<f64>>> = fields
        .iter()
        .map(|f| vec![Vector2::zeros(); f.modes.len()])
        .collect();
    for i in &config.initial {
        let (f, m) = locate(&i.field, i.mode)?;
        start[f][m] = Vector2::new(i.displacement, i.velocity);
    }
    Ok((oscillators, start))
}

/// Run `config` on modes already computed (with shapes; `config.points` and `config.order` are
/// those the modes were computed for).
pub fn run(
    fields: &[FieldModes],
    config: &Config,
    mut sink: impl FnMut(&Sample) -> Result<(), Halt>,
) -> Result<(), DynamicsError> {
    check_config(config)?;
    let modes: usize = fields.iter().map(|f| f.modes.len()).sum();
    let values: usize = fields
        .iter()
        .map(|f| f.spectrum.shapes.as_ref().map_or(0, |s| s.nrows()) + f.modes.len())
        .sum();
    let reports = config.steps as f64 / config.every as f64;
    let work = config.steps as f64 * modes as f64 + reports * values as f64;
    if work > MAX_WORK {
        return Err(DynamicsError::Invalid(format!(
            "{} steps of {modes} modes (reporting every {}) is {work:.1e} units of work, over the budget of {MAX_WORK:.0e} (about ten seconds): use fewer steps or periods, a larger --every, or fewer points",
            config.steps, config.every
        )));
    }
    if let Some(f) = fields.iter().find(|f| f.spectrum.shapes.is_none()) {
        return Err(DynamicsError::Invalid(format!(
            "field {} has no mode shapes: compute them to simulate",
            f.field.id
        )));
    }
    let (oscillators, start) = oscillators(fields, config)?;
    let noisy = config.temperature > 0.0;
    let h = config.dt;
    // Per mode, once: the step's propagator and the noise's Cholesky factor.
    let steps: Vec<Vec<(Stepper, Matrix2<f64>)>> = oscillators
        .iter()
        .map(|o| {
            o.iter()
                .map(|osc| (osc.stepper(h), osc.noise_factor(h, config.temperature)))
                .collect()
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let mut state = start.clone();
    let report =
        |state: &[Vec<Vector2<f64>>], t: f64, sink: &mut dyn FnMut(&Sample) -> Result<(), Halt>| {
            let s = checked(sample(fields, &oscillators, state, t))?;
            match sink(&s) {
                Err(Halt::Stop) => Ok(false),
                Err(Halt::Io(e)) => Err(DynamicsError::Output(e.kind(), e.to_string())),
                Ok(()) => Ok(true),
            }
        };
    if !report(&state, 0.0, &mut sink)? {
        return Ok(());
    }
    for n in 1..=config.steps {
        let t = n as f64 * h;
        if noisy {
            for (f, modes) in state.iter_mut().enumerate() {
                for (m, x) in modes.iter_mut().enumerate() {
                    let osc = &oscillators[f][m];
                    let z = Vector2::new(
                        StandardNormal.sample(&mut rng),
                        StandardNormal.sample(&mut rng),
                    );
                    let (step, factor) = &steps[f][m];
                    *x = step.advance(osc, *x, t - h) + factor * z;
                }
            }
        }
        if n % config.every == 0 {
            if !noisy {
                // The closed form from t = 0: no accumulated error however many steps.
                for (f, modes) in state.iter_mut().enumerate() {
                    for (m, x) in modes.iter_mut().enumerate() {
                        *x = oscillators[f][m].advance(start[f][m], 0.0, t);
                    }
                }
            }
            if !report(&state, t, &mut sink)? {
                return Ok(());
            }
        }
    }
    Ok(())
}

fn ids(fields: &[FieldModes]) -> String {
    fields
        .iter()
        .map(|f| f.field.id.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

fn sample(
    fields: &[FieldModes],
    osc: &[Vec<Oscillator>],
    state: &[Vec<Vector2<f64>>],
    t: f64,
) -> Sample {
    let mut energy = 0.0;
    let mut positions = Vec::new();
    let mut modal = Vec::new();
    let mut velocity = Vec::new();
    for (f, field) in fields.iter().enumerate() {
        let shapes = field
            .spectrum
            .shapes
            .as_ref()
            .expect("simulate asks for shapes");
        let q: Vec<f64> = state[f].iter().map(|x| x[0]).collect();
        for (x, o) in state[f].iter().zip(&osc[f]) {
            energy += 0.5 * (x[1] * x[1] + o.omega * o.omega * x[0] * x[0]);
        }
        // Modes at rest contribute nothing: a behaviour that drives one or two modes costs O(N)
        // per sample, not O(N²).
        let active: Vec<(usize, f64)> = q
            .iter()
            .enumerate()
            .filter(|(_, qi)| **qi != 0.0)
            .map(|(i, qi)| (i, *qi))
            .collect();
        positions.push(
            (0..shapes.nrows())
                .map(|j| {
                    active
                        .iter()
                        .fold(0.0, |acc, &(i, qi)| acc + qi * shapes[(j, i)])
                })
                .collect(),
        );
        modal.push(q);
        velocity.push(state[f].iter().map(|x| x[1]).collect());
    }
    Sample {
        t,
        energy,
        positions,
        modal,
        velocity,
        injected: None,
    }
}
