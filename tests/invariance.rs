//! An independent check of the symmetry verdicts. The engine expands transformed terms
//! symbolically; this checker instead *evaluates* a term on random polynomial fields φ(s, t) at
//! random points, before and after the transformation, in exact rational arithmetic. A finite
//! symmetry must leave the value unchanged for a random parameter; an infinitesimal one must
//! leave the first-order part unchanged, which dual numbers (p = ε, ε² = 0) give exactly.
//! Engine and checker must agree on every candidate of both densities and on product terms.

use num_rational::Ratio;
use theory_search::enumerate::{pure_powers, Bounds};
use theory_search::model::{BoundShape, Density, Model};
use theory_search::reduce::analyse;
use theory_search::rules::{Check, Transformation, REGISTRY};
use theory_search::term::Term;

type Q = Ratio<i128>;

/// a + b·ε with ε² = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Dual(Q, Q);

impl Dual {
    fn mul(self, o: Dual) -> Dual {
        Dual(self.0 * o.0, self.0 * o.1 + self.1 * o.0)
    }
    fn add(self, o: Dual) -> Dual {
        Dual(self.0 + o.0, self.1 + o.1)
    }
}

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn small(&mut self) -> i128 {
        (self.next() % 7) as i128 - 3
    }
}

/// φ(s, t) = Σ c[i][j] sⁱ tʲ, degree high enough that no derivative in the tests vanishes.
struct Field(Vec<Vec<Q>>);

impl Field {
    fn random(rng: &mut Rng, degree: usize) -> Field {
        Field(
            (0..=degree)
                .map(|_| (0..=degree).map(|_| Q::from(rng.small())).collect())
                .collect(),
        )
    }

    /// ∂tᵃ∂sᵇ φ at (s, t).
    fn derivative(&self, a: u32, b: u32, s: Q, t: Q) -> Q {
        let falling =
            |n: usize, k: u32| -> i128 { (0..k as usize).map(|j| n as i128 - j as i128).product() };
        let mut v = Q::from(0);
        for (i, row) in self.0.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                if i < b as usize || j < a as usize {
                    continue;
                }
                let f = falling(i, b) * falling(j, a);
                v += c * Q::from(f) * pow(s, i - b as usize) * pow(t, j - a as usize);
            }
        }
        v
    }
}

fn pow(x: Q, n: usize) -> Q {
    (0..n).fold(Q::from(1), |acc, _| acc * x)
}

/// ∂tᵃ∂sᵇ of the transformed field p·sᵐtⁿ + scale·φ(σs·s, σt·t), at (s, t), with p dual.
fn transformed_derivative(
    tr: &Transformation,
    phi: &Field,
    a: u32,
    b: u32,
    s: Q,
    t: Q,
    p: Dual,
) -> Dual {
    let sign = tr.scale * tr.s_sign.pow(b) * tr.t_sign.pow(a);
    let base = Q::from(sign as i128)
        * phi.derivative(
            a,
            b,
            Q::from(tr.s_sign as i128) * s,
            Q::from(tr.t_sign as i128) * t,
        );
    let shift = match tr.shift {
        Some(sh) if b <= sh.s && a <= sh.t => {
            let shape = Field(
                (0..=sh.s as usize)
                    .map(|i| {
                        (0..=sh.t as usize)
                            .map(|j| Q::from((i == sh.s as usize && j == sh.t as usize) as i128))
                            .collect()
                    })
                    .collect(),
            );
            shape.derivative(a, b, s, t)
        }
        _ => Q::from(0),
    };
    Dual(base, Q::from(0)).add(p.mul(Dual(shift, Q::from(0))))
}

/// Does the checker find `term` invariant under `tr`? Each placeholder field gets its own
/// random polynomial; only `target` is transformed.
fn checker_invariant(tr: &Transformation, term: &Term, rng: &mut Rng) -> bool {
    for _trial in 0..4 {
        let fields: Vec<Field> = (0..3).map(|_| Field::random(rng, 6)).collect();
        let s = Q::new(rng.small() * 2 + 1, 3);
        let t = Q::new(rng.small() * 2 + 1, 5);
        // Finite symmetries: a random nonzero parameter; infinitesimal: p = ε.
        let p = if tr.infinitesimal {
            Dual(Q::from(0), Q::from(1))
        } else {
            Dual(Q::new(rng.small() * 2 + 1, 2), Q::from(0))
        };
        for target in term.fields() {
            let mut before = Dual(Q::from(1), Q::from(0));
            let mut after = Dual(Q::from(1), Q::from(0));
            for f in term.factors() {
                let phi = &fields[f.field as usize];
                let orig = Dual(phi.derivative(f.deriv.t, f.deriv.s, s, t), Q::from(0));
                let image = if f.field == target {
                    transformed_derivative(tr, phi, f.deriv.t, f.deriv.s, s, t, p)
                } else {
                    orig
                };
                // The original density is compared at the image point of the coordinates.
                let mapped = if f.field == target {
                    Dual(
                        phi.derivative(
                            f.deriv.t,
                            f.deriv.s,
                            Q::from(tr.s_sign as i128) * s,
                            Q::from(tr.t_sign as i128) * t,
                        ),
                        Q::from(0),
                    )
                } else {
                    orig
                };
                for _ in 0..f.power {
                    before = before.mul(mapped);
                    after = after.mul(image);
                }
            }
            let changed = if tr.infinitesimal {
                after.1 != before.1
            } else {
                after != before
            };
            if changed {
                return false;
            }
        }
    }
    true
}

fn symmetry_rules() -> Vec<(&'static str, Transformation)> {
    REGISTRY
        .iter()
        .filter_map(|r| match r.check {
            Check::Symmetry(tr) => Some((r.code, tr)),
            Check::Structural(_) => None,
        })
        .collect()
}

/// Engine and checker give the same verdict for every symmetry rule, and the engine's fast
/// decision (`passes`) equals its explained one (`verdict`); returns how many rules.
fn assert_agree(term: &Term, rng: &mut Rng) -> usize {
    let rules = symmetry_rules();
    for (code, tr) in &rules {
        let engine = tr.check_invariant(term).is_ok();
        assert_eq!(engine, checker_invariant(tr, term, rng), "{code} on {term}");
        let rule = theory_search::rules::rule(code).unwrap();
        assert_eq!(
            rule.passes(term),
            rule.verdict(term).passed(),
            "{code} on {term}"
        );
    }
    rules.len()
}

#[test]
fn engine_and_checker_agree_on_every_candidate() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut checked = 0;
    for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
        for term in pure_powers(&Bounds::for_order(shape, 5)) {
            checked += assert_agree(&term, &mut rng);
        }
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn engine_and_checker_agree_on_every_monomial() {
    let mut rng = Rng(0xDEAD_BEEF);
    for shape in [BoundShape::TauPlusSigma, BoundShape::TauAndSigma] {
        for term in theory_search::enumerate::monomials(&Bounds::for_order(shape, 4)) {
            assert_agree(&term, &mut rng);
        }
    }
}

#[test]
fn engine_and_checker_agree_on_products() {
    let mut rng = Rng(12345);
    let texts = [
        "∂t φ·∂s φ",
        "(∂s φ)²·(∂t φ)²",
        "φ·∂ss φ",
        "∂s φ₁·∂s φ₂",
        "(∂ss φ₁)²·(∂t φ₂)²",
        "∂ts φ·∂s φ",
        "(∂tss φ)·(∂ss φ)",
        "∂t φ₁·∂t φ₂",
        "(∂s φ)³·∂ss φ",
        "φ₁²·(∂t φ₂)²",
    ];
    for text in texts {
        assert_agree(&text.parse().unwrap(), &mut rng);
    }
}

#[test]
fn every_survivor_is_invariant_under_its_fields_symmetries() {
    let model = Model::larva();
    let mut rng = Rng(777);
    let mut checked = 0;
    for order in 1..=8 {
        for density in Density::ALL {
            let a = analyse(&model, density, order).unwrap();
            for f in &a.fields {
                for rule in model.requirements(density, &f.field.id) {
                    if let Check::Symmetry(tr) = rule.check {
                        for term in &f.survivors {
                            checked += 1;
                            assert!(
                                checker_invariant(&tr, term, &mut rng),
                                "{} {term} {}",
                                f.field.id,
                                rule.code
                            );
                        }
                    }
                }
            }
        }
    }
    // Every field at every order from 2 keeps survivors under several symmetries.
    assert!(checked >= 100, "{checked} survivor checks");
}
