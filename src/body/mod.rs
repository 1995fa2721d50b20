//! One body, one path: a model at an order (with `beyond_leading`) and the values of its
//! coefficients, built once, that every numerical command and every Python function goes
//! through. It knows whether it is **linear** (every surviving term a square: the exact modal
//! theory, with scales ω and ζ) or **nonlinear** (the discretised body of
//! [`crate::dynamics::nonlinear`], linearised about its equilibrium for modes and operators).
//!
//! Coefficients are named as `equations` prints them (`c_y`, `c'1_x`) or in ASCII (`cp1_x`, a
//! field's id for its symbol); scales as `omega_<scale>`, `zeta_<scale>`. On the linear path a
//! leading square's coefficient stands for its field's scale: c = ω² sets ω = √c, and c′ = ζω
//! sets ζ = c′/ω (ω as set, or its default). On the nonlinear path every coefficient not given
//! takes its default ([`crate::dynamics::default_coefficients`]): the leading squares from the
//! scales, every other term 0.

use std::collections::BTreeMap;

use crate::discretise::{DiscretiseError, Operator};
use crate::dynamics::nonlinear::{coefficient_names, NonlinearBody, NonlinearError};
use crate::dynamics::{Config, DynamicsError, Halt, LinearisedField, LinearisedOperator, Sample};
use crate::failure::Failure;
use crate::modal::{field_modes, FieldModes, ModesError};
use crate::model::{Density, Model};
use crate::params::{ParamError, Params};
use crate::reduce::OrderError;
use crate::theory::Theory;

mod start;
pub use start::{Start, MAX_LIST};

/// The most points whose every mode `modes` computes (1.8 s measured on one core).
pub const MAX_FULL_SPECTRUM: usize = 200_000;

/// The most numbers of mode shapes computed at once.
pub const MAX_SHAPE_VALUES: usize = 20_000_000;

/// The most points a nonlinear body is linearised on: a dense eigendecomposition per field and
/// a dense least-squares Newton step per iteration towards the equilibrium (about a second).
pub const MAX_LINEARISED_POINTS: usize = 400;

/// The most points whose operators are built as dense matrices (N² numbers each).
pub const MAX_OPERATOR_POINTS: usize = 2000;

/// The most names a message lists before `… and N more`.
const LISTED: usize = 8;

/// Why a body cannot be built or used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BodyError {
    /// The engine refuses the order.
    #[error(transparent)]
    Order(#[from] OrderError),
    /// A scale out of range (ω ≤ 0, ζ < 0, not finite).
    #[error(transparent)]
    Param(#[from] ParamError),
    /// `NAME=VALUE` without its `=` or a finite number.
    #[error("parameter {name}: {why}")]
    Malformed {
        /// The name (clipped), or the whole text without `=`.
        name: String,
        /// What is wrong.
        why: &'static str,
    },
    /// A name that is neither a scale nor a coefficient of the body.
    #[error("parameter {name}: no field of the {model} model uses it ({known})")]
    Unknown {
        /// The name given.
        name: String,
        /// The model's name.
        model: String,
        /// The scales and coefficients there are (clipped).
        known: String,
    },
    /// A leading square's coefficient that is not ω² > 0 on the linear path.
    #[error("parameter {name}: the linear path takes {name} = ω² > 0, not {}", crate::report::number(*value))]
    NotPositive {
        /// The coefficient.
        name: String,
        /// Its value.
        value: f64,
    },
    /// Two coefficients that set one scale to different values.
    #[error("parameters {first} and {second} set {key} to {} and {}: {why}", crate::report::number(*was), crate::report::number(*now))]
    SharedScale {
        /// The first coefficient.
        first: String,
        /// The second.
        second: String,
        /// The scale (`omega_b`).
        key: String,
        /// The first value.
        was: f64,
        /// The second.
        now: f64,
        /// The cause, and what to do.
        why: &'static str,
    },
    /// More points than a computation's budget (docs/budgets.md).
    #[error("{what} takes at most {limit} points, not {points}{hint}")]
    TooManyPoints {
        /// Which computation.
        what: &'static str,
        /// Points asked for.
        points: usize,
        /// The budget.
        limit: usize,
        /// What to do instead.
        hint: &'static str,
    },
    /// Coefficients given for the operators of a linear body (they have none).
    #[error("the operators of a linear body have no coefficients: --param is for a nonlinear one (its linearisation)")]
    LinearOperators,
    /// A command that needs the exact modal theory, on a body without it.
    #[error("{what} needs the exact modal theory (every surviving term a square, each field's damping on its stiffness operator, no active force switched on); this body has not: use simulate, modes or operators")]
    NotModal {
        /// The command.
        what: &'static str,
    },
    /// A uniform initial state on a linear body.
    #[error("--initial {0:?}: the same displacement at every point is for a nonlinear body; this one is linear and takes FIELD:MODE=Q[,V]")]
    Uniform(String),
    /// A malformed `--initial`, `--force` or `--drive`.
    #[error("{option} {text}: {why}")]
    Assignment {
        /// The option.
        option: &'static str,
        /// The text given (clipped when written).
        text: String,
        /// What is wrong.
        why: &'static str,
    },
    /// The nonlinear body's discretisation or linearisation.
    #[error(transparent)]
    Nonlinear(#[from] NonlinearError),
    /// The modal solver.
    #[error(transparent)]
    Modes(#[from] ModesError),
    /// The operators.
    #[error(transparent)]
    Discretise(#[from] DiscretiseError),
    /// A run.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
}

impl BodyError {
    /// The kind of failure.
    pub fn failure(&self) -> Failure {
        match self {
            BodyError::Nonlinear(e) => e.failure(),
            BodyError::Modes(e) => e.failure(),
            BodyError::Dynamics(e) => e.failure(),
            _ => Failure::Usage,
        }
    }
}

/// `names` joined, at most [`LISTED`] of them, then how many more.
fn listed(names: &[String]) -> String {
    let mut s = names
        .iter()
        .take(LISTED)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > LISTED {
        s.push_str(&format!(" … and {} more", names.len() - LISTED));
    }
    s
}

/// `NAME=VALUE` as a name and a finite number.
pub fn assignment(text: &str) -> Result<(String, f64), BodyError> {
    let (name, value) = text.split_once('=').ok_or_else(|| BodyError::Malformed {
        name: crate::markup::clip(text.trim()),
        why: "expected name=value, e.g. omega_b=2.5 or c_y=4",
    })?;
    let name = name.trim().to_string();
    match value.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok((name, v)),
        _ => Err(BodyError::Malformed {
            name: crate::markup::clip(&name),
            why: "expected name=a finite number",
        }),
    }
}

/// A model at an order with its coefficients: the one value every numerical command uses.
#[derive(Debug, Clone)]
pub struct Body {
    model: Model,
    order: u32,
    linear: bool,
    modal: bool,
    /// An active (or gyroscopic) force is switched on.
    driven: bool,
    names: Vec<String>,
    params: Params,
    /// Coefficients given by name (canonical), in the order given.
    given: Vec<(String, f64)>,
}

impl Body {
    /// The body of `model` at `order` (with `beyond_leading` orders beyond the leading one in
    /// both densities, when given), its scales from `base` (a parameter file, say) and then
    /// `assignments`, each a scale or a coefficient by name.
    pub fn new(
        mut model: Model,
        order: u32,
        beyond_leading: Option<u32>,
        base: Params,
        assignments: &[(String, f64)],
    ) -> Result<Body, BodyError> {
        if let Some(k) = beyond_leading {
            model.set_beyond_leading(k);
        }
        let linear = crate::dynamics::is_quadratic(&model, order).map_err(|e| match e {
            NonlinearError::Order(o) => BodyError::Order(o),
            other => BodyError::Nonlinear(other),
        })?;
        let names = coefficient_names(&model, order)?;
        let mut params = base;
        let mut given = Vec::new();
        for (name, value) in assignments {
            if let Some(canonical) = coefficient_of(name, &names, &model) {
                given.push((canonical, *value));
            } else if is_scale(name) {
                params.set(name, *value)?;
            } else {
                return Err(unknown(name, &model, &names));
            }
        }
        let scales: Vec<&str> = model.fields.iter().map(|f| f.scale()).collect();
        if let Some(name) = params.unused(&scales).first() {
            return Err(unknown(name, &model, &names));
        }
        // An active force switched on leaves the modal theory (its operator is not symmetric).
        let active: Vec<String> = crate::dynamics::nonlinear::active_terms(&model, order)?
            .into_iter()
            .flatten()
            .map(|(_, n)| n)
            .collect();
        let driven = given.iter().any(|(n, v)| *v != 0.0 && active.contains(n));
        let modal = linear && !driven && is_modal(&model, order)?;
        let mut body = Body {
            model,
            order,
            linear,
            modal,
            driven,
            names,
            params,
            given,
        };
        if body.modal {
            body.params = body.linear_scales()?;
        }
        Ok(body)
    }

    /// The model (with `beyond_leading` applied).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The order of the expansion.
    pub fn order(&self) -> u32 {
        self.order
    }

    /// Whether every surviving term is a square (the equations are linear).
    pub fn is_linear(&self) -> bool {
        self.linear
    }

    /// Whether the exact modal theory applies: linear, and each field's damping on its one
    /// stiffness operator (ζᵢ = ζ√λᵢ). A linear body without it goes the general path: the
    /// discretised body's integrator, and the quadratic eigenproblem for its modes.
    pub fn is_modal(&self) -> bool {
        self.modal
    }

    /// The scales (on the linear path with the coefficients given folded in).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The coefficients the surviving densities name, as `equations` prints them.
    pub fn coefficient_names(&self) -> &[String] {
        &self.names
    }

    /// Every coefficient's value on the nonlinear path: the defaults, then those given.
    pub fn coefficients(&self) -> Result<BTreeMap<String, f64>, BodyError> {
        let mut values =
            crate::dynamics::default_coefficients(&self.model, self.order, &self.params)?;
        values.extend(self.given.iter().cloned());
        Ok(values)
    }

    /// The discretised nonlinear body on `points` points.
    pub fn discretised(&self, points: usize) -> Result<NonlinearBody, BodyError> {
        Ok(NonlinearBody::new(
            &self.model,
            self.order,
            points,
            &self.coefficients()?,
        )?)
    }

    /// The discretised body to linearise, on at most [`MAX_LINEARISED_POINTS`] points.
    fn linearisable(&self, points: usize) -> Result<NonlinearBody, BodyError> {
        within(
            points,
            MAX_LINEARISED_POINTS,
            "a nonlinear body's linearisation",
            "",
        )?;
        self.discretised(points)
    }

    /// Every field's modes on `points` points: exact on the linear path (the lowest `limit`
    /// of each field when given), of the linearisation about equilibrium otherwise.
    pub fn modes(
        &self,
        points: usize,
        limit: Option<usize>,
        shapes: bool,
    ) -> Result<BodyModes, BodyError> {
        if !self.modal {
            let mut fields = self.linearisable(points)?.linearise(shapes)?;
            if let Some(k) = limit {
                for f in &mut fields {
                    let k = k.min(f.eigenvalues.len());
                    f.eigenvalues.truncate(k);
                    f.frequencies.truncate(k);
                    if let Some(s) = &mut f.shapes {
                        s.truncate(k);
                    }
                }
            }
            return Ok(BodyModes::Linearised(fields));
        }
        if limit.is_none() {
            within(
                points,
                MAX_FULL_SPECTRUM,
                "the full spectrum",
                " (about two seconds): ask for the lowest K modes (--modes K)",
            )?;
        }
        if shapes && points.saturating_mul(limit.unwrap_or(points)) > MAX_SHAPE_VALUES {
            return Err(BodyError::TooManyPoints {
                what: "mode shapes of every mode",
                points,
                limit: MAX_SHAPE_VALUES / limit.unwrap_or(points).max(1),
                hint: " (20 000 000 numbers): ask for fewer modes (--modes K)",
            });
        }
        Ok(BodyModes::Exact(field_modes(
            &self.model,
            self.order,
            points,
            &self.params,
            limit,
            shapes,
        )?))
    }

    /// The operators on `points` points: the exact integer matrices of a linear body, the
    /// stiffness, damping and mass of a nonlinear body's linearisation.
    pub fn operators(&self, points: usize) -> Result<BodyOperators, BodyError> {
        within(points, MAX_OPERATOR_POINTS, "the dense operators", "")?;
        // Nonlinear, or driven by an active force: the discretised body's linearisation.
        if !self.linear || self.driven {
            let body = self.linearisable(points)?;
            return Ok(BodyOperators::Linearised(body.linearised_operators()?));
        }
        if !self.given.is_empty() {
            return Err(BodyError::LinearOperators);
        }
        Ok(BodyOperators::Exact(crate::discretise::operators(
            &self.model,
            self.order,
            points,
        )?))
    }

    /// The theory (every field's modes with shapes) on `points` points, for the behaviours and
    /// statistics, which need the exact modal path.
    pub fn theory(&self, points: usize, what: &'static str) -> Result<Theory, BodyError> {
        within(points, crate::dynamics::MAX_SIM_POINTS, what, "")?;
        if !self.modal {
            return Err(BodyError::NotModal { what });
        }
        Ok(Theory::new(
            self.model.clone(),
            self.order,
            points,
            self.params.clone(),
        )?)
    }

    /// Run `config` from `start`, handing `sink` the ids of the fields the samples hold and
    /// each sample (every number checked finite first).
    pub fn simulate(
        &self,
        config: &Config,
        start: &Start,
        mut sink: impl FnMut(&[String], &Sample) -> Result<(), Halt>,
    ) -> Result<(), BodyError> {
        if self.modal {
            if let Some((text, ..)) = start.uniform.first() {
                return Err(BodyError::Uniform(text.clone()));
            }
            let ids: Vec<String> = self.model.fields.iter().map(|f| f.id.clone()).collect();
            let mut config = config.clone();
            config.initial = start.initial.clone();
            config.forcing = start.forcing.clone();
            crate::dynamics::simulate(&self.model, &self.params, &config, |s| sink(&ids, s))?;
            return Ok(());
        }
        let linearises = !start.initial.is_empty() || !start.forcing.is_empty();
        let body = if linearises {
            self.linearisable(config.points)?
        } else {
            self.discretised(config.points)?
        };
        let ids: Vec<String> = body.fields.iter().map(|f| f.id.clone()).collect();
        let mut config = config.clone();
        config.initial = start.initial.clone();
        config.forcing = start.forcing.clone();
        let uniform: Vec<(String, f64, f64)> = start
            .uniform
            .iter()
            .map(|(_, f, q, v)| (f.clone(), *q, *v))
            .collect();
        body.run(&config, &uniform, |s| sink(&ids, s))?;
        Ok(())
    }

    /// On the linear path: the scales with each coefficient given folded in.
    fn linear_scales(&self) -> Result<Params, BodyError> {
        let mut params = self.params.clone();
        if self.given.is_empty() {
            return Ok(params);
        }
        // Which field and density each coefficient belongs to.
        let mut owner = BTreeMap::new();
        for density in [Density::Lagrangian, Density::Rayleigh] {
            let a = crate::reduce::analyse(&self.model, density, self.order)?;
            for f in &a.fields {
                for d in &f.density {
                    if let Some(p) = &d.parameter {
                        owner.insert(
                            p.clone(),
                            (density, f.field.id.clone(), f.field.scale().to_string()),
                        );
                    }
                }
            }
        }
        let mut given = self.given.clone();
        // Frequencies first (a damping coefficient is ζω with ω as set), then dampings.
        given.sort_by_key(|(name, _)| owner.get(name).map(|o| o.0));
        let mut set: BTreeMap<String, (String, String, f64)> = BTreeMap::new();
        for (name, value) in given {
            let Some((density, field, scale)) = owner.get(&name) else {
                continue;
            };
            let (key, scaled) = match density {
                Density::Lagrangian if value <= 0.0 => {
                    return Err(BodyError::NotPositive { name, value })
                }
                Density::Lagrangian => (Params::omega_name(scale), value.sqrt()),
                Density::Rayleigh => (Params::zeta_name(scale), value / params.omega(scale)),
            };
            if let Some((other, other_field, was)) = set.get(&key) {
                if (was - scaled).abs() > 1e-12 * was.abs().max(1.0) {
                    let why = if other_field == field {
                        "two terms of one field's density, and the modal path gives a field one operator per density (its damping is not modal): set one"
                    } else {
                        "the fields share this scale in the model file: give them their own scales"
                    };
                    return Err(BodyError::SharedScale {
                        first: other.clone(),
                        second: name,
                        key,
                        was: *was,
                        now: scaled,
                        why,
                    });
                }
            }
            params.set(&key, scaled)?;
            set.insert(key, (name, field.clone(), scaled));
        }
        Ok(params)
    }
}

/// `points` within the budget `limit` of `what`, or the error naming both.
fn within(
    points: usize,
    limit: usize,
    what: &'static str,
    hint: &'static str,
) -> Result<(), BodyError> {
    if points > limit {
        return Err(BodyError::TooManyPoints {
            what,
            points,
            limit,
            hint,
        });
    }
    Ok(())
}

/// Whether every field of a linear body has at most one stiffness operator and its damping on
/// the same one: the condition of the modal theory ([`crate::modal::field_modes`]).
fn is_modal(model: &Model, order: u32) -> Result<bool, BodyError> {
    let plan = crate::discretise::plan(model, order)?;
    Ok(model.fields.iter().all(|field| {
        let of = |d: Density| {
            plan.iter()
                .filter(move |p| p.field == field.id && p.density == d)
        };
        let stiff: Vec<_> = of(Density::Lagrangian).collect();
        match stiff.as_slice() {
            [] => true,
            [s] => of(Density::Rayleigh).all(|d| d.k == s.k),
            _ => false,
        }
    }))
}

/// Whether `name` has the shape of a scale (`omega_<scale>`, `zeta_<scale>`).
fn is_scale(name: &str) -> bool {
    name.split_once('_')
        .is_some_and(|(kind, scale)| matches!(kind, "omega" | "zeta") && !scale.is_empty())
}

/// The error for a name that is no scale or coefficient of `model`, listing (clipped) those
/// that are.
fn unknown(name: &str, model: &Model, names: &[String]) -> BodyError {
    let mut scales: Vec<String> = Vec::new();
    for f in &model.fields {
        for kind in ["omega", "zeta"] {
            let s = format!("{kind}_{}", f.scale());
            if !scales.contains(&s) {
                scales.push(s);
            }
        }
    }
    BodyError::Unknown {
        name: crate::markup::clip(name),
        model: model.name.clone(),
        known: format!(
            "scales: {}; coefficients: {}",
            listed(&scales),
            listed(names)
        ),
    }
}

/// A coefficient's canonical name: as `equations` prints it (`c'1_θ`), or in ASCII with `p`
/// for the prime and the field's id for its symbol (`cp1_theta`).
fn coefficient_of(name: &str, names: &[String], model: &Model) -> Option<String> {
    names
        .iter()
        .find(|n| {
            *n == name
                || n.rsplit_once('_').is_some_and(|(letter, symbol)| {
                    model.fields.iter().any(|f| {
                        f.symbol == symbol
                            && format!("{}_{}", letter.replace('\'', "p"), f.id) == name
                    })
                })
        })
        .cloned()
}

/// A body's modes: exact, or of its linearisation.
#[derive(Debug, Clone)]
pub enum BodyModes {
    /// The exact modal theory of a linear body.
    Exact(Vec<FieldModes>),
    /// The modes of a nonlinear body's linearisation about equilibrium.
    Linearised(Vec<LinearisedField>),
}

/// A body's operators: exact, or of its linearisation.
#[derive(Debug, Clone)]
pub enum BodyOperators {
    /// The exact integer matrices of a linear body.
    Exact(Vec<Operator>),
    /// Stiffness, damping and mass of a nonlinear body's linearisation.
    Linearised(Vec<LinearisedOperator>),
}
