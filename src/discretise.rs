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
/// Lagrangian before Rayleigh.
pub fn plan(model: &Model, order: u32) -> Result<Vec<Planned>, DiscretiseError> {
    let mut out = Vec::new();
    for density in Density::ALL {
        let a = analyse(model, density, order)?;
        for f in &a.fields {
            for t in &f.survivors {
                match term_shape(density, t) {
                    TermShape::Stencil(k) => out.push(Planned {
                        field: f.field.id.clone(),
                        density,
                        term: t.clone(),
                        boundary: f.field.boundary,
                        k,
                    }),
                    TermShape::Mass => {}
                    TermShape::Unsupported => {
                        return Err(DiscretiseError::Unsupported {
                            field: f.field.id.clone(),
                            density: density.key().into(),
                            term: t.to_string(),
                        })
                    }
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
