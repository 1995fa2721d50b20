//! The discretised equations of a body whose surviving terms are powers of one derivative,
//! quadratic or not: (∂sᵇφ)ⁿ in the Lagrangian, (∂t∂sᵇφ)ⁿ in the Rayleigh density, with the
//! standard kinetic term ½(∂tφ)². Its time evolution, without noise.
//!
//! **Discretisation.** The variational one, as for the linear operators: a term becomes
//! Σᵣ (S_b u)ᵣⁿ over the rows r of the b-th difference stencils S_b that fit the field's boundary
//! (the identity for b = 0), in units of the point spacing. The potential is V(u) = −Σ (the
//! Lagrangian's terms without a time derivative), the dissipation R(v) = Σ (the Rayleigh terms in
//! S_b v), the kinetic energy ½|v|². A square gives back the linear operator: ½c Σ(S u)² has the
//! force −c SᵀS u, the equation's c ∂s²ᵇ… term.
//!
//! **Integration** is in [`super::implicit`]: the average-vector-field scheme, which keeps the
//! discrete energy balance exactly.

use std::collections::BTreeMap;

use crate::boundary::Boundary;
use crate::discretise::{force_plan, force_rows, DiscretiseError};
use crate::model::{Density, Model};
use crate::reduce::analyse;

/// Why a body cannot be integrated here, or a step failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NonlinearError {
    /// A term this discretisation does not take.
    #[error("field {field}: {term} in the {density} density: {why}")]
    Term {
        /// Field symbol.
        field: String,
        /// The term.
        term: String,
        /// `lagrangian` or `rayleigh`.
        density: &'static str,
        /// Why.
        why: String,
    },
    /// A coefficient without a value.
    #[error("coefficient {name} has no value (the coefficients are {all})")]
    Missing {
        /// The coefficient.
        name: String,
        /// Every coefficient the equations name.
        all: String,
    },
    /// A coefficient that is not a finite number.
    #[error("coefficient {name} = {} is not a finite number", crate::report::number(*value))]
    NotFinite {
        /// The coefficient.
        name: String,
        /// Its value.
        value: f64,
    },
    /// The engine refuses the order.
    #[error(transparent)]
    Order(#[from] crate::reduce::OrderError),
    /// The `[active]` section's forces cannot be enumerated.
    #[error(transparent)]
    Active(crate::active::ActiveError),
    /// The grid refuses the body (too few points, a term it does not take).
    #[error(transparent)]
    Discretise(DiscretiseError),
    /// No equilibrium (∇V = 0) was found.
    #[error("field {field}: no equilibrium found (∇V = 0 has no solution Newton's method reaches from rest; |∇V| stays at {residual:.3e}): the potential may be unbounded below")]
    NoEquilibrium {
        /// Field id.
        field: String,
        /// The smallest |∇V| reached.
        residual: f64,
    },
    /// Noise through a dissipation that is not a sum of squares.
    #[error("field {field}: Langevin noise needs {why} (fluctuation–dissipation); run it at --temperature 0")]
    Noise {
        /// Field id.
        field: String,
        /// What it needs.
        why: &'static str,
    },
    /// A mass matrix ∇²T(0) that is not positive definite.
    #[error("field {field}: the kinetic energy is not positive at rest (its mass matrix ∇²T(0) is not positive definite): the motion is not defined")]
    NotPositiveMass {
        /// Field id.
        field: String,
    },
    /// A matrix of the linearisation overflowed (coefficients or states too large).
    #[error("field {field}: {what} overflows f64 (a coefficient or state too large for the numbers): use smaller coefficients")]
    Overflow {
        /// Field id.
        field: String,
        /// Which matrix.
        what: &'static str,
    },
    /// Damped roots whose real parts miss the trace: the decay rates were lost to rounding.
    #[error("field {field}: the damped roots cannot be trusted: their real parts sum to {} where the trace of the linearised matrix gives {} (roots of size {size:.1e} lose the decay rates to rounding): use smaller coefficients", crate::report::number(*sum), crate::report::number(*trace))]
    Untrusted {
        /// Field id.
        field: String,
        /// Σ Re λ of the roots found.
        sum: f64,
        /// −tr(M⁻¹C).
        trace: f64,
        /// The roots' size s.
        size: f64,
    },
    /// The quadratic eigenproblems of a linearisation are over their budget.
    #[error("the damped roots of {fields} field(s) need companion eigen-solves of {work:.1e} units (Σ(2n)³ over fields of n unknowns), over the budget of {budget:.1e} (about two seconds): use fewer points")]
    DampedBudget {
        /// Fields whose damped roots are solved.
        fields: usize,
        /// Σ(2n)³.
        work: f64,
        /// The budget.
        budget: f64,
    },
    /// Newton's method did not converge.
    #[error("the implicit step at t = {} did not converge: take a smaller time step", crate::report::number(*t))]
    NoConvergence {
        /// Time at the start of the step.
        t: f64,
    },
    /// The state left the finite numbers.
    #[error("the state is no longer finite at t = {}: the motion diverges (a smaller time step, or a potential bounded below)", crate::report::number(*t))]
    Diverged {
        /// Time at the end of the step.
        t: f64,
    },
}

/// Σᵣ c·(row·u)ⁿ over the rows of one stencil family.
#[derive(Debug, Clone)]
pub(super) struct Power {
    /// Every row's (unknown, weight) entries, one after another: the hot loops read them in order.
    entries: Vec<(usize, f64)>,
    /// Where each row starts in `entries`, and the end.
    starts: Vec<usize>,
    power: i32,
    pub(super) coefficient: f64,
}

/// xᵏ for the small k of a density's terms without a libm call.
fn pow(x: f64, k: i32) -> f64 {
    match k {
        0 => 1.0,
        1 => x,
        2 => x * x,
        3 => x * x * x,
        _ => x.powi(k),
    }
}

impl Power {
    fn new(rows: Vec<Vec<(usize, f64)>>, power: i32, coefficient: f64) -> Power {
        let mut starts = vec![0];
        let mut entries = Vec::new();
        for r in rows {
            entries.extend(r);
            starts.push(entries.len());
        }
        Power {
            entries,
            starts,
            power,
            coefficient,
        }
    }

    /// The exponent n.
    pub(super) fn power(&self) -> i32 {
        self.power
    }

    /// The stencil rows.
    pub(super) fn rows(&self) -> impl Iterator<Item = &[(usize, f64)]> {
        self.starts.windows(2).map(|w| &self.entries[w[0]..w[1]])
    }

    fn dot(row: &[(usize, f64)], u: &[f64]) -> f64 {
        row.iter().map(|&(j, w)| w * u[j]).sum()
    }

    pub(super) fn value(&self, u: &[f64]) -> f64 {
        let n = self.power;
        self.coefficient * self.rows().map(|r| pow(Self::dot(r, u), n)).sum::<f64>()
    }

    /// Adds `scale` × the gradient.
    pub(super) fn gradient(&self, u: &[f64], scale: f64, out: &mut [f64]) {
        let n = self.power;
        let c = scale * self.coefficient * f64::from(n);
        for r in self.rows() {
            let g = c * pow(Self::dot(r, u), n - 1);
            for &(j, w) in r {
                out[j] += g * w;
            }
        }
    }

    /// Adds `scale` × the Hessian, entry by entry.
    pub(super) fn hessian(&self, u: &[f64], scale: f64, add: &mut impl FnMut(usize, usize, f64)) {
        let n = self.power;
        if n < 2 {
            return;
        }
        let c = scale * self.coefficient * f64::from(n * (n - 1));
        for r in self.rows() {
            let h = c * pow(Self::dot(r, u), n - 2);
            for &(i, wi) in r {
                for &(j, wj) in r {
                    add(i, j, h * wi * wj);
                }
            }
        }
    }
}

/// One field's discretised potential and dissipation.
#[derive(Debug, Clone)]
pub struct FieldSystem {
    /// Field id.
    pub id: String,
    /// Unknowns (points, or N − 1 around a ring).
    pub unknowns: usize,
    pub(super) periodic: bool,
    /// The field's boundary.
    pub(super) boundary: Boundary,
    /// Points held at zero at the (tail, head): not unknowns.
    pub(super) held: (usize, usize),
    pub(super) potential: Vec<Power>,
    /// The kinetic energy's terms beside ½|v|² (in the velocity).
    pub(super) kinetic: Vec<Power>,
    pub(super) dissipation: Vec<Power>,
    /// The active forces (`[active]`), per unit mass.
    pub(super) active: Vec<super::ActiveForce>,
}

/// Gauss–Legendre nodes and weights on [0, 1], exact for polynomials of degree ≤ 2m − 1.
fn gauss(m: usize) -> Vec<(f64, f64)> {
    let s3 = 3f64.sqrt();
    let s35 = (3.0f64 / 5.0).sqrt();
    let raw: Vec<(f64, f64)> = match m {
        1 => vec![(0.0, 2.0)],
        2 => vec![(-1.0 / s3, 1.0), (1.0 / s3, 1.0)],
        3 => vec![(-s35, 5.0 / 9.0), (0.0, 8.0 / 9.0), (s35, 5.0 / 9.0)],
        _ => {
            let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let wa = (18.0 + 30f64.sqrt()) / 36.0;
            let wb = (18.0 - 30f64.sqrt()) / 36.0;
            vec![(-b, wb), (-a, wa), (a, wa), (b, wb)]
        }
    };
    raw.into_iter()
        .map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w))
        .collect()
}

impl FieldSystem {
    /// V(u).
    pub fn potential(&self, u: &[f64]) -> f64 {
        self.potential.iter().map(|p| p.value(u)).sum()
    }

    /// A vector on the unknowns as the body's points, zeros at held points (around a ring the
    /// unknowns, as the modal commands write them).
    pub fn embed(&self, u: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.held.0];
        out.extend_from_slice(u);
        out.resize(out.len() + self.held.1, 0.0);
        out
    }

    /// The unknowns of a vector on the body's points ([`FieldSystem::embed`] undone).
    pub fn strip(&self, points: &[f64]) -> Vec<f64> {
        points[self.held.0..self.held.0 + self.unknowns].to_vec()
    }

    /// Whether every term is a square or linear (then each step is one solve).
    pub(super) fn is_linear(&self) -> bool {
        self.active.is_empty()
            && self.potential.iter().all(|p| p.power <= 2)
            && self.dissipation.iter().all(|p| p.power == 2)
            && self.kinetic.iter().all(|p| p.power == 2)
    }

    /// The mass matrix ∇²T(v), dense.
    pub fn mass(&self, v: &[f64]) -> nalgebra::DMatrix<f64> {
        let mut m = nalgebra::DMatrix::identity(self.unknowns, self.unknowns);
        for p in &self.kinetic {
            p.hessian(v, 1.0, &mut |i, j, x| m[(i, j)] += x);
        }
        m
    }

    /// R(v).
    pub fn dissipation(&self, v: &[f64]) -> f64 {
        self.dissipation.iter().map(|p| p.value(v)).sum()
    }

    /// ∇R(v), the dissipative force's negative.
    pub fn dissipation_gradient(&self, v: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; self.unknowns];
        for p in &self.dissipation {
            p.gradient(v, 1.0, &mut g);
        }
        g
    }

    /// The active force f(u, v) (zeros without one).
    pub fn active_force(&self, u: &[f64], v: &[f64]) -> Vec<f64> {
        let mut f = vec![0.0; self.unknowns];
        for a in &self.active {
            a.add(u, v, 1.0, &mut f);
        }
        f
    }

    /// E = v·∇T(v) − T(v) + V(u): ½|v|² + Σ (n − 1)·(each kinetic term of power n) + V(u).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        0.5 * v.iter().map(|x| x * x).sum::<f64>()
            + self
                .kinetic
                .iter()
                .map(|p| f64::from(p.power - 1) * p.value(v))
                .sum::<f64>()
            + self.potential(u)
    }

    pub(super) fn quadrature(&self) -> Vec<(f64, f64)> {
        let top = self.potential.iter().map(|p| p.power).max().unwrap_or(2);
        gauss((top.max(2) as usize).div_ceil(2).min(4))
    }

    pub(super) fn bandwidth(&self) -> usize {
        self.potential
            .iter()
            .chain(&self.kinetic)
            .chain(&self.dissipation)
            .flat_map(|p| p.rows())
            .map(|r| {
                let lo = r.iter().map(|e| e.0).min().unwrap_or(0);
                let hi = r.iter().map(|e| e.0).max().unwrap_or(0);
                hi - lo
            })
            // A row that wraps around a ring spans the whole body: its corners are apart.
            .filter(|&span| !self.periodic || 2 * span < self.unknowns)
            .max()
            .unwrap_or(0)
    }
}

/// A body's discretised equations, one system per field with a kinetic term.
#[derive(Debug, Clone)]
pub struct NonlinearBody {
    /// The fields, model order.
    pub fields: Vec<FieldSystem>,
}

/// The coefficients the surviving densities name (`c1_x`, `c'_x`, …), model order.
pub fn coefficient_names(model: &Model, order: u32) -> Result<Vec<String>, NonlinearError> {
    let l = analyse(model, Density::Lagrangian, order)?;
    let r = analyse(model, Density::Rayleigh, order)?;
    let mut names = names_of(&[&l, &r]);
    names.extend(
        active_terms(model, order)?
            .into_iter()
            .flatten()
            .map(|(_, n)| n),
    );
    Ok(names)
}

/// Each field's active and gyroscopic forces (term, coefficient name), model order, as
/// `equations` adds them: none without an `[active]` section.
pub fn active_terms(
    model: &Model,
    order: u32,
) -> Result<Vec<Vec<(crate::term::Term, String)>>, NonlinearError> {
    let fields = crate::active::active_forces(model, order).map_err(NonlinearError::Active)?;
    Ok(entering_terms(&fields.unwrap_or_default()))
}

/// Each field's forces entering the equations (term, coefficient name), from `active_forces`.
pub(super) fn entering_terms(
    fields: &[crate::active::FieldForces],
) -> Vec<Vec<(crate::term::Term, String)>> {
    fields
        .iter()
        .map(|f| {
            f.entering()
                .map(|(x, name)| (x.shape.clone(), name.to_string()))
                .collect()
        })
        .collect()
}

/// The coefficient names of a force plan and its active terms, as `equations` lists them:
/// every Lagrangian coefficient, then the Rayleigh ones, then the active ones.
pub(super) fn plan_names(
    plan: &[crate::discretise::FieldForces],
    active: &[Vec<(crate::term::Term, String)>],
) -> Vec<String> {
    let mut names: Vec<String> = [Density::Lagrangian, Density::Rayleigh]
        .iter()
        .flat_map(|d| {
            plan.iter()
                .flat_map(move |f| f.terms.iter().filter(move |t| t.density == *d))
        })
        .filter_map(|t| t.parameter.clone())
        .collect();
    names.extend(active.iter().flatten().map(|(_, n)| n.clone()));
    names
}

/// The coefficient names of analysed densities, in order.
fn names_of(analyses: &[&crate::reduce::Analysis]) -> Vec<String> {
    analyses
        .iter()
        .flat_map(|a| a.fields.iter())
        .flat_map(|f| f.density.iter().filter_map(|d| d.parameter.clone()))
        .collect()
}

impl NonlinearBody {
    /// Discretise `model` at `order` on `points` points, each coefficient's value from
    /// `values` (by the name the equations print): the engine's force plan
    /// ([`crate::discretise::force_plan`]) on the grid.
    pub fn new(
        model: &Model,
        order: u32,
        points: usize,
        values: &BTreeMap<String, f64>,
    ) -> Result<NonlinearBody, NonlinearError> {
        let plan = force_plan(model, order).map_err(NonlinearError::from)?;
        let active = active_terms(model, order)?;
        Self::planned(model, &plan, &active, points, values)
    }

    /// [`Self::new`] from the model's force plan and active terms, derived once by a caller
    /// that builds many bodies of one model (`library`: one per coefficient).
    pub(super) fn planned(
        model: &Model,
        plan: &[crate::discretise::FieldForces],
        active: &[Vec<(crate::term::Term, String)>],
        points: usize,
        values: &BTreeMap<String, f64>,
    ) -> Result<NonlinearBody, NonlinearError> {
        let names = plan_names(plan, active);
        let mut fields = Vec::new();
        for f in plan.iter().filter(|f| f.kinetic) {
            if points < f.min_points() {
                return Err(NonlinearError::Discretise(DiscretiseError::TooFewPoints {
                    points,
                    k: f.top,
                    boundary: f.field.boundary.name(),
                    min: f.min_points(),
                }));
            }
            let mut system = FieldSystem {
                id: f.field.id.clone(),
                unknowns: f.unknowns(points),
                periodic: f.field.boundary == Boundary::Periodic,
                boundary: f.field.boundary,
                held: f.held,
                potential: Vec::new(),
                kinetic: Vec::new(),
                dissipation: Vec::new(),
                active: Vec::new(),
            };
            let index = model.fields.iter().position(|m| m.id == f.field.id);
            for (term, name) in index.and_then(|i| active.get(i)).into_iter().flatten() {
                let value = coefficient(Some(name), &names, values)?;
                if value == 0.0 {
                    continue;
                }
                let shape = (points, system.unknowns);
                let force = super::ActiveForce::new(term, value, shape, f.field.boundary, f.held)
                    .ok_or_else(|| NonlinearError::Term {
                    field: f.field.symbol.clone(),
                    term: term.render(&|_| f.field.symbol.clone()),
                    density: "active",
                    why: crate::active::NOT_A_FORCE.into(),
                })?;
                system.active.push(force);
            }
            for t in &f.terms {
                let value = coefficient(t.parameter.as_deref(), &names, values)?;
                // A term switched off costs nothing.
                if value == 0.0 {
                    continue;
                }
                let rows = force_rows(t.b, f.field.boundary, points, f.held);
                let power = Power::new(rows, t.power as i32, t.factor * value);
                match t.density {
                    _ if t.kinetic => system.kinetic.push(power),
                    Density::Lagrangian => system.potential.push(power),
                    Density::Rayleigh => system.dissipation.push(power),
                }
            }
            fields.push(system);
        }
        Ok(NonlinearBody { fields })
    }

    /// The total energy Σ ½|v|² + V(u).
    pub fn energy(&self, state: &[(Vec<f64>, Vec<f64>)]) -> f64 {
        self.fields
            .iter()
            .zip(state)
            .map(|(f, (u, v))| f.energy(u, v))
            .sum()
    }
}

/// The value of a term's coefficient: 1 for a fixed term, else from `values`.
fn coefficient(
    name: Option<&str>,
    names: &[String],
    values: &BTreeMap<String, f64>,
) -> Result<f64, NonlinearError> {
    let Some(name) = name else {
        return Ok(1.0);
    };
    let value = *values.get(name).ok_or_else(|| NonlinearError::Missing {
        name: name.to_string(),
        all: names.join(", "),
    })?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(NonlinearError::NotFinite {
            name: name.to_string(),
            value,
        })
    }
}

impl NonlinearError {
    /// The kind of failure: a body or value the integrator cannot take is usage; a step, an
    /// equilibrium search or a state that fails on valid input is numerical.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            NonlinearError::NoEquilibrium { .. }
            | NonlinearError::NoConvergence { .. }
            | NonlinearError::Diverged { .. }
            | NonlinearError::Overflow { .. }
            | NonlinearError::Untrusted { .. } => Failure::Numerical,
            _ => Failure::Usage,
        }
    }
}

impl From<DiscretiseError> for NonlinearError {
    fn from(e: DiscretiseError) -> NonlinearError {
        match e {
            DiscretiseError::NotAForce {
                field,
                term,
                density,
                why,
            } => NonlinearError::Term {
                field,
                term,
                density,
                why,
            },
            other => NonlinearError::Discretise(other),
        }
    }
}
