//! `discover`: the recording chooses the terms.
//!
//! **Library.** The engine's own: every coefficient of the observed field's equation at the
//! model's order and `beyond_leading` layers (conservative from L, dissipative from R), and with
//! `active` the `[active]` section's active and gyroscopic forces, each as the exact force the
//! discretised body integrates ([`crate::dynamics::library`]). No generic polynomial library.
//! Kinetic terms beyond ½(∂tφ)² are named but not estimated: they renormalise the mass, which
//! the weak form cannot tell from a rescaling of every other coefficient.
//!
//! **Estimators.** Where every candidate is linear and diagonal on the modes used (`linear`),
//! each mode's exact likelihood on the body's continuum modes and the coefficients by minimum
//! distance (`exact`, `galerkin`): any frame rate, lost frames skipped, coefficients the
//! continuum body's. Linear forces that couple the modes (an active ∂s³ or gyroscopic ∂t∂s
//! force on a free body): the modes' joint exact likelihood (`coupled`). Otherwise
//! (`--estimator weak`, or forces nonlinear): the weak form in time on the grid's modes, with instruments from earlier
//! windows and the state just before each window (two-stage least squares; see `weak`): unbiased under thermal (Langevin) noise and
//! white tracking noise for terms linear in the data; a nonlinear term's products of noisy
//! derivatives keep a bias of order (noise/signal)² in its own direction (not corrected).
//!
//! **Selection and scores** (`regress`): backward elimination over the library by the moment
//! criterion J/σ² + |S| ln n (Sargan's statistic and a BIC penalty); beside it the nested
//! theories (leading order passive; with the `beyond_leading` layers; with the active forces),
//! each scored by the same criterion and by the held-out moment residual over five contiguous
//! blocks of time, on the whole library's instruments. **Uncertainty:** a moving-block
//! bootstrap over time ([`regress::BLOCKS`] blocks, or whole animals when there are several):
//! each term's inclusion frequency (selection rerun per draw); with enough draws the reported
//! model is the median-probability one (the terms kept in more than half of them); the
//! 2.5–97.5 % percentiles of its coefficients.
//!
//! **Lengths** of a free chain are measured against the mean segment over the whole recording,
//! not `fit`'s first frame (`data`): a uniform strain offset would turn a cubic into a square.
//!
//! **Units.** Coefficients in body lengths (h = 1/(N − 1)) and the data's time unit, and on the
//! grid of N points (what `simulate --points N --param` takes). Inside, time is measured in
//! frames (`weak`), so no decision depends on the unit the time column is written in; each
//! coefficient is taken back to that unit at the end.

mod animals;
mod coupled;
mod data;
mod exact;
mod galerkin;
mod linear;
mod modes;
mod onward;
mod regress;
mod replay;
mod report;
mod verdict;
mod wald;
mod weak;

use std::io::BufRead;
use std::path::PathBuf;

pub use animals::{AnimalAnswer, AnimalTerm, CoefficientSpread};
pub use onward::{Onward, OnwardRefusal, MAX_PHASE_STEP};
pub use replay::{Replay, STEPS_PER_FRAME};
pub use report::{Comparison, DiscoverReport, DiscoveredTerm, Method, Selection};
pub use verdict::{Conclusion, Finding, Goodness, Verdict};

use crate::dynamics::nonlinear::NonlinearError;
use crate::dynamics::{library, Candidate};
use crate::equations::{derive_nonlinear_each, NonlinearEquation};
use crate::fit::{FitError, FitSettings, Input};
use crate::model::Model;
use crate::recording::{InputKind, RecordingSettings, Setting};

/// At most this many bootstrap draws.
pub const MAX_DRAWS: usize = 10_000;

/// At most this many recordings: each is fitted on its own (its modes' spectra, 0.05–0.3 s
/// for a few thousand frames, about a second for 10⁶) and estimated alone (the 38 larvae of
/// docs/discover.md: 0.1–0.5 s each with 200 draws), before they are pooled.
pub const MAX_RECORDINGS: usize = 100;

/// Settings of `discover`.
#[derive(Debug, Clone)]
pub struct DiscoverSettings {
    /// How the recordings are read and projected (`order` is the theory's).
    pub recording: RecordingSettings,
    /// Include the `[active]` section's forces in the library.
    pub active: bool,
    /// Bootstrap draws (0: no intervals).
    pub bootstrap: usize,
    /// Seed of the draws.
    pub seed: u64,
    /// Simulate the discovered equation and read it back (`replay`), for the figure.
    pub replay: bool,
    /// Which estimator (`auto`: the exact likelihood where the library allows it).
    pub estimator: Estimator,
}

/// `discover`'s estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Estimator {
    /// The exact likelihood where every candidate is linear and diagonal on the modes, else
    /// the weak form.
    Auto,
    /// The weak form in time on the grid's modes (coefficients the grid's).
    Weak,
    /// The exact likelihood, or a refusal saying why it does not apply.
    Exact,
}

impl DiscoverSettings {
    /// Defaults for `kind`: the recording's ([`RecordingSettings::new`]), the passive library,
    /// 200 draws, seed 1, no replay.
    pub fn new(kind: InputKind) -> Self {
        DiscoverSettings {
            recording: RecordingSettings::new(kind),
            active: false,
            bootstrap: 200,
            seed: 1,
            replay: false,
            estimator: Estimator::Auto,
        }
    }

    /// Set the option `name` (Python's keyword; the command line's flag with `_` for `-`) to
    /// `value`, checked; a recording option goes to [`RecordingSettings::set`]. `Ok(false)`:
    /// no such option.
    pub fn set(&mut self, name: &str, value: &Setting) -> Result<bool, DiscoverError> {
        let fit = |e: crate::recording::RecordingError| DiscoverError::Fit(e.into());
        match name {
            "active" => self.active = value.switch(name).map_err(fit)?,
            "bootstrap" => self.bootstrap = value.count(name, MAX_DRAWS).map_err(fit)?,
            "seed" => self.seed = value.count(name, usize::MAX).map_err(fit)? as u64,
            "estimator" => {
                let choices = [
                    ("auto", Estimator::Auto),
                    ("weak", Estimator::Weak),
                    ("exact", Estimator::Exact),
                ];
                self.estimator = value.choice(name, &choices).map_err(fit)?
            }
            _ => return self.recording.set(name, value).map_err(fit),
        }
        Ok(true)
    }

    /// The settings from (name, value) pairs, each checked, then the whole: the one
    /// constructor both faces call. A name that is no option is refused.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, Setting)>,
    ) -> Result<DiscoverSettings, DiscoverError> {
        let mut settings = DiscoverSettings::new(InputKind::Midline);
        let unknown = |name| {
            let why = format!("discover has no option {name:?}");
            DiscoverError::Fit(FitError::Invalid(why))
        };
        crate::recording::apply_pairs(pairs, |n, v| settings.set(n, v), unknown)?;
        settings
            .recording
            .check()
            .map_err(|e| DiscoverError::Fit(e.into()))?;
        Ok(settings)
    }

    /// The settings `fit` reads and projects each recording with.
    pub(super) fn fit(&self) -> FitSettings {
        FitSettings {
            recording: self.recording.clone(),
            ..FitSettings::new(self.recording.kind)
        }
    }
}

/// One recording to read.
pub enum Source<'a> {
    /// A file.
    File(PathBuf),
    /// A named stream.
    Reader(String, Box<dyn BufRead + Send + 'a>),
    /// One animal's frames held in memory (Python's arrays).
    Track(crate::recording::Track),
}

/// Why `discover` cannot answer.
#[derive(Debug, thiserror::Error)]
pub enum DiscoverError {
    /// Reading or projecting a recording failed.
    #[error(transparent)]
    Fit(FitError),
    /// The library could not be built.
    #[error(transparent)]
    Library(#[from] NonlinearError),
    /// The discovered body cannot be simulated.
    #[error("the discovered equation cannot be replayed: {0}")]
    Replay(Box<crate::body::BodyError>),
    /// The equations could not be derived.
    #[error(transparent)]
    Equations(#[from] crate::equations::EquationError),
    /// `--active` for a model without an `[active]` section.
    #[error("--active: the model {model} has no [active] section, so it allows no active forces")]
    NoActive {
        /// Model name.
        model: String,
    },
    /// The observations cover part of a ring.
    #[error("the recording covers part of a ring: the grid's modes are not all determined, so the forces cannot be evaluated (discover needs the whole body)")]
    PartialRing,
    /// Too many values to hold.
    #[error("the recording holds more than {max} values (frames × points): discover keeps every posture in memory; use fewer frames or points")]
    TooLarge {
        /// The limit.
        max: usize,
    },
    /// No mode's time scales are determined.
    #[error("no mode of {recording} has its time scales resolved: the lowest mode's Ω and ζ are determined neither by fit's spectrum nor by the mode's own exact likelihood (Ω to 10 %, ζ to 20 %, not on an over-damped ridge; fit says why for each mode)")]
    NoResolvedMode {
        /// The recording.
        recording: String,
    },
    /// The field has no coefficient to estimate.
    #[error("field {field} has no coefficient to estimate at this order")]
    EmptyLibrary {
        /// The field.
        field: String,
    },
    /// Too few windows for the instruments.
    #[error("{rows} windows of the weak form, too few for {needed} (the library's {terms} terms and their instruments): record longer, or at a higher frame rate")]
    TooFewRows {
        /// Rows available.
        rows: usize,
        /// Rows needed.
        needed: usize,
        /// Library terms.
        terms: usize,
    },
    /// The instruments do not determine the coefficients.
    #[error("the earlier windows do not determine the {terms} coefficients (the instruments are degenerate): the recording may be too regular or too short")]
    Degenerate {
        /// Library terms.
        terms: usize,
    },
    /// A coefficient or the noise is beyond the floats in the data's time unit.
    #[error("the discovered coefficients are beyond the floating-point range in the data's time unit (Δt = {dt}): rescale the time column")]
    OutOfRange {
        /// The sampling interval, as printed.
        dt: String,
    },
    /// The weak form's sums are not finite (the postures overflow them).
    #[error("the weak form's sums of the recording are not finite (the postures' values overflow them): rescale the recording")]
    NonFinite,
    /// More recordings than [`MAX_RECORDINGS`].
    #[error("{count} recordings: discover fits and estimates each one on its own (up to a few seconds each), so it takes at most {MAX_RECORDINGS}; pool them in fewer files, or use fit for many animals")]
    TooManyRecordings {
        /// How many were given.
        count: usize,
    },
    /// The weak form's sums over the library are over their budget.
    #[error("the weak form's sums are {work:.1e} units of work (frames × points × modes used × {terms} library terms), over the budget of {:.0e} (about ten seconds): use fewer points, frames or recordings, a lower --order or fewer beyond_leading layers", weak::MAX_WORK)]
    WeakBudget {
        /// frames × points × modes × terms.
        work: f64,
        /// Library terms.
        terms: usize,
    },
    /// `--estimator exact` where the exact likelihood does not apply.
    #[error("--estimator exact: {why}, so only the weak form applies (--estimator weak)")]
    ExactUnavailable {
        /// Why.
        why: String,
    },
    /// Too many bootstrap draws.
    #[error("--bootstrap takes at most {MAX_DRAWS} draws, not {0}")]
    Draws(usize),
}

impl DiscoverError {
    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            DiscoverError::Fit(e) => e.failure(),
            DiscoverError::Library(e) => e.failure(),
            DiscoverError::Replay(e) => e.failure(),
            DiscoverError::Equations(_)
            | DiscoverError::NoActive { .. }
            | DiscoverError::PartialRing
            | DiscoverError::Draws(_)
            | DiscoverError::TooManyRecordings { .. }
            | DiscoverError::WeakBudget { .. }
            | DiscoverError::ExactUnavailable { .. }
            | DiscoverError::EmptyLibrary { .. } => Failure::Usage,
            DiscoverError::TooLarge { .. }
            | DiscoverError::NoResolvedMode { .. }
            | DiscoverError::TooFewRows { .. }
            | DiscoverError::Degenerate { .. }
            | DiscoverError::OutOfRange { .. }
            | DiscoverError::NonFinite => Failure::Input,
        }
    }
}

impl From<crate::body::BodyError> for DiscoverError {
    fn from(e: crate::body::BodyError) -> Self {
        DiscoverError::Replay(Box::new(e))
    }
}

/// One library with its rows.
struct Theory {
    label: String,
    candidates: Vec<Candidate>,
    rows: weak::Rows,
}

/// The observed field's candidates of `library` (with the `[active]` section's forces or
/// without), and its kinetic coefficients beyond ½(∂tφ)²: those renormalise the mass, which
/// the weak form cannot tell from a rescaling of every other coefficient, so they are named
/// (`not_estimated`) but not regressed.
fn candidates(library: &[Candidate], active: bool) -> (Vec<Candidate>, Vec<String>) {
    let (kinetic, rest): (Vec<&Candidate>, Vec<&Candidate>) =
        library.iter().partition(|c| c.kinetic);
    let kept = rest
        .into_iter()
        .filter(|c| active || !c.entering)
        .cloned()
        .collect();
    (kept, kinetic.into_iter().map(|c| c.name.clone()).collect())
}

/// Discover the terms `sources` need.
pub fn discover(
    sources: Vec<Source<'_>>,
    model: &Model,
    settings: &DiscoverSettings,
) -> Result<DiscoverReport, DiscoverError> {
    if settings.bootstrap > MAX_DRAWS {
        return Err(DiscoverError::Draws(settings.bootstrap));
    }
    if settings.active && model.active.is_none() {
        return Err(DiscoverError::NoActive {
            model: crate::markup::clip(&model.name),
        });
    }
    // Postures need only the grid's modes: the leading order's operator, whatever the layers.
    let mut leading = model.clone();
    leading.set_beyond_leading(0);
    let fit = settings.fit();
    if sources.len() > MAX_RECORDINGS {
        return Err(DiscoverError::TooManyRecordings {
            count: sources.len(),
        });
    }
    let several = sources.len() > 1;
    let mut unread: Vec<animals::AnimalAnswer> = Vec::new();
    let mut recordings: Vec<data::Recording> = Vec::new();
    for source in sources {
        let (input, name) = match source {
            Source::File(p) => {
                let name = p.display().to_string();
                (Input::File(p), name)
            }
            Source::Reader(name, reader) => (
                Input::Reader {
                    name: name.clone(),
                    reader,
                },
                name,
            ),
            Source::Track(track) => {
                let name = track.name.clone();
                (Input::Tracks(vec![track]), name)
            }
        };
        let held = recordings.iter().map(data::Recording::values).sum();
        match data::read(input, name.clone(), &leading, &fit, held) {
            Ok(r) => recordings.push(r),
            // One unreadable animal among several is skipped with its reason.
            Err(e) if several && !matches!(e, DiscoverError::TooLarge { .. }) => {
                unread.push(animals::AnimalAnswer::refused(&name, e.to_string()));
            }
            Err(e) => return Err(e),
        }
    }
    if recordings.is_empty() {
        if let Some(why) = unread.first().and_then(|a| a.refused.clone()) {
            return Err(DiscoverError::Fit(FitError::Invalid(why)));
        }
    }
    let Some(first) = recordings.first() else {
        return Err(DiscoverError::Fit(FitError::Invalid(
            "no recordings to fit".into(),
        )));
    };
    let field = first.fit.field.clone();
    let points = first.fit.model_points;
    // The nested theories: leading order passive; the model's layers; with active forces.
    let mut nested = vec![("leading order, passive".to_string(), leading.clone(), false)];
    let layers = model
        .lagrangian
        .beyond_leading
        .max(model.rayleigh.beyond_leading);
    if layers > 0 {
        nested.push((
            format!("+ {layers} order(s) beyond leading"),
            model.clone(),
            false,
        ));
    }
    if settings.active {
        nested.push(("+ active forces".to_string(), model.clone(), true));
    }
    let mut libraries: Vec<(String, Vec<Candidate>)> = Vec::new();
    let mut not_estimated = Vec::new();
    // One library per distinct model (the layers' and the active theory's are the same).
    let mut built: Option<(Model, Vec<Candidate>)> = None;
    for (label, m, active) in nested {
        let all = match &built {
            Some((b, all)) if *b == m => all.clone(),
            _ => library(&m, settings.recording.order, points, &field)?,
        };
        // The last theory is the whole library: its kinetic terms are the ones named.
        let (candidates, kinetic) = candidates(&all, active);
        built = Some((m, all));
        not_estimated = kinetic;
        libraries.push((label, candidates));
    }
    let Some((_, whole)) = libraries.last() else {
        return Err(DiscoverError::EmptyLibrary { field });
    };
    if whole.is_empty() {
        return Err(DiscoverError::EmptyLibrary { field });
    }
    let each;
    let why = match settings.estimator {
        Estimator::Weak => {
            each = unread;
            "--estimator weak".to_string()
        }
        _ => {
            let names: linear::Nested = libraries
                .iter()
                .map(|(l, c)| (l.clone(), c.iter().map(|c| c.name.clone()).collect()))
                .collect();
            let whole = (whole.as_slice(), &names);
            each = animals::alone(&mut recordings, model, settings, whole, &field, unread);
            match linear::estimate(&recordings, model, settings, whole.0, &names, &field)? {
                Ok(report) => {
                    let report = animals::attach(report, each);
                    return finish(report, &recordings, model, settings, not_estimated);
                }
                Err(why) if settings.estimator == Estimator::Exact => {
                    return Err(DiscoverError::ExactUnavailable {
                        why: why.to_string(),
                    })
                }
                Err(why) => why.to_string(),
            }
        }
    };
    // The weak form pools the animals with a mode it can use; the others are refused alone.
    let usable = |r: &data::Recording| weak::used(r).next().is_some();
    if !recordings.iter().any(usable) || recordings.len() == 1 {
        if let Some(r) = recordings.iter().find(|r| !usable(r)) {
            return Err(DiscoverError::NoResolvedMode {
                recording: crate::markup::clip(&r.name),
            });
        }
    }
    recordings.retain(usable);
    let mut theories = Vec::new();
    for (label, candidates) in libraries {
        weak::check_work(&recordings, candidates.len())?;
        let rows = weak::rows(&recordings, &candidates);
        theories.push(Theory {
            label,
            candidates,
            rows,
        });
    }
    let Some((full, nested)) = theories.split_last_mut() else {
        return Err(DiscoverError::EmptyLibrary { field });
    };
    // Every theory is scored on the whole library's instruments and weights (the rows are
    // the same windows), so their criteria compare.
    let all: Vec<usize> = (0..full.candidates.len()).collect();
    let gram = regress::Gram::new(&full.rows, &vec![1.0; full.rows.len()]);
    if let Some((beta, _)) = gram.fit(&all) {
        full.rows.reweight(&all, &beta);
    }
    for t in nested {
        t.rows.instruments.clone_from(&full.rows.instruments);
        t.rows.weight.clone_from(&full.rows.weight);
    }
    let mut report = report::assemble(&recordings, model, settings, &theories, &field)?;
    report.method = Method::WeakForm { why };
    let report = animals::attach(report, each);
    finish(report, &recordings, model, settings, not_estimated)
}

/// The onward line and the replay of a report.
fn finish(
    mut report: DiscoverReport,
    recordings: &[data::Recording],
    model: &Model,
    settings: &DiscoverSettings,
    not_estimated: Vec<String>,
) -> Result<DiscoverReport, DiscoverError> {
    let mut leading = model.clone();
    leading.set_beyond_leading(0);
    let fit = settings.fit();
    report.not_estimated = not_estimated;
    let held = (recordings.iter())
        .filter_map(|r| r.fit.held_movement)
        .max_by(f64::total_cmp);
    report.verdict = Some(verdict::Verdict::of(
        &report,
        model,
        settings.recording.order,
        held,
    ));
    if let Selection::NoModel { .. } = report.selection {
        report.equation = "none: no term was kept in more than half of the draws".into();
        report.onward_refused = Some("no model was selected".into());
        return Ok(report);
    }
    // What simulate refuses is never printed: the body the line makes, then its replay.
    let onward = replay::discovered_body(model, settings.recording.order, &report.library)
        .map_err(|e| OnwardRefusal::Simulate(crate::markup::one_line(&e.to_string())))
        .and_then(|body| onward::onward(&report, &recordings[0], model, &body));
    match onward {
        Ok(o) => report.onward = Some(o),
        Err(why) => report.onward_refused = Some(why.to_string()),
    }
    if settings.replay && report.onward_refused.is_none() {
        let modes: Vec<usize> = report.modes.iter().map(|m| m.0).collect();
        let rec = &recordings[0];
        report.replay = Some(replay::replay(
            rec,
            model,
            &leading,
            &fit,
            &report.library,
            &modes,
            report.onward.as_ref(),
        )?);
    }
    Ok(report)
}

/// Each coefficient's term as `equations` prints it (`−c_y ∂s⁴ y`), and the equation of a set
/// of them.
pub(super) struct Notation {
    derived: crate::equations::Derivation<NonlinearEquation>,
    field: String,
}

impl Notation {
    fn new(model: &Model, order: u32, field: &str) -> Result<Notation, DiscoverError> {
        Ok(Notation {
            // The general derivation: one notation for linear and nonlinear bodies alike.
            derived: derive_nonlinear_each(model, order, crate::enumerate::Basis::Powers)?,
            field: field.to_string(),
        })
    }

    /// `∂t² y = …` with only the coefficients in `keep`.
    pub(super) fn equation(&self, keep: &[&str]) -> String {
        let found = self
            .derived
            .equations
            .iter()
            .find(|e| e.field.id == self.field);
        found.map_or_else(String::new, |e| {
            let mut e = e.clone();
            e.rhs.retain(|t| keep.contains(&t.coefficient.as_str()));
            e.text()
        })
    }

    /// One coefficient's terms, without the left-hand side.
    pub(super) fn term(&self, name: &str) -> String {
        let e = self.equation(&[name]);
        e.split_once(" = ")
            .map_or(e.clone(), |(_, r)| r.to_string())
    }
}
