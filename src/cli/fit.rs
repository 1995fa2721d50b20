//! `theory-search fit`: the theory fitted to tracked midlines or segment lengths.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{emit, CliError, ModelArgs};
use crate::fit::{fit_inputs, FitReport, FitSettings, Input, SinkError};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::{Projector, Setting};
use crate::report::Output;

/// Arguments of `fit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The recordings (`-` for standard input): `t x₁ y₁ … x_K y_K` or `t ℓ₁ … ℓ_K` per line,
    /// DeepLabCut CSV or WCON. Several files, a directory (its .csv, .txt, .wcon and .json
    /// files) or a pattern with `*` and `?` in the file name are several animals: one pooled fit
    /// and each animal's own.
    #[arg(value_name = "FILE", required = true)]
    input: Vec<PathBuf>,
    #[command(flatten)]
    recording: super::recording::RecordingArgs,
    /// Welch window in frames (default: chosen from the data, so that the lowest mode lies
    /// 16 frequency bins above zero).
    #[arg(long, value_name = "FRAMES")]
    window: Option<usize>,
    /// Frequency estimator: peak (rhythmic behaviour) or centroid (aperiodic).
    #[arg(long, value_enum, default_value_t = FitEstimator::Peak)]
    estimator: FitEstimator,
    /// Non-zero modes used to fit ω and β (`--modes K` too, as `modes` names its count).
    #[arg(long, default_value_t = 4, visible_alias = "modes", value_name = "K")]
    fit_modes: usize,
    /// Fix ω instead of fitting it.
    #[arg(allow_hyphen_values = true, long)]
    omega: Option<f64>,
    /// Bootstrap replicates for 95 % intervals: whole animals (or one animal's whole runs)
    /// are drawn with replacement.
    #[arg(long, value_name = "B", default_value_t = 0)]
    bootstrap: usize,
    /// Seed of the bootstrap draws (same seed, same intervals).
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
    /// Also write the fit's figures into this directory (SVG unless `--figure-format`).
    #[arg(long, value_name = "DIR")]
    figures: Option<PathBuf>,
    #[command(flatten)]
    page: super::options::FitPageArgs,
    /// Also write every frame's modal coordinates to this CSV file (t, q_<mode>, …).
    #[arg(long, value_name = "FILE")]
    series: Option<PathBuf>,
    /// Also write the per-animal table (each animal's own fit) to this CSV file.
    #[arg(long, value_name = "FILE")]
    animals: Option<PathBuf>,
    /// Also write the fitted scale as a parameter file (`omega_<scale> = ω`, in the data's time
    /// unit), for `--params FILE` of `modes`, `simulate`, `behave` and `stats`.
    #[arg(long, value_name = "FILE")]
    params_out: Option<PathBuf>,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format (csv: one row per mode).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Frequency estimators of `fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum FitEstimator {
    Peak,
    Centroid,
}

/// Fit and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    // Figure options are checked before the (possibly long) fit.
    let page = args.page.page()?;
    let model = args.model.load()?;
    let mut pairs = args.recording.pairs(args.model.order);
    pairs.extend([
        ("estimator", super::recording::choice(args.estimator)),
        ("fit_modes", super::recording::count(args.fit_modes)),
        ("bootstrap", super::recording::count(args.bootstrap)),
        ("seed", Setting::Int(args.seed.into())),
    ]);
    pairs.extend(args.window.map(|w| ("window", super::recording::count(w))));
    pairs.extend(args.omega.map(|w| ("omega", Setting::Float(w))));
    let settings = FitSettings::from_pairs(pairs)?;
    let inputs: Vec<Input<'_>> = crate::recording::recordings(&args.input)?
        .into_iter()
        .map(|p| {
            if p.as_os_str() == "-" {
                Input::Reader {
                    name: "-".into(),
                    reader: Box::new(std::io::BufReader::new(std::io::stdin())),
                }
            } else {
                Input::File(p)
            }
        })
        .collect();
    let params = Params::default();
    let mut sink = series_sink(args.series.as_deref())?;
    let result = if args.series.is_some() {
        let mut each = |p: &Projector, t: f64, q: &[f64]| write_series(&mut sink, p, t, q);
        fit_inputs(inputs, &model, &params, &settings, Some(&mut each))
    } else {
        fit_inputs(inputs, &model, &params, &settings, None)
    };
    finish_series(sink)?;
    let mut report = result?;
    report.inputs = super::recording::inputs(&args.input, &args.recording);
    report.model_argument = args.model.model.as_ref().map(|p| p.display().to_string());
    if let Some(dir) = &args.figures {
        crate::figures::write_fit(dir, &report, &page).map_err(super::figures::usage)?;
    }
    if let Some(path) = &args.params_out {
        write_params(path, &model, &report)?;
    }
    if let Some(path) = &args.animals {
        std::fs::write(path, report.animals_csv())
            .map_err(|e| CliError::Output(format!("cannot write {}: {e}", path.display())))?;
    }
    emit(out, &report, args.format)
}

/// The `--series` CSV: its path, the writer, and whether the header is out.
type Series<'a> = Option<(&'a Path, csv::Writer<std::fs::File>, bool)>;

fn series_sink(series: Option<&Path>) -> Result<Series<'_>, CliError> {
    series
        .map(|path| {
            csv::Writer::from_path(path)
                .map(|w| (path, w, false))
                .map_err(|e| CliError::Output(format!("cannot write {}: {e}", path.display())))
        })
        .transpose()
}

/// The modal series file could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {source}", .path.display())]
struct SeriesError {
    path: std::path::PathBuf,
    source: csv::Error,
}

/// One frame's modal coordinates as a CSV record (t, q_<mode>, …), header first.
fn write_series(sink: &mut Series<'_>, p: &Projector, t: f64, q: &[f64]) -> Result<(), SinkError> {
    let Some((path, out, started)) = sink.as_mut() else {
        return Ok(());
    };
    let fail = |source: csv::Error| -> SinkError {
        Box::new(SeriesError {
            path: path.to_path_buf(),
            source,
        })
    };
    if !*started {
        let mut names = vec!["t".to_string()];
        names.extend((0..q.len()).map(|j| format!("q_{}", p.first_mode + j)));
        out.write_record(&names).map_err(fail)?;
        *started = true;
    }
    let cells = std::iter::once(t)
        .chain(q.iter().copied())
        .map(|v| v.to_string());
    out.write_record(cells).map_err(fail)
}

fn finish_series(sink: Series<'_>) -> Result<(), CliError> {
    if let Some((path, mut out, _)) = sink {
        out.flush()
            .map_err(|e| CliError::Output(format!("cannot write {}: {e}", path.display())))?;
    }
    Ok(())
}

/// The fitted ω as a parameter file, with β and the units in comments.
/// `v` as a TOML float that reads back exactly: Rust's shortest round-trip form, which always
/// has a `.` or an exponent (`9.55736315946994e18`, never an integer TOML would reject).
fn toml_float(v: f64) -> String {
    format!("{v:?}")
}

fn write_params(path: &Path, model: &Model, report: &FitReport) -> Result<(), CliError> {
    let scale = model
        .field(&report.field)
        .map(|f| f.scale().to_string())
        .unwrap_or_else(|| report.field.clone());
    let time = report
        .units
        .time
        .as_deref()
        .unwrap_or("the recording's time unit");
    let text = format!(
        "# Fitted by theory-search fit from {} frames of field {} (model {}).\n\
         # ω is in radians per {time}; β = {} {time}² with amplitudes in point spacings\n\
         # (simulate --temperature {}).\n\
         omega_{scale} = {}\n",
        report.frames,
        report.field,
        model.name,
        crate::report::number(report.beta),
        crate::report::number(1.0 / report.beta),
        toml_float(report.omega)
    );
    std::fs::write(path, text)
        .map_err(|e| CliError::Output(format!("cannot write {}: {e}", path.display())))
}
