//! Continuum equations of motion derived from the surviving densities.
//!
//! For each field, with `v = ∂tφ`, the dissipative Euler–Lagrange equation is
//!
//! ```text
//! δL/δφ = δR/δv,      δF/δu = Σ_α (−1)^|α| ∂^α ∂F/∂(∂^α u)
//! ```
//!
//! (integration by parts, boundary terms dropped). For a quadratic term `C·∂^αφ·∂^βφ` the
//! variational derivative is `C[(−1)^|α| + (−1)^|β|] ∂^{α+β}φ`; R enters through the velocity
//! jet at fixed time, so a Rayleigh factor `∂t∂sᵏφ` is `∂sᵏv`, varied in s alone, and a factor
//! with more time derivatives does not vary (as on the general path, [`derive_nonlinear`]). The standard kinetic term `½(∂tφ)²` gives `−∂t²φ`; solving for it
//! gives `∂t²φ = Σ sign·prefactor·coefficient·∂tᵗ∂sˢφ`, exact. For the larva:
//! `∂t²x = c_x ∂s²x + 2 c'_x ∂t∂s²x` and `∂t²y = −c_y ∂s⁴y − 2 c'_y ∂t∂s⁴y`.
//! Each term prints its exact rational factor, as on the general path; it is also kept in
//! [`RhsTerm::prefactor`]. Whether a parameter's sign is fixed is derived, with its
//! reason, by [`SignClaim`].

use std::collections::BTreeMap;

use num_rational::Rational64;
use num_traits::{Signed, Zero};

use crate::active::Force;
use crate::enumerate::Basis;
use crate::model::{Density, Field, Model};
use crate::reduce::{analyse_basis, Analysis, DensityTerm, OrderError};
use crate::term::{Deriv, Term};

mod nonlinear;
mod render;
pub use nonlinear::{derive_nonlinear, derive_nonlinear_each, NonlinearEquation, PolyTerm};
pub use render::{derivative_text, json, EquationReport, NonlinearReport, Shown};

/// What kind of force a right-hand-side term is: the variation of the Lagrangian
/// (`conservative`: the kinetic and potential terms, a gyroscopic term included: it does no
/// work, though odd under time reversal; an `[active]` section's gyroscopic forces `g_x` are
/// of this kind), −δR/δv of the Rayleigh density (`dissipative`), or neither (`active`: from a
/// model's `[active]` section, `crate::active`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ForceKind {
    /// From the Lagrangian.
    Conservative,
    /// From the Rayleigh density.
    Dissipative,
    /// From neither.
    Active,
}

/// One term `sign · prefactor · coefficient · ∂tᵗ∂sˢφ` of a right-hand side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RhsTerm {
    /// Derivative of the field.
    pub deriv: Deriv,
    /// +1 or −1.
    pub sign: i64,
    /// Exact positive prefactor, folded into `coefficient` when printed.
    pub prefactor: Rational64,
    /// The free parameter (`c_x`, `c'_x`).
    pub coefficient: String,
    /// What fixes the parameter's sign, if anything.
    pub claim: SignClaim,
    /// Which density the term comes from.
    pub kind: ForceKind,
}

/// Whether a parameter's sign is fixed, and by what.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "sign", content = "reason", rename_all = "kebab-case")]
pub enum SignClaim {
    /// Positive as printed, for the reason given.
    Positive(&'static str),
    /// Negative as printed would be stable: the parameter must be negative.
    Negative(&'static str),
    /// Either sign is allowed, for the reason given.
    Free(&'static str),
}

impl SignClaim {
    /// Derived from the dispersion relation of ∂t²φ = Σ: with φ ∝ e^{i(qs−ωt)}, a term
    /// c·∂sᵇφ (b even) adds (−1)^{b/2} c qᵇ to −ω², and c·∂t∂sᵇφ adds a damping rate. The lowest
    /// and highest even b of each kind dominate as q → 0 and q → ∞, so their signs are fixed:
    /// the stable sign is (−1)^{b/2+1}. Odd b is odd under s → −s and no square's variation:
    /// nothing fixes it. Other terms are bounded only jointly.
    fn of(deriv: Deriv, sign: i64, extreme: bool) -> SignClaim {
        if deriv.s % 2 == 1 {
            return SignClaim::Free("odd in ∂s, not the variation of a square: neither energy nor dissipation fixes its sign, and s → −s flips it");
        }
        let reason = match deriv.t {
            0 if extreme => "the energy must be bounded below, ω² > 0 as q → 0 and as q → ∞",
            1 if extreme => "dissipation cannot be negative, by the second law",
            0 | 1 => {
                return SignClaim::Free(
                    "stability bounds it only together with the other terms of its kind",
                )
            }
            _ => return SignClaim::Free("no energy or dissipation argument here fixes it"),
        };
        let stable = if (deriv.s / 2) % 2 == 0 { -1 } else { 1 };
        if sign == stable {
            SignClaim::Positive(reason)
        } else {
            SignClaim::Negative(reason)
        }
    }

    /// `c_x > 0 (reason)`.
    pub fn describe(&self, coefficient: &str) -> String {
        match self {
            SignClaim::Positive(r) => format!("{coefficient} > 0: {r}"),
            SignClaim::Negative(r) => format!("{coefficient} < 0: {r}"),
            SignClaim::Free(r) => format!("{coefficient} of either sign: {r}"),
        }
    }
}

/// `∂t²φ = Σ rhs` for one field.
#[derive(Debug, Clone)]
pub struct Equation {
    /// The field.
    pub field: Field,
    /// Right-hand side, by ascending time then space derivative.
    pub rhs: Vec<RhsTerm>,
    /// The `[active]` section's terms on the right that are not forces (a section without OST).
    pub not_forces: Vec<NotAForce>,
}

/// An `[active]` term on the right-hand side that is inertia, not a force
/// ([`crate::active::NOT_A_FORCE`]): no command integrates, linearises or emits it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct NotAForce {
    /// Its coefficient (`a2_x`).
    pub coefficient: String,
    /// The term (`∂ttt x`).
    pub term: String,
}

/// The entering forces of one field that are inertia ([`crate::active::Force::is_inertia`]).
pub fn not_forces(forces: &[Force]) -> Vec<NotAForce> {
    forces
        .iter()
        .filter(|f| f.is_inertia())
        .filter_map(|f| {
            Some(NotAForce {
                coefficient: f.coefficient.clone()?,
                term: f.term.clone(),
            })
        })
        .collect()
}

/// Why the equations cannot be written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EquationError {
    /// The order is out of range.
    #[error(transparent)]
    Order(#[from] OrderError),
    /// No standard kinetic term survives, so there is no `∂t²φ` to solve for.
    #[error("field {field}: no kinetic term (∂t {field})² survives at order {order}, so there is no ∂t²{field} to solve for")]
    NoKinetic {
        /// Field id.
        field: String,
        /// The order asked for.
        order: u32,
    },
    /// A surviving term is not quadratic: its equation would not be linear.
    #[error("field {field}: surviving term {term} is not quadratic; only linear equations of motion are derived")]
    NotQuadratic {
        /// Field id.
        field: String,
        /// The term.
        term: String,
    },
    /// The `[active]` section's forces cannot be enumerated at this order.
    #[error(transparent)]
    Active(#[from] crate::active::ActiveError),
}

/// A linear right-hand side `Σ value·parameter·∂^D φ`, keyed by (derivative, parameter): the
/// quadratic case of a [`crate::parts::JetPoly`] equation, where every monomial is one derivative.
pub type Linear = BTreeMap<(Deriv, Option<String>), Rational64>;

fn add(into: &mut Linear, deriv: Deriv, param: &Option<String>, value: Rational64) {
    let e = into
        .entry((deriv, param.clone()))
        .or_insert_with(Rational64::zero);
    *e += value;
    if e.is_zero() {
        into.remove(&(deriv, param.clone()));
    }
}

fn parity(d: Deriv) -> Rational64 {
    Rational64::from_integer(if d.order() % 2 == 0 { 1 } else { -1 })
}

/// The two derivatives of a quadratic single-field term (equal for a square), or `None`.
pub fn quadratic_parts(term: &Term) -> Option<(Deriv, Deriv)> {
    match term.factors() {
        [f] if f.power == 2 => Some((f.deriv, f.deriv)),
        [f, g] if f.power == 1 && g.power == 1 && f.field == g.field => Some((f.deriv, g.deriv)),
        _ => None,
    }
}

fn plus(a: Deriv, b: Deriv) -> Deriv {
    Deriv::new(a.t + b.t, a.s + b.s)
}

/// δL/δφ of `C·term` (Lagrangian) or δR/δv of it (Rayleigh), added to `into`.
/// `C = sign·prefactor·parameter`.
pub fn variational_derivative(density: Density, dt: &DensityTerm, into: &mut Linear) -> bool {
    let Some((a, b)) = quadratic_parts(&dt.term) else {
        return false;
    };
    let c = dt.prefactor * Rational64::from_integer(dt.sign);
    for (x, y) in [(a, b), (b, a)] {
        match density {
            // ∂F/∂(∂^x φ) = C·∂^y φ; then (−1)^|x| ∂^x of it.
            Density::Lagrangian => add(into, plus(x, y), &dt.parameter, c * parity(x)),
            // R enters through the velocity jet at fixed time, as on the general path: only a
            // factor ∂t∂sᵏφ = ∂sᵏv depends on v, varied in s alone; a factor with ∂t² or more
            // is an acceleration, not a velocity, and contributes nothing.
            Density::Rayleigh if x.t == 1 => {
                let xv = Deriv::new(0, x.s);
                add(into, plus(xv, y), &dt.parameter, c * parity(xv))
            }
            Density::Rayleigh => {}
        }
    }
    true
}

/// Field `index`'s linear equation, read off the one general derivation
/// ([`nonlinear::general_rhs`]): every right-hand-side monomial must be one derivative.
fn field_equation(
    (l, r, active): (&Analysis, &Analysis, &[Force]),
    index: usize,
    order: u32,
    notes: &mut Vec<String>,
) -> Result<Equation, EquationError> {
    let field = l.fields[index].field.clone();
    // A surviving term that is not quadratic makes the equation nonlinear (the caller takes
    // the general form instead). The (derivative, parameter) pairs that come from an energy
    // square (∂sᵏφ)² of L or a dissipation square (∂t∂sᵏφ)² of R are the only ones whose
    // signs energy or the second law can fix.
    let mut squares: Vec<(Deriv, Option<String>)> = Vec::new();
    for analysis in [l, r] {
        for dt in &analysis.fields[index].density {
            let Some((a, b)) = quadratic_parts(&dt.term) else {
                return Err(EquationError::NotQuadratic {
                    field: field.id.clone(),
                    term: dt.term.render(&|_| field.symbol.clone()),
                });
            };
            let energy = analysis.density == Density::Lagrangian && a.t == 0;
            let dissipation = analysis.density == Density::Rayleigh && a.t == 1;
            if a == b && (energy || dissipation) {
                squares.push((Deriv::new(a.t, 2 * a.s), dt.parameter.clone()));
            }
        }
    }
    // A linear force no density carries (`uncarried = "enter"`) is still the variation of a
    // square: b ∂s²ᵏφ of ½b φ∂s²ᵏφ = ±½b(∂sᵏφ)², b ∂t∂s²ᵏφ of the Rayleigh ½b v∂s²ᵏv.
    for f in active {
        let (conservative, dissipative) = (
            f.kind == crate::active::ForceClass::Conservative,
            f.kind == crate::active::ForceClass::Dissipative,
        );
        if let [x] = f.shape.factors() {
            let square = (conservative && x.deriv.t == 0) || (dissipative && x.deriv.t == 1);
            if x.power == 1 && x.deriv.s % 2 == 0 && square {
                squares.push((x.deriv, f.coefficient.clone()));
            }
        }
    }
    let general = nonlinear::general_rhs(l, r, active, index, notes).ok_or_else(|| {
        EquationError::NoKinetic {
            field: field.symbol.clone(),
            order,
        }
    })?;
    let mut rhs: Vec<(RhsTerm, bool)> = Vec::with_capacity(general.len());
    for t in general {
        let deriv = match t.monomial.as_slice() {
            [(d, 1)] => *d,
            _ => {
                return Err(EquationError::NotQuadratic {
                    field: field.id.clone(),
                    term: format!("{:?}", t.monomial),
                })
            }
        };
        let parameter = (t.coefficient != "1").then(|| t.coefficient.clone());
        let square = squares.contains(&(deriv, parameter));
        rhs.push((
            RhsTerm {
                deriv,
                sign: if t.value.is_negative() { -1 } else { 1 },
                prefactor: t.value.abs(),
                coefficient: t.coefficient,
                claim: SignClaim::Free(""),
                kind: t.kind,
            },
            square,
        ));
    }
    rhs.sort_by_key(|(t, _)| (t.deriv.t, t.deriv.s));
    // The lowest and highest even space order among the terms of each time order.
    let extremes = |t: u32| {
        let even = rhs
            .iter()
            .filter(|(r, _)| r.deriv.t == t && r.deriv.s % 2 == 0)
            .map(|(r, _)| r.deriv.s);
        (even.clone().min(), even.max())
    };
    let bounds: Vec<(Option<u32>, Option<u32>)> = (0..=2).map(extremes).collect();
    for (r, square) in &mut rhs {
        let (lo, hi) = bounds
            .get(r.deriv.t as usize)
            .copied()
            .unwrap_or((None, None));
        let extreme = Some(r.deriv.s) == lo || Some(r.deriv.s) == hi;
        r.claim = if r.kind == ForceKind::Active {
            SignClaim::Free("an active force: it is neither energy nor dissipation, and its sign sets the direction it drives")
        } else if *square || r.deriv.t > 1 || r.deriv.s % 2 == 1 {
            SignClaim::of(r.deriv, r.sign, extreme)
        } else {
            SignClaim::Free("not the variation of an energy or dissipation square: nothing fixes its sign alone")
        };
    }
    let not_forces = not_forces(active);
    let rhs = rhs
        .into_iter()
        .map(|(mut r, _)| {
            if not_forces.iter().any(|n| n.coefficient == r.coefficient) {
                r.claim = SignClaim::Free("inertia, not a force (the note under its equation)");
            }
            r
        })
        .collect();
    Ok(Equation {
        field,
        rhs,
        not_forces,
    })
}

/// The equations of motion of every field of `model` at `order`, plus the analyses' notes.
pub fn derive(model: &Model, order: u32) -> Result<(Vec<Equation>, Vec<String>), EquationError> {
    derive_basis(model, order, Basis::Powers)
}

/// The equations of motion when the candidates are `basis` (an error if any field has none).
pub fn derive_basis(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<(Vec<Equation>, Vec<String>), EquationError> {
    derive_each(model, order, basis)?.complete()
}

/// What a derivation gives: the equations of the fields that have one, and why each other
/// field has none (a field without a kinetic term does not block the others).
#[derive(Debug, Clone)]
pub struct Derivation<E> {
    /// The equations, in model field order.
    pub equations: Vec<E>,
    /// Why each field without an equation has none.
    pub underived: Vec<EquationError>,
    /// The analyses' notes.
    pub notes: Vec<String>,
}

impl<E> Derivation<E> {
    /// The equations and notes when every field has an equation; the first reason otherwise.
    pub fn complete(self) -> Result<(Vec<E>, Vec<String>), EquationError> {
        match self.underived.into_iter().next() {
            Some(e) => Err(e),
            None => Ok((self.equations, self.notes)),
        }
    }
}

/// The equations of a model at an order, as `equations` gives them: the linear ones when every
/// survivor is quadratic, else the exact nonlinear ones. The one place that choice is made: the
/// command line and Python both ask it.
#[derive(Debug, Clone)]
pub enum Derived {
    /// Every survivor quadratic: ∂t²φ = Σ ± c ∂tᵃ∂sᵇφ.
    Linear(Derivation<Equation>),
    /// Not all quadratic: the exact Euler–Lagrange equations.
    Nonlinear(Derivation<NonlinearEquation>),
}

/// [`Derived`] for `model` at `order` over `basis`.
pub fn derive_any(model: &Model, order: u32, basis: Basis) -> Result<Derived, EquationError> {
    match derive_each(model, order, basis) {
        Err(EquationError::NotQuadratic { .. }) => {
            derive_nonlinear_each(model, order, basis).map(Derived::Nonlinear)
        }
        other => other.map(Derived::Linear),
    }
}

/// Every field's linear equation that can be derived; an error only when the surviving terms
/// are not all quadratic ([`EquationError::NotQuadratic`]: use [`derive_nonlinear_each`]) or
/// the order is out of range.
pub fn derive_each(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<Derivation<Equation>, EquationError> {
    let (l, r, active, notes) = analyses(model, order, basis)?;
    let mut d = Derivation {
        equations: Vec::new(),
        underived: Vec::new(),
        notes,
    };
    for i in 0..model.fields.len() {
        let forces = active.get(i).map_or(&[][..], |f| &f[..]);
        match field_equation((&l, &r, forces), i, order, &mut d.notes) {
            Ok(e) => d.equations.push(e),
            Err(e @ EquationError::NoKinetic { .. }) => d.underived.push(e),
            Err(e) => return Err(e),
        }
    }
    Ok(d)
}

/// One field's linear equation, with its sign claims, when that field's terms are quadratic
/// (another field's nonlinear terms do not stop it, as they stop [`derive_each`]); `None` for a
/// field the model lacks.
pub fn derive_field(
    model: &Model,
    order: u32,
    basis: Basis,
    id: &str,
) -> Result<Option<Equation>, EquationError> {
    let Some(index) = model.fields.iter().position(|f| f.id == id) else {
        return Ok(None);
    };
    let (l, r, active, mut notes) = analyses(model, order, basis)?;
    let forces = active.get(index).map_or(&[][..], |f| &f[..]);
    field_equation((&l, &r, forces), index, order, &mut notes).map(Some)
}

/// Both densities' analyses, each field's lowest-order active and gyroscopic forces (none
/// without an `[active]` section) and what the analyses say is missing.
type Analyses = (Analysis, Analysis, Vec<Vec<Force>>, Vec<String>);

fn analyses(model: &Model, order: u32, basis: Basis) -> Result<Analyses, EquationError> {
    crate::reduce::check_work(
        model,
        &[Density::Lagrangian, Density::Rayleigh],
        order,
        basis,
    )?;
    let l = analyse_basis(model, Density::Lagrangian, order, basis)?;
    let r = analyse_basis(model, Density::Rayleigh, order, basis)?;
    let notes = l
        .fields
        .iter()
        .chain(&r.fields)
        .flat_map(|f| f.missing.clone())
        .collect();
    let active = crate::active::active_forces(model, order)?
        .map(|fields| {
            fields
                .into_iter()
                .map(|f| f.entering().map(|(x, _)| x.clone()).collect())
                .collect()
        })
        .unwrap_or_default();
    Ok((l, r, active, notes))
}
