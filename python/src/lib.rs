//! The native half of the `theory_search` Python package: thin wrappers over the library (never
//! the CLI binary). Structured results cross as JSON text (the same documents the CLI's
//! `--format json` prints) and numbers as numpy arrays; every error becomes a Python exception of
//! the `TheorySearchError` family with the library's one-line message, and long work runs with
//! the GIL released.

use std::collections::HashMap;

use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray3};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use theory_search::enumerate::Basis;
use theory_search::fit::{
    fit_inputs, FitError, FitReport, FitSettings, Frame, Input, InputKind, Track,
};
use theory_search::modal::{field_modes, Params};
use theory_search::model::{one_line, Density, Model};

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
    OutputError,
    TheorySearchError,
    "Output that cannot be written (the CLI's exit code 1)."
);

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

fn params_of(params: Option<HashMap<String, f64>>) -> PyResult<Params> {
    let mut p = Params::default();
    for (name, value) in params.unwrap_or_default() {
        p.set(&name, value).map_err(usage)?;
    }
    Ok(p)
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
fn table_json(
    py: Python<'_>,
    order: u32,
    model: Option<&str>,
    basis: &str,
    density: &str,
) -> PyResult<String> {
    let model = model_of(model)?;
    let basis = basis_of(basis)?;
    let densities = match density {
        "both" => vec![Density::Lagrangian, Density::Rayleigh],
        "lagrangian" => vec![Density::Lagrangian],
        "rayleigh" => vec![Density::Rayleigh],
        other => {
            return Err(usage(format!(
                "density must be \"lagrangian\", \"rayleigh\" or \"both\", not {other:?}"
            )))
        }
    };
    py.detach(|| {
        let analyses = densities
            .into_iter()
            .map(|d| theory_search::reduce::analyse_basis(&model, d, order, basis))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        Ok(theory_search::table::json_report(&model, &analyses).to_string())
    })
    .map_err(|e: String| usage(e))
}

/// The equations of motion as the CLI's JSON document (linear, or exact nonlinear).
#[pyfunction]
#[pyo3(signature = (order, model, basis))]
fn equations_json(order: u32, model: Option<&str>, basis: &str) -> PyResult<String> {
    use theory_search::equations::{derive_basis, derive_nonlinear, EquationError};
    use theory_search::report::Report;
    let model = model_of(model)?;
    let basis = basis_of(basis)?;
    let report = |e: Vec<_>, n| theory_search::equations::EquationReport {
        model: model.name.clone(),
        order,
        equations: e,
        notes: n,
    };
    match derive_basis(&model, order, basis) {
        Ok((e, n)) => Ok(report(e, n).json().to_string()),
        Err(EquationError::NotQuadratic { .. }) => {
            let (e, n) = derive_nonlinear(&model, order, basis).map_err(usage)?;
            let r = theory_search::equations::EquationReport {
                model: model.name.clone(),
                order,
                equations: e,
                notes: n,
            };
            Ok(r.json().to_string())
        }
        Err(e) => Err(usage(e)),
    }
}

/// Every operator on `points` points: dicts with the exact integer matrix as a numpy array.
#[pyfunction]
#[pyo3(signature = (points, order, model))]
fn operators<'py>(
    py: Python<'py>,
    points: usize,
    order: u32,
    model: Option<&str>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let model = model_of(model)?;
    let ops = py
        .detach(|| theory_search::discretise::operators(&model, order, points))
        .map_err(usage)?;
    ops.into_iter()
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
        .collect()
}

/// Each field's modes: eigenvalues, frequencies, damping ratios, variance shares, and the
/// shapes (points × modes) when asked.
#[pyfunction]
#[pyo3(signature = (points, order, model, params, shapes, k))]
fn modes<'py>(
    py: Python<'py>,
    points: usize,
    order: u32,
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
    shapes: bool,
    k: Option<usize>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let model = model_of(model)?;
    let params = params_of(params)?;
    let all = py
        .detach(|| field_modes(&model, order, points, &params, k, shapes))
        .map_err(usage)?;
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

/// Simulate (Langevin at `temperature`, or deterministic at 0): times and each field's
/// positions and modal coordinates, one row per kept step.
#[pyfunction]
#[pyo3(signature = (points, steps, dt, every, temperature, seed, order, model, params))]
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
    model: Option<&str>,
    params: Option<HashMap<String, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = model_of(model)?;
    let params = params_of(params)?;
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
    let fields = model.fields.len();
    let (t, energy, positions, modal) = py
        .detach(|| {
            let mut t = Vec::new();
            let mut energy = Vec::new();
            let mut positions: Vec<Vec<Vec<f64>>> = vec![Vec::new(); fields];
            let mut modal: Vec<Vec<Vec<f64>>> = vec![Vec::new(); fields];
            theory_search::dynamics::simulate(&model, &params, &config, |s| {
                t.push(s.t);
                energy.push(s.energy);
                for f in 0..fields {
                    positions[f].push(s.positions[f].clone());
                    modal[f].push(s.modal[f].clone());
                }
                Ok(())
            })
            .map(|_| (t, energy, positions, modal))
        })
        .map_err(usage)?;
    let out = PyDict::new(py);
    out.set_item("t", PyArray1::from_vec(py, t))?;
    out.set_item("energy", PyArray1::from_vec(py, energy))?;
    let (p, q) = (PyDict::new(py), PyDict::new(py));
    for (f, field) in model.fields.iter().enumerate() {
        p.set_item(
            &field.id,
            PyArray2::from_vec2(py, &positions[f]).map_err(usage)?,
        )?;
        q.set_item(
            &field.id,
            PyArray2::from_vec2(py, &modal[f]).map_err(usage)?,
        )?;
    }
    out.set_item("positions", p)?;
    out.set_item("modal", q)?;
    Ok(out)
}

/// The fit's settings from keyword arguments.
fn settings_of(options: Option<&Bound<'_, PyDict>>) -> PyResult<FitSettings> {
    let mut s = FitSettings::new(InputKind::Midline);
    let Some(options) = options else {
        return Ok(s);
    };
    for (key, value) in options.iter() {
        let key: String = key.extract()?;
        match key.as_str() {
            "kind" => {
                s.kind = match value.extract::<String>()?.as_str() {
                    "midline" => InputKind::Midline,
                    "lengths" => InputKind::Lengths,
                    other => {
                        return Err(usage(format!(
                            "kind must be \"midline\" or \"lengths\", not {other:?}"
                        )))
                    }
                }
            }
            "field" => s.field = value.extract()?,
            "order" => s.order = value.extract()?,
            "points" => s.points = value.extract()?,
            "window" => s.window = value.extract()?,
            "fit_modes" => s.fit_modes = value.extract()?,
            "omega" => s.omega = value.extract()?,
            "ring" => s.ring = value.extract()?,
            "fill_gaps" => s.fill_gaps = value.extract()?,
            "head" => {
                s.head_first = match value.extract::<String>()?.as_str() {
                    "first" => true,
                    "last" => false,
                    other => {
                        return Err(usage(format!(
                            "head must be \"first\" or \"last\", not {other:?}"
                        )))
                    }
                }
            }
            "fps" => s.fps = value.extract()?,
            "min_likelihood" => s.min_likelihood = value.extract()?,
            "track_column" => s.track_column = value.extract()?,
            "bootstrap" => s.bootstrap = value.extract()?,
            "seed" => s.seed = value.extract()?,
            "time_unit" => s.time_unit = value.extract()?,
            "length_unit" => s.length_unit = value.extract()?,
            other => return Err(usage(format!("fit has no option {other:?}"))),
        }
    }
    Ok(s)
}

fn fit_error(e: FitError) -> PyErr {
    let text = one_line(&e.to_string());
    match e.innermost() {
        FitError::Invalid(_) => UsageError::new_err(text),
        FitError::Open(io) if io.kind() == std::io::ErrorKind::NotFound => {
            MissingError::new_err(text)
        }
        _ => InputError::new_err(text),
    }
}

/// The report as JSON plus the arrays JSON leaves out: frequencies, spectra (modes ×
/// frequencies), principal components (components × modes), mode shapes (modes × points).
type FitOut<'py> = (
    String,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
);

fn fit_out<'py>(py: Python<'py>, r: FitReport) -> PyResult<FitOut<'py>> {
    let json = serde_json::to_string(&r).map_err(usage)?;
    let two = |v: &Vec<Vec<f64>>| PyArray2::from_vec2(py, v).map_err(usage);
    Ok((
        json,
        PyArray1::from_vec(py, r.frequencies.clone()),
        two(&r.psd)?,
        two(&r.components)?,
        two(&r.shapes)?,
    ))
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
    let model = model_of(model)?;
    let settings = settings_of(options)?;
    if animals.len() != times.len() {
        return Err(usage("one time array per animal"));
    }
    let mut tracks = Vec::with_capacity(animals.len());
    for (i, (a, t)) in animals.iter().zip(&times).enumerate() {
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
    fit_out(py, report)
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
    let model = model_of(model)?;
    let settings = settings_of(options)?;
    let inputs = paths
        .into_iter()
        .map(|p| Input::File(p.into()))
        .collect::<Vec<_>>();
    let report = py
        .detach(|| fit_inputs(inputs, &model, &Params::default(), &settings, None))
        .map_err(fit_error)?;
    fit_out(py, report)
}

/// Run a command line of the `theory-search` CLI in this process (GIL released); its standard
/// output as bytes. Every command is reachable this way with the CLI's own parsing, messages and
/// numbers; the error is typed by the CLI's error variant, never read from its text.
#[pyfunction]
fn run_cli<'py>(py: Python<'py>, args: Vec<String>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
    use theory_search::cli::CliError;
    let mut all = vec!["theory-search".to_string()];
    all.extend(args);
    let (out, result) = py.detach(|| {
        let mut out = Vec::new();
        let result = theory_search::cli::run(all, &mut out);
        (out, result)
    });
    match result {
        Ok(()) => Ok(pyo3::types::PyBytes::new(py, &out)),
        Err(e) => {
            let text = one_line(&e.to_string());
            Err(match e {
                CliError::Usage(_) | CliError::Role(_) => UsageError::new_err(text),
                CliError::Missing(_) => MissingError::new_err(text),
                CliError::Output(_) => OutputError::new_err(text),
                _ => InputError::new_err(text),
            })
        }
    }
}

/// Whether every surviving term of `model` at `order` is a square (the exact modal path).
#[pyfunction]
#[pyo3(signature = (order, model))]
fn is_quadratic(order: u32, model: Option<&str>) -> PyResult<bool> {
    theory_search::dynamics::is_quadratic(&model_of(model)?, order).map_err(usage)
}

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TheorySearchError", py.get_type::<TheorySearchError>())?;
    m.add("UsageError", py.get_type::<UsageError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("MissingError", py.get_type::<MissingError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(is_quadratic, m)?)?;
    m.add_function(wrap_pyfunction!(larva_toml, m)?)?;
    m.add_function(wrap_pyfunction!(check_model, m)?)?;
    m.add_function(wrap_pyfunction!(table_json, m)?)?;
    m.add_function(wrap_pyfunction!(equations_json, m)?)?;
    m.add_function(wrap_pyfunction!(operators, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(fit_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(fit_paths, m)?)?;
    Ok(())
}
