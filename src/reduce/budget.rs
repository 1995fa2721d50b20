//! The work an analysis may do, checked before it starts: orders in range, candidates and
//! products within the budgets of docs/budgets.md.

use crate::enumerate::{count_products, Basis, Bounds, MAX_CANDIDATES, MAX_ORDER};
use crate::model::{Density, Model};

/// An order the engine will not analyse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OrderError {
    /// Outside `1..=MAX_ORDER`.
    #[error("order {0} is out of range: use an order from 1 to {MAX_ORDER}")]
    OutOfRange(u32),
    /// The basis has too many candidates at this order.
    #[error("order {order} has {count} candidate {what}, more than the {limit} the tool enumerates: use a lower order{advice}")]
    TooManyCandidates {
        /// What the candidates are (`monomials`, `products of 2 fields`).
        what: String,
        /// More advice, where the command has another way (`or --basis powers`).
        advice: &'static str,
        /// The order asked for.
        order: u32,
        /// How many candidates it has.
        count: u128,
        /// The limit.
        limit: u128,
    },
    /// The interaction tables would decide too many products in all.
    #[error("the {density} interaction tables at order {order} decide {count} candidate products over every set of fields, more than the {limit} budget (about ten seconds): use a lower order or one --density")]
    TooManyInteractions {
        /// Which density.
        density: String,
        /// The order asked for.
        order: u32,
        /// How many products in all.
        count: u128,
        /// The budget.
        limit: u128,
    },
}

/// Refuse, from counts alone and before any term is built, an analysis of `densities` at
/// `order` that is out of range or over the candidate limit: a command analysing both densities
/// checks both first, so it never decides one only to refuse the other.
pub fn check_work(
    model: &Model,
    densities: &[Density],
    order: u32,
    basis: Basis,
) -> Result<(), OrderError> {
    check_work_within(model, densities, order, basis, MAX_CANDIDATES)
}

/// [`check_work`] with another candidate limit (a streamed table's, [`MAX_STREAMED`]).
pub fn check_work_within(
    model: &Model,
    densities: &[Density],
    order: u32,
    basis: Basis,
    limit: u128,
) -> Result<(), OrderError> {
    if order == 0 || order > MAX_ORDER {
        return Err(OrderError::OutOfRange(order));
    }
    if basis == Basis::Monomials {
        for &d in densities {
            let bounds = Bounds::for_order(model.density(d).bound, order);
            check_candidates_within(order, &bounds, 1, limit)?;
        }
    }
    Ok(())
}

/// Refuse an enumeration of more than [`MAX_CANDIDATES`] products of `fields` fields.
pub fn check_candidates(order: u32, bounds: &Bounds, fields: u32) -> Result<(), OrderError> {
    check_candidates_within(order, bounds, fields, MAX_CANDIDATES)
}

fn check_candidates_within(
    order: u32,
    bounds: &Bounds,
    fields: u32,
    limit: u128,
) -> Result<(), OrderError> {
    let count = count_products(bounds, fields);
    if count > limit {
        return Err(OrderError::TooManyCandidates {
            what: if fields == 1 {
                "monomials".into()
            } else {
                format!("products of {fields} fields")
            },
            // One field's densities have the powers basis; products of fields do not.
            advice: if fields == 1 {
                " or --basis powers"
            } else {
                ""
            },
            order,
            count,
            limit,
        });
    }
    Ok(())
}
