//! Figures of the modes: their shapes and the spectrum.

use super::plot::*;
use super::{err, FigureError};
use crate::theory::Theory;

/// Fig. 2A: the first four non-zero mode shapes of every field.
pub(super) fn mode_shapes(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let n = theory.points;
    let fields = &theory.modes;
    let titles: Vec<String> = fields
        .iter()
        .map(|f| {
            let ends = match f.field.boundary {
                crate::model::Boundary::Ends { tail, head } if tail != head => {
                    f.field.boundary.name()
                }
                b => format!("{b} ends"),
            };
            format!("{} ({}, {ends})", f.field.symbol, f.field.meaning).to_lowercase()
        })
        .collect();
    let mut panels = Vec::new();
    for (f, title) in fields.iter().zip(&titles) {
        let shapes = f.spectrum.shapes.as_ref().ok_or_else(|| err("no shapes"))?;
        let first = f.spectrum.nullity;
        let series = (first..(first + 4).min(shapes.ncols()))
            .map(|i| {
                let pts = (0..shapes.nrows())
                    .map(|j| (j as f64, shapes[(j, i)]))
                    .collect();
                self::series(format!("mode {i}"), pts, Mark::Line)
            })
            .collect();
        panels.push(panel(
            title,
            "segment j (0 = tail)",
            "vᵢ(j), unit norm",
            series,
        ));
    }
    let rows = fields.len().div_ceil(2);
    render(
        width,
        &format!("Mode shapes on N = {n} points (paper Fig. 2A)"),
        380,
        (rows, 2),
        &panels,
    )
}

/// Fig. 2B–C: eigenvalues and equipartition variance shares.
pub(super) fn spectrum(theory: &Theory, width: u32) -> Result<String, FigureError> {
    let n = theory.points;
    let fields = &theory.modes;
    let nonzero = |f: &crate::modal::FieldModes| -> Vec<(usize, f64, f64)> {
        f.modes
            .iter()
            .filter(|m| m.eigenvalue > 0.0 && m.zero_mode.is_none())
            .map(|m| (m.index, m.eigenvalue, m.variance_share))
            .collect()
    };
    let eig = fields
        .iter()
        .map(|f| {
            let pts = nonzero(f)
                .iter()
                .map(|&(i, l, _)| (i as f64, l.log10()))
                .collect();
            series(f.field.symbol.clone(), pts, Mark::Dots)
        })
        .collect();
    let eig = merge_identical(eig);
    let share = fields
        .iter()
        .map(|f| {
            let mut acc = 0.0;
            let pts = nonzero(f)
                .iter()
                .map(|&(i, _, s)| {
                    acc += s;
                    (i as f64, 100.0 * acc)
                })
                .collect();
            series(f.field.symbol.clone(), pts, Mark::Line)
        })
        .collect();
    let share = merge_identical(share);
    let mut right = panel(
        "cumulative variance share at equipartition",
        "mode index i",
        "Σ share (%)",
        share,
    );
    right.zero = true;
    render(
        width,
        &format!("Eigenvalues and variance shares, N = {n} (paper Fig. 2B–C)"),
        400,
        (1, 2),
        &[
            panel(
                "eigenvalues λᵢ of each operator",
                "mode index i",
                "log₁₀ λᵢ",
                eig,
            ),
            right,
        ],
    )
}
