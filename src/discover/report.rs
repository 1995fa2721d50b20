//! The discovered equation, its library, the nested theories and their scores, and the
//! onward `simulate` line: text, JSON and CSV.

use serde::Serialize;

use super::data::Recording;
use super::regress::{cross_validated, draw, generator, percentiles, Gram};
use super::weak::{in_data_unit, time_unit};
use super::{DiscoverError, DiscoverSettings, Notation, Theory};
use crate::equations::ForceKind;
use crate::model::Model;
use crate::report::{number, Report};

/// Held-out folds of time for the cross-validated residual.
pub const FOLDS: usize = 5;

/// One candidate term and what the recording says of it.
#[derive(Debug, Clone, Serialize)]
pub struct DiscoveredTerm {
    /// Its terms in the equation, as `equations` prints them (`−c_y ∂s⁴ y`).
    pub term: String,
    /// The coefficient's name.
    pub name: String,
    /// Conservative, dissipative or active.
    pub kind: ForceKind,
    /// The coefficient in body lengths and the data's time unit: the selected model's value
    /// for a selected term, the whole library's fit otherwise.
    pub coefficient: f64,
    /// The same on the grid of [`DiscoverReport::replay_points`] points (what `simulate
    /// --points` takes there): for the exact estimator on continuum modes, the grid's
    /// coefficient whose body comes nearest the continuum estimate's modes
    /// (`galerkin::nearest_on_grid`), not a change of unit.
    pub on_points: f64,
    /// 95 % bootstrap interval (body lengths), for a selected term with draws.
    pub interval: Option<[f64; 2]>,
    /// Share of bootstrap draws whose selection kept it.
    pub inclusion: Option<f64>,
    /// Kept by the selection.
    pub selected: bool,
}

/// One nested theory's scores.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// Which theory.
    pub model: String,
    /// Its coefficients.
    pub terms: Vec<String>,
    /// Held-out moment objective per row over [`FOLDS`] blocks of time, in units of the
    /// whole library's residual variance (`regress::cross_validated`): small when the theory
    /// holds every force present.
    pub cv_residual: Option<f64>,
    /// J/σ² + k ln n (Sargan's statistic plus a BIC penalty; lower is better).
    pub criterion: Option<f64>,
}

/// What `discover` found.
#[derive(Debug, Clone, Serialize)]
pub struct DiscoverReport {
    /// The recordings.
    pub recordings: Vec<String>,
    /// The observed field.
    pub field: String,
    /// Model points N.
    pub points: usize,
    /// The grid `on_points` and the onward line are for: N, or for coefficients of the
    /// continuum at least [`super::galerkin::REPLAY_POINTS`] (the lattice's own lowest shapes
    /// at 12 points, read through the continuum projector, lose 7 % of their variance).
    pub replay_points: usize,
    /// Frames used (every run).
    pub frames: usize,
    /// The theory's order.
    pub order: u32,
    /// Orders beyond the leading one in the library.
    pub beyond_leading: u32,
    /// Active forces in the library.
    pub active: bool,
    /// Each mode used and its windows' half-width in frames (per recording, the first's).
    pub modes: Vec<(usize, usize)>,
    /// Rows of the weak form.
    pub rows: usize,
    /// The estimator, in one line.
    pub estimator: String,
    /// Which estimator ran, and why that one.
    pub method: Method,
    /// The discovered equation in the notation of `equations`.
    pub equation: String,
    /// The selected terms.
    pub selected: Vec<DiscoveredTerm>,
    /// Every candidate.
    pub library: Vec<DiscoveredTerm>,
    /// The nested theories and the selection, scored.
    pub comparison: Vec<Comparison>,
    /// 1 − RSS/Σy² of the selected model (weighted rows).
    pub r2: f64,
    /// Force-noise intensity q of the residual, ⟨ξ(t)ξ(t′)⟩ = q δ(t − t′) per point (body
    /// lengths² per time³): the Langevin part's temperature times its damping, with any
    /// tracking noise's share.
    pub noise: f64,
    /// Bootstrap draws.
    pub bootstrap: usize,
    /// Their seed.
    pub seed: u64,
    /// Which rule chose the reported terms.
    pub selection: Selection,
    /// The selected theory's misfit to the modes (exact estimator).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goodness: Option<super::verdict::Goodness>,
    /// Whether the theory holds here (set by `discover` once the report is whole).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<super::verdict::Verdict>,
    /// The sampling interval.
    pub dt: f64,
    /// The data's time unit when it was given (`--time-unit`, or a WCON file's own).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_unit: Option<String>,
    /// The model as the onward `simulate` line names it (set by the caller).
    pub model_argument: Option<String>,
    /// The recordings and reading options as the command line gave them (set by the caller):
    /// the `Next:` command starts from them.
    #[serde(skip)]
    pub inputs: Vec<String>,
    /// Kinetic coefficients beyond ½(∂tφ)²: in the library, not estimated (they renormalise
    /// the mass, which the weak form cannot tell from a rescaling of every other coefficient);
    /// the onward line sets them to 0.
    pub not_estimated: Vec<String>,
    /// The discovered equation simulated and read back (when asked).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replay: Option<super::Replay>,
    /// How the onward `simulate` line replays the recording (set by `discover` when
    /// `simulate` takes the discovered equation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub onward: Option<super::onward::Onward>,
    /// Why `simulate` would refuse the discovered equation (no onward line is printed then).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub onward_refused: Option<String>,
    /// Several recordings: each animal's answer alone (`animals`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub animals: Vec<super::animals::AnimalAnswer>,
    /// Several recordings: how each pooled coefficient differs between them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub between: Vec<super::animals::CoefficientSpread>,
}

/// Which estimator ran.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The exact likelihood (`exact`): every candidate linear and diagonal on the modes.
    Exact,
    /// The modes' joint exact likelihood (`coupled`): linear forces that couple the modes.
    Joint,
    /// The weak form (`weak`), and why not the exact likelihood.
    WeakForm {
        /// Why the exact likelihood did not run.
        why: String,
    },
}

const ESTIMATOR: &str = "weak form in time on the grid's modes, bumps (1 − τ²)⁸, two-stage least squares with the two previous windows and the state just before as instruments";

/// The fewest bootstrap draws whose inclusion frequencies choose the model.
pub const MEDIAN_DRAWS: usize = 20;

/// Which rule chose the reported terms.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "rule", rename_all = "snake_case")]
pub enum Selection {
    /// The median-probability model (Barbieri & Berger 2004): the terms kept in more than half
    /// of the draws' selections.
    MedianProbability,
    /// Fewer than [`MEDIAN_DRAWS`] draws: the whole recording's backward elimination.
    Elimination,
    /// Enough draws, and no term kept in more than half of them: no model.
    NoModel {
        /// The most often kept term and its share of the draws.
        best: Option<(String, f64)>,
    },
}

/// The reported terms and the rule that chose them, from each term's inclusion count over
/// `draws` and the whole recording's `elimination`. A term the whole recording's selection
/// keeps by a small margin of its criterion, which most resamples drop, is noise the
/// criterion's scale did not expect (on nearly noise-free recordings a tracking-noise bias is
/// "significant"): with enough draws they decide, and when none keeps any term in more than
/// half, no model is reported (never the elimination's pick in its place).
pub(super) fn choose(
    included: &[usize],
    draws: usize,
    elimination: &[usize],
    names: &[String],
) -> (Vec<usize>, Selection) {
    if draws < MEDIAN_DRAWS {
        return (elimination.to_vec(), Selection::Elimination);
    }
    let set: Vec<usize> = (0..included.len())
        .filter(|&i| 2 * included[i] > draws)
        .collect();
    if !set.is_empty() {
        return (set, Selection::MedianProbability);
    }
    let best = (0..included.len())
        .max_by_key(|&i| included[i])
        .filter(|&i| included[i] > 0)
        .map(|i| (names[i].clone(), included[i] as f64 / draws as f64));
    (Vec::new(), Selection::NoModel { best })
}

/// Fit, select, score and bootstrap the theories (the last is the whole library).
pub(super) fn assemble(
    recordings: &[Recording],
    model: &Model,
    settings: &DiscoverSettings,
    theories: &[Theory],
    field: &str,
) -> Result<DiscoverReport, DiscoverError> {
    let full = theories.last().expect("at least one theory");
    let p = full.candidates.len();
    let rows = &full.rows;
    let q = rows.instruments.first().map_or(0, Vec::len);
    let needed = q + p + 10;
    if rows.len() < needed {
        return Err(DiscoverError::TooFewRows {
            rows: rows.len(),
            needed,
            terms: p,
        });
    }
    let all: Vec<usize> = (0..p).collect();
    let gram = Gram::new(rows, &vec![1.0; rows.len()]);
    if !gram.finite() {
        return Err(DiscoverError::NonFinite);
    }
    let (whole, _) = gram
        .fit(&all)
        .ok_or(DiscoverError::Degenerate { terms: p })?;
    // Every theory's criterion in units of the whole library's residual variance.
    let sigma2 = gram
        .variance(&all)
        .ok_or(DiscoverError::Degenerate { terms: p })?;
    // The bootstrap: inclusion by rerunning the selection; the median-probability model;
    // intervals of its terms (the draws again, from the same seed, when it is not the
    // whole recording's selection).
    let elimination = gram.select(&all);
    let mut included = vec![0usize; p];
    let mut draws: Vec<Vec<f64>> = vec![Vec::new(); elimination.len()];
    let resample = |each: &mut dyn FnMut(&Gram)| {
        let mut rng = generator(settings.seed);
        for _ in 0..settings.bootstrap {
            each(&Gram::new(rows, &draw(rows, recordings.len(), &mut rng)));
        }
    };
    let fits = |g: &Gram, set: &[usize], draws: &mut Vec<Vec<f64>>| {
        if let Some((b, _)) = g.fit(set) {
            for (d, x) in draws.iter_mut().zip(b) {
                d.push(x);
            }
        }
    };
    resample(&mut |g| {
        for i in g.select(&all) {
            included[i] += 1;
        }
        fits(g, &elimination, &mut draws);
    });
    let names: Vec<String> = full.candidates.iter().map(|c| c.name.clone()).collect();
    let (selected, selection) = choose(&included, settings.bootstrap, &elimination, &names);
    if selected != elimination {
        draws = vec![Vec::new(); selected.len()];
        resample(&mut |g| fits(g, &selected, &mut draws));
    }
    let (beta, _) = gram
        .fit(&selected)
        .ok_or(DiscoverError::Degenerate { terms: p })?;
    let rss = gram.residual(&selected, &beta);
    let points = recordings[0].fit.model_points;
    let notation = Notation::new(model, settings.recording.order, field)?;
    // The rows measure time in frames: each coefficient back in the data's unit.
    let unit = time_unit(recordings);
    let library: Vec<DiscoveredTerm> = full
        .candidates
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let at = selected.iter().position(|&s| s == i);
            let grid = in_data_unit(at.map_or(whole[i], |j| beta[j]), unit, c.time_power);
            let scale = c.to_body_lengths(points);
            let interval = at.and_then(|j| {
                percentiles(&mut draws[j].clone(), recordings.len(), |x| {
                    in_data_unit(x, unit, c.time_power) * scale
                })
            });
            DiscoveredTerm {
                term: notation.term(&c.name),
                name: c.name.clone(),
                kind: c.kind,
                coefficient: grid * scale,
                on_points: grid,
                interval,
                inclusion: (settings.bootstrap > 0)
                    .then(|| included[i] as f64 / settings.bootstrap as f64),
                selected: at.is_some(),
            }
        })
        .collect();
    let keep: Vec<&str> = library
        .iter()
        .filter(|t| t.selected)
        .map(|t| t.name.as_str())
        .collect();
    let mut comparison: Vec<Comparison> = theories
        .iter()
        .map(|t| {
            let all: Vec<usize> = (0..t.candidates.len()).collect();
            score(&t.label, t, &all, sigma2)
        })
        .collect();
    comparison.push(score("selected", full, &selected, sigma2));
    let h = 1.0 / (points as f64 - 1.0);
    // q in body lengths² per time unit³.
    let noise = in_data_unit(noise(rows, &selected, &beta), unit, -3) * h * h;
    let beyond = library
        .iter()
        .flat_map(|t| {
            [t.coefficient, t.on_points]
                .into_iter()
                .chain(t.interval.into_iter().flatten())
        })
        .chain([noise])
        .any(|x| !x.is_finite());
    if beyond {
        return Err(DiscoverError::OutOfRange {
            dt: crate::report::fixed(unit, 4),
        });
    }
    let first = &recordings[0];
    Ok(DiscoverReport {
        recordings: recordings.iter().map(|r| r.name.clone()).collect(),
        field: field.to_string(),
        points,
        replay_points: points,
        frames: recordings.iter().flat_map(|r| &r.runs).map(Vec::len).sum(),
        order: settings.recording.order,
        beyond_leading: model
            .lagrangian
            .beyond_leading
            .max(model.rayleigh.beyond_leading),
        active: settings.active,
        modes: super::weak::used(first)
            .map(|m| (m.mode, super::weak::half_width(m.omega, first.dt)))
            .collect(),
        rows: rows.len(),
        estimator: ESTIMATOR.to_string(),
        method: Method::WeakForm { why: String::new() },
        equation: notation.equation(&keep),
        selected: library.iter().filter(|t| t.selected).cloned().collect(),
        library,
        comparison,
        r2: 1.0 - rss / gram.total().max(f64::MIN_POSITIVE),
        noise,
        bootstrap: settings.bootstrap,
        seed: settings.seed,
        selection,
        goodness: None,
        verdict: None,
        dt: first.dt,
        time_unit: first.fit.units.time.clone(),
        model_argument: None,
        inputs: Vec::new(),
        not_estimated: Vec::new(),
        replay: None,
        onward: None,
        onward_refused: None,
        animals: Vec::new(),
        between: Vec::new(),
    })
}

fn score(label: &str, theory: &Theory, set: &[usize], sigma2: f64) -> Comparison {
    let rows = &theory.rows;
    let gram = Gram::new(rows, &vec![1.0; rows.len()]);
    Comparison {
        model: label.to_string(),
        terms: set
            .iter()
            .map(|&i| theory.candidates[i].name.clone())
            .collect(),
        cv_residual: cross_validated(rows, set, FOLDS, sigma2),
        criterion: gram.criterion(set, sigma2),
    }
}

/// q = Σ e² / Σ ∫ψ² over the rows (unweighted residuals), on the grid, time in frames.
fn noise(rows: &super::weak::Rows, set: &[usize], beta: &[f64]) -> f64 {
    let e2: f64 = (0..rows.len())
        .map(|r| rows.residual(r, set, beta).powi(2))
        .sum();
    e2 / rows.norm.iter().sum::<f64>().max(f64::MIN_POSITIVE)
}

pub(super) fn interval_text(i: Option<[f64; 2]>) -> String {
    i.map_or("—".into(), |[a, b]| {
        format!("[{}, {}]", short(a), short(b))
    })
}

pub(super) use crate::report::short;

impl DiscoverReport {
    /// The data's time unit in words: `s`, or "the data's time unit" when none was given.
    pub fn time_words(&self) -> String {
        self.time_unit
            .as_ref()
            .map_or("the data's time unit".to_string(), |u| u.clone())
    }
}

impl Report for DiscoverReport {
    fn text(&self) -> String {
        let names: Vec<String> = self
            .recordings
            .iter()
            .map(|r| crate::markup::clip(r))
            .collect();
        let mut out = format!(
            "Discovered equation of field {} from {} ({} frames on {} points, Δt = {}{}):\n  {}\n",
            self.field,
            names.join(", "),
            self.frames,
            self.points,
            number(self.dt),
            self.time_unit
                .as_ref()
                .map_or(String::new(), |u| format!(" {u}")),
            self.equation
        );
        // What the answer is worth comes before how it was found.
        if let Some(v) = &self.verdict {
            out += &v.text();
            out += &self.next_line(v.next);
        }
        out += &format!(
            "Library: order {}, {} order(s) beyond leading, active forces {}: {} candidates.\n",
            self.order,
            self.beyond_leading,
            if self.active { "in" } else { "out" },
            self.library.len()
        );
        out += &match &self.method {
            Method::Exact | Method::Joint => format!(
                "Estimator: {}; {} frames on modes {}.\n",
                self.estimator,
                self.rows,
                self.modes
                    .iter()
                    .map(|(m, _)| m.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Method::WeakForm { why } => format!(
                "Estimator: {}{}; {} rows on modes {}.\n",
                self.estimator,
                if why.is_empty() {
                    String::new()
                } else {
                    format!(" ({why})")
                },
                self.rows,
                self.modes
                    .iter()
                    .map(|(m, h)| format!("{m} (±{h} frames)"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        out += "\n  term                          kind          coefficient    95 % interval                 inclusion  selected\n";
        for t in &self.library {
            out += &format!(
                "  {:<30}{:<14}{:<15}{:<30}{:<11}{}\n",
                t.term,
                format!("{:?}", t.kind).to_lowercase(),
                short(t.coefficient),
                interval_text(t.interval),
                t.inclusion
                    .map_or("—".into(), |x| format!("{:.0} %", 100.0 * x)),
                if t.selected { "yes" } else { "no" }
            );
        }
        if !self.not_estimated.is_empty() {
            out += &format!(
                "Not estimated: {} (kinetic terms beyond ½(∂t{})² renormalise the mass; the weak form cannot tell them from a rescaling of every other coefficient).\n",
                self.not_estimated.join(", "),
                self.field
            );
        }
        out += &format!(
            "(coefficients in body lengths and {}; intervals from ",
            self.time_words()
        );
        let draws = match self.recordings.len() {
            1 => "moving-block draws",
            _ => "draws of whole animals (expanded percentiles)",
        };
        out += &match (&self.selection, self.bootstrap) {
            (Selection::Elimination, 0) => "no draws: --bootstrap B; the selection is the whole recording's backward elimination)\n".to_string(),
            (Selection::Elimination, b) => format!(
                "{b} {draws}, seed {}; fewer than {MEDIAN_DRAWS}, so the selection is the whole recording's backward elimination)\n",
                self.seed
            ),
            (Selection::MedianProbability, b) => format!(
                "{b} {draws}, seed {}; the selection is the terms kept in more than half of them)\n",
                self.seed
            ),
            (Selection::NoModel { .. }, b) => format!(
                "{b} {draws}, seed {}; no term was kept in more than half of them, so no model is selected)\n",
                self.seed
            ),
        };
        out += match self.method {
            Method::Exact => "\nTheories compared (the criterion J + k ln n, J the modes' information-weighted distance, χ² with 2M − k degrees of freedom where the theory holds; lower is better):\n",
            Method::Joint => "\nTheories compared (the criterion J + k ln n, J the Wald distance of the whole library's estimate from the theory's, the likelihood ratio's quadratic form, χ² on the terms left out where they are absent; lower is better):\n",
            Method::WeakForm { .. } => "\nTheories compared (held-out moment residual over 5 blocks of time and the criterion J/σ² + k ln n; lower is better):\n",
        };
        for c in &self.comparison {
            out += &format!(
                "  {:<34} {:<40} cv {:<10} criterion {}\n",
                c.model,
                c.terms.join(", "),
                c.cv_residual.map_or("—".into(), |x| format!("{x:.4}")),
                c.criterion.map_or("—".into(), |x| format!("{x:.1}"))
            );
        }
        out += &format!(
            "R² = {:.4}; residual force noise q = {} (body lengths²/{}³ per point)\n",
            self.r2,
            short(self.noise),
            self.time_unit
                .as_ref()
                .map_or("time".to_string(), |u| u.clone())
        );
        out += &super::animals::text(self);
        out += &match &self.onward_refused {
            None => format!(
                "Onward: {}\n{}",
                self.simulate_line(),
                self.onward_words()
                    .map_or(String::new(), |w| format!("  {w}\n"))
            ),
            Some(why) => format!("Onward: none: {why}, so there is nothing to replay or draw\n"),
        };
        out
    }

    fn json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).unwrap_or_default();
        if let Some(o) = v.as_object_mut() {
            let line = match self.onward_refused {
                None => self.simulate_line().into(),
                Some(_) => serde_json::Value::Null,
            };
            o.insert("simulate".into(), line);
        }
        v
    }

    fn csv(&self) -> Option<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let _ = w.write_record([
            "name",
            "term",
            "kind",
            "coefficient",
            "on_points",
            "low",
            "high",
            "inclusion",
            "selected",
        ]);
        for t in &self.library {
            let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:e}"));
            let _ = w.write_record([
                t.name.clone(),
                t.term.clone(),
                format!("{:?}", t.kind).to_lowercase(),
                format!("{:e}", t.coefficient),
                format!("{:e}", t.on_points),
                opt(t.interval.map(|i| i[0])),
                opt(t.interval.map(|i| i[1])),
                opt(t.inclusion),
                t.selected.to_string(),
            ]);
        }
        String::from_utf8(w.into_inner().ok()?).ok()
    }

    fn check(&self) -> Result<(), crate::report::NonFinite> {
        crate::report::check_finite(self)
    }
}
