//! Difference operators from the surviving quadratic terms.
//!
//! A surviving term `(∂sᵏφ)²` (Lagrangian) or `(∂t∂sᵏφ)²` (Rayleigh, on the velocity) becomes the
//! quadratic form `Σ_p (Δᵏφ)_p²` of the k-th forward difference `Δᵏ` (weights
//! `(−1)^{k−j} C(k, j)`, j = 0…k) over the stencil positions `p` the boundary allows, so the
//! operator is `D = Σ_p w_pᵀ w_p`: symmetric, positive semi-definite, exact integers.
//!
//! * periodic: `N−1` unknowns (head and tail are one point), every position, indices mod `N−1`;
//!   needs `N−1 ≥ k+1`.
//! * otherwise each end on its own, and only stencils inside the body (`p = 0…N−1−k`). A free
//!   end holds nothing: its natural conditions (no force, no moment) come out of the variation.
//!   A pinned end holds the value (the end point is zero and not an unknown); a clamped end
//!   holds value and slope (the end point and its neighbour), or the value alone when k = 1.
//!   The held points are the ghost-point rule: they enter the stencils as zeros.
//!   The null space is the polynomials of degree < k that vanish on the held points: k − (held)
//!   of them when positive (free–free beam: translation and rotation; pinned–free: rotation
//!   about the pin; cantilever: none).
//!
//! For the larva: `D2,c` (x, periodic, k = 1), `D2,f` (θ, free, k = 1), `D4` (y, z, free, k = 2),
//! equal to the paper's Eq. 3–5.

use serde::Serialize;

use crate::model::{Boundary, Density, Model};
use crate::reduce::{analyse, OrderError};
use crate::term::Term;

/// Why an operator cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DiscretiseError {
    /// The order is out of range.
    #[error(transparent)]
    Order(#[from] OrderError),
    /// Too few points for the stencil.
    #[error(
        "{points} points are too few for a {boundary} stencil of order {k}: need at least {min}"
    )]
    TooFewPoints {
        /// Points asked for.
        points: usize,
        /// The stencil order.
        k: u32,
        /// Boundary condition name.
        boundary: String,
        /// The least number of points that works.
        min: usize,
    },
    /// A surviving term the force discretisation does not take (see [`force_plan`]).
    #[error("field {field}: {term} in the {density} density: {why}")]
    NotAForce {
        /// Field symbol.
        field: String,
        /// The term.
        term: String,
        /// Density name.
        density: &'static str,
        /// Why.
        why: String,
    },
    /// A surviving term that is not a square of one derivative.
    #[error("field {field}: cannot discretise {term} in the {density} density: only squares (∂sᵏφ)² (or (∂t∂sᵏφ)² for R) become operators")]
    Unsupported {
        /// Field id.
        field: String,
        /// Density name.
        density: String,
        /// The term.
        term: String,
    },
}

/// `Δᵏ`: the k-th forward difference weights, `(−1)^{k−j} C(k, j)`.
pub fn stencil(k: u32) -> Vec<i64> {
    let mut w = vec![1i64];
    for _ in 0..k {
        // Multiply by (E − 1): shift minus identity.
        let mut next = vec![0i64; w.len() + 1];
        for (j, &c) in w.iter().enumerate() {
            next[j + 1] += c;
            next[j] -= c;
        }
        w = next;
    }
    w
}

/// The paper's name for an operator of stencil order `k` with this boundary, if it has one.
pub fn seed_name(k: u32, boundary: Boundary) -> Option<&'static str> {
    match (k, boundary) {
        (1, Boundary::Periodic) => Some("D2,c, paper Eq. 3"),
        (1, Boundary::FREE) => Some("D2,f, paper Eq. 4"),
        (2, Boundary::FREE) => Some("D4, paper Eq. 5"),
        _ => None,
    }
}

/// For each stencil position, the (unknown index, weight) pairs it touches.
///
/// Periodic: every position around the ring of `N − 1` unknowns. Otherwise the positions whose
/// stencil lies inside the body (`p = 0…N−1−k`, covering points `p…p+k`): a free end adds no
/// condition (the natural one comes out of the variation), and a held end's points are zero,
/// so they drop out of the rows and are not unknowns.
pub fn stencil_rows(
    k: u32,
    boundary: Boundary,
    points: usize,
) -> Result<Vec<Vec<(usize, i64)>>, DiscretiseError> {
    if points < boundary.min_points(k) {
        return Err(DiscretiseError::TooFewPoints {
            points,
            k,
            boundary: boundary.name(),
            min: boundary.min_points(k),
        });
    }
    let w = stencil(k);
    let n = boundary.unknowns(k, points);
    let rows = match boundary {
        Boundary::Periodic => (0..n)
            .map(|p| {
                w.iter()
                    .enumerate()
                    .map(|(j, &c)| ((p + j) % n, c))
                    .collect()
            })
            .collect(),
        Boundary::Ends { .. } => {
            let (tail, _) = boundary.held(k);
            (0..points - k as usize)
                .map(|p| {
                    w.iter()
                        .enumerate()
                        .filter_map(|(j, &c)| {
                            (p + j).checked_sub(tail).filter(|&i| i < n).map(|i| (i, c))
                        })
                        .collect::<Vec<_>>()
                })
                .filter(|row| !row.is_empty())
                .collect()
        }
    };
    Ok(rows)
}

/// The exact operator `Σ_p w_pᵀ w_p` as a dense integer matrix.
pub fn operator_matrix(
    k: u32,
    boundary: Boundary,
    points: usize,
) -> Result<Vec<Vec<i64>>, DiscretiseError> {
    let n = boundary.unknowns(k, points);
    let mut m = vec![vec![0i64; n]; n];
    for row in stencil_rows(k, boundary, points)? {
        for &(i, a) in &row {
            for &(j, b) in &row {
                m[i][j] += a * b;
            }
        }
    }
    Ok(m)
}

/// One derived operator of one field and density.
#[derive(Debug, Clone, Serialize)]
pub struct Operator {
    /// Field id.
    pub field: String,
    /// `lagrangian` or `rayleigh`.
    pub density: String,
    /// The surviving term it comes from, of the generic field φ.
    pub term: String,
    /// Boundary condition.
    pub boundary: String,
    /// Stencil order k (space derivatives).
    pub k: u32,
    /// The paper's name for the operator, if it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed_name: Option<&'static str>,
    /// Number of unknowns.
    pub size: usize,
    /// The exact matrix.
    pub matrix: Vec<Vec<i64>>,
}

/// What a surviving term becomes on the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermShape {
    /// The standard kinetic term: the identity mass matrix, no operator.
    Mass,
    /// `(∂sᵏφ)²` in L or `(∂t∂sᵏφ)²` in R: the operator of stencil order k.
    Stencil(u32),
    /// Anything else.
    Unsupported,
}

/// The grid shape of a surviving term of `density`.
pub fn term_shape(density: Density, term: &Term) -> TermShape {
    match (density, term.factors()) {
        (Density::Lagrangian, _) if *term == Term::power(1, 0, 2) => TermShape::Mass,
        (Density::Lagrangian, [f]) if f.power == 2 && f.deriv.t == 0 => {
            TermShape::Stencil(f.deriv.s)
        }
        (Density::Rayleigh, [f]) if f.power == 2 && f.deriv.t == 1 => TermShape::Stencil(f.deriv.s),
        _ => TermShape::Unsupported,
    }
}

/// One operator to build: which field, density and term, with its boundary and stencil order.
#[derive(Debug, Clone)]
pub struct Planned {
    /// Field id.
    pub field: String,
    /// Density.
    pub density: Density,
    /// The surviving term, of the generic field φ.
    pub term: Term,
    /// Boundary condition of the field.
    pub boundary: Boundary,
    /// Stencil order.
    pub k: u32,
}

/// The operators the surviving terms of `model` at `order` give, in model field order,
/// Lagrangian before Rayleigh; refused when a term is not a square (a nonlinear body).
pub fn plan(model: &Model, order: u32) -> Result<Vec<Planned>, DiscretiseError> {
    for density in Density::ALL {
        let a = analyse(model, density, order)?;
        for f in &a.fields {
            if let Some(t) = f
                .survivors
                .iter()
                .find(|t| term_shape(density, t) == TermShape::Unsupported)
            {
                return Err(DiscretiseError::Unsupported {
                    field: f.field.id.clone(),
                    density: density.key().into(),
                    term: t.to_string(),
                });
            }
        }
    }
    plan_squares(model, order)
}

/// The operators of the squares among the surviving terms of `model` at `order` (the other
/// terms are forces: [`force_plan`]), in the order of [`plan`].
pub fn plan_squares(model: &Model, order: u32) -> Result<Vec<Planned>, DiscretiseError> {
    let mut out = Vec::new();
    for density in Density::ALL {
        let a = analyse(model, density, order)?;
        for f in &a.fields {
            for t in &f.survivors {
                if let TermShape::Stencil(k) = term_shape(density, t) {
                    out.push(Planned {
                        field: f.field.id.clone(),
                        density,
                        term: t.clone(),
                        boundary: f.field.boundary,
                        k,
                    });
                }
            }
        }
    }
    let rank = |id: &str| model.fields.iter().position(|f| f.id == id);
    out.sort_by_key(|p| (rank(&p.field), p.density));
    Ok(out)
}

/// Every operator of `model` at `order` on `points` points.
pub fn operators(
    model: &Model,
    order: u32,
    points: usize,
) -> Result<Vec<Operator>, DiscretiseError> {
    plan(model, order)?
        .into_iter()
        .map(
            |Planned {
                 field,
                 density,
                 term,
                 boundary,
                 k,
             }| {
                let matrix = operator_matrix(k, boundary, points)?;
                Ok(Operator {
                    field,
                    density: density.key().into(),
                    term: term.to_string(),
                    boundary: boundary.name(),
                    k,
                    seed_name: seed_name(k, boundary),
                    size: matrix.len(),
                    matrix,
                })
            },
        )
        .collect()
}

/// The JSON document of `operators`, serialized straight from the operators.
#[derive(Debug, Serialize)]
pub struct OperatorsJson<'a> {
    /// Points along the body.
    pub points: usize,
    /// The order.
    pub order: u32,
    /// The operators.
    pub operators: &'a [Operator],
}

/// `operators`: every operator of a model at an order on N points.
pub struct OperatorReport<'a> {
    /// The model (for symbols).
    pub model: &'a Model,
    /// The order.
    pub order: u32,
    /// Points along the body.
    pub points: usize,
    /// The operators.
    pub operators: Vec<Operator>,
}

impl crate::report::Report for OperatorReport<'_> {
    /// The non-zero entries, one row each.
    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &[
                "field", "density", "term", "boundary", "k", "row", "column", "value",
            ],
            self.operators.iter().flat_map(|op| {
                op.matrix.iter().enumerate().flat_map(move |(i, row)| {
                    row.iter()
                        .enumerate()
                        .filter(|(_, v)| **v != 0)
                        .map(move |(j, v)| {
                            vec![
                                op.field.clone(),
                                op.density.clone(),
                                op.term.clone(),
                                op.boundary.clone(),
                                op.k.to_string(),
                                i.to_string(),
                                j.to_string(),
                                v.to_string(),
                            ]
                        })
                })
            }),
        ))
    }

    fn text(&self) -> String {
        let mut out = format!(
            "Difference operators of the {} model on N = {} points:\n",
            self.model.name, self.points
        );
        for op in &self.operators {
            let symbol = self.model.symbol(&op.field);
            let term = op
                .term
                .parse::<Term>()
                .map(|t| t.render(&|_| symbol.clone()))
                .unwrap_or_else(|_| op.term.clone());
            out += &format!(
                "\n{} · {} · {term} · {} boundary · {}×{} · D = Σ (Δ{}{symbol})²{}\n",
                op.field,
                op.density,
                op.boundary,
                op.size,
                op.size,
                crate::term::superscript(op.k),
                op.seed_name.map(|n| format!(" = {n}")).unwrap_or_default(),
            );
            let width = op
                .matrix
                .iter()
                .flatten()
                .map(|v| v.to_string().len())
                .max()
                .unwrap_or(1);
            for row in &op.matrix {
                let cells: Vec<String> = row.iter().map(|v| format!("{v:>width$}")).collect();
                out += &format!("  {}\n", cells.join(" "));
            }
        }
        out
    }

    fn json(&self) -> serde_json::Value {
        crate::report::to_json(&OperatorsJson {
            points: self.points,
            order: self.order,
            operators: &self.operators,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stencils_are_binomial() {
        assert_eq!(stencil(1), [-1, 1]);
        assert_eq!(stencil(2), [1, -2, 1]);
        assert_eq!(stencil(3), [-1, 3, -3, 1]);
    }

    #[test]
    fn too_few_points_is_an_error() {
        assert!(operator_matrix(2, Boundary::FREE, 2).is_err());
        assert!(operator_matrix(1, Boundary::Periodic, 2).is_err());
        assert_eq!(
            operator_matrix(1, Boundary::FREE, 2).unwrap(),
            [[1, -1], [-1, 1]]
        );
    }
}

/// The highest power of a force term: the integrator's quadrature is exact to degree 7.
pub const MAX_FORCE_POWER: u32 = 8;

/// One surviving term as a force: `Σ_r a·(Δᵇφ)_rⁿ` over the stencil rows, in the potential V = −L
/// (terms without ∂t), the kinetic energy T (the Lagrangian's terms in the velocity ∂tφ) or in R
/// (the Rayleigh terms, in the velocity), with `a = factor × coefficient`.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceTerm {
    /// Lagrangian (then in V, or in T for a term in the velocity) or Rayleigh.
    pub density: Density,
    /// A Lagrangian term in the velocity (∂t∂sᵇφ)ⁿ: part of the kinetic energy T, beside ½(∂tφ)².
    pub kinetic: bool,
    /// Space derivatives b (the stencil order; 0 the value itself).
    pub b: u32,
    /// The power n.
    pub power: u32,
    /// The exact factor of V (−prefactor·sign for L) or R (prefactor·sign), as a float.
    pub factor: f64,
    /// The coefficient's name, or `None` for a fixed term (coefficient 1).
    pub parameter: Option<String>,
    /// The term as printed, in the field's symbol.
    pub text: String,
}

/// One field's force plan.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldForces {
    /// The model's field (id, symbol, meaning, boundary).
    pub field: crate::model::Field,
    /// Whether the standard kinetic term ½(∂tφ)² survives (without it the field does not move).
    pub kinetic: bool,
    /// Points held at the (tail, head): what the field's highest stencil holds, for every term.
    pub held: (usize, usize),
    /// The highest stencil order among its terms.
    pub top: u32,
    /// The terms other than the kinetic one.
    pub terms: Vec<ForceTerm>,
}

impl FieldForces {
    /// Unknowns on `points` points: N − 1 around a ring, the points not held otherwise.
    pub fn unknowns(&self, points: usize) -> usize {
        match self.field.boundary {
            Boundary::Periodic => points.saturating_sub(1),
            Boundary::Ends { .. } => points.saturating_sub(self.held.0 + self.held.1),
        }
    }

    /// The least number of points this field takes.
    pub fn min_points(&self) -> usize {
        self.field.boundary.min_points(self.top)
    }
}

/// Every surviving term of `model` at `order` as a force, per field in model order: a power of
/// one derivative, (∂sᵇφ)ⁿ or (∂t∂sᵇφ)ⁿ in L, (∂t∂sᵇφ)ⁿ in R, beside the standard kinetic term
/// ½(∂tφ)². The
/// discretisation is the variational one of the operators (a square gives back c·D); others
/// (products of several factors, ∂t twice, powers above [`MAX_FORCE_POWER`]) are
/// refused in one line.
pub fn force_plan(model: &Model, order: u32) -> Result<Vec<FieldForces>, DiscretiseError> {
    use num_traits::ToPrimitive;
    let l = analyse(model, Density::Lagrangian, order)?;
    let r = analyse(model, Density::Rayleigh, order)?;
    let mut out = Vec::new();
    for (lf, rf) in l.fields.iter().zip(&r.fields) {
        let field = &lf.field;
        let mut plan = FieldForces {
            field: field.clone(),
            kinetic: false,
            held: (0, 0),
            top: 0,
            terms: Vec::new(),
        };
        for (density, terms) in [
            (Density::Lagrangian, &lf.density),
            (Density::Rayleigh, &rf.density),
        ] {
            for dt in terms {
                let text = dt.term.render(&|_| field.symbol.clone());
                let refuse = |why: &str| DiscretiseError::NotAForce {
                    field: field.symbol.clone(),
                    term: text.clone(),
                    density: density.key(),
                    why: why.into(),
                };
                let [f] = dt.term.factors() else {
                    return Err(refuse(
                        "products of several factors are not discretised yet",
                    ));
                };
                let (a, b, n) = (f.deriv.t, f.deriv.s, f.power);
                match (density, a) {
                    (Density::Lagrangian, 1) if b == 0 && n == 2 && dt.parameter.is_none() => {
                        plan.kinetic = true;
                        continue;
                    }
                    (Density::Lagrangian, 0 | 1) | (Density::Rayleigh, 1) => {}
                    _ => return Err(refuse("a term may hold ∂t at most once")),
                }
                if n > MAX_FORCE_POWER {
                    return Err(refuse(&format!(
                        "powers above {MAX_FORCE_POWER} are not integrated"
                    )));
                }
                let exact = dt.prefactor.to_f64().unwrap_or(f64::NAN) * dt.sign as f64;
                plan.top = plan.top.max(b);
                plan.terms.push(ForceTerm {
                    density,
                    b,
                    power: n,
                    // V = −L, T = L (its terms in the velocity); R as written.
                    factor: match (density, a) {
                        (Density::Lagrangian, 0) => -exact,
                        _ => exact,
                    },
                    kinetic: density == Density::Lagrangian && a == 1,
                    parameter: dt.parameter.clone(),
                    text,
                });
            }
        }
        if field.boundary != Boundary::Periodic {
            plan.held = field.boundary.held(plan.top);
        }
        out.push(plan);
    }
    Ok(out)
}

/// The centred difference weights of ∂sᵇ at a point, offsets −r…r (the stencil of an active
/// force's factor): ∂s²ᵐ the m-fold (1, −2, 1), ∂s²ᵐ⁺¹ that convolved with (−½, 0, ½).
pub fn centred(b: u32) -> Vec<f64> {
    let even: Vec<f64> = stencil(b - b % 2).iter().map(|&w| w as f64).collect();
    if b % 2 == 0 {
        return even;
    }
    let at = |j: usize| even.get(j).copied().unwrap_or(0.0);
    (0..even.len() + 2)
        .map(|j| 0.5 * (j.checked_sub(2).map_or(0.0, at) - at(j)))
        .collect()
}

/// The rows of Δᵇ for a field with `held` points at its ends (or around a ring), as
/// (unknown, weight) entries: around a ring every position, indices mod N − 1; with ends every
/// position along the body, the held points dropped (they are zeros). b = 0 is the identity.
pub fn force_rows(
    b: u32,
    boundary: Boundary,
    points: usize,
    held: (usize, usize),
) -> Vec<Vec<(usize, f64)>> {
    let w = stencil(b);
    if boundary == Boundary::Periodic {
        let n = points.saturating_sub(1);
        return (0..n)
            .map(|p| {
                w.iter()
                    .enumerate()
                    .map(|(j, &c)| ((p + j) % n, c as f64))
                    .collect()
            })
            .collect();
    }
    let (tail, head) = held;
    (0..(points + 1).saturating_sub(w.len()))
        .map(|p| {
            w.iter()
                .enumerate()
                .filter(|&(j, _)| (tail..points.saturating_sub(head)).contains(&(p + j)))
                .map(|(j, &c)| (p + j - tail, c as f64))
                .collect::<Vec<_>>()
        })
        .filter(|r| !r.is_empty())
        .collect()
}
