//! Figures of the modes: their shapes and the spectrum. A mode number keeps its colour in
//! every panel (mode 3 of x and mode 3 of y alike), so one key serves the figure.

use super::plot::*;
use super::{err, FigureError};
use crate::theory::Theory;

/// The most characters of a mode-shape panel's title: two lines of a panel at 85 mm.
const TITLE_CHARS: usize = 36;

/// The leading words of a field's meaning that a panel title holds: brackets left out, none
/// after a colon, as many as keep `rest` + the words within [`TITLE_CHARS`], never ending on a little
/// word ("roll about the" is "roll"), at least one.
fn short_meaning(meaning: &str, rest: usize) -> String {
    const LITTLE: [&str; 9] = [
        "about", "the", "of", "in", "from", "to", "and", "a", "along",
    ];
    let head = meaning.split(':').next().unwrap_or("");
    let mut depth = 0usize;
    let head: String = (head.chars())
        .filter(|c| {
            depth = match c {
                '(' => depth + 1,
                ')' => depth.saturating_sub(1),
                _ => depth,
            };
            depth == 0 && *c != ')'
        })
        .collect();
    let words: Vec<&str> = head.split_whitespace().collect();
    let mut take = words.len();
    while take > 1
        && (rest + words[..take].join(" ").chars().count() > TITLE_CHARS
            || LITTLE.contains(&words[take - 1]))
    {
        take -= 1;
    }
    words[..take.min(words.len())].join(" ")
}

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
            let symbol = &f.field.symbol;
            let rest = symbol.chars().count() + ends.chars().count() + 5;
            let meaning = short_meaning(&f.field.meaning, rest);
            format!("{symbol} ({meaning}, {ends})").to_lowercase()
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
                self::series(format!("mode {i}"), pts, Mark::Line).hue(i)
            })
            .collect();
        panels.push(panel(
            title,
            "point j (0 = tail)",
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

#[cfg(test)]
mod tests {
    use super::short_meaning;

    #[test]
    fn a_meaning_is_cut_to_whole_words_that_fit() {
        let rest = "θ (, free ends)".chars().count();
        assert_eq!(
            short_meaning("torsional rotation about the midline", rest),
            "torsional rotation"
        );
        assert_eq!(short_meaning("roll about the midline", rest), "roll");
        assert_eq!(
            short_meaning("mediolateral (left–right) bending: the tail beat", rest),
            "mediolateral bending"
        );
        assert_eq!(
            short_meaning("axial displacement", rest),
            "axial displacement"
        );
        assert_eq!(short_meaning("", rest), "");
    }
}
