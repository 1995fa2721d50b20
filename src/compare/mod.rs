//! Two groups of animals compared (a mutant against the wild type, before and after a drug):
//! each animal fitted alone, the groups' means of each quantity, and their difference with an
//! interval and a p-value that treat the animal as the unit.
//!
//! **Quantities.** Per animal, from its own `fit`: the continuum constant (κ of a beam, c of a
//! string or ring, in body lengths and the data's time unit) and each mode's Ω and ζ, for the
//! modes every compared animal resolves. The three laws' verdicts are counted per group.
//!
//! **Difference.** For a quantity with values xₐᵢ in group a (nₐ animals), the estimate is
//! D = x̄_B − x̄_A, the unweighted means over animals (the population of animals is what a
//! biologist compares; an animal's measurement error is inside the spread between animals).
//! Its 95 % interval is Welch's, ± t₀.₉₇₅,ν √(s²_A/n_A + s²_B/n_B) with ν by Welch–Satterthwaite
//! (a percentile interval of animals resampled within each group undercovers ten-animal groups:
//! 17 of 20 in `tests/compare.rs`); its p-value tests "no difference" by permutation: the animals' group labels shuffled [`CompareSettings::permutations`] times,
//! p = (1 + #{|D*| ≥ |D|}) / (1 + P), exact under exchangeability whatever the distribution.
//! The ratio x̄_B / x̄_A is reported beside D.
//!
//! **Animals that cannot be fitted** (too short, no continuum constant) are listed with the
//! reason and left out; a group needs [`MIN_ANIMALS`] fitted animals.

mod report;

use rand::{RngExt, SeedableRng};
use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::discover::{discover, DiscoverError, DiscoverSettings, Source};
use crate::failure::Failure;
use crate::fit::{fit_inputs, FitError, FitReport, FitSettings, Input};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::Setting;

pub use report::{AnimalRow, CompareReport, Difference, Excluded, GroupSummary};

/// The fewest fitted animals a group needs (one cannot be resampled).
pub const MIN_ANIMALS: usize = 2;

/// At most this many permutations (each is a pass over the animals' values).
pub const MAX_PERMUTATIONS: usize = 1_000_000;

/// One group: its name and its animals' recordings (one animal each).
pub struct Group<'a> {
    /// Its name in the report.
    pub name: String,
    /// Its animals.
    pub inputs: Vec<Input<'a>>,
}

/// How the groups are compared.
#[derive(Debug, Clone)]
pub struct CompareSettings {
    /// Each animal's fit.
    pub fit: FitSettings,
    /// Label permutations for its p-value.
    pub permutations: usize,
    /// Seed of both.
    pub seed: u64,
    /// Also `discover` each animal and compare its equation's coefficients (a term its
    /// selection left out has coefficient 0 in its equation).
    pub discover: bool,
}

impl CompareSettings {
    /// Each animal's fit at its defaults, 9 999 permutations, seed 1.
    pub fn new(kind: crate::recording::InputKind) -> Self {
        CompareSettings {
            fit: FitSettings::new(kind),
            permutations: 9999,
            seed: 1,
            discover: false,
        }
    }

    /// One named setting: the comparison's own, or the recording's (`fit`'s recording
    /// options). `false` for a name that is neither.
    pub fn set(&mut self, name: &str, value: &Setting) -> Result<bool, CompareError> {
        let fit = |e: crate::recording::RecordingError| CompareError::Fit(e.into());
        match name {
            "permutations" => {
                self.permutations = value.count(name, MAX_PERMUTATIONS).map_err(fit)?
            }
            "seed" => self.seed = value.count(name, usize::MAX).map_err(fit)? as u64,
            "discover" => self.discover = value.switch(name).map_err(fit)?,
            _ => return self.fit.recording.set(name, value).map_err(fit),
        }
        Ok(true)
    }

    /// The settings from (name, value) pairs, each checked, then the whole: the one
    /// constructor both faces call. A name that is no option is refused.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, Setting)>,
    ) -> Result<CompareSettings, CompareError> {
        let mut settings = CompareSettings::new(crate::recording::InputKind::Midline);
        let unknown = |name| CompareError::Invalid(format!("compare has no option {name:?}"));
        crate::recording::apply_pairs(pairs, |n, v| settings.set(n, v), unknown)?;
        crate::fit::check_settings(&settings.fit)?;
        if settings.permutations == 0 {
            return Err(CompareError::Invalid(format!(
                "permutations 0: from 1 to {MAX_PERMUTATIONS}"
            )));
        }
        Ok(settings)
    }
}

/// Why the groups cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A setting out of range.
    #[error("{0}")]
    Invalid(String),
    /// Too few animals of a group could be fitted.
    #[error("group {group}: {fitted} of its {given} animal(s) could be fitted, and a comparison needs {MIN_ANIMALS} a group{}", why.as_ref().map_or(String::new(), |w| format!(" ({w})")))]
    TooFew {
        /// The group.
        group: String,
        /// Animals given.
        given: usize,
        /// Animals fitted.
        fitted: usize,
        /// Why the first one left out was.
        why: Option<String>,
    },
    /// A recording holds several animals: each must be its own file here.
    #[error(
        "{recording} holds {animals} animals: give each animal as its own file to compare groups"
    )]
    SeveralAnimals {
        /// The recording.
        recording: String,
        /// Its animals.
        animals: usize,
    },
    /// A recording that cannot be read (every animal's failure that is not the animal's own).
    #[error(transparent)]
    Fit(#[from] FitError),
}

impl CompareError {
    /// The kind of failure.
    pub fn failure(&self) -> Failure {
        match self {
            CompareError::Invalid(_) => Failure::Usage,
            CompareError::TooFew { .. } | CompareError::SeveralAnimals { .. } => Failure::Input,
            CompareError::Fit(e) => e.failure(),
        }
    }
}

/// One animal's values: κ (or c), then each compared mode's Ω and ζ.
struct Fitted {
    group: usize,
    name: String,
    report: FitReport,
    /// With `discover`: each library term's name and its coefficient in the discovered
    /// equation (0 where the selection left it out).
    terms: Vec<(String, f64)>,
}

/// Fit every animal of `groups` alone and compare the groups.
pub fn compare(
    groups: Vec<Group<'_>>,
    model: &Model,
    params: &Params,
    settings: &CompareSettings,
) -> Result<CompareReport, CompareError> {
    if groups.len() != 2 {
        return Err(CompareError::Invalid(format!(
            "compare takes two groups, not {}",
            groups.len()
        )));
    }
    let n = settings.permutations;
    if !(1..=MAX_PERMUTATIONS).contains(&n) {
        return Err(CompareError::Invalid(format!(
            "permutations {n}: from 1 to {MAX_PERMUTATIONS}"
        )));
    }
    for group in &groups {
        if let Some(Input::File(_)) = group
            .inputs
            .iter()
            .find(|i| matches!(i, Input::File(p) if p.as_os_str() == "-"))
        {
            return Err(CompareError::Invalid(
                "compare reads each animal from its own file: standard input (-) cannot be a group"
                    .into(),
            ));
        }
    }
    let mut fitted = Vec::new();
    let mut excluded = Vec::new();
    let mut names = Vec::new();
    for (g, group) in groups.into_iter().enumerate() {
        let given = group.inputs.len();
        let mut kept = 0;
        let mut first_why = None;
        for input in group.inputs {
            let name = input_name(&input);
            let source = discover_source(&input, settings)?;
            match fit_inputs(vec![input], model, params, &settings.fit, None) {
                Ok(report) if report.animals.len() > 1 => {
                    return Err(CompareError::SeveralAnimals {
                        recording: crate::markup::clip(&name),
                        animals: report.animals.len(),
                    })
                }
                Ok(report) if report.continuum.is_some() => {
                    match discovered(source, model, settings) {
                        Ok(terms) => {
                            kept += 1;
                            fitted.push(Fitted {
                                group: g,
                                name,
                                report,
                                terms,
                            });
                        }
                        Err(e) => {
                            let why = crate::markup::bound_line(&e.to_string());
                            first_why.get_or_insert(why.clone());
                            excluded.push(Excluded::new(&group.name, &name, why));
                        }
                    }
                }
                Ok(_) => {
                    let why = "the field has no continuum constant".to_string();
                    first_why.get_or_insert(why.clone());
                    excluded.push(Excluded::new(&group.name, &name, why));
                }
                // An animal's own data may fail its fit; a file that cannot be read fails all.
                Err(e) if e.failure() != Failure::Usage => {
                    let why = crate::markup::bound_line(&e.to_string());
                    first_why.get_or_insert(why.clone());
                    excluded.push(Excluded::new(&group.name, &name, why));
                }
                Err(e) => return Err(e.into()),
            }
        }
        if kept < MIN_ANIMALS {
            return Err(CompareError::TooFew {
                group: group.name,
                given,
                fitted: kept,
                why: first_why,
            });
        }
        names.push(group.name);
    }
    Ok(summarise(&fitted, names, excluded, settings))
}

/// What `discover` reads of `input` (with `--discover`): the same file or frames.
fn discover_source<'a>(
    input: &Input<'_>,
    settings: &CompareSettings,
) -> Result<Option<Source<'a>>, CompareError> {
    if !settings.discover {
        return Ok(None);
    }
    match input {
        Input::File(p) => Ok(Some(Source::File(p.clone()))),
        Input::Tracks(t) if t.len() == 1 => Ok(Some(Source::Track(t[0].clone()))),
        _ => Err(CompareError::Invalid(
            "compare --discover reads each animal from a file or one track".into(),
        )),
    }
}

/// Why an animal's equation could not be compared (it is left out, with this reason).
#[derive(Debug, thiserror::Error)]
pub enum Undiscovered {
    /// `discover` failed on it.
    #[error("discover: {0}")]
    Failed(#[from] DiscoverError),
    /// `discover` selected no term.
    #[error("discover: no model was selected")]
    NoModel,
}

/// The discovered equation's coefficients of `source` (none without `--discover`).
fn discovered(
    source: Option<Source<'_>>,
    model: &Model,
    settings: &CompareSettings,
) -> Result<Vec<(String, f64)>, Undiscovered> {
    let Some(source) = source else {
        return Ok(Vec::new());
    };
    let asked = DiscoverSettings {
        recording: settings.fit.recording.clone(),
        bootstrap: 0,
        seed: settings.seed,
        ..DiscoverSettings::new(settings.fit.recording.kind)
    };
    let report = discover(vec![source], model, &asked)?;
    if !report.library.iter().any(|t| t.selected) {
        return Err(Undiscovered::NoModel);
    }
    Ok(report
        .library
        .iter()
        .map(|t| (t.name.clone(), if t.selected { t.coefficient } else { 0.0 }))
        .collect())
}

fn input_name(input: &Input<'_>) -> String {
    match input {
        Input::File(p) => p.display().to_string(),
        Input::Reader { name, .. } => name.clone(),
        Input::Tracks(t) => t.first().map(|t| t.name.clone()).unwrap_or_default(),
    }
}

/// The modes every animal resolves (their Ω and ζ are compared).
fn common_modes(fitted: &[Fitted]) -> Vec<usize> {
    let resolved = |f: &Fitted| -> Vec<usize> {
        (f.report.modes_fit.iter())
            .filter(|m| m.resolved && m.omega.is_finite() && m.zeta.is_finite())
            .map(|m| m.mode)
            .collect()
    };
    let mut common = fitted.first().map(resolved).unwrap_or_default();
    for f in fitted {
        let own = resolved(f);
        common.retain(|m| own.contains(m));
    }
    common
}

/// Each compared quantity's name and its value per animal.
fn quantities(fitted: &[Fitted], modes: &[usize]) -> Vec<(String, Vec<f64>)> {
    let constant = fitted[0]
        .report
        .continuum
        .as_ref()
        .map_or("kappa", |c| c.name);
    let mut out = vec![(
        constant.to_string(),
        fitted
            .iter()
            .map(|f| f.report.continuum.as_ref().map_or(f64::NAN, |c| c.constant))
            .collect(),
    )];
    for &m in modes {
        let of = |f: &Fitted, pick: fn(&crate::fit::ModeSpectralFit) -> f64| {
            (f.report.modes_fit.iter())
                .find(|x| x.mode == m)
                .map_or(f64::NAN, pick)
        };
        out.push((
            format!("Omega_{m}"),
            fitted.iter().map(|f| of(f, |x| x.omega)).collect(),
        ));
        out.push((
            format!("zeta_{m}"),
            fitted.iter().map(|f| of(f, |x| x.zeta)).collect(),
        ));
    }
    // The coefficients of the terms some animal's equation has, in the library's order.
    let names: Vec<&String> = fitted[0].terms.iter().map(|(n, _)| n).collect();
    for (i, name) in names.into_iter().enumerate() {
        let values: Vec<f64> = fitted
            .iter()
            .map(|f| f.terms.get(i).map_or(f64::NAN, |t| t.1))
            .collect();
        if values.iter().any(|&v| v != 0.0) {
            out.push((name.clone(), values));
        }
    }
    out
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Welch's 95 % interval of `estimate` = x̄_b − x̄_a: ± t₀.₉₇₅,ν √(s²ₐ/nₐ + s²_b/n_b), ν by
/// Welch–Satterthwaite. (The percentile interval of animals resampled within each group
/// covered no difference in 17 of 20 pairs of 10-animal groups: a resampled mean's spread is
/// (n − 1)/n of the mean's variance and has no t tail.)
fn welch(a: &[f64], b: &[f64], estimate: f64) -> [f64; 2] {
    let share = |v: &[f64]| {
        let m = mean(v);
        let n = v.len() as f64;
        (
            v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n,
            n,
        )
    };
    let ((va, na), (vb, nb)) = (share(a), share(b));
    let se = (va + vb).sqrt();
    let nu = (va + vb).powi(2) / (va * va / (na - 1.0) + vb * vb / (nb - 1.0));
    let t = StudentsT::new(0.0, 1.0, nu)
        .map(|d| d.inverse_cdf(0.975))
        .unwrap_or(0.0);
    [estimate - t * se, estimate + t * se]
}

/// One group's 95 % interval of its mean: x̄ ± t₀.₉₇₅,ₙ₋₁ s/√n.
fn group_interval(v: &[f64]) -> [f64; 2] {
    let (m, n) = (mean(v), v.len() as f64);
    let s = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let t = StudentsT::new(0.0, 1.0, n - 1.0)
        .map(|d| d.inverse_cdf(0.975))
        .unwrap_or(f64::NAN);
    [m - t * s / n.sqrt(), m + t * s / n.sqrt()]
}

/// The difference of group means of `values` (`groups[i]` each animal's group), its
/// resampled percentile interval and its permutation p-value.
fn difference(
    name: &str,
    values: &[f64],
    groups: &[usize],
    settings: &CompareSettings,
) -> Difference {
    let split = |labels: &[usize]| -> [Vec<f64>; 2] {
        let mut out = [Vec::new(), Vec::new()];
        for (v, &g) in values.iter().zip(labels) {
            out[g].push(*v);
        }
        out
    };
    let [a, b] = split(groups);
    let estimate = mean(&b) - mean(&a);
    let interval = welch(&a, &b, estimate);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(settings.seed);
    let mut labels = groups.to_vec();
    let mut beyond = 0usize;
    for _ in 0..settings.permutations {
        // Fisher–Yates.
        for i in (1..labels.len()).rev() {
            labels.swap(i, rng.random_range(0..=i));
        }
        let [pa, pb] = split(&labels);
        if (mean(&pb) - mean(&pa)).abs() >= estimate.abs() * (1.0 - 1e-12) {
            beyond += 1;
        }
    }
    Difference {
        quantity: name.to_string(),
        means: [mean(&a), mean(&b)],
        group_intervals: [group_interval(&a), group_interval(&b)],
        estimate,
        interval,
        ratio: mean(&b) / mean(&a),
        p: (1 + beyond) as f64 / (1 + settings.permutations) as f64,
    }
}

fn summarise(
    fitted: &[Fitted],
    names: Vec<String>,
    excluded: Vec<Excluded>,
    settings: &CompareSettings,
) -> CompareReport {
    let modes = common_modes(fitted);
    let groups: Vec<usize> = fitted.iter().map(|f| f.group).collect();
    let quantities = quantities(fitted, &modes);
    let differences = quantities
        .iter()
        .map(|(name, values)| difference(name, values, &groups, settings))
        .collect();
    let animals = fitted
        .iter()
        .flat_map(|f| quantities.iter().map(move |(q, values)| (f, q, values)))
        .enumerate()
        .map(|(k, (f, q, values))| AnimalRow {
            group: names[f.group].clone(),
            animal: f.name.clone(),
            quantity: q.clone(),
            value: values[k / quantities.len()],
        })
        .collect();
    let summaries = names
        .iter()
        .enumerate()
        .map(|(g, name)| {
            GroupSummary::of(
                name,
                fitted.iter().filter(|f| f.group == g).map(|f| &f.report),
            )
        })
        .collect();
    let first = &fitted[0].report;
    CompareReport {
        constant: first.continuum.as_ref().map_or("kappa", |c| c.name),
        unit: first
            .continuum
            .as_ref()
            .map(|c| c.unit.clone())
            .unwrap_or_default(),
        field: first.field.clone(),
        modes,
        groups: summaries,
        differences,
        animals,
        excluded,
        permutations: settings.permutations,
        seed: settings.seed,
    }
}
