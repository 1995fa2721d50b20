//! Terms of a density: products of powers of derivatives of placeholder fields.
//!
//! A [`Term`] is `∏ᵢ (∂tᵃⁱ∂sᵇⁱ φ_{fᵢ})^{nᵢ}`. It is kept canonical (factors merged, sorted, powers ≥ 1),
//! so two terms are equal exactly when they are the same monomial. Its four orders follow from
//! rescaling φ → a·φ, t → t·t₀, s → s·s₀ (paper Eq. 36–37):
//!
//! * δ, the derivative order: the highest `a + b` of any factor;
//! * ε, the amplitude order: `Σ n`;
//! * τ, the time-scale order: `Σ n·a`;
//! * σ, the space-scale order: `Σ n·b`.
//!
//! Text form (what `Display` writes and `FromStr` reads back): `φ`, `φ³`, `∂t φ`, `(∂ts φ)²`,
//! `(∂t φ)²·(∂s φ)²`; placeholder field k > 0 is `φ₁`, `φ₂`, …. A derivative repeats its letters
//! up to four times (`∂ttss`) and writes a superscript beyond (`∂t⁵s`). The parser also takes
//! ASCII: `(dts phi)^2`, `phi_1`, `*` for `·`, and spaces are optional.
//!
//! `Ord` is the canonical table order: by δ, then ε, then factor by factor (field, derivative order,
//! time derivatives first, power).

use std::cmp::{Ordering, Reverse};
use std::fmt;

mod parse;
pub use parse::ParseWhy;

/// A mixed partial derivative `∂tᵗ∂sˢ`; `t = s = 0` is the field itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Deriv {
    /// Order in time.
    pub t: u32,
    /// Order in arc length.
    pub s: u32,
}

impl Deriv {
    /// `∂tᵗ∂sˢ`.
    pub const fn new(t: u32, s: u32) -> Self {
        Deriv { t, s }
    }

    /// Total derivative order `t + s`.
    pub const fn order(self) -> u32 {
        self.t + self.s
    }
}

/// One factor `(∂tᵗ∂sˢ φ_field)^power` of a term.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Factor {
    /// Placeholder field index: 0 is the single-field `φ`, k > 0 is `φₖ` in interaction terms.
    pub field: u8,
    /// Which derivative of the field.
    pub deriv: Deriv,
    /// Power, at least 1 in a canonical term.
    pub power: u32,
}

impl Factor {
    fn sort_key(&self) -> (u8, u32, Reverse<u32>, u32) {
        (
            self.field,
            self.deriv.order(),
            Reverse(self.deriv.t),
            self.power,
        )
    }
}

impl Ord for Factor {
    fn cmp(&self, other: &Self) -> Ordering {
        self.sort_key().cmp(&other.sort_key())
    }
}

impl PartialOrd for Factor {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The four orders of a term (paper Appendix A).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Orders {
    /// δ: highest derivative order of any factor.
    pub delta: u32,
    /// ε: amplitude order, the total power.
    pub epsilon: u32,
    /// τ: order in the inverse time scale.
    pub tau: u32,
    /// σ: order in the inverse space scale.
    pub sigma: u32,
}

/// A product of factors, kept canonical.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Term {
    factors: Vec<Factor>,
}

/// Why a list of factors or a string is not a term.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TermError {
    /// No factor with a positive power: a constant, which never changes the physics.
    #[error("a term needs at least one factor with a positive power (constants are not terms)")]
    Empty,
    /// The text could not be read as a term.
    #[error("cannot read term {text:?}: {why}")]
    Parse {
        /// The text that was given.
        text: String,
        /// What is wrong with it.
        why: ParseWhy,
    },
}

impl Term {
    /// The canonical term of `factors`: equal derivatives of the same field are merged, zero
    /// powers dropped, factors sorted.
    pub fn new(factors: impl IntoIterator<Item = Factor>) -> Result<Term, TermError> {
        let mut merged: Vec<Factor> = Vec::new();
        for f in factors {
            if f.power == 0 {
                continue;
            }
            match merged
                .iter_mut()
                .find(|g| g.field == f.field && g.deriv == f.deriv)
            {
                Some(g) => g.power += f.power,
                None => merged.push(f),
            }
        }
        if merged.is_empty() {
            return Err(TermError::Empty);
        }
        merged.sort();
        Ok(Term { factors: merged })
    }

    /// A term of factors already canonical (distinct kinds, sorted, powers ≥ 1), as the
    /// enumeration builds them; checked in debug builds.
    pub(crate) fn from_canonical(factors: Vec<Factor>) -> Term {
        debug_assert!(
            !factors.is_empty()
                && factors
                    .windows(2)
                    .all(|w| w[0] < w[1] && (w[0].field, w[0].deriv) != (w[1].field, w[1].deriv))
                && factors.iter().all(|f| f.power > 0)
        );
        Term { factors }
    }

    /// The pure power `(∂tᵗ∂sˢ φ)ⁿ` of the single placeholder field; `n ≥ 1`.
    pub fn power(t: u32, s: u32, n: u32) -> Term {
        assert!(n > 0, "a pure power needs n ≥ 1");
        Term {
            factors: vec![Factor {
                field: 0,
                deriv: Deriv::new(t, s),
                power: n,
            }],
        }
    }

    /// The factors, in canonical order.
    pub fn factors(&self) -> &[Factor] {
        &self.factors
    }

    /// The four orders δ, ε, τ, σ.
    pub fn orders(&self) -> Orders {
        let f = &self.factors;
        Orders {
            delta: f.iter().map(|f| f.deriv.order()).max().unwrap_or(0),
            epsilon: f.iter().map(|f| f.power).sum(),
            tau: f.iter().map(|f| f.power * f.deriv.t).sum(),
            sigma: f.iter().map(|f| f.power * f.deriv.s).sum(),
        }
    }

    /// True if any factor carries a time derivative.
    pub fn has_time_derivative(&self) -> bool {
        self.factors.iter().any(|f| f.deriv.t > 0)
    }

    /// The highest time-derivative order of any factor.
    pub fn max_time_order(&self) -> u32 {
        self.factors.iter().map(|f| f.deriv.t).max().unwrap_or(0)
    }

    /// The placeholder fields the term involves, ascending, without repeats.
    pub fn fields(&self) -> Vec<u8> {
        let mut v: Vec<u8> = self.factors.iter().map(|f| f.field).collect();
        v.dedup();
        v
    }

    /// The text form with each placeholder field written by `name` (e.g. the field's symbol).
    pub fn render(&self, name: &dyn Fn(u8) -> String) -> String {
        let mut out = String::new();
        for (i, f) in self.factors.iter().enumerate() {
            if i > 0 {
                out.push('·');
            }
            let field = name(f.field);
            // Writing to a String cannot fail.
            let _ = write_factor(&mut out, f, |w| fmt::Write::write_str(w, &field));
        }
        out
    }

    /// The text form (what `Display` writes) into `w`, without an allocation per factor: the
    /// tables write hundreds of thousands of terms.
    pub fn write_text<W: fmt::Write>(&self, w: &mut W) -> fmt::Result {
        for (i, f) in self.factors.iter().enumerate() {
            if i > 0 {
                w.write_char('·')?;
            }
            write_factor(w, f, |w| {
                w.write_char('φ')?;
                if f.field > 0 {
                    write_script(w, f.field as u32, SUBSCRIPTS)?;
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    /// The term as LaTeX math (without `$`), each placeholder field written by `name`.
    pub fn render_latex(&self, name: &dyn Fn(u8) -> String) -> String {
        self.factors
            .iter()
            .map(|f| {
                let field = name(f.field);
                let base = if f.deriv.order() == 0 {
                    field
                } else {
                    let sub = format!(
                        "{}{}",
                        latex_letters('t', f.deriv.t),
                        latex_letters('s', f.deriv.s)
                    );
                    format!("\\partial_{{{sub}}}{field}")
                };
                match (f.power, f.deriv.order()) {
                    (1, _) => base,
                    (n, 0) => format!("{base}^{{{n}}}"),
                    (n, _) => format!("({base})^{{{n}}}"),
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

impl Ord for Term {
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (self.orders(), other.orders());
        (a.delta, a.epsilon)
            .cmp(&(b.delta, b.epsilon))
            .then_with(|| self.factors.cmp(&other.factors))
    }
}

impl PartialOrd for Term {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The name of placeholder field `k`: `φ`, `φ₁`, `φ₂`, ….
pub fn placeholder(k: u8) -> String {
    if k == 0 {
        "φ".to_string()
    } else {
        format!("φ{}", to_script(k as u32, SUBSCRIPTS))
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_text(f)
    }
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
const SUBSCRIPTS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];

/// `n` in the given digit set (superscript or subscript).
pub fn to_script(n: u32, digits: [char; 10]) -> String {
    let mut out = String::new();
    let _ = write_script(&mut out, n, digits);
    out
}

/// `n` in the given digit set, written into `w`.
fn write_script<W: fmt::Write>(w: &mut W, n: u32, digits: [char; 10]) -> fmt::Result {
    if n >= 10 {
        write_script(w, n / 10, digits)?;
    }
    w.write_char(digits[(n % 10) as usize])
}

/// `n` as superscript digits, e.g. `²`.
pub fn superscript(n: u32) -> String {
    to_script(n, SUPERSCRIPTS)
}

/// `count` derivative letters: repeated up to four times, with an exponent (`exp`) beyond.
fn letters_with(letter: char, count: u32, exp: fn(u32) -> String) -> String {
    match count {
        0 => String::new(),
        1..=4 => std::iter::repeat_n(letter, count as usize).collect(),
        _ => format!("{letter}{}", exp(count)),
    }
}

fn latex_letters(letter: char, count: u32) -> String {
    letters_with(letter, count, |n| format!("^{{{n}}}"))
}

/// `count` derivative letters into `w`, as [`letters_with`] with superscript exponents.
fn write_letters<W: fmt::Write>(w: &mut W, letter: char, count: u32) -> fmt::Result {
    match count {
        0 => Ok(()),
        1..=4 => (0..count).try_for_each(|_| w.write_char(letter)),
        _ => {
            w.write_char(letter)?;
            write_script(w, count, SUPERSCRIPTS)
        }
    }
}

/// One factor, `φ³`, `∂ts φ` or `(∂ts φ)²`, with the field written by `field`.
fn write_factor<W: fmt::Write>(
    w: &mut W,
    f: &Factor,
    field: impl Fn(&mut W) -> fmt::Result,
) -> fmt::Result {
    let derived = f.deriv.order() > 0;
    let bracket = derived && f.power > 1;
    if bracket {
        w.write_char('(')?;
    }
    if derived {
        w.write_char('∂')?;
        write_letters(w, 't', f.deriv.t)?;
        write_letters(w, 's', f.deriv.s)?;
        w.write_char(' ')?;
    }
    field(w)?;
    if bracket {
        w.write_char(')')?;
    }
    if f.power > 1 {
        write_script(w, f.power, SUPERSCRIPTS)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_matches_the_papers_notation() {
        assert_eq!(Term::power(1, 1, 2).to_string(), "(∂ts φ)²");
        assert_eq!(Term::power(0, 0, 3).to_string(), "φ³");
        assert_eq!(Term::power(1, 0, 1).to_string(), "∂t φ");
        assert_eq!(Term::power(5, 1, 2).to_string(), "(∂t⁵s φ)²");
    }

    #[test]
    fn parses_unicode_ascii_and_spacing_variants() {
        let want = Term::power(1, 1, 2);
        for text in [
            "(∂ts φ)²",
            "(∂tsφ)²",
            "(∂ts φ)^2",
            "(dts phi)^2",
            "(∂t∂s φ)²",
            "(∂st φ)²",
        ] {
            assert_eq!(text.parse::<Term>().unwrap(), want, "{text}");
        }
        assert_eq!("∂ssssφ".parse::<Term>().unwrap(), Term::power(0, 4, 1));
        assert_eq!("∂s⁴ φ".parse::<Term>().unwrap(), Term::power(0, 4, 1));
    }

    #[test]
    fn products_merge_and_sort() {
        let t: Term = "(∂s φ)·∂t φ·∂s φ".parse().unwrap();
        assert_eq!(t.to_string(), "∂t φ·(∂s φ)²");
        assert_eq!(
            t.orders(),
            Orders {
                delta: 1,
                epsilon: 3,
                tau: 1,
                sigma: 2
            }
        );
    }

    #[test]
    fn rejects_malformed_text() {
        for bad in ["", "ψ", "(∂t φ", "∂t φ²", "(∂x φ)²", "φ^", "(∂t φ)⁰", "φ φ"]
        {
            assert!(bad.parse::<Term>().is_err(), "{bad:?} parsed");
        }
    }

    #[test]
    fn orders_follow_the_seed_example() {
        // paper Eq. 36–37: (∂⁵x/∂t²∂s³)² has ε = 2, τ = 4, σ = 6.
        let o = Term::power(2, 3, 2).orders();
        assert_eq!((o.delta, o.epsilon, o.tau, o.sigma), (5, 2, 4, 6));
    }
}
