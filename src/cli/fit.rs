//! `theory-search fit`: the theory fitted to tracked midlines or segment lengths.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{emit, CliError, ModelArgs};
use crate::fit::{fit_each, Estimator, FitError, FitReport, FitSettings, InputKind, Projector};
use crate::modal::Params;
use crate::model::Model;
use crate::report::Output;

/// Arguments of `fit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The recordings (`-` for standard input): `t x₁ y₁ … x_K y_K` or `t ℓ₁ … ℓ_K` per line.
    /// Several files, or a directory (its .csv and .txt files), are several animals: one pooled
    /// fit and each animal's own.
    #[arg(value_name = "FILE", required = true)]
    input: Vec<PathBuf>,
    /// What the columns after time hold.
    #[arg(long, value_enum, default_value_t = FitKind::Midline)]
    kind: FitKind,
    /// The model field the data observe (default: the lateral field for midlines, the axial
    /// one for lengths).
    #[arg(long)]
    field: Option<String>,
    /// Model points N for midlines (resampled by arc length when the data have another K).
    #[arg(long, default_value_t = 12)]
    points: usize,
    /// Welch window in frames.
    #[arg(long, default_value_t = 256)]
    window: usize,
    /// Frequency estimator: peak (rhythmic behaviour) or centroid (aperiodic).
    #[arg(long, value_enum, default_value_t = FitEstimator::Peak)]
    estimator: FitEstimator,
    /// Non-zero modes used to fit ω and β.
    #[arg(long, default_value_t = 4)]
    fit_modes: usize,
    /// Fix ω instead of fitting it.
    #[arg(long)]
    omega: Option<f64>,
    /// Lengths only: the number of segments around the whole body when only the first K
    /// were measured (fits the lowest whole modes by least squares).
    #[arg(long, value_name = "R")]
    ring: Option<usize>,
    /// Bridge gaps of at most K lost frames linearly; longer gaps split the recording into runs
    /// (the covariance pools every usable frame, the spectra use windows inside one run).
    #[arg(long, value_name = "K", default_value_t = 0)]
    fill_gaps: usize,
    /// Frames per second of a DeepLabCut file (its rows hold frame indices; without it the
    /// time unit is one frame).
    #[arg(long, value_name = "F")]
    fps: Option<f64>,
    /// DeepLabCut points tracked below this likelihood make their frame lost.
    #[arg(long, value_name = "P", default_value_t = 0.6)]
    min_likelihood: f64,
    /// Which end the data list first: `last` (head last, the model's order) or `first` (head
    /// first, as most trackers write).
    #[arg(long, value_enum, default_value_t = HeadEnd::Last)]
    head: HeadEnd,
    /// Also write the fit's SVG figures into this directory.
    #[arg(long, value_name = "DIR")]
    figures: Option<PathBuf>,
    /// Also write every frame's modal coordinates to this CSV file (t, q_<mode>, …).
    #[arg(long, value_name = "FILE")]
    series: Option<PathBuf>,
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

/// Input kinds of `fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum FitKind {
    Midline,
    Lengths,
}

/// Where the head is in each frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum HeadEnd {
    First,
    Last,
}

/// Frequency estimators of `fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum FitEstimator {
    Peak,
    Centroid,
}

/// Fit and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let mut settings = FitSettings::new(match args.kind {
        FitKind::Midline => InputKind::Midline,
        FitKind::Lengths => InputKind::Lengths,
    });
    settings.field = args.field.clone();
    settings.order = args.model.order;
    settings.points = args.points;
    settings.window = args.window;
    settings.estimator = match args.estimator {
        FitEstimator::Peak => Estimator::Peak,
        FitEstimator::Centroid => Estimator::Centroid,
    };
    settings.fit_modes = args.fit_modes;
    settings.omega = args.omega;
    if args.ring.is_some() && args.kind != FitKind::Lengths {
        return Err(CliError::Usage(
            "--ring applies to --kind lengths only".into(),
        ));
    }
    settings.ring = args.ring;
    settings.fill_gaps = args.fill_gaps;
    settings.head_first = args.head == HeadEnd::First;
    settings.fps = args.fps;
    settings.min_likelihood = args.min_likelihood;
    let inputs = recordings(&args.input)?;
    let report = if inputs.len() == 1 {
        fit_input(&inputs[0], args.series.as_deref(), &model, &settings)?
    } else {
        fit_pooled(&inputs, args.series.as_deref(), &model, &settings)?
    };
    if let Some(dir) = &args.figures {
        crate::figures::write_fit(dir, &report).map_err(|e| CliError::Output(e.to_string()))?;
    }
    if let Some(path) = &args.params_out {
        write_params(path, &model, &report)?;
    }
    emit(out, &report, args.format)
}

/// The recordings named: files as given, a directory's .csv and .txt files in name order.
fn recordings(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, CliError> {
    let mut out = Vec::new();
    for path in inputs {
        if path.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| CliError::Input(format!("cannot read {}: {e}", path.display())))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "csv" || x == "txt"))
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(CliError::Input(format!(
                    "{}: no .csv or .txt recordings in this directory",
                    path.display()
                )));
            }
            out.extend(files);
        } else {
            out.push(path.clone());
        }
    }
    if out.len() > 1 && out.iter().any(|p| p.as_os_str() == "-") {
        return Err(CliError::Usage(
            "standard input (-) is one recording: give files instead to pool several".into(),
        ));
    }
    Ok(out)
}

/// Each recording alone (its errors name its file), then all pooled.
fn fit_pooled(
    inputs: &[PathBuf],
    series: Option<&Path>,
    model: &Model,
    settings: &FitSettings,
) -> Result<FitReport, CliError> {
    let mut animals = Vec::new();
    for path in inputs {
        let alone = fit_input(path, None, model, settings)?;
        animals.push(crate::fit::AnimalFit::of(
            &path.display().to_string(),
            &alone,
        ));
    }
    let readers = inputs
        .iter()
        .map(|p| {
            std::fs::File::open(p)
                .map(std::io::BufReader::new)
                .map_err(|e| CliError::Input(format!("cannot open {}: {e}", p.display())))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut sink = series_sink(series)?;
    let mut report =
        crate::fit::fit_animals(readers, model, &Params::default(), settings, |p, t, q| {
            write_series(&mut sink, p, t, q)
        })
        .map_err(|e| match e {
            FitError::Output(m) => CliError::Output(m),
            other => CliError::Usage(format!("pooled fit: {other}")),
        })?;
    finish_series(sink)?;
    report.animals = animals;
    Ok(report)
}

/// Run the fit on a file or standard input, streaming the modal series to `series` if asked
/// (written with the `csv` crate).
fn fit_input(
    input: &Path,
    series: Option<&Path>,
    model: &Model,
    settings: &FitSettings,
) -> Result<FitReport, CliError> {
    let params = Params::default();
    let mut sink = series_sink(series)?;
    let each = |p: &Projector, t: f64, q: &[f64]| write_series(&mut sink, p, t, q);
    let result = if input.as_os_str() == "-" {
        fit_each(std::io::stdin().lock(), model, &params, settings, each)
    } else {
        let file = std::fs::File::open(input)
            .map_err(|e| CliError::Input(format!("cannot open {}: {e}", input.display())))?;
        fit_each(
            std::io::BufReader::new(file),
            model,
            &params,
            settings,
            each,
        )
    };
    finish_series(sink)?;
    result.map_err(|e| match e {
        FitError::Invalid(m) => CliError::Usage(m),
        FitError::Output(m) => CliError::Output(m),
        other => CliError::Input(format!("{}: {other}", input.display())),
    })
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

/// One frame's modal coordinates as a CSV record (t, q_<mode>, …), header first.
fn write_series(sink: &mut Series<'_>, p: &Projector, t: f64, q: &[f64]) -> Result<(), String> {
    let Some((path, out, started)) = sink.as_mut() else {
        return Ok(());
    };
    let fail = |e: csv::Error| format!("cannot write {}: {e}", path.display());
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
fn write_params(path: &Path, model: &Model, report: &FitReport) -> Result<(), CliError> {
    let scale = model
        .field(&report.field)
        .map(|f| f.scale().to_string())
        .unwrap_or_else(|| report.field.clone());
    let text = format!(
        "# Fitted by theory-search fit from {} frames of field {} (model {}).\n\
         # ω is in radians per unit of the recording's time; β = {} in units of the point spacing\n\
         # (lengths) and of that time: it scales as time² / length².\n\
         omega_{scale} = {}\n",
        report.frames, report.field, model.name, report.beta, report.omega
    );
    std::fs::write(path, text)
        .map_err(|e| CliError::Output(format!("cannot write {}: {e}", path.display())))
}
