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

use std::fmt;

use num_rational::Rational64;
use num_traits::One;

use crate::term::{Deriv, Factor, Term};

mod transform;
pub use transform::{NotInvariant, Poly, Shift, Transformation};

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
            Check::Symmetry(tr) => tr.check_invariant(term).map_err(|e| e.to_string()),
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
