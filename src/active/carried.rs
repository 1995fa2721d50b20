//! Forces nothing carries. A covariant force can be variational (f = δL/δφ) or of Rayleigh
//! form (f = δR/δv) and still be given by no density the model admits: on a lateral field y,
//! ROT (y → y + p·s) leaves ∂s²y unchanged, yet strikes (∂s y)² and y·∂s²y, the only densities
//! whose variation it is (under the map they change by a total derivative, a boundary term in
//! the action, so E of the change vanishes and the force keeps its form). Such a force is in
//! neither the equations (no density gives it) nor the active list (it is not active).
//!
//! **Carried** means: in the span of E(L) over the `[lagrangian]` monomials of its block that
//! every requirement of the field admits, and of δR/δv over the admitted `[rayleigh]`
//! monomials (exact elimination, as `basis`). A density of a force of degree ε with τ time and
//! σ space derivatives has degree ε + 1 and the same τ and σ (L), or one time derivative more
//! (R). The rules to blame are those whose removal alone would carry it.

use std::collections::BTreeMap;

use num_rational::Rational64;

use super::basis::{big, jets, Echelon};
use super::{Force, ForceClass};
use crate::jet::{euler_lagrange, poly_of, space_euler, term_of, JetPoly};
use crate::model::{Density, Model};
use crate::rules::{Check, Rule};
use crate::term::Term;

/// The `[lagrangian]` and `[rayleigh]` rules one field's densities must pass.
pub(super) struct DensityRules {
    lagrangian: Vec<&'static Rule>,
    rayleigh: Vec<&'static Rule>,
}

impl DensityRules {
    /// Field `id`'s requirements in `model`.
    pub(super) fn of(model: &Model, id: &str) -> DensityRules {
        let rules = |d: Density| -> Vec<&'static Rule> {
            model
                .density(d)
                .requirements
                .get(id)
                .into_iter()
                .flatten()
                .filter_map(|c| crate::rules::rule(c))
                .collect()
        };
        DensityRules {
            lagrangian: rules(Density::Lagrangian),
            rayleigh: rules(Density::Rayleigh),
        }
    }
}

/// The span of the admitted densities' images in one block of (ε, τ, σ), the rules `skip`
/// (codes) not applied.
fn span(rules: &DensityRules, block: (u32, u32, u32), skip: &[&str]) -> Echelon {
    let (e, t, s) = block;
    let admits = |set: &[&'static Rule], m: &Term| {
        set.iter()
            .filter(|r| !skip.contains(&r.code))
            .all(|r| r.passes(m))
    };
    let one = |m: &crate::jet::JetMono| JetPoly::from([(m.clone(), Rational64::from_integer(1))]);
    let mut basis = Echelon::default();
    let lagrangian = jets(e + 1, t, s, false).into_iter().filter_map(|m| {
        let term = term_of(&m)?;
        admits(&rules.lagrangian, &term).then(|| euler_lagrange(&one(&m)))
    });
    let rayleigh = jets(e + 1, t + 1, s, false).into_iter().filter_map(|m| {
        let term = term_of(&m)?;
        admits(&rules.rayleigh, &term).then(|| space_euler(&one(&m)).remove(&1))?
    });
    for image in lagrangian.chain(rayleigh) {
        let (rest, _) = basis.reduce(big(&image), 0);
        basis.push(rest, Vec::new());
    }
    basis
}

/// Whether `span` reaches force `t`.
fn reaches(span: &Echelon, t: &Term) -> bool {
    span.reduce(big(&poly_of(t)), 0).0.is_empty()
}

/// The variational and Rayleigh forces among `forces` that no admitted density carries, each
/// with its `why` extended by the rules that strike its densities.
pub(super) fn uncarried(rules: &DensityRules, forces: &[(Term, Force)]) -> Vec<(Term, Force)> {
    let mut spans: BTreeMap<(u32, u32, u32), Echelon> = BTreeMap::new();
    let mut out = Vec::new();
    for (t, f) in forces {
        if !matches!(f.kind, ForceClass::Conservative | ForceClass::Dissipative) {
            continue;
        }
        let o = t.orders();
        let block = (o.epsilon, o.tau, o.sigma);
        let span = spans
            .entry(block)
            .or_insert_with(|| span(rules, block, &[]));
        if reaches(span, t) {
            continue;
        }
        let mut force = f.clone();
        let class = match f.kind {
            ForceClass::Dissipative => "of Rayleigh form",
            _ => "variational",
        };
        force.why = format!("{class}, yet {}", blame(rules, block, t, f.kind));
        out.push((t.clone(), force));
    }
    out
}

/// Which requirements strike every density that gives `t`, in one clause.
fn blame(rules: &DensityRules, block: (u32, u32, u32), t: &Term, kind: ForceClass) -> String {
    let (set, section) = match kind {
        ForceClass::Dissipative => (&rules.rayleigh, "[rayleigh]"),
        _ => (&rules.lagrangian, "[lagrangian]"),
    };
    let carried_without = |skip: &[&str]| reaches(&span(rules, block, skip), t);
    let mut alone: Vec<&'static Rule> = set
        .iter()
        .copied()
        .filter(|r| carried_without(&[r.code]))
        .collect();
    let together = alone.is_empty();
    if together {
        // No rule alone: an irreducible set, by dropping each rule the others do not need.
        alone = set.clone();
        for r in set {
            let rest: Vec<&str> = alone
                .iter()
                .filter(|x| x.code != r.code)
                .map(|x| x.code)
                .collect();
            if carried_without(&rest) {
                alone.retain(|x| x.code != r.code);
            }
        }
    }
    let Some(first) = alone.first() else {
        return format!("no density {section} admits gives it");
    };
    let codes: Vec<&str> = alone.iter().map(|r| r.code).collect();
    let how = match (&first.check, kind) {
        (Check::Symmetry(_), ForceClass::Dissipative) => {
            " (under the map such a density changes by a term with no variation in v, so the force keeps its form)"
        }
        (Check::Symmetry(_), _) => {
            " (under the map such a density changes by a total derivative, a boundary term in the action, so the force keeps its form)"
        }
        (Check::Structural(_), _) => "",
    };
    let verb = match (codes.len(), together) {
        (1, _) => "strikes",
        (_, true) => "together strike",
        (_, false) => "each strike",
    };
    format!(
        "{} in {section} {verb} every density that gives it{how}",
        codes.join(", ")
    )
}
