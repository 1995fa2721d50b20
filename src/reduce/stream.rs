//! Tables too large to hold: every candidate decided once to find what each field admits,
//! then again as each row is written.

use super::{check_work_within, field_results, Analysis, Decider, Marks, OrderError, Row};
use crate::enumerate::{Basis, Bounds};
use crate::model::{Density, Model};
use crate::term::Term;

/// The most monomials a streamed table decides and writes (text or CSV, about ten seconds);
/// held analyses stop at [`MAX_CANDIDATES`].
pub const MAX_STREAMED: u128 = 20_000_000;

/// The single-field monomial analysis of `density` at `order` without holding its rows: every
/// candidate is decided once to find what each field admits (only those are kept), and decided
/// again by [`for_each_row`] as the table is written. For tables past [`MAX_CANDIDATES`].
pub fn analyse_streamed(
    model: &Model,
    density: Density,
    order: u32,
) -> Result<Analysis, OrderError> {
    check_work_within(model, &[density], order, Basis::Monomials, MAX_STREAMED)?;
    let bounds = Bounds::for_order(model.density(density).bound, order);
    let decider = Decider::new(model, density, &bounds);
    let mut admitted: Vec<Vec<Term>> = vec![Vec::new(); model.fields.len()];
    let mut candidates = 0;
    crate::enumerate::for_each_monomial(&bounds, &mut |term| {
        candidates += 1;
        let row = decider.row(term);
        for (i, list) in admitted.iter_mut().enumerate() {
            if row.admitted[i] {
                list.push(row.term.clone());
            }
        }
    });
    let fields = field_results(model, density, order, Basis::Monomials, admitted);
    Ok(Analysis {
        density,
        order,
        bounds,
        basis: Basis::Monomials,
        columns: decider.columns,
        rows: Vec::new(),
        candidates,
        fields,
    })
}

/// Every row of `analysis` in canonical order, to `f`: the held rows, or for a streamed analysis
/// each candidate enumerated and decided again (with its survivor marks). After an error from
/// `f` the rest are skipped.
pub fn for_each_row(
    model: &Model,
    analysis: &Analysis,
    f: &mut dyn FnMut(&Row) -> std::io::Result<()>,
) -> std::io::Result<()> {
    if analysis.rows.len() == analysis.candidates {
        return analysis.rows.iter().try_for_each(f);
    }
    let decider = Decider::new(model, analysis.density, &analysis.bounds);
    let survivors: Vec<std::collections::HashSet<&Term>> = analysis
        .fields
        .iter()
        .map(|f| f.survivors.iter().collect())
        .collect();
    let mut result = Ok(());
    crate::enumerate::for_each_monomial(&analysis.bounds, &mut |term| {
        if result.is_ok() {
            let mut row = decider.row(term);
            // Only an admitted term can survive: most rows need no lookup.
            row.included = Marks::from_iter(
                (0..survivors.len()).map(|i| row.admitted[i] && survivors[i].contains(&row.term)),
            );
            result = f(&row);
        }
    });
    result
}
