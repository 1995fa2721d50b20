//! `discover` with the exact estimators where the library allows them: every candidate linear
//! in the field, every recording at one frame interval; forces diagonal on the modes used by
//! each mode's likelihood and minimum distance (`exact`), forces that couple them by the modes'
//! joint likelihood (`coupled`). Otherwise the reason, and the weak form runs (`mod`).

use super::data::{Basis, Recording};

use super::coupled::{CONDENSED, COUPLED};
use super::exact::{columns, drawn, moments, Distance, ModeData, ModeFit, Quadratic};
use super::galerkin::ModalForce;
use super::modes::{used, Used};
use super::regress::percentiles;
use super::report::{choose, Comparison, DiscoverReport, DiscoveredTerm, Method, Selection};
use super::verdict::Goodness;
use super::weak::in_data_unit;
use super::{galerkin, DiscoverError, DiscoverSettings, Notation};
use crate::dynamics::Candidate;
use crate::model::Model;

/// The estimator's line in the report.
mod joint;

const EXACT: &str = "each mode's exact likelihood (Kalman filter over the frames, lost frames skipped, tracking noise as observation noise), the coefficients by minimum distance on the modes' Ω² and 2ζΩ";

/// Why the exact estimator does not apply (the weak form runs instead).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(super) enum NotExact {
    /// Several recordings at different intervals or projections.
    #[error("the recordings differ in frame interval or projection")]
    Mixed,
    /// A force is nonlinear in the field.
    #[error("the library holds forces nonlinear in the field")]
    Nonlinear,
    /// A mode's information is singular.
    #[error("a mode's information is singular")]
    Singular,
}

/// The theories to score: label and candidate names.
pub(super) type Nested = Vec<(String, Vec<String>)>;

/// The exact estimator's report, or why it does not apply.
pub(super) fn estimate(
    recordings: &[Recording],
    model: &Model,
    settings: &DiscoverSettings,
    library: &[Candidate],
    nested: &Nested,
    field: &str,
) -> Result<Result<DiscoverReport, NotExact>, DiscoverError> {
    let first = &recordings[0];
    if recordings
        .iter()
        .any(|r| (r.dt - first.dt).abs() > 1e-6 * first.dt || r.basis != first.basis)
    {
        return Ok(Err(NotExact::Mixed));
    }
    let available = match &first.basis {
        Basis::Continuum { gains, .. } => gains.len(),
        Basis::Grid => first.shapes.len(),
    };
    let Used {
        modes,
        mut fits,
        mut data,
        mut own,
    } = used(recordings, available)?;
    let modes = &modes[..];
    let names: Vec<String> = library.iter().map(|c| c.name.clone()).collect();
    let points = first.fit.model_points;
    // The modes in the likelihood: the resolved ones. (Tried for the coupled likelihood: every
    // continuum coordinate up to MAX_MODES, the unresolved ones as mostly tracking noise, led it
    // to a wrong optimum at 14 frames a period, a_y ≈ 0. The modes above are condensed into
    // the used ones instead (`coupled`); one more as a latent state, its noise by
    // fluctuation–dissipation, moved c_y and a_y by 0.1–0.2 % and covered no more often.)
    let (whole_forces, continuum) = match &first.basis {
        Basis::Continuum {
            stencil, boundary, ..
        } => {
            let found = galerkin::continuum(
                model,
                settings.recording.order,
                field,
                (*stencil, *boundary),
                modes.len() + CONDENSED,
                &names,
            )?;
            match found {
                Some(f) => (f, true),
                None => (
                    galerkin::grid(library, &first.shapes[..modes.len()], points),
                    false,
                ),
            }
        }
        Basis::Grid => (
            galerkin::grid(library, &first.shapes[..modes.len()], points),
            false,
        ),
    };
    // The used modes' matrices; the coupled likelihood condenses the modes above them.
    let forces: Vec<Option<ModalForce>> = (whole_forces.iter())
        .map(|f| f.as_ref().map(|f| f.block(modes.len())))
        .collect();
    let (cols, diagonal) = columns(&forces);
    if cols.iter().any(Option::is_none) {
        return Ok(Err(NotExact::Nonlinear));
    }
    let mut cols: Vec<Vec<[f64; 2]>> = cols.into_iter().flatten().collect();
    // Each mode's own (Ω, ζ) is the diagonal estimator's datum: none that fit cannot tell from
    // an alias out of the beam's order (the joint likelihood places such a mode itself).
    if diagonal {
        let keep = super::modes::unaliased(first, modes, &fits);
        fits.truncate(keep);
        data.truncate(keep);
        cols.iter_mut().for_each(|c| c.truncate(keep));
        super::modes::keep_own(first, &modes[..keep], &mut own);
    }
    let frames: f64 = data[0]
        .blocks
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .count() as f64;
    let problem = Problem {
        fits: &fits,
        data: &data,
        frames,
        settings,
        names: &names,
        noise: first.noise.as_ref(),
        sigma: (first.fit.tracking_noise.as_ref())
            .filter(|t| !t.bound)
            .map(|t| t.sigma),
    };
    let found = if diagonal {
        problem.diagonal(&cols)
    } else {
        let forces: Vec<ModalForce> = whole_forces.into_iter().flatten().collect();
        problem.coupled(&forces, &cols)
    };
    let Estimate {
        chosen,
        fitted: (beta, covariance, draws),
        scored,
        noise,
        goodness,
        method,
    } = match found? {
        Ok(e) => e,
        Err(why) => return Ok(Err(why)),
    };
    let (all, whole) = (chosen.all, chosen.whole);
    let (selected, selection) = (chosen.selected, chosen.selection);
    let (included, draws_made) = (chosen.included, chosen.draws_made);
    let unit = first.dt;
    // The grid body the onward line runs: nearest the continuum estimate on the modes used, on
    // a grid fine enough that its shapes are the continuum's (else the recording's N, in its units).
    let fine = points.max(galerkin::REPLAY_POINTS);
    let order = (settings.recording.order, field);
    let grid = continuum.then(|| galerkin::grid_at(model, order, fine, fits.len(), &names));
    let on_grid =
        (grid.flatten()).and_then(|g| galerkin::nearest_on_grid(&forces, &g, &selected, &beta));
    let replay_points = if on_grid.is_some() { fine } else { points };
    let notation = Notation::new(model, settings.recording.order, field)?;
    let terms: Vec<DiscoveredTerm> = library
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let at = selected.iter().position(|&s| s == i);
            let fitted = at
                .map(|k| beta[k])
                .or_else(|| all.iter().position(|&a| a == i).map(|k| whole[k]));
            let body = in_data_unit(fitted.unwrap_or(0.0), unit, c.time_power);
            let grid = (on_grid.as_ref().zip(at))
                .map_or(body, |(g, k)| in_data_unit(g[k], unit, c.time_power));
            // The wider of the one-step draws' percentiles and the information's ±1.96 se:
            // at 8 frames per period the draws alone covered c′_y in 2 of 4 recordings.
            let interval = at.and_then(|k| {
                let se = 1.96 * covariance[(k, k)].max(0.0).sqrt();
                let wald = [beta[k] - se, beta[k] + se];
                let drawn =
                    percentiles(&mut draws[k].clone(), recordings.len(), |x| x).unwrap_or(wald);
                let (a, b) = (drawn[0].min(wald[0]), drawn[1].max(wald[1]));
                let (a, b) = (
                    in_data_unit(a, unit, c.time_power),
                    in_data_unit(b, unit, c.time_power),
                );
                (draws_made > 0).then_some([a.min(b), a.max(b)])
            });
            DiscoveredTerm {
                term: notation.term(&c.name),
                name: c.name.clone(),
                kind: c.kind,
                coefficient: body,
                on_points: grid / c.to_body_lengths(replay_points),
                interval,
                inclusion: (draws_made > 0).then(|| included[i] as f64 / draws_made as f64),
                selected: at.is_some(),
            }
        })
        .collect();
    let keep: Vec<&str> = terms
        .iter()
        .filter(|t| t.selected)
        .map(|t| t.name.as_str())
        .collect();
    let index = |n: &String| names.iter().position(|x| x == n);
    let mut comparison: Vec<Comparison> = nested
        .iter()
        .map(|(label, members)| {
            let set: Vec<usize> = members
                .iter()
                .filter_map(index)
                .filter(|i| all.contains(i))
                .collect();
            Comparison {
                model: label.clone(),
                terms: set.iter().map(|&i| names[i].clone()).collect(),
                cv_residual: None,
                criterion: scored.criterion(&set, frames),
            }
        })
        .collect();
    comparison.push(Comparison {
        model: "selected".into(),
        terms: selected.iter().map(|&i| names[i].clone()).collect(),
        cv_residual: None,
        criterion: scored.criterion(&selected, frames),
    });
    let j_of = |set: &[usize]| scored.fit(set).map_or(f64::NAN, |f| f.2);
    let (j_selected, empty) = (j_of(&selected), j_of(&[]).max(f64::MIN_POSITIVE));
    let noise = in_data_unit(noise, unit, -3);
    if terms
        .iter()
        .flat_map(|t| {
            [t.coefficient, t.on_points]
                .into_iter()
                .chain(t.interval.into_iter().flatten())
        })
        .chain([noise])
        .any(|x| !x.is_finite())
    {
        return Err(DiscoverError::OutOfRange {
            dt: crate::report::fixed(unit, 4),
        });
    }
    let estimator = if method == Method::Joint {
        COUPLED
    } else {
        EXACT
    };
    let estimator = if continuum {
        format!("{estimator}, on the body's continuum modes (coefficients the continuum's)")
    } else {
        format!("{estimator}, on the grid's modes (coefficients the grid's: the field has no continuum shapes here)")
    };
    let estimator = if own.is_empty() {
        estimator
    } else {
        let list: Vec<String> = own.iter().map(usize::to_string).collect();
        format!(
            "{estimator}; mode(s) {} without a spectral peak fit resolves (over-damped, flat or uncertain there), fitted from the exact likelihood's own starts",
            list.join(", ")
        )
    };
    Ok(Ok(DiscoverReport {
        recordings: recordings.iter().map(|r| r.name.clone()).collect(),
        field: field.to_string(),
        points,
        replay_points,
        frames: recordings.iter().map(|r| r.modal.len()).sum(),
        order: settings.recording.order,
        beyond_leading: model
            .lagrangian
            .beyond_leading
            .max(model.rayleigh.beyond_leading),
        active: settings.active,
        modes: fits
            .iter()
            .zip(modes)
            .map(|(_, &j)| (first.fit.modes_fit[j].mode, 0))
            .collect(),
        rows: frames as usize,
        estimator,
        method,
        equation: notation.equation(&keep),
        selected: terms.iter().filter(|t| t.selected).cloned().collect(),
        library: terms,
        comparison,
        r2: 1.0 - j_selected / empty,
        noise,
        bootstrap: settings.bootstrap,
        seed: settings.seed,
        selection,
        goodness,
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
    }))
}

/// The library's terms chosen: what the whole recording and the draws keep.
struct Chosen {
    /// The candidates with a force on the used modes.
    all: Vec<usize>,
    /// The whole library's estimate on `all`.
    whole: Vec<f64>,
    selected: Vec<usize>,
    selection: Selection,
    /// Per candidate, the draws whose selection kept it.
    included: Vec<usize>,
    draws_made: usize,
}

/// What either exact estimator gives the report.
struct Estimate {
    chosen: Chosen,
    /// The selected set's estimate, its covariance and, per selected term, its draws.
    fitted: (Vec<f64>, nalgebra::DMatrix<f64>, Vec<Vec<f64>>),
    /// J(S) on every subset.
    scored: Box<dyn Quadratic>,
    /// The modes' mean force noise (time in frames).
    noise: f64,
    goodness: Option<Goodness>,
    method: Method,
}

/// The fitted modes and what the estimators share.
struct Problem<'a> {
    fits: &'a [ModeFit],
    data: &'a [ModeData],
    frames: f64,
    settings: &'a DiscoverSettings,
    names: &'a [String],
    /// The tracking noise's covariance between the coordinates up to its σ² (the first
    /// recording's), and σ as the measurement layer measured it (body lengths; `None` where
    /// it is only a bound).
    noise: Option<&'a nalgebra::DMatrix<f64>>,
    sigma: Option<f64>,
}

impl Problem<'_> {
    /// Each bootstrap draw's count per unit (blocks of time, or animals).
    fn counts(&self) -> Vec<Vec<usize>> {
        let units = self.data[0].unit.iter().max().map_or(1, |u| u + 1);
        let mut rng = super::regress::generator(self.settings.seed);
        (0..self.settings.bootstrap)
            .map(|_| {
                let mut count = vec![0usize; units];
                for _ in 0..units {
                    count[rand::RngExt::random_range(&mut rng, 0..units)] += 1;
                }
                count
            })
            .collect()
    }

    /// Backward elimination on the whole recording and on each draw; the reported terms.
    fn choose_terms<Q: Quadratic>(
        &self,
        scored: &Q,
        resamples: &[Q],
        all: Vec<usize>,
        whole: Vec<f64>,
        candidates: usize,
    ) -> Chosen {
        let elimination = scored.select(&all, self.frames);
        let mut included = vec![0usize; candidates];
        for d in resamples {
            for i in d.select(&all, self.frames) {
                included[i] += 1;
            }
        }
        let draws_made = resamples.len();
        let (selected, selection) = choose(&included, draws_made, &elimination, self.names);
        Chosen {
            all,
            whole,
            selected,
            selection,
            included,
            draws_made,
        }
    }

    /// The modes' (Ω², 2ζΩ), their weights and the library's diagonal columns on them.
    fn distance(&self, cols: &[Vec<[f64; 2]>]) -> Result<Distance, NotExact> {
        let used = self.fits.len();
        let mut distance = Distance {
            y: Vec::new(),
            weight: Vec::new(),
            columns: cols.iter().map(|c| c[..used].to_vec()).collect(),
        };
        for f in self.fits {
            let (y, w) = moments(&f.fit.estimate, &f.covariance).ok_or(NotExact::Singular)?;
            distance.y.push(y);
            distance.weight.push(w);
        }
        Ok(distance)
    }

    /// The minimum distance on the modes' (Ω², 2ζΩ): forces diagonal on the modes.
    fn diagonal(
        &self,
        cols: &[Vec<[f64; 2]>],
    ) -> Result<Result<Estimate, NotExact>, DiscoverError> {
        let used = self.fits.len();
        let distance = match self.distance(cols) {
            Ok(d) => d,
            Err(why) => return Ok(Err(why)),
        };
        let all: Vec<usize> = (0..cols.len())
            .filter(|&m| {
                distance.columns[m]
                    .iter()
                    .any(|e| e[0] != 0.0 || e[1] != 0.0)
            })
            .collect();
        let Some((whole, _, _)) = distance.fit(&all) else {
            return Err(DiscoverError::Degenerate { terms: all.len() });
        };
        // The one-step bootstrap: inclusion, then the reported set's percentiles.
        let resamples: Vec<Distance> = (self.counts().iter())
            .filter_map(|count| drawn(self.fits, self.data, count))
            .map(|mut d| {
                d.columns.clone_from(&distance.columns);
                d
            })
            .collect();
        let chosen = self.choose_terms(&distance, &resamples, all, whole, cols.len());
        let selected = chosen.selected.clone();
        let Some((beta, covariance, j_selected)) = distance.fit(&selected) else {
            return Err(DiscoverError::Degenerate {
                terms: selected.len(),
            });
        };
        let draws = set_draws(&resamples, &selected);
        let misfit = distance.residuals(&selected, &beta);
        let strays: Vec<f64> = (resamples.iter())
            .filter_map(|d| d.recentred(&selected, &misfit))
            .collect();
        let goodness = Goodness::new(j_selected, 2 * used - selected.len().min(2 * used), &strays);
        // The modal force noise 4ζΩ³σ² (time in frames), averaged over the modes.
        let noise = (self.fits.iter())
            .map(|f| {
                let p = f.fit.estimate;
                4.0 * p.zeta * p.omega.powi(3) * p.variance
            })
            .sum::<f64>()
            / used as f64;
        Ok(Ok(Estimate {
            chosen,
            fitted: (beta, covariance, draws),
            scored: Box::new(distance),
            noise,
            goodness,
            method: Method::Exact,
        }))
    }
}

/// Each selected term's estimate over the draws.
fn set_draws<Q: Quadratic>(resamples: &[Q], selected: &[usize]) -> Vec<Vec<f64>> {
    let mut draws: Vec<Vec<f64>> = vec![Vec::new(); selected.len()];
    for d in resamples {
        if let Some((b, _, _)) = d.fit(selected) {
            for (v, x) in draws.iter_mut().zip(b) {
                v.push(x);
            }
        }
    }
    draws
}
