//! Text written into markup: LaTeX symbols, and escaping for Markdown tables and LaTeX, so
//! that text from a model file never changes the structure of what it is written into.

const GREEK: [(char, &str); 12] = [
    ('φ', "\\phi"),
    ('θ', "\\theta"),
    ('ψ', "\\psi"),
    ('χ', "\\chi"),
    ('α', "\\alpha"),
    ('β', "\\beta"),
    ('γ', "\\gamma"),
    ('ξ', "\\xi"),
    ('η', "\\eta"),
    ('ρ', "\\rho"),
    ('κ', "\\kappa"),
    ('ζ', "\\zeta"),
];

/// A symbol in LaTeX math: Greek letters to commands, the rest unchanged.
pub fn latex_symbol(s: &str) -> String {
    s.chars()
        .map(|c| {
            GREEK
                .iter()
                .find(|(g, _)| *g == c)
                .map(|(_, l)| format!("{l} "))
                .unwrap_or_else(|| c.to_string())
        })
        .collect::<String>()
        .trim_end()
        .to_string()
}
