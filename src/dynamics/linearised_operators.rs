//! `operators` of a nonlinear body: the operators of its linearisation. About each field's
//! equilibrium u* (∇V(u*) = 0, as for `modes`), the stiffness K = ∇²V(u*) and the damping
//! C = ∇²R(0) are the matrices the linear equations M ü = −K(u − u*) − C u̇ act with, in units of
//! the point spacing: for a square ½c(∂sᵏφ)² they are c times the linear operator D. With
//! kinetic terms beyond ½(∂tφ)² the mass M = ∇²T(0) multiplies ü (the identity otherwise).

use super::nonlinear::{FieldSystem, NonlinearBody, NonlinearError};

/// One field's linearised operators.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LinearisedOperator {
    /// Field id.
    pub field: String,
    /// Boundary name.
    pub boundary: String,
    /// u* at each point (zero where held; around a ring at each unknown).
    pub equilibrium: Vec<f64>,
    /// |∇V(u*)| reached.
    pub residual: f64,
    /// Number of unknowns (the matrices' size).
    pub size: usize,
    /// K = ∇²V(u*).
    pub stiffness: Vec<Vec<f64>>,
    /// C = ∇²R(0).
    pub damping: Vec<Vec<f64>>,
    /// M = ∇²T(0), the mass (the identity with the standard kinetic term alone).
    pub mass: Vec<Vec<f64>>,
    /// With active forces f: A = ∂f/∂u(u*, 0) and B = ∂f/∂v(u*, 0), not symmetric, entering
    /// M ü = −K(u − u*) − C u̇ + A(u − u*) + B u̇.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub active: Option<[Vec<Vec<f64>>; 2]>,
}

impl FieldSystem {
    /// The linearised operators about the equilibrium.
    pub fn linearised_operator(&self) -> Result<LinearisedOperator, NonlinearError> {
        let (equilibrium, residual) = self.equilibrium()?;
        let rows = |m: nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
            m.row_iter().map(|r| r.iter().copied().collect()).collect()
        };
        let zero = vec![0.0; self.unknowns];
        let active = (!self.active.is_empty()).then(|| {
            let n = self.unknowns;
            let (mut du, mut dv) = (
                nalgebra::DMatrix::zeros(n, n),
                nalgebra::DMatrix::zeros(n, n),
            );
            for a in &self.active {
                a.jacobians((&equilibrium, &zero), &mut du, &mut dv);
            }
            [rows(du), rows(dv)]
        });
        Ok(LinearisedOperator {
            active,
            field: self.id.clone(),
            boundary: self.boundary.name(),
            equilibrium: self.embed(&equilibrium),
            residual,
            size: self.unknowns,
            stiffness: rows(self.hessian_at(&equilibrium)?),
            damping: rows(self.finite(self.damping_at(&zero), "the damping ∇²R(0)")?),
            mass: rows(self.finite(self.mass(&zero), "the mass ∇²T(0)")?),
        })
    }
}

impl NonlinearBody {
    /// Every field's linearised operators.
    pub fn linearised_operators(&self) -> Result<Vec<LinearisedOperator>, NonlinearError> {
        self.fields
            .iter()
            .map(|f| f.linearised_operator())
            .collect()
    }
}

/// `operators` of a nonlinear body.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LinearisedOperatorsReport {
    /// Model name.
    pub model: String,
    /// Order of the theory.
    pub order: u32,
    /// Points along the body.
    pub points: usize,
    /// Always true: these are the operators of a linearisation.
    pub linearised: bool,
    /// The fields.
    pub fields: Vec<LinearisedOperator>,
}

/// A matrix as aligned text, one row per line.
fn matrix_text(m: &[Vec<f64>]) -> String {
    let cells: Vec<Vec<String>> = m
        .iter()
        .map(|r| r.iter().map(|x| crate::report::number(*x)).collect())
        .collect();
    let width = cells
        .iter()
        .flatten()
        .map(|c| c.chars().count())
        .max()
        .unwrap_or(1);
    cells
        .iter()
        .map(|r| {
            let row: Vec<String> = r.iter().map(|c| format!("{c:>width$}")).collect();
            format!("  {}\n", row.join(" "))
        })
        .collect()
}

impl crate::report::Report for LinearisedOperatorsReport {
    fn text(&self) -> String {
        use std::fmt::Write as _;
        let why = match self.fields.iter().any(|f| f.active.is_some()) {
            true => "active forces are switched on, so these are K = ∇²V(u*), C = ∇²R(0) and the active forces' A = ∂f/∂u, B = ∂f/∂v",
            false => "the equations are nonlinear, so these are K = ∇²V(u*) and C = ∇²R(0)",
        };
        let mut s = format!(
            "Linearised operators of the {} model at order {} on N = {} points: {why} about each field's equilibrium u*, in units of the point spacing (M ü = −K(u − u*) − C u̇, M = I unless printed).\n",
            self.model, self.order, self.points
        );
        for f in &self.fields {
            let at = if f.equilibrium.iter().all(|&x| x == 0.0) {
                "at rest (u* = 0)".to_string()
            } else {
                let cells: Vec<String> = f
                    .equilibrium
                    .iter()
                    .map(|x| crate::report::number(*x))
                    .collect();
                format!("u* = [{}] (|∇V| = {:.1e})", cells.join(", "), f.residual)
            };
            let n = f.size;
            let _ = writeln!(
                s,
                "\n{} · {} boundary · equilibrium {at}",
                f.field, f.boundary
            );
            let _ = write!(
                s,
                "{} · stiffness K = ∇²V(u*) · {n}×{n}\n{}",
                f.field,
                matrix_text(&f.stiffness)
            );
            let _ = write!(
                s,
                "{} · damping C = ∇²R(0) · {n}×{n}\n{}",
                f.field,
                matrix_text(&f.damping)
            );
            let identity = f.mass.iter().enumerate().all(|(i, r)| {
                r.iter()
                    .enumerate()
                    .all(|(j, &x)| x == if i == j { 1.0 } else { 0.0 })
            });
            if !identity {
                let _ = write!(
                    s,
                    "{} · mass M = ∇²T(0) · {n}×{n}\n{}",
                    f.field,
                    matrix_text(&f.mass)
                );
            }
            if let Some([a, b]) = &f.active {
                let _ = write!(
                    s,
                    "{0} · active A = ∂f/∂u (M ü = … + A(u − u*) + B u̇; not symmetric) · {n}×{n}\n{1}{0} · active B = ∂f/∂v · {n}×{n}\n{2}",
                    f.field,
                    matrix_text(a),
                    matrix_text(b)
                );
            }
        }
        s
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    /// The non-zero entries, one row each.
    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["field", "matrix", "row", "column", "value"],
            self.fields.iter().flat_map(|f| {
                [
                    ("stiffness", &f.stiffness),
                    ("damping", &f.damping),
                    ("mass", &f.mass),
                ]
                .into_iter()
                .chain(
                    f.active
                        .iter()
                        .flat_map(|[a, b]| [("active_u", a), ("active_v", b)]),
                )
                .flat_map(move |(name, m)| {
                    m.iter().enumerate().flat_map(move |(i, row)| {
                        row.iter()
                            .enumerate()
                            .filter(|(_, x)| **x != 0.0)
                            .map(move |(j, x)| {
                                vec![
                                    f.field.clone(),
                                    name.to_string(),
                                    i.to_string(),
                                    j.to_string(),
                                    crate::report::number(*x),
                                ]
                            })
                    })
                })
            }),
        ))
    }

    fn check(&self) -> Result<(), crate::report::NonFinite> {
        crate::report::check_finite(self)
    }
}
