//! The native half of the `theory_search` Python package: thin wrappers over the library (never
//! the CLI binary). Structured results cross as Python objects converted directly from the
//! documents the CLI's `--format json` prints (no JSON text between) and numbers as numpy arrays; every error becomes a Python exception of
//! the `TheorySearchError` family with the library's one-line message, and long work runs with
//! the GIL released.

use std::collections::HashMap;

use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray3};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use theory_search::body::{Body, BodyError, BodyModes, BodyOperators, Start};
use theory_search::enumerate::Basis;
use theory_search::failure::Failure;
use theory_search::fit::{fit_inputs, FitError, FitReport, FitSettings, Input};
use theory_search::modal::Params;
use theory_search::model::{one_line, Model};
use theory_search::recording::{Frame, Setting, Track};

mod commands;

create_exception!(
    _native,
    TheorySearchError,
    PyException,
    "Any error of theory-search."
);
create_exception!(
    _native,
    UsageError,
    TheorySearchError,
    "A bad argument, setting or model (the CLI's exit code 2)."
);
create_exception!(
    _native,
    InputError,
    TheorySearchError,
    "Unreadable or malformed data (the CLI's exit code 1)."
);
create_exception!(
    _native,
    MissingError,
    TheorySearchError,
    "A file that does not exist (the CLI's exit code 1)."
);
create_exception!(
    _native,
    NumericalError,
    TheorySearchError,
    "A computation that failed on valid input (the CLI's exit code 3)."
);
create_exception!(
    _native,
    OutputError,
    TheorySearchError,
    "Output that cannot be written (the CLI's exit code 1)."
);

/// A document (the value the command line's `--format json` prints) as Python objects:
/// dicts, lists, floats, ints, strings and None, converted directly, with no JSON text between.
fn document<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| usage(e.to_string()))
}

fn usage(e: impl std::fmt::Display) -> PyErr {
    UsageError::new_err(one_line(&e.to_string()))
}

/// The model from TOML text, or the embedded larva.
fn model_of(toml: Option<&str>) -> PyResult<Model> {
    match toml {
        None => Ok(Model::larva()),
        Some(text) => Model::from_toml(text).map_err(usage),
    }
}

fn basis_of(basis: &str) -> PyResult<Basis> {
    match basis {
        "powers" => Ok(Basis::Powers),
        "monomials" => Ok(Basis::Monomials),
        other => Err(usage(format!(
            "basis must be \"powers\" or \"monomials\", not {other:?}"
        ))),
    }
}

/// The embedded larva model as TOML text.
#[pyfunction]
fn larva_toml() -> &'static str {
    Model::larva_toml()
}

/// Validate model TOML; returns the model's name and field ids.
#[pyfunction]
fn check_model(toml: &str) -> PyResult<(String, Vec<String>)> {
    let m = Model::from_toml(toml).map_err(usage)?;
    Ok((
        m.name.clone(),
        m.fields.iter().map(|f| f.id.clone()).collect(),
    ))
}

/// Table 1 and its Rayleigh twin as the CLI's JSON document.
#[pyfunction]
#[pyo3(signature = (order, model, basis, density))]
fn table_json<'py>(
    py: Python<'py>,
    order: u32,
    model: Option<&str>,
    basis: &str,
    density: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let model = model_of(model)?;
    let basis = basis_of(basis)?;
    let densities = commands::densities_of(Some(density))?;

    let value = py
        .detach(|| {
            let analyses = densities
                .into_iter()
                .map(|d| theory_search::reduce::analyse_basis(&model, d, order, basis))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| e.to_string())?;
            Ok(theory_search::table::json_report(&model, &analyses))
        })
        .map_err(|e: String| usage(e))?;
    document(py, &value)
}

/// The active forces of `theory-search active`, as its JSON.
#[pyfunction]
#[pyo3(signature = (order, beyond_leading, model))]
fn active_json<'py>(
    py: Python<'py>,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    use theory_search::report::Report;
    let mut model = model_of(model)?;
    if let Some(k) = beyond_leading {
        model.set_beyond_leading(k);
    }
    let report = theory_search::active::ActiveReport::of(&model, order).map_err(usage)?;
    document(py, &report.json())
}

/// The equations of motion as the CLI's JSON document (linear, or exact nonlinear).
#[pyfunction]
#[pyo3(signature = (order, model, basis))]
fn equations_json<'py>(
    py: Python<'py>,
    order: u32,
    model: Option<&str>,
    basis: &str,
) -> PyResult<Bound<'py, PyAny>> {
    use theory_search::equations::{derive_any, Derivation, Derived, EquationReport};
    use theory_search::report::Report;
    let model = model_of(model)?;
    // Every field's equation, or the first reason one has none (the command line's exit 2).
    fn json<E>(name: &str, order: u32, d: Derivation<E>) -> PyResult<serde_json::Value>
    where
        EquationReport<E>: Report,
    {
        let (equations, notes) = d.complete().map_err(usage)?;
        let report = EquationReport {
            model: name.to_string(),
            order,
            equations,
            notes,
        };
        Ok(report.json())
    }
    let value = match derive_any(&model, order, basis_of(basis)?).map_err(usage)? {
        Derived::Linear(d) => json(&model.name, order, d)?,
        Derived::Nonlinear(d) => json(&model.name, order, d)?,
    };
    document(py, &value)
}

/// The library's error as its Python exception, by the kind of failure.
fn raised(failure: Failure, text: String) -> PyErr {
    match failure {
        Failure::Usage => UsageError::new_err(text),
        Failure::Input => InputError::new_err(text),
        Failure::Numerical => NumericalError::new_err(text),
        Failure::Output => OutputError::new_err(text),
    }
}

fn body_error(e: BodyError) -> PyErr {
    raised(e.failure(), one_line(&e.to_string()))
}

/// The body of the model at `order`, its scales and coefficients by name (as `--param`).
fn body_of(
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
) -> PyResult<Body> {
    let mut assignments: Vec<(String, f64)> = params.unwrap_or_default().into_iter().collect();
    // A dict has no order; the library's checks then go name by name, the same every time.
    assignments.sort_by(|a, b| a.0.cmp(&b.0));
    Body::new(
        model_of(model)?,
        order,
        beyond_leading,
        Params::default(),
        &assignments,
    )
    .map_err(body_error)
}

/// Rows as a numpy matrix (rows × columns; `columns` when there are no rows).
fn matrix<'py>(
    py: Python<'py>,
    rows: &[Vec<f64>],
    columns: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    let a = numpy::ndarray::Array2::from_shape_fn(
        (n, if n == 0 { columns } else { rows[0].len() }),
        |(i, j)| rows[i][j],
    );
    Ok(a.into_pyarray(py))
}

/// Every operator on `points` points: dicts with the exact integer matrix as a numpy array
/// (a linear body), or the stiffness, damping and mass of the linearisation (a nonlinear one).
#[pyfunction]
#[pyo3(signature = (points, order, beyond_leading, model, params))]
fn operators<'py>(
    py: Python<'py>,
    points: usize,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let body = body_of(order, beyond_leading, model, params)?;
    let ops = py.detach(|| body.operators(points)).map_err(body_error)?;
    match ops {
        BodyOperators::Exact(ops) => ops
            .into_iter()
            .map(|op| {
                let d = PyDict::new(py);
                d.set_item("field", &op.field)?;
                d.set_item("density", &op.density)?;
                d.set_item("term", &op.term)?;
                d.set_item("boundary", &op.boundary)?;
                d.set_item("k", op.k)?;
                d.set_item(
                    "matrix",
                    PyArray2::from_vec2(py, &op.matrix).map_err(usage)?,
                )?;
                Ok(d)
            })
            .collect(),
        BodyOperators::Linearised(fields) => fields
            .into_iter()
            .map(|op| {
                let d = PyDict::new(py);
                d.set_item("field", &op.field)?;
                d.set_item("boundary", &op.boundary)?;
                d.set_item("linearised", true)?;
                d.set_item("equilibrium", PyArray1::from_vec(py, op.equilibrium))?;
                d.set_item("residual", op.residual)?;
                d.set_item("stiffness", matrix(py, &op.stiffness, op.size)?)?;
                d.set_item("damping", matrix(py, &op.damping, op.size)?)?;
                d.set_item("mass", matrix(py, &op.mass, op.size)?)?;
                Ok(d)
            })
            .collect(),
    }
}

/// Each field's modes: eigenvalues, frequencies, damping ratios, variance shares, and the
/// shapes (points × modes) when asked; of a nonlinear body, its linearisation's (frequencies
/// NaN where λ < 0, an unstable direction; the equilibrium and its residual).
#[pyfunction]
#[pyo3(signature = (points, order, beyond_leading, model, params, shapes, k))]
#[allow(clippy::too_many_arguments)]
fn modes<'py>(
    py: Python<'py>,
    points: usize,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    shapes: bool,
    k: Option<usize>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let body = body_of(order, beyond_leading, model, params)?;
    let all = py
        .detach(|| body.modes(points, k, shapes))
        .map_err(body_error)?;
    let all = match all {
        BodyModes::Exact(all) => all,
        BodyModes::Linearised(fields) => {
            return fields
                .into_iter()
                .map(|f| {
                    let d = PyDict::new(py);
                    d.set_item("field", &f.field)?;
                    d.set_item("linearised", true)?;
                    d.set_item("equilibrium", PyArray1::from_vec(py, f.equilibrium))?;
                    d.set_item("residual", f.residual)?;
                    let frequencies: Vec<f64> = f
                        .frequencies
                        .iter()
                        .map(|w| w.unwrap_or(f64::NAN))
                        .collect();
                    d.set_item("frequencies", PyArray1::from_vec(py, frequencies))?;
                    let (decay, damped): (Vec<f64>, Vec<f64>) =
                        f.damped.iter().map(|r| (r.decay_rate, r.frequency)).unzip();
                    d.set_item("decay_rates", PyArray1::from_vec(py, decay))?;
                    d.set_item("damped_frequencies", PyArray1::from_vec(py, damped))?;
                    if let Some(s) = &f.shapes {
                        // Modes as columns, as numpy.linalg.eigh.
                        let n = s.first().map_or(0, Vec::len);
                        let a =
                            numpy::ndarray::Array2::from_shape_fn((n, s.len()), |(i, j)| s[j][i]);
                        d.set_item("shapes", a.into_pyarray(py))?;
                    }
                    d.set_item("eigenvalues", PyArray1::from_vec(py, f.eigenvalues))?;
                    Ok(d)
                })
                .collect();
        }
    };
    all.into_iter()
        .map(|fm| {
            let d = PyDict::new(py);
            let column = |f: &dyn Fn(&theory_search::modal::Mode) -> f64| -> Vec<f64> {
                fm.modes.iter().map(f).collect()
            };
            d.set_item("field", &fm.field.id)?;
            d.set_item("k", fm.k)?;
            d.set_item("omega", fm.omega)?;
            d.set_item("zeta", fm.zeta)?;
            d.set_item("nullity", fm.spectrum.nullity)?;
            d.set_item("inverse_trace", fm.spectrum.inverse_trace)?;
            d.set_item(
                "eigenvalues",
                PyArray1::from_vec(py, column(&|m| m.eigenvalue)),
            )?;
            d.set_item(
                "frequencies",
                PyArray1::from_vec(py, column(&|m| m.frequency)),
            )?;
            d.set_item(
                "damping_ratios",
                PyArray1::from_vec(py, column(&|m| m.damping_ratio)),
            )?;
            d.set_item(
                "variance_shares",
                PyArray1::from_vec(py, column(&|m| m.variance_share)),
            )?;
            if let Some(s) = &fm.spectrum.shapes {
                let cols = fm.modes.len().min(s.ncols());
                // Straight into numpy's buffer: no nested vectors for N × k numbers.
                let a =
                    numpy::ndarray::Array2::from_shape_fn((s.nrows(), cols), |(i, j)| s[(i, j)]);
                d.set_item("shapes", a.into_pyarray(py))?;
            }
            Ok(d)
        })
        .collect()
}

/// What a run starts from and what pushes it, as the command line's texts.
type StartTexts = (Vec<String>, Vec<String>, Vec<String>);

/// Simulate (Langevin at `temperature`, or deterministic at 0) from `start` (`--initial`,
/// `--force`, `--drive` texts): times, energies and each field's positions and modal
/// coordinates (none for a nonlinear body), one row per kept step.
#[pyfunction]
#[pyo3(signature = (points, steps, dt, every, temperature, seed, order, beyond_leading, model, params, start))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    points: usize,
    steps: u64,
    dt: f64,
    every: u64,
    temperature: f64,
    seed: u64,
    order: u32,
    beyond_leading: Option<u32>,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    start: StartTexts,
) -> PyResult<Bound<'py, PyDict>> {
    let body = body_of(order, beyond_leading, model, params)?;
    let start = Start::parse(&start.0, &start.1, &start.2).map_err(body_error)?;
    let config = theory_search::dynamics::Config {
        points,
        order,
        dt,
        steps,
        every,
        temperature,
        seed,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    type Series = (
        Vec<String>,
        Vec<f64>,
        (Vec<f64>, Vec<f64>),
        Vec<Vec<Vec<f64>>>,
        Vec<Vec<Vec<f64>>>,
    );
    let (ids, t, (energy, injected), positions, modal) = py
        .detach(|| -> Result<Series, BodyError> {
            let mut out: Series = Default::default();
            body.simulate(&config, &start, |ids, s| {
                let (names, t, (energy, injected), positions, modal) = &mut out;
                if names.is_empty() {
                    *names = ids.to_vec();
                    *positions = vec![Vec::new(); ids.len()];
                    *modal = vec![Vec::new(); ids.len()];
                }
                t.push(s.t);
                energy.push(s.energy);
                injected.extend(s.injected);
                for f in 0..ids.len() {
                    positions[f].push(s.positions[f].clone());
                    modal[f].push(s.modal.get(f).cloned().unwrap_or_default());
                }
                Ok(())
            })?;
            Ok(out)
        })
        .map_err(body_error)?;
    let out = PyDict::new(py);
    out.set_item("t", PyArray1::from_vec(py, t))?;
    out.set_item("energy", PyArray1::from_vec(py, energy))?;
    // As the CSV: the active forces' injected work only for a body with active forces.
    if !injected.is_empty() {
        out.set_item("injected", PyArray1::from_vec(py, injected))?;
    }
    let (p, q) = (PyDict::new(py), PyDict::new(py));
    for (f, id) in ids.iter().enumerate() {
        p.set_item(id, matrix(py, &positions[f], 0)?)?;
        q.set_item(id, matrix(py, &modal[f], 0)?)?;
    }
    out.set_item("positions", p)?;
    out.set_item("modal", q)?;
    Ok(out)
}

/// The library's limits, so Python checks what the command line checks without copying them.
#[pyfunction]
fn limits(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("order", theory_search::enumerate::MAX_ORDER)?;
    d.set_item("beyond_leading", theory_search::model::MAX_BEYOND_LEADING)?;
    d.set_item("points", theory_search::modal::MAX_POINTS)?;
    d.set_item("simulate_points", theory_search::dynamics::MAX_SIM_POINTS)?;
    d.set_item("operator_points", theory_search::body::MAX_OPERATOR_POINTS)?;
    d.set_item("text_file", theory_search::cli::MAX_TEXT_FILE)?;
    // The recording's default, for trackers' objects read in Python (DeepLabCut, SLEAP, movement).
    let recording = theory_search::recording::RecordingSettings::new(
        theory_search::recording::InputKind::Midline,
    );
    d.set_item("min_likelihood", recording.min_likelihood)?;
    Ok(d)
}

/// One keyword argument as the library's [`Setting`]: the library checks its type and range,
/// in the command line's words.
fn setting_of(key: &str, value: &Bound<'_, PyAny>) -> PyResult<Setting> {
    use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(Setting::Bool(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return value.extract::<i128>().map(Setting::Int).map_err(|_| {
            usage(format!(
                "{}: a whole number out of range",
                theory_search::markup::clip(key)
            ))
        });
    }
    if let Ok(x) = value.cast::<PyFloat>() {
        return Ok(Setting::Float(x.value()));
    }
    if let Ok(t) = value.cast::<PyString>() {
        return Ok(Setting::Text(t.to_string()));
    }
    // numpy's scalars: whole numbers first, then reals.
    if let Ok(i) = value.extract::<i128>() {
        return Ok(Setting::Int(i));
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(Setting::Float(x));
    }
    let kind = value
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    Err(usage(format!(
        "{} must be a number, text or a switch, not a {}",
        theory_search::markup::clip(key),
        theory_search::markup::clip(&kind)
    )))
}

/// Keyword arguments as (name, value) pairs (`None` values left to the defaults).
fn pairs_of(options: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, Setting)>> {
    let mut pairs = Vec::new();
    for (key, value) in options.into_iter().flat_map(|o| o.iter()) {
        let key: String = key
            .extract()
            .map_err(|_| usage("option names must be text"))?;
        if !value.is_none() {
            pairs.push((key.clone(), setting_of(&key, &value)?));
        }
    }
    Ok(pairs)
}

/// The fit's settings from keyword arguments, by the library's one constructor.
fn settings_of(options: Option<&Bound<'_, PyDict>>) -> PyResult<FitSettings> {
    let pairs = pairs_of(options)?;
    FitSettings::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.clone()))).map_err(fit_error)
}

fn fit_error(e: FitError) -> PyErr {
    let text = one_line(&e.to_string());
    if e.is_missing() {
        return MissingError::new_err(text);
    }
    raised(e.failure(), text)
}

/// The report as JSON plus the arrays JSON leaves out: frequencies, spectra (modes ×
/// frequencies), principal components (components × modes), mode shapes (modes × points).
type FitOut<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Vec<String>,
);

/// `fit`'s figure options (`figures`, `figure_format`, `figure_width`, `figure_dpi`), taken out
/// of `options`: the folder to write the fit's figures into and the page, checked before the
/// fit.
fn figure_page(
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Option<(std::path::PathBuf, theory_search::figures::Page)>> {
    use theory_search::figures::{Format, Page};
    let Some(options) = options else {
        return Ok(None);
    };
    let take = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
        let v = options.get_item(key)?;
        if v.is_some() {
            options.del_item(key)?;
        }
        Ok(v)
    };
    let (dir, format, width, dpi) = (
        take("figures")?,
        take("figure_format")?,
        take("figure_width")?,
        take("figure_dpi")?,
    );
    let Some(dir) = dir.filter(|d| !d.is_none()) else {
        if format.is_some() || width.is_some() || dpi.is_some() {
            return Err(usage(
                "figure_format, figure_width and figure_dpi need figures=DIR",
            ));
        }
        return Ok(None);
    };
    let bad = |what: &str| usage(format!("fit option {what}: expected a number"));
    let mut page = Page {
        format: Format::Svg,
        width_mm: 180.0,
        dpi: 300.0,
    };
    if let Some(f) = format {
        let name: String = f
            .extract()
            .map_err(|_| usage("figure_format must be \"svg\", \"png\" or \"pdf\""))?;
        page.format = name.parse().map_err(usage)?;
    }
    if let Some(w) = width {
        page.width_mm = w.extract().map_err(|_| bad("figure_width"))?;
    }
    if let Some(d) = dpi {
        page.dpi = d.extract().map_err(|_| bad("figure_dpi"))?;
    }
    page.check().map_err(usage)?;
    let dir: std::path::PathBuf = dir
        .extract()
        .map_err(|_| usage("figures must be a folder's path"))?;
    Ok(Some((dir, page)))
}

/// Write the fit's figures where asked; their paths.
fn write_figures(
    r: &FitReport,
    page: Option<(std::path::PathBuf, theory_search::figures::Page)>,
) -> PyResult<Vec<String>> {
    let Some((dir, page)) = page else {
        return Ok(Vec::new());
    };
    match theory_search::figures::write_fit(&dir, r, &page) {
        Ok(paths) => Ok(paths.iter().map(|p| p.display().to_string()).collect()),
        Err(e) => Err(raised(e.failure(), one_line(&e.to_string()))),
    }
}

fn fit_out<'py>(py: Python<'py>, r: FitReport, figures: Vec<String>) -> PyResult<FitOut<'py>> {
    let json = document(py, &serde_json::to_value(&r).map_err(usage)?)?;
    let two = |v: &Vec<Vec<f64>>| PyArray2::from_vec2(py, v).map_err(usage);
    Ok((
        json,
        PyArray1::from_vec(py, r.frequencies.clone()),
        two(&r.psd)?,
        two(&r.components)?,
        two(&r.shapes)?,
        figures,
    ))
}

/// A folder to write figures into, and their page.
type Page = Option<(std::path::PathBuf, theory_search::figures::Page)>;

/// What a fit is asked: the model, the figure page (taken out of `options` first) and the
/// settings from the rest.
fn fit_asked(
    model: Option<&str>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<(Model, Page, FitSettings)> {
    let model = model_of(model)?;
    let page = figure_page(options)?;
    Ok((model, page, settings_of(options)?))
}

/// Animals' midlines (frames × points × 2, NaN where a point was lost: its frame is lost) and
/// their frames' times as the library's tracks.
fn tracks_of(
    animals: &[PyReadonlyArray3<'_, f64>],
    times: &[PyReadonlyArray1<'_, f64>],
) -> PyResult<Vec<Track>> {
    if animals.len() != times.len() {
        return Err(usage("one time array per animal"));
    }
    let mut tracks = Vec::with_capacity(animals.len());
    for (i, (a, t)) in animals.iter().zip(times).enumerate() {
        let a = a.as_array();
        let t = t.as_array();
        let (frames, points, two) = a.dim();
        if two != 2 {
            return Err(usage(format!(
                "midlines must be frames × points × 2, not × {two}"
            )));
        }
        if t.len() != frames {
            return Err(usage(format!(
                "animal {}: {} times for {frames} frames",
                i + 1,
                t.len()
            )));
        }
        let frames = (0..frames)
            .map(|f| {
                let values: Vec<f64> = (0..points)
                    .flat_map(|p| [a[[f, p, 0]], a[[f, p, 1]]])
                    .collect();
                let lost = values.iter().any(|v| !v.is_finite());
                Frame {
                    t: t[f],
                    values: (!lost).then_some(values),
                }
            })
            .collect();
        tracks.push(Track {
            name: format!("animal {}", i + 1),
            frames,
        });
    }
    Ok(tracks)
}

/// Fit midlines given as an array (animals × frames × points × 2 flattened to frames ×
/// points × 2 per animal): NaN marks a lost point (its frame is lost).
#[pyfunction]
#[pyo3(signature = (animals, times, model, options))]
fn fit_arrays<'py>(
    py: Python<'py>,
    animals: Vec<PyReadonlyArray3<'py, f64>>,
    times: Vec<PyReadonlyArray1<'py, f64>>,
    model: Option<&str>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<FitOut<'py>> {
    let (model, page, settings) = fit_asked(model, options)?;
    let tracks = tracks_of(&animals, &times)?;
    let report = py
        .detach(|| {
            fit_inputs(
                vec![Input::Tracks(tracks)],
                &model,
                &Params::default(),
                &settings,
                None,
            )
        })
        .map_err(fit_error)?;
    let written = write_figures(&report, page)?;
    fit_out(py, report, written)
}

/// Fit recordings read from files (any format `fit` reads), each one animal or several.
#[pyfunction]
#[pyo3(signature = (paths, model, options))]
fn fit_paths<'py>(
    py: Python<'py>,
    paths: Vec<String>,
    model: Option<&str>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<FitOut<'py>> {
    let (model, page, settings) = fit_asked(model, options)?;
    // Files, directories and patterns, as the command line takes them.
    let paths: Vec<std::path::PathBuf> = paths.into_iter().map(Into::into).collect();
    let inputs = theory_search::recording::recordings(&paths)
        .map_err(|e| fit_error(e.into()))?
        .into_iter()
        .map(Input::File)
        .collect::<Vec<_>>();
    let report = py
        .detach(|| fit_inputs(inputs, &model, &Params::default(), &settings, None))
        .map_err(fit_error)?;
    let written = write_figures(&report, page)?;
    fit_out(py, report, written)
}

/// `discover` on recordings given as paths (files, directories, patterns) or as arrays (one
/// animal each), through the library: the report's JSON (the command's `--format json`) and
/// the figures written. `model_path` is the model file's path when the model came from one
/// (named in the onward `simulate` line).
#[pyfunction]
#[pyo3(signature = (paths, animals, times, model, model_path, options))]
fn discover_json<'py>(
    py: Python<'py>,
    paths: Vec<String>,
    animals: Vec<PyReadonlyArray3<'py, f64>>,
    times: Vec<PyReadonlyArray1<'py, f64>>,
    model: Option<&str>,
    model_path: Option<String>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    use theory_search::discover::{discover, DiscoverSettings, Source};
    use theory_search::report::Report;
    let mut model = model_of(model)?;
    let page = figure_page(options)?;
    let mut pairs = pairs_of(options)?;
    // The model's layers, as the command line's --beyond-leading sets them.
    if let Some(i) = pairs.iter().position(|(k, _)| k == "beyond_leading") {
        let (_, value) = pairs.remove(i);
        let k = value
            .count(
                "beyond_leading",
                theory_search::model::MAX_BEYOND_LEADING as usize,
            )
            .map_err(|e| usage(e.to_string()))?;
        model.set_beyond_leading(k as u32);
    }
    let discover_error =
        |e: theory_search::discover::DiscoverError| raised(e.failure(), one_line(&e.to_string()));
    let mut settings =
        DiscoverSettings::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.clone())))
            .map_err(discover_error)?;
    settings.replay = page.is_some();
    let mut sources: Vec<Source<'_>> = Vec::new();
    if !paths.is_empty() {
        let paths: Vec<std::path::PathBuf> = paths.into_iter().map(Into::into).collect();
        let found =
            theory_search::recording::recordings(&paths).map_err(|e| fit_error(e.into()))?;
        sources.extend(found.into_iter().map(Source::File));
    }
    sources.extend(tracks_of(&animals, &times)?.into_iter().map(Source::Track));
    let mut report = py
        .detach(|| discover(sources, &model, &settings))
        .map_err(discover_error)?;
    report.model_argument = model_path;
    let mut written = Vec::new();
    if let (Some((dir, page)), None) = (page, &report.onward_refused) {
        let path = theory_search::figures::write_discover(&dir, &report, &page)
            .map_err(|e| raised(e.failure(), one_line(&e.to_string())))?;
        written.push(path.display().to_string());
    }
    report
        .check()
        .map_err(|e| raised(Failure::Numerical, one_line(&e.to_string())))?;
    Ok((document(py, &report.json())?, written))
}

/// `compare` on two groups of animals, each group given as paths (files, directories,
/// patterns; each file one animal) and arrays (each one animal), through the library: the
/// report's JSON (the command's `--format json`).
#[pyfunction]
#[pyo3(signature = (first, second, names, model, options))]
fn compare_json<'py>(
    py: Python<'py>,
    first: GroupIn<'py>,
    second: GroupIn<'py>,
    names: (String, String),
    model: Option<&str>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    use theory_search::compare::{compare, CompareSettings, Group};
    use theory_search::report::Report;
    let model = model_of(model)?;
    let page = figure_page(options)?;
    let pairs = pairs_of(options)?;
    let compare_error =
        |e: theory_search::compare::CompareError| raised(e.failure(), one_line(&e.to_string()));
    let settings = CompareSettings::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.clone())))
        .map_err(compare_error)?;
    let mut groups = Vec::new();
    for (name, (paths, animals, times)) in [(names.0, first), (names.1, second)] {
        let paths: Vec<std::path::PathBuf> = paths.into_iter().map(Into::into).collect();
        let found = if paths.is_empty() {
            Vec::new()
        } else {
            theory_search::recording::recordings(&paths).map_err(|e| fit_error(e.into()))?
        };
        let mut inputs: Vec<Input<'_>> = found.into_iter().map(Input::File).collect();
        // Each array its own input: one animal, fitted alone.
        for track in tracks_of(&animals, &times)? {
            inputs.push(Input::Tracks(vec![track]));
        }
        groups.push(Group { name, inputs });
    }
    let report = py
        .detach(|| compare(groups, &model, &Params::default(), &settings))
        .map_err(compare_error)?;
    report
        .check()
        .map_err(|e| raised(Failure::Numerical, one_line(&e.to_string())))?;
    let mut written = Vec::new();
    if let Some((dir, page)) = page {
        let path = theory_search::figures::write_compare(&dir, &report, &page)
            .map_err(|e| raised(e.failure(), one_line(&e.to_string())))?;
        written.push(path.display().to_string());
    }
    Ok((document(py, &report.json())?, written))
}

/// One group of `compare`: paths, and animals' midlines with their times.
type GroupIn<'py> = (
    Vec<String>,
    Vec<PyReadonlyArray3<'py, f64>>,
    Vec<PyReadonlyArray1<'py, f64>>,
);

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TheorySearchError", py.get_type::<TheorySearchError>())?;
    m.add("UsageError", py.get_type::<UsageError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("MissingError", py.get_type::<MissingError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add("NumericalError", py.get_type::<NumericalError>())?;
    m.add_function(wrap_pyfunction!(commands::count_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::rules_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::terms_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::asymmetry_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::mathieu_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::stats_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::behave_json, m)?)?;
    m.add_function(wrap_pyfunction!(commands::figures, m)?)?;
    m.add_function(wrap_pyfunction!(limits, m)?)?;
    m.add_function(wrap_pyfunction!(larva_toml, m)?)?;
    m.add_function(wrap_pyfunction!(check_model, m)?)?;
    m.add_function(wrap_pyfunction!(table_json, m)?)?;
    m.add_function(wrap_pyfunction!(equations_json, m)?)?;
    m.add_function(wrap_pyfunction!(active_json, m)?)?;
    m.add_function(wrap_pyfunction!(operators, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(fit_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(fit_paths, m)?)?;
    m.add_function(wrap_pyfunction!(discover_json, m)?)?;
    m.add_function(wrap_pyfunction!(compare_json, m)?)?;
    Ok(())
}
