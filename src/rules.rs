//! The requirements a term must meet, as values in one registry.
//!
//! A [`Rule`] has a stable code (the table column, e.g. `TRAN`), a kebab-case name, a one-line
//! meaning and a [`Check`]. Symmetry rules are decided by *applying* their [`Transformation`] to the
//! term and comparing the result with the original, exactly, as polynomials in the jet variables
//! `∂tᵃ∂sᵇφ`, the coordinates `s, t` and the transformation's parameter. Structural rules
//! (Ostrogradsky, standard kinetic term, dissipative) are predicates on the term's shape. A failed
//! rule says why: for a symmetry, the change the transformation makes to the term.
//!
//! Which rules a field must satisfy is data (see [`crate::model`]); this module only decides them.

use std::collections::BTreeMap;
use std::fmt;

use num_rational::Rational64;
use num_traits::{One, Signed, Zero};

use crate::term::{placeholder, superscript, Deriv, Factor, Term};

/// The verdict of one rule on one term.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// The term satisfies the rule.
    Pass,
    /// The term fails the rule.
    Reject {
        /// Code of the rule that failed.
        rule: &'static str,
        /// Why, in one line.
        why: String,
    },
}

impl Verdict {
    /// True for [`Verdict::Pass`].
    pub fn passed(&self) -> bool {
        matches!(self, Verdict::Pass)
    }
}

/// Why a term fails a structural predicate, formatted only when asked (deciding a table of
/// 10⁵ candidates builds no message).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Failure {
    /// The reason; `{k}` in it stands for `k`.
    pub text: &'static str,
    /// The number the reason names, if any.
    pub k: u32,
}

impl Failure {
    const fn new(text: &'static str) -> Failure {
        Failure { text, k: 0 }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text.replace("{k}", &self.k.to_string()))
    }
}

/// How a rule is decided.
#[derive(Debug, Clone, Copy)]
pub enum Check {
    /// A predicate on the term's structure; `Err` says why it fails.
    Structural(fn(&Term) -> Result<(), Failure>),
    /// Invariance of the term under a transformation of the field.
    Symmetry(Transformation),
}

/// A requirement, as one value of the registry.
#[derive(Debug, Clone, Copy)]
pub struct Rule {
    /// Stable code, also the table column label.
    pub code: &'static str,
    /// Kebab-case name.
    pub name: &'static str,
    /// One-line meaning.
    pub meaning: &'static str,
    /// How the verdict is reached.
    pub check: Check,
}

impl Rule {
    /// Decide the rule on `term`.
    pub fn verdict(&self, term: &Term) -> Verdict {
        let outcome = match &self.check {
            Check::Structural(pred) => pred(term).map_err(|e| e.to_string()),
            Check::Symmetry(tr) => tr.check_invariant(term),
        };
        match outcome {
            Ok(()) => Verdict::Pass,
            Err(why) => Verdict::Reject {
                rule: self.code,
                why,
            },
        }
    }

    /// Does `term` satisfy the rule? The same decision as [`Rule::verdict`], without building
    /// the explanation, and without expanding the product: a transformation of field f maps each
    /// factor ∂^αf to ±∂^αf (+ p·∂^αg when it shifts). What it does to each *factor kind*
    /// (f, α) is found by applying it to that factor alone ([`FactorImage`]); the product is
    /// invariant exactly when no factor of f is shifted (the p¹ coefficient
    /// Σ nᵢ·(∂^αᵢ g)·∏ⱼ≠ᵢ… vanishes only then: its terms are distinct monomials) and the signs
    /// of f's factors, each to its power, multiply to +1. [`Rule::passes_by_expansion`] is the
    /// whole-product computation the tests compare this with. For many terms, prepare the rule
    /// once ([`Rule::prepare`]).
    pub fn passes(&'static self, term: &Term) -> bool {
        self.prepare(0).passes(term)
    }

    /// The rule made ready for many terms whose factors have derivative order ≤ `max_order`:
    /// a symmetry's image of every factor kind is found up front, by applying the map to that
    /// factor alone exactly as [`Rule::passes`] does, so deciding a term is a table lookup per
    /// factor (what the candidate tables use: one rule, 10⁵ terms).
    pub fn prepare(&'static self, max_order: u32) -> PreparedRule {
        let stride = max_order as usize + 1;
        let images = match &self.check {
            Check::Structural(_) => Vec::new(),
            Check::Symmetry(tr) => (0..stride * stride)
                .map(|i| {
                    let deriv = Deriv::new((i / stride) as u32, (i % stride) as u32);
                    image_of_factor(tr, 0, deriv)
                })
                .collect(),
        };
        PreparedRule {
            rule: self,
            images,
            stride,
        }
    }

    /// [`Rule::passes`] by applying the transformation to the whole product and comparing, to
    /// first order in a shift's parameter (slower; the checker of the factor-kind path).
    pub fn passes_by_expansion(&self, term: &Term) -> bool {
        match &self.check {
            Check::Structural(pred) => pred(term).is_ok(),
            Check::Symmetry(tr) => {
                let first_order = Transformation {
                    infinitesimal: true,
                    ..*tr
                };
                let original = Poly::of_term(term);
                term.fields()
                    .into_iter()
                    .all(|f| first_order.apply(term, f) == original)
            }
        }
    }

    /// How the rule is decided, in words (for the generated rule docs).
    pub fn decided_by(&self) -> String {
        match &self.check {
            Check::Structural(_) => "predicate on the term's structure".to_string(),
            Check::Symmetry(tr) => format!("apply {tr} and compare"),
        }
    }
}

/// A rule with its factor-kind images computed (from [`Rule::prepare`]).
#[derive(Debug, Clone)]
pub struct PreparedRule {
    /// The rule.
    pub rule: &'static Rule,
    /// Image of ∂tᵃ∂sᵇ at `a·stride + b` (empty for a structural rule).
    images: Vec<FactorImage>,
    stride: usize,
}

impl PreparedRule {
    /// Does `term` satisfy the rule? The same answer as [`Rule::passes`].
    pub fn passes(&self, term: &Term) -> bool {
        match &self.rule.check {
            Check::Structural(pred) => pred(term).is_ok(),
            Check::Symmetry(tr) => by_factor_kinds(term, None, |f| self.image(tr, f)),
        }
    }

    /// Is `term` unchanged when only placeholder `field` is transformed (a symmetry of one
    /// field of an interaction term)? Structural rules judge the whole term.
    pub fn passes_field(&self, term: &Term, field: u8) -> bool {
        match &self.rule.check {
            Check::Structural(pred) => pred(term).is_ok(),
            Check::Symmetry(tr) => by_factor_kinds(term, Some(field), |f| self.image(tr, f)),
        }
    }

    fn image(&self, tr: &Transformation, f: &Factor) -> FactorImage {
        let (a, b) = (f.deriv.t as usize, f.deriv.s as usize);
        match self.images.get(a * self.stride + b) {
            Some(&image) if b < self.stride => image,
            // Beyond the prepared orders: derive it now.
            _ => image_of_factor(tr, f.field, f.deriv),
        }
    }
}

/// A symmetry's verdict on a product from its factors' images: invariant exactly when no factor
/// is shifted and, field by field, the signs of the factors (each to its power) multiply to +1.
/// With `only`, just that field's factors are transformed.
fn by_factor_kinds(term: &Term, only: Option<u8>, image: impl Fn(&Factor) -> FactorImage) -> bool {
    let mut sign = 1i64;
    let mut field = None;
    for f in term
        .factors()
        .iter()
        .filter(|f| only.is_none_or(|o| o == f.field))
    {
        if field != Some(f.field) {
            // Factors are sorted by field: a field's sign is complete when the next begins.
            if sign != 1 {
                return false;
            }
            field = Some(f.field);
        }
        match image(f) {
            FactorImage::Shifted => return false,
            FactorImage::Signed(s) if f.power % 2 == 1 => sign *= s,
            FactorImage::Signed(_) => {}
        }
    }
    sign == 1
}

/// What a transformation does to one factor ∂^αf of the field it moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FactorImage {
    /// ∂^αf → ±∂^αf.
    Signed(i64),
    /// ∂^αf picks up a shift p·∂^αg ≠ 0.
    Shifted,
}

/// Apply `tr` (to first order in its parameter) to the one-factor term ∂^α`field` and compare
/// with ±the factor.
fn image_of_factor(tr: &Transformation, field: u8, deriv: Deriv) -> FactorImage {
    let first_order = Transformation {
        infinitesimal: true,
        ..*tr
    };
    Term::new([Factor {
        field,
        deriv,
        power: 1,
    }])
    .map(|single| {
        let original = Poly::of_term(&single);
        let moved = first_order.apply(&single, field);
        if moved == original {
            FactorImage::Signed(1)
        } else if moved == original.scaled(-Rational64::one()) {
            FactorImage::Signed(-1)
        } else {
            FactorImage::Shifted
        }
    })
    .unwrap_or(FactorImage::Shifted)
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
    pub fn check_invariant(&self, term: &Term) -> Result<(), String> {
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

    /// `Ok` if `term` is invariant when only placeholder field `field` is transformed.
    pub fn check_invariant_field(&self, term: &Term, field: u8) -> Result<(), String> {
        let original = Poly::of_term(term);
        let change = self
            .apply(term, field)
            .add(&original.scaled(-Rational64::one()));
        if change.is_zero() {
            return Ok(());
        }
        let order = if self.infinitesimal {
            ", to first order,"
        } else {
            ""
        };
        Err(format!(
            "{} changes {term}{order} by {change}",
            self.describe(field)
        ))
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
            Mono {
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
struct Mono {
    param: u32,
    s: u32,
    t: u32,
    /// Jet variables with their powers, sorted by (field, derivative).
    jet: Vec<(u8, Deriv, u32)>,
}

impl Mono {
    fn mul(&self, other: &Mono) -> Mono {
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
        Mono {
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
    terms: BTreeMap<Mono, Rational64>,
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
            Mono {
                param: 0,
                s: 0,
                t: 0,
                jet: Vec::new(),
            },
            Rational64::one(),
        )
    }

    fn from_mono(m: Mono, c: Rational64) -> Poly {
        let mut p = Poly::zero();
        if !c.is_zero() {
            p.terms.insert(m, c);
        }
        p
    }

    fn jet(field: u8, deriv: Deriv) -> Poly {
        Poly::from_mono(
            Mono {
                param: 0,
                s: 0,
                t: 0,
                jet: vec![(field, deriv, 1)],
            },
            Rational64::one(),
        )
    }

    fn of_term(term: &Term) -> Poly {
        term.factors().iter().fold(Poly::one(), |acc, f| {
            acc.mul(&Poly::jet(f.field, f.deriv).pow(f.power))
        })
    }

    /// True if every coefficient is zero.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    fn scaled(&self, c: Rational64) -> Poly {
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

fn ostrogradsky(term: &Term) -> Result<(), Failure> {
    match term.max_time_order() {
        0 | 1 => Ok(()),
        k => Err(Failure {
            text: "holds a time derivative of order {k} > 1 (Ostrogradsky instability)",
            k,
        }),
    }
}

fn standard_kinetic(term: &Term) -> Result<(), Failure> {
    if !term.has_time_derivative() || term.factors() == Term::power(1, 0, 2).factors() {
        Ok(())
    } else {
        Err(Failure::new(
            "holds a time derivative but is not the standard kinetic term (∂t φ)²",
        ))
    }
}

fn dissipative(term: &Term) -> Result<(), Failure> {
    // R is a function of the velocity field v = ∂tφ and its space derivatives: every factor
    // carries exactly one time derivative. (For pure powers: "a first time derivative and no
    // higher one", as in the paper; for products it also rules out ∂sφ·∂tsφ = ∂t(½(∂sφ)²),
    // which would act as a stiffness, not as damping.)
    match term.max_time_order() {
        0 => Err(Failure::new(
            "holds no time derivative, so ∂R/∂(∂t φ) vanishes",
        )),
        1 if term.factors().iter().all(|f| f.deriv.t == 1) => Ok(()),
        1 => Err(Failure::new(
            "has a factor without a time derivative: R must be a function of the velocity ∂t φ",
        )),
        k => Err(Failure {
            text: "holds a time derivative of order {k} > 1; R enters only through ∂R/∂(∂t φ)",
            k,
        }),
    }
}

/// Every rule the engine knows. Adding a requirement is adding one value here.
pub static REGISTRY: &[Rule] = &[
    Rule {
        code: "OST",
        name: "ostrogradsky-stable",
        meaning: "no time derivative above first order (those bring the Ostrogradsky instability)",
        check: Check::Structural(ostrogradsky),
    },
    Rule {
        code: "TRAN",
        name: "translation-invariant",
        meaning: "invariant under a uniform translation of the field, φ → φ + Δ",
        check: Check::Symmetry(Transformation::shift("Δ", 0, 0, false)),
    },
    Rule {
        code: "REF",
        name: "reflection-invariant",
        meaning: "invariant under the reflection φ → −φ",
        check: Check::Symmetry(Transformation::reflect_field()),
    },
    Rule {
        code: "KIN",
        name: "standard-kinetic",
        meaning: "a term with a time derivative must be the standard kinetic energy (∂t φ)²",
        check: Check::Structural(standard_kinetic),
    },
    Rule {
        code: "ROT",
        name: "rotation-invariant",
        meaning: "invariant under an infinitesimal rigid rotation, φ → φ + Δ·s",
        check: Check::Symmetry(Transformation::shift("Δ", 1, 0, true)),
    },
    Rule {
        code: "DIS",
        name: "dissipative",
        meaning: "a function of the velocity: every factor holds exactly one time derivative",
        check: Check::Structural(dissipative),
    },
    Rule {
        code: "GAL",
        name: "boost-invariant",
        meaning: "invariant under a Galilean boost, φ → φ + v·t",
        check: Check::Symmetry(Transformation::shift("v", 0, 1, false)),
    },
    Rule {
        code: "SPIN",
        name: "rotation-rate-invariant",
        meaning: "invariant under rotation at a constant rate, φ → φ + Ω·s·t (infinitesimal)",
        check: Check::Symmetry(Transformation::shift("Ω", 1, 1, true)),
    },
    Rule {
        code: "PAR",
        name: "parity-invariant",
        meaning: "invariant under the anterior–posterior reflection s → −s",
        check: Check::Symmetry(Transformation::reflect_coordinate(false)),
    },
    Rule {
        code: "TREV",
        name: "time-reversal-invariant",
        meaning: "invariant under time reversal t → −t",
        check: Check::Symmetry(Transformation::reflect_coordinate(true)),
    },
];

/// The rule with this code, if any.
pub fn rule(code: &str) -> Option<&'static Rule> {
    REGISTRY.iter().find(|r| r.code == code)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn why(code: &str, term: &str) -> Option<String> {
        match rule(code).unwrap().verdict(&term.parse().unwrap()) {
            Verdict::Pass => None,
            Verdict::Reject { why, .. } => Some(why),
        }
    }

    #[test]
    fn codes_and_names_are_unique() {
        for (i, a) in REGISTRY.iter().enumerate() {
            for b in &REGISTRY[i + 1..] {
                assert_ne!(a.code, b.code);
                assert_ne!(a.name, b.name);
            }
        }
    }

    #[test]
    fn rotation_names_the_change_it_makes() {
        assert_eq!(
            why("ROT", "(∂s φ)²").unwrap(),
            "φ → φ + Δ·s changes (∂s φ)², to first order, by 2Δ·∂s φ"
        );
        assert_eq!(why("ROT", "(∂ss φ)²"), None);
        assert_eq!(why("ROT", "∂t φ"), None);
    }

    #[test]
    fn translation_expands_exactly() {
        assert_eq!(
            why("TRAN", "φ²").unwrap(),
            "φ → φ + Δ changes φ² by 2Δ·φ + Δ²"
        );
    }

    #[test]
    fn reflection_and_parity() {
        assert_eq!(why("REF", "φ³").unwrap(), "φ → −φ changes φ³ by −2·φ³");
        assert_eq!(
            why("PAR", "∂t φ·∂s φ").unwrap(),
            "φ → φ(−s, t) changes ∂t φ·∂s φ by −2·∂t φ·∂s φ"
        );
        assert_eq!(
            why("TREV", "∂t φ·∂s φ").unwrap(),
            "φ → φ(s, −t) changes ∂t φ·∂s φ by −2·∂t φ·∂s φ"
        );
        assert_eq!(why("PAR", "(∂s φ)²"), None);
    }

    #[test]
    fn boosts_and_spins() {
        assert!(why("GAL", "(∂t φ)²").is_some());
        assert_eq!(why("GAL", "(∂ts φ)²"), None);
        assert!(why("SPIN", "(∂ts φ)²").is_some());
        assert_eq!(why("SPIN", "(∂tss φ)²"), None);
    }

    #[test]
    fn interaction_terms_transform_one_field_at_a_time() {
        // ∂sφ₁·∂sφ₂ picks up Δ·∂sφ₂ when φ₁ rotates.
        assert!(why("ROT", "∂s φ₁·∂s φ₂").is_some());
        assert_eq!(why("ROT", "∂ss φ₁·∂ss φ₂"), None);
    }
}
