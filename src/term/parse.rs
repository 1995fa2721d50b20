//! Reading a term from text: `(∂ts φ)²`, `(dts phi)^2`, `∂t φ₁·∂s φ₂`, with a typed reason
//! when the text is not a term.

use std::str::FromStr;

use super::{Deriv, Factor, Term, TermError, SUBSCRIPTS, SUPERSCRIPTS};

/// What is wrong with the text of a term.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParseWhy {
    /// Nothing but white space.
    #[error("empty text")]
    Empty,
    /// An exponent past `u32`.
    #[error("exponent {0} is too large")]
    ExponentTooLarge(String),
    /// `∂` with neither t nor s.
    #[error("'∂' must be followed by t or s")]
    NoVariable,
    /// No `φ` where the field belongs.
    #[error("expected the field φ")]
    NoField,
    /// `^` with no digits after it.
    #[error("'^' must be followed by digits")]
    NoDigits,
    /// A field index past `u8`.
    #[error("field index {0} is out of range")]
    FieldIndex(String),
    /// `(` without `)`.
    #[error("missing ')'")]
    MissingParen,
    /// `∂t φ²`: ambiguous.
    #[error("put a derivative in parentheses to raise it to a power: (∂t φ)²")]
    PowerOfDerivative,
    /// A character after the factor.
    #[error("unexpected {0:?}")]
    Unexpected(char),
    /// A zero power.
    #[error("a factor's power must be at least 1")]
    ZeroPower,
    /// No factor with a positive power.
    #[error("{0}")]
    Term(Box<TermError>),
}

impl FromStr for Term {
    type Err = TermError;

    fn from_str(text: &str) -> Result<Term, TermError> {
        let fail = |why: ParseWhy| TermError::Parse {
            text: text.to_string(),
            why,
        };
        if text.trim().is_empty() {
            return Err(fail(ParseWhy::Empty));
        }
        let mut factors = Vec::new();
        for part in text.split(['·', '*']) {
            factors.push(parse_factor(part).map_err(fail)?);
        }
        Term::new(factors).map_err(|e| fail(ParseWhy::Term(Box::new(e))))
    }
}

/// A cursor over the characters of one factor, skipping white space.
struct Cursor<'a> {
    chars: std::iter::Peekable<std::str::Chars<'a>>,
}

impl Cursor<'_> {
    fn peek(&mut self) -> Option<char> {
        while self.chars.peek().is_some_and(|c| c.is_whitespace()) {
            self.chars.next();
        }
        self.chars.peek().copied()
    }

    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.chars.next();
            true
        } else {
            false
        }
    }

    fn eat_word(&mut self, word: &str) -> bool {
        let _ = self.peek();
        let rest: String = self.chars.clone().take(word.chars().count()).collect();
        if rest == word {
            for _ in word.chars() {
                self.chars.next();
            }
            true
        } else {
            false
        }
    }

    /// An exponent: superscript digits, or `^` and ASCII digits. `None` if there is none.
    fn exponent(&mut self) -> Result<Option<u32>, ParseWhy> {
        let mut digits = String::new();
        if self.eat('^') {
            while let Some(c) = self.chars.peek().copied().filter(char::is_ascii_digit) {
                digits.push(c);
                self.chars.next();
            }
            if digits.is_empty() {
                return Err(ParseWhy::NoDigits);
            }
        } else {
            while let Some(i) = self
                .chars
                .peek()
                .and_then(|c| SUPERSCRIPTS.iter().position(|d| d == c))
            {
                digits.push(char::from(b'0' + i as u8));
                self.chars.next();
            }
            if digits.is_empty() {
                return Ok(None);
            }
        }
        digits
            .parse()
            .map(Some)
            .map_err(|_| ParseWhy::ExponentTooLarge(digits))
    }

    /// The derivative after `∂` (or `d`): letters t and s, each with an optional exponent.
    fn derivative(&mut self) -> Result<Deriv, ParseWhy> {
        let mut d = Deriv::default();
        loop {
            let slot = match self.chars.peek() {
                // `∂t∂s` is read as `∂ts`: partial derivatives commute.
                Some('∂') => {
                    self.chars.next();
                    continue;
                }
                Some('t') => &mut d.t,
                Some('s') => &mut d.s,
                _ => break,
            };
            self.chars.next();
            *slot += self.exponent()?.unwrap_or(1);
        }
        if d.order() == 0 {
            return Err(ParseWhy::NoVariable);
        }
        Ok(d)
    }

    /// A placeholder field: `φ`, `phi`, then an optional index (`₁` or `_1`).
    fn field(&mut self) -> Result<u8, ParseWhy> {
        if !(self.eat('φ') || self.eat_word("phi")) {
            return Err(ParseWhy::NoField);
        }
        let mut digits = String::new();
        if self.chars.peek() == Some(&'_') {
            self.chars.next();
            while let Some(c) = self.chars.peek().copied().filter(char::is_ascii_digit) {
                digits.push(c);
                self.chars.next();
            }
        } else {
            while let Some(i) = self
                .chars
                .peek()
                .and_then(|c| SUBSCRIPTS.iter().position(|d| d == c))
            {
                digits.push(char::from(b'0' + i as u8));
                self.chars.next();
            }
        }
        if digits.is_empty() {
            Ok(0)
        } else {
            digits.parse().map_err(|_| ParseWhy::FieldIndex(digits))
        }
    }

    /// `∂… φ` or `φ`.
    fn derivative_of_field(&mut self) -> Result<(Deriv, u8), ParseWhy> {
        let deriv = if self.eat('∂') || self.eat('d') {
            self.derivative()?
        } else {
            Deriv::default()
        };
        Ok((deriv, self.field()?))
    }
}

fn parse_factor(text: &str) -> Result<Factor, ParseWhy> {
    let mut c = Cursor {
        chars: text.chars().peekable(),
    };
    let (deriv, field, power) = if c.eat('(') {
        let (deriv, field) = c.derivative_of_field()?;
        if !c.eat(')') {
            return Err(ParseWhy::MissingParen);
        }
        (deriv, field, c.exponent()?.unwrap_or(1))
    } else {
        let (deriv, field) = c.derivative_of_field()?;
        let power = c.exponent()?;
        if deriv.order() > 0 && power.is_some() {
            return Err(ParseWhy::PowerOfDerivative);
        }
        (deriv, field, power.unwrap_or(1))
    };
    if let Some(extra) = c.peek() {
        return Err(ParseWhy::Unexpected(extra));
    }
    if power == 0 {
        return Err(ParseWhy::ZeroPower);
    }
    Ok(Factor {
        field,
        deriv,
        power,
    })
}
