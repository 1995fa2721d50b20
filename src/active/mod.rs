//! Active forces: the terms f of ∂t²φ = … + f that symmetry allows and that no Lagrangian or
//! Rayleigh density gives.
//!
//! **Candidates** are the single-field monomials f in the jet ∂tᵃ∂sᵇφ within the `[active]`
//! section's bound at the order asked (the orders δ, ε, τ, σ of a density term). **A force
//! transforms as its field**: under φ → c·φ(±s, ±t) + p·sᵐtⁿ the equation stays true exactly
//! when the image of f equals c·f (to first order in p for an infinitesimal shift), so each
//! symmetry rule is decided by applying its transformation to f and comparing with c·f: under
//! φ → −φ an allowed force is odd, under s → −s it is even (the field's own parity), under a
//! translation or a rotation it is unchanged. Ostrogradsky's rule keeps second time derivatives
//! out (they are inertia); KIN and DIS are rules about densities, which the model refuses here.
//!
//! **Classes.** A polynomial force is variational (f = δL/δφ for some density L; the Helmholtz
//! condition, its Fréchet derivative self-adjoint) exactly when the Volterra homotopy density
//! H(f) = ∫₀¹ φ·f[λφ] dλ = φ·f/(ε + 1) gives it back: E(H(f)) = f. Such a force is
//! *conservative* when even under time reversal and *gyroscopic* when odd (a Lagrangian
//! ∂t φ·∂s φ, which KIN strikes out, does no work and splits forward from backward waves). A
//! force of the velocity jet alone is of *Rayleigh* form when v·f/(ε + 1) (v = ∂tφ) gives it
//! back through δ/δv over s (its power (ε + 1)c∫R has the coefficient's sign when R is definite in
//! v, and none when R is odd in v: each force's `why` says which). Every other force is
//! *active*: its power has no sign and it is not a variational derivative.

mod basis;
mod carried;
mod field;

pub use basis::Dependent;

use crate::enumerate::{monomials, Bounds, MAX_ORDER};
use crate::jet::{euler_lagrange, mono_of, poly_of, space_euler, JetPoly};
use crate::model::Model;
use crate::rules::{Check, Rule};
use crate::term::{Deriv, Orders, Term};

/// The most candidate forces one field's enumeration may build.
pub const MAX_FORCE_CANDIDATES: usize = 200_000;

/// The budget of classifying the covariant forces of every field: Σ 1.5^(τ+σ) over them (an
/// Euler–Lagrange expansion grows about 1.5× with each derivative a force carries; about a
/// microsecond a unit measured, so about three seconds). The symmetry filter before it is cheap.
pub const MAX_CLASSIFY_WORK: f64 = 3e6;

/// The classification work of one force (see [`MAX_CLASSIFY_WORK`]).
fn classify_work(t: &Term) -> f64 {
    let o = t.orders();
    1.5f64.powi((o.tau + o.sigma) as i32)
}

/// Why active forces cannot be enumerated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ActiveError {
    /// The order is out of range.
    #[error("order {0} is out of range: use an order from 1 to {MAX_ORDER}")]
    Order(u32),
    /// Too many candidates at this order.
    #[error("order {order} has more than {MAX_FORCE_CANDIDATES} candidate forces per field: use a lower order")]
    TooMany {
        /// The order asked for.
        order: u32,
    },
    /// Classifying the covariant candidates is over its budget.
    #[error("order {order} leaves {count} covariant candidate forces to classify, {:.1e} units of work (Σ 1.5^(τ+σ) over them), over the budget of {:.0e} (about three seconds): use a lower order or more requirements in [active]", *.work as f64, MAX_CLASSIFY_WORK)]
    TooMuchWork {
        /// The order asked for.
        order: u32,
        /// Covariant candidates over every field.
        count: usize,
        /// Their classification work, in whole units.
        work: u64,
    },
    /// The model has no `[active]` section.
    #[error("the {} model has no [active] section: add one (bound, columns, requirements per field, as [rayleigh]) to enumerate active forces", crate::markup::clip(.model))]
    NoSection {
        /// The model's name.
        model: String,
    },
}

/// What a force is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ForceClass {
    /// δL/δφ of some density, even under time reversal.
    Conservative,
    /// δL/δφ of some density, odd under time reversal: no work, waves split.
    Gyroscopic,
    /// −δR/δv of a density of the velocity jet.
    Dissipative,
    /// Neither: power of no sign, not a variational derivative.
    Active,
}

/// One covariant force term of one field.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Force {
    /// The term, in the field's symbol.
    pub term: String,
    /// Its orders.
    #[serde(skip)]
    pub orders: Orders,
    /// Its class.
    pub kind: ForceClass,
    /// +1 even, −1 odd under t → −t.
    pub time_parity: i8,
    /// +1 even, −1 odd under s → −s.
    pub space_parity: i8,
    /// Why it is in its class, in one line.
    pub why: String,
    /// The coefficient it enters the equations with: `a_y` for an active force, `g_y` for a
    /// gyroscopic one (`a1_y`, `a2_y`, … when a field has several); none for the other classes
    /// (the admitted densities give those).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coefficient: Option<String>,
    /// The term itself (placeholder field 0).
    #[serde(skip)]
    pub shape: Term,
}

/// One field's forces.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FieldForces {
    /// Field id.
    pub field: String,
    /// Candidates enumerated.
    pub candidates: usize,
    /// Those every required rule allows.
    pub covariant: usize,
    /// How many of those are conservative, gyroscopic, dissipative and active.
    pub counts: [usize; 4],
    /// The lowest-order active forces (the model's `beyond_leading` layers).
    pub active: Vec<Force>,
    /// The lowest-order gyroscopic forces: variational, yet odd under time reversal.
    pub gyroscopic: Vec<Force>,
    /// Active monomials of the lowest-order blocks that add no direction: the listed active
    /// forces give them, up to a variational or Rayleigh force (`basis`).
    pub dependent: Vec<Dependent>,
    /// The lowest-order covariant variational and Rayleigh forces that no admitted density
    /// gives (`carried`), with the rules that strike their densities; each has a coefficient
    /// `b_φ` (and enters) only under `uncarried = "enter"`.
    pub uncarried: Vec<Force>,
}

/// Why a force term with a factor of two time derivatives or more is not a force any command
/// moves: `equations` says it under the equation, and `simulate`, `modes` and `emit` refuse it.
pub const NOT_A_FORCE: &str = "a factor with two time derivatives or more is inertia, not a force: it raises the equation's order in time (a position and a velocity no longer fix the motion), so no integrator moves it (OST keeps it out)";

/// Whether a force is closed skew at the ends of the grid: one factor g ∂t∂sᵇφ, b odd, the
/// gyroscopic force of L = ½g φ∂t∂sᵇφ. Its centred difference B is antisymmetric where the
/// stencil fits; a point where it would leave the body reads it on the points where it fits, so
/// Bᵢⱼ = −Bⱼᵢ and v·Bv = 0: the grid's form of L's natural conditions at free ends, whose point
/// forces cancel the continuum's end work g/2[v²] (for b = 1).
pub fn closes_skew(term: &Term) -> bool {
    matches!(term.factors(), [f] if f.power == 1 && f.deriv.t == 1 && f.deriv.s % 2 == 1)
}

impl Force {
    /// Whether a factor has two time derivatives or more ([`NOT_A_FORCE`]).
    pub fn is_inertia(&self) -> bool {
        self.shape.factors().iter().any(|f| f.deriv.t > 1)
    }
}

impl FieldForces {
    /// The forces that enter the field's equation, each with its coefficient: the lowest
    /// active ones, then the lowest gyroscopic ones (the other classes the admitted densities
    /// give already). `equations`, the discretised body and `emit` all take them from here.
    pub fn entering(&self) -> impl Iterator<Item = (&Force, &str)> {
        self.active
            .iter()
            .chain(&self.gyroscopic)
            .chain(&self.uncarried)
            .filter_map(|f| Some((f, f.coefficient.as_deref()?)))
    }
}

/// The last few models' forces: one command asks for them several times (`discover`'s library,
/// its equations, its replay body), and at high orders each asking costs seconds.
static RECENT: std::sync::Mutex<Vec<(Model, u32, Vec<FieldForces>)>> =
    std::sync::Mutex::new(Vec::new());

/// The active forces of a model at an order (`None` when it has no `[active]` section).
pub fn active_forces(model: &Model, order: u32) -> Result<Option<Vec<FieldForces>>, ActiveError> {
    if model.active.is_none() {
        return Ok(None);
    }
    let recent = || RECENT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, _, forces)) = recent().iter().find(|(m, o, _)| *o == order && m == model) {
        return Ok(Some(forces.clone()));
    }
    let forces = derive_active_forces(model, order)?;
    let mut kept = recent();
    if kept.len() >= 4 {
        kept.remove(0);
    }
    kept.push((model.clone(), order, forces.clone()));
    Ok(Some(forces))
}

fn derive_active_forces(model: &Model, order: u32) -> Result<Vec<FieldForces>, ActiveError> {
    let Some(spec) = &model.active else {
        return Ok(Vec::new());
    };
    if order == 0 || order > MAX_ORDER {
        return Err(ActiveError::Order(order));
    }
    let bounds = Bounds::for_order(spec.bound, order);
    // Counted before any is built (the generating function of `enumerate`).
    if crate::enumerate::count_products(&bounds, 1) > MAX_FORCE_CANDIDATES as u128 {
        return Err(ActiveError::TooMany { order });
    }
    let candidates = monomials(&bounds);
    // Every field's covariant candidates (a cheap filter), then their classification budgeted
    // before any is classified.
    let covariant: Vec<Vec<&Term>> = model
        .fields
        .iter()
        .map(|f| field::covariant_of(spec, &f.id, &candidates))
        .collect();
    let (count, work) = covariant
        .iter()
        .flatten()
        .fold((0, 0.0), |(n, w), t| (n + 1, w + classify_work(t)));
    if work > MAX_CLASSIFY_WORK {
        return Err(ActiveError::TooMuchWork {
            order,
            count,
            work: work as u64,
        });
    }
    Ok(model
        .fields
        .iter()
        .zip(&covariant)
        .map(|(f, cov)| {
            let rules = carried::DensityRules::of(model, &f.id);
            field::field_forces(spec, (&f.id, &f.symbol), &rules, candidates.len(), cov)
        })
        .collect())
}

/// Does rule `r` allow force `t` (placeholder field 0)? A structural rule judges its shape; a
/// symmetry maps f to c·f (see the module header).
pub fn allows(r: &Rule, t: &Term) -> bool {
    match &r.check {
        Check::Structural(pred) => pred(t).is_ok(),
        Check::Symmetry(tr) => tr.is_covariant_field(t, 0),
    }
}

/// The class of force `t`, with its parities and why.
pub fn classify(t: &Term, name: &dyn Fn(u8) -> String) -> Force {
    let parity = |odd: bool| if odd { -1 } else { 1 };
    let (ts, ss): (u32, u32) = t.factors().iter().fold((0, 0), |(a, b), f| {
        (a + f.deriv.t * f.power, b + f.deriv.s * f.power)
    });
    let (time_parity, space_parity) = (parity(ts % 2 == 1), parity(ss % 2 == 1));
    let f = poly_of(t);
    let degree = t.orders().epsilon;
    let (kind, why) = if euler_lagrange(&homotopy(t, Deriv::new(0, 0), degree)) == f {
        if time_parity > 0 {
            (
                ForceClass::Conservative,
                "δL/δφ of L = φ·f/(ε+1), even under t → −t".to_string(),
            )
        } else {
            (ForceClass::Gyroscopic, gyroscopic_power(t))
        }
    } else if t.factors().iter().all(|x| x.deriv.t == 1)
        && space_euler(&homotopy(t, Deriv::new(1, 0), degree)).get(&1) == Some(&f)
    {
        (
            ForceClass::Dissipative,
            rayleigh_power(t, i64::from(degree)),
        )
    } else {
        let why = if t.factors().iter().all(|x| x.deriv.t == 1) {
            "a velocity force that is no δR/δv: not self-adjoint, power of no sign"
        } else if time_parity < 0 {
            "odd under t → −t and not self-adjoint: power of no sign"
        } else {
            "not self-adjoint (no δL/δφ), and not a function of the velocity alone"
        };
        (ForceClass::Active, why.to_string())
    };
    Force {
        term: t.render(name),
        orders: t.orders(),
        kind,
        time_parity,
        space_parity,
        why,
        coefficient: None,
        shape: t.clone(),
    }
}

/// What a gyroscopic force's power is, read from its term: with L = φ·f/(ε+1) linear in the
/// velocity (one factor ∂tφ, the rest without time derivatives) its power vanishes; with more
/// time derivatives in L (no OST: ∂tφ·∂t²φ) it is a time derivative (∂tφ·∂t²φ·∂tφ = d/dt(v³/3)),
/// not zero.
fn gyroscopic_power(t: &Term) -> String {
    let times: u32 = t.factors().iter().map(|f| f.deriv.t * f.power).sum();
    if times == 1 {
        "δL/δφ of L = φ·f/(ε+1), odd under t → −t and linear in the velocity: it does no work"
            .to_string()
    } else {
        "δL/δφ of L = φ·f/(ε+1), odd under t → −t; L is not linear in the velocity, so its power is not zero (a time derivative: it exchanges energy with the motion)".to_string()
    }
}

/// What a Rayleigh-form force's power is, read from its term. For R = v·f/(ε+1), homogeneous
/// of degree ε + 1 in the velocity jet, the power ∫v·δR/δv ds = (ε+1)∫R ds (Euler's theorem, up
/// to the ends' terms): R odd in v (ε even) changes sign with the motion; R a product of even
/// powers is definite; R = v·∂sᵇv (ε = 1) is (−1)^{b/2}(∂s^{b/2}v)² by parts (b even). Any
/// other R has no sign fixed by its form.
fn rayleigh_power(t: &Term, degree: i64) -> String {
    let head = "δR/δv of R = v·f/(ε+1), v = ∂tφ";
    if degree % 2 == 0 {
        return format!(
            "{head}: R is odd in v, so its power (ε+1)c∫R changes sign with the motion: no sign"
        );
    }
    let mut r = mono_of(t);
    match r.iter_mut().find(|(d, _)| *d == Deriv::new(1, 0)) {
        Some((_, n)) => *n += 1,
        None => r.push((Deriv::new(1, 0), 1)),
    }
    if r.iter().all(|(_, n)| n % 2 == 0) {
        return format!(
            "{head}: R is a product of even powers, so its power has the coefficient's sign"
        );
    }
    // ε = 1: f is one factor ∂sᵇv.
    if let ([x], 1) = (t.factors(), degree) {
        let d = x.deriv;
        if d.s % 2 == 0 {
            let sign = if d.s % 4 == 0 { "" } else { "the opposite of " };
            return format!(
                "{head}: R = v·∂s^{}v is (−1)^{} (∂s^{} v)² by parts, so its power has {sign}the coefficient's sign",
                d.s,
                d.s / 2,
                d.s / 2
            );
        }
        return format!(
            "{head}: R = v·∂s^{}v is a total s-derivative (b odd), so it does work only at the ends",
            d.s
        );
    }
    format!("{head}: its power (ε+1)c∫R has no sign fixed by its form")
}

/// The homotopy density u·f/(ε + 1), `u` the factor ∂^`u` φ.
fn homotopy(t: &Term, u: Deriv, degree: u32) -> JetPoly {
    basis::times(&poly_of(t), u, degree)
}

/// The active forces of a model at an order, as printed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ActiveReport {
    /// The model's name.
    pub model: String,
    /// The order.
    pub order: u32,
    /// Per field.
    pub fields: Vec<FieldForces>,
}

impl ActiveReport {
    /// The report of `model` at `order`: what `theory-search active` prints and Python's
    /// `active()` returns (an error for a model without an `[active]` section).
    pub fn of(model: &Model, order: u32) -> Result<ActiveReport, ActiveError> {
        let fields = active_forces(model, order)?.ok_or_else(|| ActiveError::NoSection {
            model: model.name.clone(),
        })?;
        Ok(ActiveReport {
            model: model.name.clone(),
            order,
            fields,
        })
    }
}

impl crate::report::Report for ActiveReport {
    fn text(&self) -> String {
        use std::fmt::Write as _;
        let mut t = format!(
            "Active forces of the {} model at order {} (terms f of ∂t²φ = … + f that symmetry allows and no Lagrangian or Rayleigh density gives)\n",
            crate::markup::clip(&self.model),
            self.order
        );
        let sign = |p: i8| if p > 0 { "even" } else { "odd" };
        for f in &self.fields {
            let [c, g, d, a] = f.counts;
            let _ = writeln!(
                t,
                "\n{}: {} candidates, {} covariant: {c} conservative, {g} gyroscopic, {d} dissipative, {a} active",
                f.field, f.candidates, f.covariant
            );
            for (what, list) in [("active", &f.active), ("gyroscopic", &f.gyroscopic)] {
                if list.is_empty() {
                    let _ = writeln!(t, "  lowest-order {what}: none");
                    continue;
                }
                let _ = writeln!(t, "  lowest-order {what}:");
                for x in list {
                    let o = x.orders;
                    let _ = writeln!(
                        t,
                        "    {:<24} δ={} ε={} τ={} σ={}  t→−t {}, s→−s {}: {}",
                        x.term,
                        o.delta,
                        o.epsilon,
                        o.tau,
                        o.sigma,
                        sign(x.time_parity),
                        sign(x.space_parity),
                        x.why
                    );
                }
            }
            for d in &f.dependent {
                let _ = writeln!(t, "  not listed: {} {}", d.term, d.why);
            }
            if !f.uncarried.is_empty() {
                let _ = writeln!(t, "  carried by no density:");
            }
            for x in &f.uncarried {
                let enters = match &x.coefficient {
                    Some(c) => format!("enters as {c}"),
                    None => "in no equation (uncarried = \"enter\" in [active] adds it)".into(),
                };
                let o = x.orders;
                let _ = writeln!(
                    t,
                    "    {:<24} δ={} ε={} τ={} σ={}  {}; {enters}",
                    x.term, o.delta, o.epsilon, o.tau, o.sigma, x.why
                );
            }
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    /// One row per listed force (the lowest active, gyroscopic and uncarried, of each field),
    /// the text's columns; the counts per class are the JSON's.
    fn csv(&self) -> Option<String> {
        let rows = self.fields.iter().flat_map(|f| {
            [
                ("active", &f.active),
                ("gyroscopic", &f.gyroscopic),
                ("uncarried", &f.uncarried),
            ]
            .into_iter()
            .flat_map(move |(class, list)| {
                list.iter().map(move |x| {
                    let o = x.orders;
                    vec![
                        f.field.clone(),
                        class.to_string(),
                        x.term.clone(),
                        x.coefficient.clone().unwrap_or_default(),
                        o.delta.to_string(),
                        o.epsilon.to_string(),
                        o.tau.to_string(),
                        o.sigma.to_string(),
                        x.time_parity.to_string(),
                        x.space_parity.to_string(),
                        x.why.clone(),
                    ]
                })
            })
        });
        Some(crate::report::csv_table(
            &[
                "field",
                "class",
                "term",
                "coefficient",
                "delta",
                "epsilon",
                "tau",
                "sigma",
                "time_parity",
                "space_parity",
                "why",
            ],
            rows,
        ))
    }
}
