//! `discover` with the exact estimator (`exact`) where the library allows it: every candidate
//! linear in the field and diagonal on the modes used, every recording at one frame interval.
//! Otherwise the reason, and the weak form runs (`mod`).

use super::data::{Basis, Recording};
use super::exact::{columns, drawn, fit_mode, mode_data, moments, Distance, ModeFit, MAX_MODES};
use super::report::{choose, percentiles, Comparison, DiscoverReport, DiscoveredTerm, Method};
use super::verdict::Goodness;
use super::weak::in_data_unit;
use super::{galerkin, DiscoverError, DiscoverSettings, Notation};
use crate::dynamics::Candidate;
use crate::model::Model;
use crate::statespace::Oscillator;

/// The estimator's line in the report.
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
    /// A force couples modes.
    #[error("forces of the library couple modes")]
    Coupled,
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
    let modes: Vec<usize> = (first.fit.modes_fit.iter().enumerate())
        .take_while(|(j, m)| *j < available && (m.resolved || m.exact.is_some()))
        .map(|(j, _)| j)
        .take(MAX_MODES)
        .collect();
    if modes.is_empty() {
        return Err(DiscoverError::NoResolvedMode {
            recording: crate::markup::clip(&first.name),
        });
    }
    let names: Vec<String> = library.iter().map(|c| c.name.clone()).collect();
    let points = first.fit.model_points;
    let (forces, continuum) = match &first.basis {
        Basis::Continuum {
            stencil, boundary, ..
        } => {
            let found = galerkin::continuum(
                model,
                settings.recording.order,
                field,
                (*stencil, *boundary),
                modes.len(),
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
    let (cols, diagonal) = columns(&forces);
    if cols.iter().any(Option::is_none) {
        return Ok(Err(NotExact::Nonlinear));
    }
    if !diagonal {
        return Ok(Err(NotExact::Coupled));
    }
    let cols: Vec<Vec<[f64; 2]>> = cols.into_iter().flatten().collect();
    let data = mode_data(recordings, &modes);
    let mut fits: Vec<ModeFit> = Vec::new();
    for (d, &j) in data.iter().zip(&modes) {
        let m = &first.fit.modes_fit[j];
        let gain = match &first.basis {
            Basis::Continuum { gains, .. } => gains[j],
            Basis::Grid => 1.0,
        };
        let variance = (m.variance / (gain * gain)).max(f64::MIN_POSITIVE);
        let start = Oscillator {
            omega: (m.omega * first.dt).clamp(1e-6, std::f64::consts::PI * 1.9),
            zeta: m.zeta.clamp(1e-3, 10.0),
            variance,
            noise: (m.noise / (gain * gain)).max(variance * 1e-4),
        };
        match fit_mode(d, start) {
            Some(f) => fits.push(f),
            None => break,
        }
    }
    if fits.is_empty() {
        return Err(DiscoverError::NoResolvedMode {
            recording: crate::markup::clip(&first.name),
        });
    }
    let used = fits.len();
    let mut distance = Distance {
        y: Vec::new(),
        weight: Vec::new(),
        columns: cols.iter().map(|c| c[..used].to_vec()).collect(),
    };
    for f in &fits {
        let Some((y, w)) = moments(&f.fit.estimate, &f.covariance) else {
            return Ok(Err(NotExact::Singular));
        };
        distance.y.push(y);
        distance.weight.push(w);
    }
    let all: Vec<usize> = (0..library.len())
        .filter(|&m| {
            distance.columns[m]
                .iter()
                .any(|e| e[0] != 0.0 || e[1] != 0.0)
        })
        .collect();
    let frames: f64 = data[0]
        .blocks
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .count() as f64;
    let Some((whole, _, _)) = distance.fit(&all) else {
        return Err(DiscoverError::Degenerate { terms: all.len() });
    };
    let elimination = distance.select(&all, frames);
    // The one-step bootstrap: inclusion, then the reported set's percentiles.
    let units = data[0].unit.iter().max().map_or(1, |u| u + 1);
    let mut rng = super::regress::generator(settings.seed);
    let mut resamples: Vec<Distance> = Vec::new();
    for _ in 0..settings.bootstrap {
        let mut count = vec![0usize; units];
        for _ in 0..units {
            count[rand::RngExt::random_range(&mut rng, 0..units)] += 1;
        }
        if let Some(mut d) = drawn(&fits, &data[..used], &count) {
            d.columns.clone_from(&distance.columns);
            resamples.push(d);
        }
    }
    let mut included = vec![0usize; library.len()];
    for d in &resamples {
        for i in d.select(&all, frames) {
            included[i] += 1;
        }
    }
    let draws_made = resamples.len();
    let (selected, selection) = choose(&included, draws_made, &elimination, &names);
    let mut draws: Vec<Vec<f64>> = vec![Vec::new(); selected.len()];
    for d in &resamples {
        if let Some((b, _, _)) = d.fit(&selected) {
            for (v, x) in draws.iter_mut().zip(b) {
                v.push(x);
            }
        }
    }
    let Some((beta, covariance, j_selected)) = distance.fit(&selected) else {
        return Err(DiscoverError::Degenerate {
            terms: selected.len(),
        });
    };
    let misfit = distance.residuals(&selected, &beta);
    let strays: Vec<f64> = (resamples.iter())
        .filter_map(|d| d.recentred(&selected, &misfit))
        .collect();
    let unit = first.dt;
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
            // The wider of the one-step draws' percentiles and the information's ±1.96 se:
            // at 8 frames per period the draws alone covered c′_y in 2 of 4 recordings.
            let interval = at.and_then(|k| {
                let se = 1.96 * covariance[(k, k)].max(0.0).sqrt();
                let wald = [beta[k] - se, beta[k] + se];
                let drawn = percentiles(&mut draws[k].clone(), |x| x).unwrap_or(wald);
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
                on_points: body / c.to_body_lengths(points),
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
                criterion: distance.criterion(&set, frames),
            }
        })
        .collect();
    comparison.push(Comparison {
        model: "selected".into(),
        terms: selected.iter().map(|&i| names[i].clone()).collect(),
        cv_residual: None,
        criterion: distance.criterion(&selected, frames),
    });
    let empty = distance.objective(&[], &[]).max(f64::MIN_POSITIVE);
    // The modal force noise 4ζΩ³σ² (time in frames), averaged over the modes.
    let noise = fits
        .iter()
        .map(|f| {
            let p = f.fit.estimate;
            4.0 * p.zeta * p.omega.powi(3) * p.variance
        })
        .sum::<f64>()
        / used as f64;
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
    let estimator = if continuum {
        format!("{EXACT}, on the body's continuum modes (coefficients the continuum's)")
    } else {
        format!("{EXACT}, on the grid's modes (coefficients the grid's: the field has no continuum shapes here)")
    };
    Ok(Ok(DiscoverReport {
        recordings: recordings.iter().map(|r| r.name.clone()).collect(),
        field: field.to_string(),
        points,
        frames: recordings.iter().map(|r| r.modal.len()).sum(),
        order: settings.recording.order,
        beyond_leading: model
            .lagrangian
            .beyond_leading
            .max(model.rayleigh.beyond_leading),
        active: settings.active,
        modes: fits
            .iter()
            .zip(&modes)
            .map(|(_, &j)| (first.fit.modes_fit[j].mode, 0))
            .collect(),
        rows: frames as usize,
        estimator,
        method: Method::Exact,
        equation: notation.equation(&keep),
        selected: terms.iter().filter(|t| t.selected).cloned().collect(),
        library: terms,
        comparison,
        r2: 1.0 - j_selected / empty,
        noise,
        bootstrap: settings.bootstrap,
        seed: settings.seed,
        selection,
        goodness: Goodness::new(j_selected, 2 * used - selected.len().min(2 * used), &strays),
        verdict: None,
        dt: first.dt,
        time_unit: first.fit.units.time.clone(),
        model_argument: None,
        not_estimated: Vec::new(),
        replay: None,
        onward: None,
        onward_refused: None,
    }))
}
