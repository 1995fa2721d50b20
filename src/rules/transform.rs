//! The transformations a symmetry applies, and the exact polynomial algebra that applies them
//! to a term: a term is expanded into a polynomial in the field's derivatives, the map applied,
//! and the image compared with the original.

use std::collections::BTreeMap;
use std::fmt;

use num_rational::Rational64;
use num_traits::{One, Signed, Zero};

use crate::term::{placeholder, superscript, Deriv, Factor, Term};

/// How a transformation changes a term that is not invariant under it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{transformation} changes {term}{} by {change}", if *.first_order { ", to first order," } else { "" })]
pub struct NotInvariant {
    /// The transformation, as applied to the field (`φ → −φ`).
    pub transformation: String,
    /// The term.
    pub term: Term,
    /// Whether only the first order in the shift's parameter was compared.
    pub first_order: bool,
    /// The image minus the term.
    pub change: Poly,
}

/// A transformation of one field, `φ(s, t) → scale·φ(s_sign·s, t_sign·t) + p·sᵐtⁿ`, with `p`
/// the symbolic parameter of an optional shift. An infinitesimal transformation is compared to
/// first order in `p` only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transformation {
    /// Factor multiplying the field: 1, or −1 for a reflection of the field.
    pub scale: i64,
    /// Sign of arc length under the map (−1: anterior–posterior reflection).
    pub s_sign: i64,
    /// Sign of time under the map (−1: time reversal).
    pub t_sign: i64,
    /// The polynomial added to the field, if any.
    pub shift: Option<Shift>,
    /// Compare only to first order in the shift parameter.
    pub infinitesimal: bool,
}

/// The shift `p·sᵐtⁿ` of a [`Transformation`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shift {
    /// Name of the parameter (Δ, v, Ω).
    pub param: &'static str,
    /// Power m of arc length.
    pub s: u32,
    /// Power n of time.
    pub t: u32,
}

impl Transformation {
    const IDENTITY: Transformation = Transformation {
        scale: 1,
        s_sign: 1,
        t_sign: 1,
        shift: None,
        infinitesimal: false,
    };

    /// `φ → φ + p·sᵐtⁿ`.
    pub const fn shift(param: &'static str, s: u32, t: u32, infinitesimal: bool) -> Self {
        Transformation {
            shift: Some(Shift { param, s, t }),
            infinitesimal,
            ..Self::IDENTITY
        }
    }

    /// `φ → −φ`.
    pub const fn reflect_field() -> Self {
        Transformation {
            scale: -1,
            ..Self::IDENTITY
        }
    }

    /// `s → −s` (or `t → −t` with `time = true`).
    pub const fn reflect_coordinate(time: bool) -> Self {
        Transformation {
            s_sign: if time { 1 } else { -1 },
            t_sign: if time { -1 } else { 1 },
            ..Self::IDENTITY
        }
    }

    /// The image of `term` when placeholder field `field` is transformed (the others are not).
    pub fn apply(&self, term: &Term, field: u8) -> Poly {
        let mut out = Poly::one();
        for f in term.factors() {
            let jet = Poly::jet(f.field, f.deriv);
            let image = if f.field == field {
                let sign =
                    self.scale * self.s_sign.pow(f.deriv.s % 2) * self.t_sign.pow(f.deriv.t % 2);
                let mut image = jet.scaled(Rational64::from_integer(sign));
                if let Some(shift) = &self.shift {
                    image = image.add(&shift.derivative(f.deriv));
                }
                image
            } else {
                jet
            };
            out = out.mul(&image.pow(f.power));
            if self.infinitesimal {
                out = out.truncated(1);
            }
        }
        out
    }

    /// `Ok` if `term` is invariant under the transformation of each field it involves; otherwise
    /// the change the transformation makes.
    pub fn check_invariant(&self, term: &Term) -> Result<(), NotInvariant> {
        term.fields()
            .into_iter()
            .try_for_each(|field| self.check_invariant_field(term, field))
    }

    /// Is `term` unchanged when only placeholder `field` is transformed? For a shift, first order
    /// in the parameter decides it exactly (see [`Rule::passes`]).
    pub fn is_invariant_field(&self, term: &Term, field: u8) -> bool {
        let first_order = Transformation {
            infinitesimal: true,
            ..*self
        };
        first_order.apply(term, field) == Poly::of_term(term)
    }

    /// Does `term`, read as a force on placeholder field `field`, transform as that field does:
    /// is its image `scale`·`term` (to first order in a shift's parameter)? The rule for a
    /// term of an equation of motion, where a density's rule is invariance.
    pub fn is_covariant_field(&self, term: &Term, field: u8) -> bool {
        let first_order = Transformation {
            infinitesimal: true,
            ..*self
        };
        first_order.apply(term, field)
            == Poly::of_term(term).scaled(Rational64::from_integer(self.scale))
    }

    /// `Ok` if `term` is invariant when only placeholder field `field` is transformed.
    pub fn check_invariant_field(&self, term: &Term, field: u8) -> Result<(), NotInvariant> {
        let original = Poly::of_term(term);
        let change = self
            .apply(term, field)
            .add(&original.scaled(-Rational64::one()));
        if change.is_zero() {
            return Ok(());
        }
        Err(NotInvariant {
            transformation: self.describe(field),
            term: term.clone(),
            first_order: self.infinitesimal,
            change,
        })
    }

    fn describe(&self, field: u8) -> String {
        let phi = placeholder(field);
        let coord = |sign: i64, c: &str| {
            if sign < 0 {
                format!("−{c}")
            } else {
                c.to_string()
            }
        };
        let mut image = if (self.s_sign, self.t_sign) == (1, 1) {
            phi.clone()
        } else {
            format!(
                "{phi}({}, {})",
                coord(self.s_sign, "s"),
                coord(self.t_sign, "t")
            )
        };
        if self.scale < 0 {
            image = format!("−{image}");
        }
        if let Some(shift) = &self.shift {
            image = format!("{image} + {}", shift.monomial());
        }
        format!("{phi} → {image}")
    }
}

impl fmt::Display for Transformation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.describe(0))?;
        if self.infinitesimal {
            f.write_str(" (infinitesimal)")?;
        }
        Ok(())
    }
}

impl Shift {
    fn monomial(&self) -> String {
        let mut m = self.param.to_string();
        for (c, k) in [("s", self.s), ("t", self.t)] {
            match k {
                0 => {}
                1 => m += &format!("·{c}"),
                k => m += &format!("·{c}{}", superscript(k)),
            }
        }
        m
    }

    /// `∂tᵃ∂sᵇ (p·sᵐtⁿ)`, as a polynomial in p, s, t.
    fn derivative(&self, d: Deriv) -> Poly {
        if d.s > self.s || d.t > self.t {
            return Poly::zero();
        }
        let falling = |n: u32, k: u32| ((n - k + 1)..=n).map(i64::from).product::<i64>();
        let coef = falling(self.s, d.s) * falling(self.t, d.t);
        Poly::from_mono(
            TransformMono {
                param: 1,
                s: self.s - d.s,
                t: self.t - d.t,
                jet: Vec::new(),
            },
            Rational64::from_integer(coef),
        )
        .with_param(self.param)
    }
}

/// A monomial `pᵏ sᵐ tⁿ ∏ (∂…φ_f)^e` of the transformation algebra.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct TransformMono {
    param: u32,
    s: u32,
    t: u32,
    /// Jet variables with their powers, sorted by (field, derivative).
    jet: Vec<(u8, Deriv, u32)>,
}

impl TransformMono {
    fn mul(&self, other: &TransformMono) -> TransformMono {
        // Merge the two sorted jet lists, adding powers of equal variables.
        let (a, b) = (&self.jet, &other.jet);
        let mut jet = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let take_a = j == b.len() || (i < a.len() && (a[i].0, a[i].1) <= (b[j].0, b[j].1));
            let take_b = i == a.len() || (j < b.len() && (b[j].0, b[j].1) <= (a[i].0, a[i].1));
            match (take_a, take_b) {
                (true, true) => {
                    jet.push((a[i].0, a[i].1, a[i].2 + b[j].2));
                    i += 1;
                    j += 1;
                }
                (true, false) => {
                    jet.push(a[i]);
                    i += 1;
                }
                _ => {
                    jet.push(b[j]);
                    j += 1;
                }
            }
        }
        TransformMono {
            param: self.param + other.param,
            s: self.s + other.s,
            t: self.t + other.t,
            jet,
        }
    }
}

/// A polynomial with exact rational coefficients in the jet variables, `s`, `t` and one
/// transformation parameter: what a transformed term expands to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Poly {
    terms: BTreeMap<TransformMono, Rational64>,
    param: &'static str,
}

impl Poly {
    fn zero() -> Poly {
        Poly {
            terms: BTreeMap::new(),
            param: "",
        }
    }

    fn one() -> Poly {
        Poly::from_mono(
            TransformMono {
                param: 0,
                s: 0,
                t: 0,
                jet: Vec::new(),
            },
            Rational64::one(),
        )
    }

    fn from_mono(m: TransformMono, c: Rational64) -> Poly {
        let mut p = Poly::zero();
        if !c.is_zero() {
            p.terms.insert(m, c);
        }
        p
    }

    fn jet(field: u8, deriv: Deriv) -> Poly {
        Poly::from_mono(
            TransformMono {
                param: 0,
                s: 0,
                t: 0,
                jet: vec![(field, deriv, 1)],
            },
            Rational64::one(),
        )
    }

    pub(super) fn of_term(term: &Term) -> Poly {
        term.factors().iter().fold(Poly::one(), |acc, f| {
            acc.mul(&Poly::jet(f.field, f.deriv).pow(f.power))
        })
    }

    /// True if every coefficient is zero.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    pub(super) fn scaled(&self, c: Rational64) -> Poly {
        let mut p = Poly::zero();
        p.param = self.param;
        for (m, v) in &self.terms {
            if !(v * c).is_zero() {
                p.terms.insert(m.clone(), v * c);
            }
        }
        p
    }

    fn add(&self, other: &Poly) -> Poly {
        let mut p = self.clone();
        if p.param.is_empty() {
            p.param = other.param;
        }
        for (m, v) in &other.terms {
            let e = p.terms.entry(m.clone()).or_insert_with(Rational64::zero);
            *e += v;
            if e.is_zero() {
                p.terms.remove(m);
            }
        }
        p
    }

    fn mul(&self, other: &Poly) -> Poly {
        let mut p = Poly::zero();
        p.param = if self.param.is_empty() {
            other.param
        } else {
            self.param
        };
        for (a, x) in &self.terms {
            for (b, y) in &other.terms {
                let m = a.mul(b);
                let e = p.terms.entry(m).or_insert_with(Rational64::zero);
                *e += x * y;
            }
        }
        p.terms.retain(|_, v| !v.is_zero());
        p
    }

    fn pow(&self, n: u32) -> Poly {
        (0..n).fold(Poly::one(), |acc, _| acc.mul(self))
    }

    /// Drop every monomial of degree above `max` in the parameter.
    fn truncated(mut self, max: u32) -> Poly {
        self.terms.retain(|m, _| m.param <= max);
        self
    }

    fn with_param(mut self, name: &'static str) -> Poly {
        self.param = name;
        self
    }
}

impl fmt::Display for Poly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.terms.is_empty() {
            return f.write_str("0");
        }
        for (i, (m, c)) in self.terms.iter().enumerate() {
            let negative = c.is_negative();
            let mag = c.abs();
            match (i, negative) {
                (0, true) => f.write_str("−")?,
                (0, false) => {}
                (_, true) => f.write_str(" − ")?,
                (_, false) => f.write_str(" + ")?,
            }
            let mut prefix = if mag.is_one() {
                String::new()
            } else {
                mag.to_string()
            };
            for (name, k) in [(self.param, m.param), ("s", m.s), ("t", m.t)] {
                match k {
                    0 => {}
                    1 => prefix += name,
                    k => prefix += &format!("{name}{}", superscript(k)),
                }
            }
            let jet = Term::new(m.jet.iter().map(|&(field, deriv, power)| Factor {
                field,
                deriv,
                power,
            }));
            match (prefix.is_empty(), jet) {
                (true, Ok(j)) => write!(f, "{j}")?,
                (true, Err(_)) => f.write_str("1")?,
                (false, Ok(j)) => write!(f, "{prefix}·{j}")?,
                (false, Err(_)) => f.write_str(&prefix)?,
            }
        }
        Ok(())
    }
}
