//! Surviving densities as formulas (`L_x = ½(∂t x)² − ½ c_x (∂s x)²`), and the signs and
//! exact prefactors they are written with.

use std::fmt;

use num_rational::Rational64;
use num_traits::{One, Signed};

use super::{Analysis, FieldResult, Row};
use crate::model::Density;
use crate::rules::Verdict;

/// What goes before the `index`-th term of a sum: `" "`, `" −"`, `" + "` or `" − "`, with `minus`
/// the minus sign to use (`−` in text, `-` in LaTeX).
pub fn sign_joiner(index: usize, negative: bool, minus: &str) -> String {
    match (index, negative) {
        (0, false) => " ".to_string(),
        (0, true) => format!(" {minus}"),
        (_, false) => " + ".to_string(),
        (_, true) => format!(" {minus} "),
    }
}

/// `½`, `1`, `3/2`: an exact prefactor as people write it.
pub fn prefactor_text(r: Rational64) -> String {
    if r == Rational64::new(1, 2) {
        "½".to_string()
    } else if r.is_one() {
        String::new()
    } else {
        r.abs().to_string()
    }
}

impl Row {
    /// Why the term fails column `i` of `analysis` (recomputed: rows keep only the decision).
    pub fn why(&self, analysis: &Analysis, i: usize) -> Option<String> {
        match analysis.columns[i].verdict(&self.term) {
            Verdict::Pass => None,
            Verdict::Reject { why, .. } => Some(why),
        }
    }
}

impl FieldResult {
    /// The surviving density as a formula, e.g. `L_x = ½(∂t x)² − ½ c_x (∂s x)²`.
    pub fn formula(&self, density: Density) -> String {
        let sym = &self.field.symbol;
        let mut out = format!("{}_{sym} =", density.letter());
        if self.density.is_empty() {
            return out + " 0";
        }
        for (i, dt) in self.density.iter().enumerate() {
            let sign = sign_joiner(i, dt.sign < 0, "−");
            let mut coef = prefactor_text(dt.prefactor);
            if let Some(p) = &dt.parameter {
                if !coef.is_empty() {
                    coef.push(' ');
                }
                coef += p;
                coef.push(' ');
            }
            let term = dt.term.render(&|_| sym.clone());
            out += &format!("{sign}{coef}{term}");
        }
        out
    }
}

impl fmt::Display for Analysis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for field in &self.fields {
            writeln!(f, "{}", field.formula(self.density))?;
        }
        Ok(())
    }
}
