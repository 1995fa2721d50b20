//! The commands that are one library call each (the behaviours, the statistics, the term
//! tables, the rule registry, the figures): typed arguments in, the library's own result out
//! as the document the command line's `--format json` prints. Every range and name is checked
//! by the library, in the command line's words; the command line is never run.

use std::collections::HashMap;

use pyo3::prelude::*;
use theory_search::behaviour::{self, PairKind, PairReport, RightingReport, RightingSettings};
use theory_search::model::{one_line, Density};
use theory_search::report::Report;
use theory_search::theory::Theory;

use crate::{basis_of, body_of, model_of, raised, usage};

/// The report as the command line's `--format json` document, as Python objects (its numbers
/// checked finite first, as the command line checks them).
fn json_of<'py>(py: Python<'py>, report: &dyn Report) -> PyResult<Bound<'py, PyAny>> {
    report.check().map_err(|e| usage(e.0))?;
    crate::document(py, &report.json())
}

fn behaviour_error(e: behaviour::BehaviourError) -> PyErr {
    raised(e.failure(), one_line(&e.to_string()))
}

fn order_error(e: impl std::fmt::Display) -> PyErr {
    usage(e)
}

/// The densities a `density` word names (`both` when none).
pub(crate) fn densities_of(density: Option<&str>) -> PyResult<Vec<Density>> {
    match density.unwrap_or("both") {
        "both" => Ok(Density::ALL.to_vec()),
        "lagrangian" => Ok(vec![Density::Lagrangian]),
        "rayleigh" => Ok(vec![Density::Rayleigh]),
        other => Err(usage(format!(
            "density must be \"lagrangian\", \"rayleigh\" or \"both\", not {}",
            theory_search::markup::clip(other)
        ))),
    }
}

/// The model (TOML text or the larva) with `beyond_leading` orders kept, in range.
fn model_at(
    model: Option<&str>,
    beyond_leading: Option<u32>,
) -> PyResult<theory_search::model::Model> {
    let mut model = model_of(model)?;
    if let Some(k) = beyond_leading {
        let most = theory_search::model::MAX_BEYOND_LEADING;
        if k > most {
            return Err(usage(format!(
                "beyond_leading must be between 0 and {most}, not {k}"
            )));
        }
        model.set_beyond_leading(k);
    }
    Ok(model)
}

/// The theory of a body on `points` points, for `what`.
fn theory_of(
    points: usize,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    what: &'static str,
) -> PyResult<Theory> {
    body_of(order, beyond_leading, model, params)?
        .theory(points, what)
        .map_err(crate::body_error)
}

/// `count`: candidate terms per density at orders 1 … `max_order`.
#[pyfunction]
#[pyo3(signature = (max_order, model, basis))]
pub(crate) fn count_json<'py>(
    py: Python<'py>,
    max_order: u32,
    model: Option<&str>,
    basis: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let model = model_of(model)?;
    let report = theory_search::catalogue::CountReport::new(&model, basis_of(basis)?, max_order)
        .map_err(order_error)?;
    json_of(py, &report)
}

/// `rules`: the registry, and with a model or an order what the model requires.
#[pyfunction]
#[pyo3(signature = (order, model))]
pub(crate) fn rules_json<'py>(
    py: Python<'py>,
    order: Option<u32>,
    model: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    use theory_search::catalogue::{Requirements, RulesReport};
    let requirements = if model.is_some() || order.is_some() {
        let model = model_of(model)?;
        let order = order.unwrap_or(theory_search::model::DEFAULT_ORDER);
        Some(
            py.detach(|| Requirements::new(&model, order))
                .map_err(order_error)?,
        )
    } else {
        None
    };
    json_of(
        py,
        &RulesReport {
            header: theory_search::codegen::header("<!--", " -->"),
            requirements,
        },
    )
}

/// `parts` (the admitted monomials modulo total derivatives; default density the Lagrangian)
/// or `interactions` (which terms could couple each set of fields; default both densities).
#[pyfunction]
#[pyo3(signature = (table, order, beyond_leading, model, density))]
pub(crate) fn terms_json<'py>(
    py: Python<'py>,
    table: &str,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    density: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    use theory_search::interaction::InteractionsReport;
    use theory_search::parts::PartsReport;
    let model = model_at(model, beyond_leading)?;
    match table {
        "parts" => {
            let densities = densities_of(Some(density.unwrap_or("lagrangian")))?;
            let report = py
                .detach(|| PartsReport::new(&model, &densities, order))
                .map_err(order_error)?;
            json_of(py, &report)
        }
        _ => {
            let densities = densities_of(density)?;
            let report = py
                .detach(|| InteractionsReport::new(&model, &densities, order))
                .map_err(order_error)?;
            json_of(py, &report)
        }
    }
}

/// A pair's ω: given (no scales beside it), the first axial pair of the body named by any of
/// `model`, `points` and `params`, else 1 (the unit of frequency).
#[allow(clippy::too_many_arguments)]
fn pair_omega(
    omega: Option<f64>,
    points: Option<usize>,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    what: &'static str,
) -> PyResult<f64> {
    let scales_given = params.as_ref().is_some_and(|p| !p.is_empty());
    if let Some(w) = omega {
        return behaviour::given_pair_frequency(w, scales_given).map_err(behaviour_error);
    }
    if model.is_none() && points.is_none() && !scales_given && beyond_leading.is_none() {
        return Ok(1.0);
    }
    let theory = theory_of(
        points.unwrap_or(12),
        order,
        beyond_leading,
        model,
        params,
        what,
    )?;
    behaviour::pair_frequency(&theory, what).map_err(behaviour_error)
}

/// `asymmetry`: forward/backward waves of the self-interacting axial pair (App. C).
#[pyfunction]
#[pyo3(signature = (coupling, amplitude, omega, points, order, beyond_leading, model, params))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn asymmetry_json<'py>(
    py: Python<'py>,
    coupling: f64,
    amplitude: f64,
    omega: Option<f64>,
    points: Option<usize>,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let omega = pair_omega(
        omega,
        points,
        order,
        beyond_leading,
        model,
        params,
        "asymmetry",
    )?;
    let a = behaviour::asymmetry(coupling, amplitude, omega).map_err(behaviour_error)?;
    json_of(py, &a)
}

/// `mathieu`: the Floquet chart of a bare equation (App. D).
#[pyfunction]
#[pyo3(signature = (lambda_, ratio_min, ratio_max, epsilon_max, columns, rows))]
pub(crate) fn mathieu_json<'py>(
    py: Python<'py>,
    lambda_: f64,
    ratio_min: f64,
    ratio_max: f64,
    epsilon_max: f64,
    columns: usize,
    rows: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let chart = py
        .detach(|| {
            behaviour::chart(
                lambda_,
                (ratio_min, ratio_max),
                epsilon_max,
                (columns, rows),
            )
        })
        .map_err(behaviour_error)?;
    json_of(py, &chart)
}

/// What a statistic is asked, beyond its body.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct StatsAsk {
    beta: Option<f64>,
    samples: Option<usize>,
    seed: u64,
    field: Option<String>,
    steps: u64,
    temperature: f64,
    momentum: f64,
    omega: Option<f64>,
}

/// `stats explore | equipartition | pair`.
#[pyfunction]
#[pyo3(signature = (kind, points, order, beyond_leading, model, params, ask))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn stats_json<'py>(
    py: Python<'py>,
    kind: &str,
    points: Option<usize>,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    ask: StatsAsk,
) -> PyResult<Bound<'py, PyAny>> {
    match kind {
        "explore" => {
            let t = theory_of(
                points.unwrap_or(12),
                order,
                beyond_leading,
                model,
                params,
                "stats explore",
            )?;
            let samples = ask.samples.unwrap_or(100_000);
            let beta = ask.beta.unwrap_or(10_000.0);
            let e = py
                .detach(|| behaviour::explore(&t, beta, samples, ask.seed))
                .map_err(behaviour_error)?;
            json_of(py, &e)
        }
        "equipartition" => {
            let t = theory_of(
                points.unwrap_or(12),
                order,
                beyond_leading,
                model,
                params,
                "stats equipartition",
            )?;
            let field = ask.field.as_deref();
            let c = py
                .detach(|| {
                    behaviour::equipartition_from_dynamics(
                        &t,
                        field,
                        ask.steps,
                        ask.temperature,
                        ask.seed,
                    )
                })
                .map_err(behaviour_error)?;
            json_of(py, &c)
        }
        "pair" => {
            let omega = pair_omega(
                ask.omega,
                points,
                order,
                beyond_leading,
                model,
                params,
                "stats pair",
            )?;
            let beta = ask.beta.unwrap_or(1.0);
            let r = py
                .detach(|| PairReport::new(omega, beta, ask.momentum, ask.samples, ask.seed))
                .map_err(behaviour_error)?;
            json_of(py, &r)
        }
        other => Err(usage(format!(
            "stats is \"explore\", \"equipartition\" or \"pair\", not {}",
            theory_search::markup::clip(other)
        ))),
    }
}

/// What a behaviour is asked, beyond its body.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct BehaveAsk {
    momentum: f64,
    periods: f64,
    force: f64,
    duration: f64,
    tolerance: f64,
    mode_damping: Option<f64>,
    theta0: f64,
    attachment: String,
    sweep: Vec<f64>,
}

/// `behave peristalsis | rolling | rearing | hunching | self-righting`.
#[pyfunction]
#[pyo3(signature = (behaviour, points, order, beyond_leading, model, params, ask))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn behave_json<'py>(
    py: Python<'py>,
    behaviour: &str,
    points: usize,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    ask: BehaveAsk,
) -> PyResult<Bound<'py, PyAny>> {
    let what: &'static str = match behaviour {
        "peristalsis" => "behave peristalsis",
        "rolling" => "behave rolling",
        "rearing" => "behave rearing",
        "hunching" => "behave hunching",
        "self-righting" => "behave self-righting",
        other => {
            return Err(usage(format!(
            "the behaviours are peristalsis, rolling, rearing, hunching and self-righting, not {}",
            theory_search::markup::clip(other)
        )))
        }
    };
    let theory = theory_of(points, order, beyond_leading, model, params, what)?;
    match behaviour {
        "peristalsis" | "rolling" => {
            let kind = if behaviour == "rolling" {
                PairKind::Rolling
            } else {
                PairKind::Peristalsis
            };
            let o = py
                .detach(|| behaviour::pair_orbit(&theory, kind, ask.momentum, ask.periods))
                .map_err(behaviour_error)?;
            json_of(py, &o)
        }
        "rearing" | "hunching" => {
            let name = if behaviour == "rearing" {
                "Rearing"
            } else {
                "Hunching"
            };
            let field = behaviour::role_fields(&theory.model, what)
                .map_err(|e| behaviour_error(e.into()))?[0];
            let r = py
                .detach(|| behaviour::step_response(&theory, name, field, ask.force, ask.duration))
                .map_err(behaviour_error)?;
            json_of(py, &r)
        }
        _ => {
            let settings = RightingSettings {
                theta0: ask.theta0,
                tolerance: ask.tolerance,
                mode_damping: RightingSettings::mode_damping_for(&theory, ask.mode_damping, false)
                    .map_err(behaviour_error)?,
                attachment: ask.attachment.parse().map_err(behaviour_error)?,
                ..Default::default()
            };
            let r = py
                .detach(|| -> Result<_, behaviour::BehaviourError> {
                    Ok(RightingReport {
                        righting: behaviour::self_righting(&theory, &settings)?,
                        sweep: behaviour::righting_sweep(&theory, &settings, &ask.sweep)?,
                    })
                })
                .map_err(behaviour_error)?;
            json_of(py, &r)
        }
    }
}

/// The paths written, and (figure, why) of each figure skipped.
type Written = (Vec<String>, Vec<(String, String)>);

/// `figures`: the figures of a body written into `directory`; the paths written and the
/// (figure, why) of each one the body cannot make.
#[pyfunction]
#[pyo3(signature = (directory, only, points, order, beyond_leading, model, params, format, width, dpi, samples, seed))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn figures<'py>(
    py: Python<'py>,
    directory: std::path::PathBuf,
    only: Option<&str>,
    points: usize,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    format: &str,
    width: f64,
    dpi: f64,
    samples: usize,
    seed: u64,
) -> PyResult<Written> {
    use theory_search::figures::{figure_names, write_figures, FigureSettings, Page};
    let settings = FigureSettings {
        points,
        seed,
        samples,
        page: Page {
            format: format.parse().map_err(usage)?,
            width_mm: width,
            dpi,
        },
    };
    let figure_error =
        |e: theory_search::figures::FigureError| raised(e.failure(), one_line(&e.to_string()));
    settings.check().map_err(figure_error)?;
    let theory = theory_of(points, order, beyond_leading, model, params, "figures")?;
    let names = figure_names(only);
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let written = py
        .detach(|| write_figures(&directory, &names, &theory, &settings, |_| {}))
        .map_err(figure_error)?;
    Ok((
        written
            .written
            .iter()
            .map(|p| p.display().to_string())
            .collect(),
        written.skipped,
    ))
}
