//! One field's forces: its covariant candidates classified, the active ones reduced to a
//! basis block by block (`basis`), the variational and Rayleigh ones no admitted density
//! carries (`carried`), and the lowest layers of each class listed.

use std::collections::BTreeMap;

use super::basis::{self, Dependent};
use super::{allows, carried, classify, FieldForces, Force, ForceClass};
use crate::model::{DensitySpec, Uncarried};
use crate::rules::Rule;
use crate::term::{Orders, Term};

/// The candidates every rule `spec` requires of field `id` allows.
pub(super) fn covariant_of<'a>(
    spec: &DensitySpec,
    id: &str,
    candidates: &'a [Term],
) -> Vec<&'a Term> {
    // The model refuses KIN and DIS here (rules about densities).
    let rules: Vec<&'static Rule> = spec
        .requirements
        .get(id)
        .into_iter()
        .flatten()
        .filter_map(|c| crate::rules::rule(c))
        .collect();
    candidates
        .iter()
        .filter(|t| rules.iter().all(|r| allows(r, t)))
        .collect()
}

pub(super) fn field_forces(
    spec: &DensitySpec,
    (id, symbol): (&str, &str),
    rules: &carried::DensityRules,
    candidates: usize,
    covariant: &[&Term],
) -> FieldForces {
    let name = |_: u8| symbol.to_string();
    let mut counts = [0; 4];
    let mut by_class: Vec<(Term, Force)> = Vec::new();
    for t in covariant {
        let f = classify(t, &name);
        counts[f.kind as usize] += 1;
        by_class.push(((*t).clone(), f));
    }
    // The active monomials, reduced to a basis block by block (`basis`).
    let mut blocks: BTreeMap<(u32, u32, u32), Vec<Term>> = BTreeMap::new();
    for (t, f) in &by_class {
        if f.kind == ForceClass::Active {
            let o = t.orders();
            blocks
                .entry((o.epsilon, o.tau, o.sigma))
                .or_default()
                .push(t.clone());
        }
    }
    // Which forces add no direction, every block modulo a prime (fast); the blocks whose
    // forces are listed again exactly, for the combinations the report prints.
    let mut gone: Vec<Term> = Vec::new();
    for terms in blocks.values() {
        gone.extend(
            basis::dependent_modulo_prime(terms)
                .into_iter()
                .map(|i| terms[i].clone()),
        );
    }
    let without = |gone: &[Term]| -> Vec<(Term, Force)> {
        let mut list = by_class.clone();
        list.retain(|(t, _)| !gone.contains(t));
        list
    };
    let block = |o: Orders| (o.epsilon, o.tau, o.sigma);
    let render = |t: &Term| t.render(&name);
    let mut dependent: Vec<(Term, Dependent)> = Vec::new();
    let listed_blocks: std::collections::BTreeSet<_> = lowest_layers(
        &without(&gone),
        Some(ForceClass::Active),
        spec.beyond_leading,
    )
    .iter()
    .map(|(t, _)| block(t.orders()))
    .collect();
    for key in &listed_blocks {
        let terms = &blocks[key];
        let (kept, words) = basis::reduce_block(terms, &render);
        let dropped = (0..terms.len()).filter(|i| !kept.contains(i));
        gone.retain(|t| block(t.orders()) != *key);
        for (i, d) in dropped.zip(words) {
            gone.push(terms[i].clone());
            dependent.push((terms[i].clone(), d));
        }
    }
    counts[ForceClass::Active as usize] -= gone.len();
    by_class = without(&gone);
    let uncarried = carried::uncarried(rules, &by_class);
    let lowest_of = |list: &[(Term, Force)], kind: Option<ForceClass>| -> Vec<Force> {
        let list = lowest_layers(list, kind, spec.beyond_leading);
        list.into_iter().map(|(_, f)| f).collect()
    };
    let lowest = |kind: ForceClass| lowest_of(&by_class, Some(kind));
    let named = |letter: &str, mut list: Vec<Force>| {
        let several = list.len() > 1;
        for (k, f) in list.iter_mut().enumerate() {
            f.coefficient = Some(match several {
                true => format!("{letter}{}_{symbol}", k + 1),
                false => format!("{letter}_{symbol}"),
            });
        }
        list
    };
    let active = lowest(ForceClass::Active);
    let listed: Vec<_> = active.iter().map(|f| block(f.orders)).collect();
    FieldForces {
        field: id.to_string(),
        candidates,
        covariant: covariant.len(),
        counts,
        active: named("a", active),
        gyroscopic: named("g", lowest(ForceClass::Gyroscopic)),
        uncarried: match spec.uncarried {
            Uncarried::Enter => named("b", lowest_of(&uncarried, None)),
            Uncarried::List => lowest_of(&uncarried, None),
        },
        dependent: dependent
            .into_iter()
            .filter(|(t, _)| listed.contains(&block(t.orders())))
            .map(|(_, d)| d)
            .collect(),
    }
}

/// The forces of `list` of class `kind` (any with `None`) in the lowest `beyond` + 1 layers of
/// their orders.
fn lowest_layers(
    list: &[(Term, Force)],
    kind: Option<ForceClass>,
    beyond: u32,
) -> Vec<(Term, Force)> {
    let of_kind = |f: &Force| kind.is_none_or(|k| f.kind == k);
    let terms: Vec<Term> = list
        .iter()
        .filter(|(_, f)| of_kind(f))
        .map(|(t, _)| t.clone())
        .collect();
    let kept: std::collections::HashSet<Term> =
        crate::reduce::layers(&terms, beyond).into_iter().collect();
    list.iter()
        .filter(|(t, f)| of_kind(f) && kept.contains(t))
        .cloned()
        .collect()
}
