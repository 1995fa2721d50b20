//! The general derivation: the exact Euler–Lagrange expression of every surviving term,
//! nonlinear ones included, with the Rayleigh density taken through the velocity jet.

use std::collections::BTreeMap;

use num_rational::Rational64;
use num_traits::Zero;

use super::{analyses, Derivation, EquationError};
use crate::enumerate::Basis;
use crate::model::{Density, Field, Model};
use crate::reduce::Analysis;
use crate::term::Deriv;

/// One term `value · coefficient · Π ∂^α φ` of a nonlinear right-hand side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PolyTerm {
    /// The product of field derivatives (sorted, with powers); empty is the constant 1.
    pub monomial: crate::parts::JetMono,
    /// Exact signed rational factor.
    pub value: Rational64,
    /// The free parameter (`c_x`), or `1`.
    pub coefficient: String,
    /// Which density it comes from (a parameter belongs to one density).
    pub kind: super::ForceKind,
}

/// `∂t²φ = Σ rhs` for one field, any polynomial density: the exact Euler–Lagrange equation.
#[derive(Debug, Clone)]
pub struct NonlinearEquation {
    /// The field.
    pub field: Field,
    /// Right-hand side, by parameter then monomial.
    pub rhs: Vec<PolyTerm>,
    /// The `[active]` section's terms on the right that are not forces (a section without OST).
    pub not_forces: Vec<super::NotAForce>,
}

/// The exact equations of motion of any surviving densities, quadratic or not:
/// ∂t²φ = E(L − ½(∂tφ)²) − δR/δv, with E the full Euler–Lagrange operator
/// ([`crate::parts::euler_lagrange`]) and δR/δv the Euler operator in s of the velocity
/// v = ∂tφ ([`crate::parts::space_euler`]). A term whose contribution vanishes (a total
/// derivative, as a linear ∂ssφ) is dropped with a note.
pub fn derive_nonlinear(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<(Vec<NonlinearEquation>, Vec<String>), EquationError> {
    derive_nonlinear_each(model, order, basis)?.complete()
}

/// [`derive_nonlinear`] for every field that has a kinetic term; each other field's reason in
/// [`Derivation::underived`].
pub fn derive_nonlinear_each(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<Derivation<NonlinearEquation>, EquationError> {
    let (l, r, active, mut notes) = analyses(model, order, basis)?;
    let mut equations = Vec::new();
    let mut underived = Vec::new();
    for (i, field) in model.fields.iter().enumerate() {
        let forces = active.get(i).map_or(&[][..], |f| &f[..]);
        match general_rhs(&l, &r, forces, i, &mut notes) {
            Some(rhs) => equations.push(NonlinearEquation {
                field: field.clone(),
                rhs,
                not_forces: super::not_forces(forces),
            }),
            None => underived.push(EquationError::NoKinetic {
                field: field.symbol.clone(),
                order,
            }),
        }
    }
    Ok(Derivation {
        equations,
        underived,
        notes,
    })
}

/// The one derivation of field `i`: ∂t²φ = E(L − ½(∂tφ)²) − δR/δv + Σ aₖ fₖ, the right-hand
/// side by parameter and monomial (exact values; the `[active]` section's active and gyroscopic
/// forces fₖ enter as written, forces per unit mass), or `None` when no kinetic term gives ∂t²φ. Notes say which terms contribute
/// nothing, and why, and which R terms hold more than the velocity.
pub(super) fn general_rhs(
    l: &Analysis,
    r: &Analysis,
    active: &[crate::active::Force],
    i: usize,
    notes: &mut Vec<String>,
) -> Option<Vec<PolyTerm>> {
    use crate::parts::{euler_lagrange, mono_of, space_euler, JetPoly};
    let field = &l.fields[i].field;
    // Σ over parameters of the E(L) − δR/δv polynomials.
    let mut total: BTreeMap<Option<String>, JetPoly> = BTreeMap::new();
    // The kinetic term (no parameter) is the Lagrangian's.
    let mut kinds: BTreeMap<Option<String>, super::ForceKind> = BTreeMap::new();
    for (analysis, sign) in [(l, 1), (r, -1)] {
        let kind = match analysis.density {
            Density::Lagrangian => super::ForceKind::Conservative,
            Density::Rayleigh => super::ForceKind::Dissipative,
        };
        for dt in &analysis.fields[i].density {
            kinds.entry(dt.parameter.clone()).or_insert(kind);
            let c = dt.prefactor * Rational64::from_integer(dt.sign * sign);
            let p: JetPoly = [(mono_of(&dt.term), c)].into_iter().collect();
            let e = match analysis.density {
                Density::Lagrangian => euler_lagrange(&p),
                Density::Rayleigh => {
                    let parts = space_euler(&p);
                    if parts.keys().any(|&a| a != 1) {
                        notes.push(format!(
                            "R_{}: {} depends on more than the velocity jet; only its dependence on ∂t{} enters",
                            field.symbol,
                            dt.term.render(&|_| field.symbol.clone()),
                            field.symbol
                        ));
                    }
                    parts.get(&1).cloned().unwrap_or_default()
                }
            };
            if e.is_empty() {
                // Say why, truly: a null Lagrangian is a total derivative; a Rayleigh term
                // may simply not depend on the velocity.
                let why = match analysis.density {
                    Density::Lagrangian => "a total derivative",
                    Density::Rayleigh => {
                        "its δR/δ(∂tφ) over the velocity jet at fixed time vanishes"
                    }
                };
                notes.push(format!(
                    "{}_{}: {} contributes nothing to the equation ({why}) and is dropped",
                    analysis.density.letter(),
                    field.symbol,
                    dt.term.render(&|_| field.symbol.clone())
                ));
            }
            let into = total.entry(dt.parameter.clone()).or_default();
            for (m, v) in e {
                let entry = into.entry(m.clone()).or_insert_with(Rational64::zero);
                *entry += v;
                if entry.is_zero() {
                    into.remove(&m);
                }
            }
        }
    }
    let acceleration: crate::parts::JetMono = vec![(Deriv::new(2, 0), 1)];
    let lead = total
        .get_mut(&None)
        .and_then(|p| p.remove(&acceleration))
        .unwrap_or_else(Rational64::zero);
    if lead.is_zero() {
        return None;
    }
    let mut rhs: Vec<PolyTerm> = total
        .into_iter()
        .flat_map(|(param, p)| {
            let kind = kinds
                .get(&param)
                .copied()
                .unwrap_or(super::ForceKind::Conservative);
            let coefficient = param.unwrap_or_else(|| "1".into());
            p.into_iter().map(move |(monomial, v)| PolyTerm {
                monomial,
                value: -v / lead,
                coefficient: coefficient.clone(),
                kind,
            })
        })
        .collect();
    // A force the densities already give enters once, with the densities' coefficient: two
    // coefficients of one force are one parameter no data can split.
    let given: Vec<(crate::parts::JetMono, String)> = rhs
        .iter()
        .map(|t| (t.monomial.clone(), t.coefficient.clone()))
        .collect();
    let active = active.iter().filter(|f| {
        let m = mono_of(&f.shape);
        let Some((_, by)) = given.iter().find(|(g, _)| *g == m) else {
            return true;
        };
        notes.push(format!(
            "{} {}: the densities already give this force ({by}), so it enters once",
            f.coefficient.as_deref().unwrap_or("1"),
            f.shape.render(&|_| field.symbol.clone()),
        ));
        false
    });
    use crate::active::ForceClass;
    rhs.extend(active.map(|f| PolyTerm {
        monomial: mono_of(&f.shape),
        value: Rational64::from_integer(1),
        coefficient: f.coefficient.clone().unwrap_or_else(|| "1".into()),
        kind: match f.kind {
            ForceClass::Gyroscopic | ForceClass::Conservative => super::ForceKind::Conservative,
            ForceClass::Dissipative => super::ForceKind::Dissipative,
            ForceClass::Active => super::ForceKind::Active,
        },
    }));
    rhs.sort_by_key(|t| {
        let degree: u32 = t.monomial.iter().map(|(_, n)| n).sum();
        (degree, t.monomial.clone(), t.coefficient.clone())
    });
    Some(rhs)
}
