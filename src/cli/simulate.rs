//! `theory-search simulate`: the modal dynamics, streamed as CSV.

use std::io::Write;
use std::path::PathBuf;

use super::{CliError, ModelArgs, ParamArgs};
use crate::dynamics::{
    sample_header, sample_row, simulate, Config, DynamicsError, Forcing, Halt, Initial, Sample,
};

/// Arguments of `simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of points along the body (the paper uses 12): at least what the model's operators
    /// need (3 for the larva; the error names it), up to 2000.
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=crate::dynamics::MAX_SIM_POINTS as u64))]
    points: u64,
    /// Time step.
    #[arg(allow_hyphen_values = true, long, default_value_t = 0.01)]
    dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 1000)]
    steps: u64,
    /// Write a row every K steps (the initial state is always written).
    #[arg(long, default_value_t = 1, value_name = "K")]
    every: u64,
    /// Initial modal state FIELD:MODE=Q[,Q̇], e.g. `theta:1=3.14` or `y:2=0,0.5` (repeatable).
    #[arg(long = "initial", value_name = "FIELD:MODE=Q[,V]")]
    initial: Vec<String>,
    /// Constant modal force FIELD:MODE=F (repeatable).
    #[arg(long = "force", value_name = "FIELD:MODE=F")]
    force: Vec<String>,
    /// Sinusoidal modal force FIELD:MODE=F0,OMEGA[,PHASE]: F0·cos(OMEGA·t + PHASE) (repeatable).
    #[arg(long = "drive", value_name = "FIELD:MODE=F0,OMEGA[,PHASE]")]
    drive: Vec<String>,
    /// Thermal energy kT of the Langevin noise (0: none).
    #[arg(allow_hyphen_values = true, long, default_value_t = 0.0)]
    temperature: f64,
    /// Seed of the noise (same seed, same run).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the series here instead of standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Output format: CSV (a header, then one row per sample) or JSON (`columns` and `rows`),
    /// both streamed as the run goes.
    #[arg(long, value_enum, default_value_t = SeriesFormat::Csv)]
    format: SeriesFormat,
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    model: ModelArgs,
}

/// How a time series is written (it is streamed, so there is no aligned text form).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum SeriesFormat {
    /// CSV: a header, then one row per sample.
    Csv,
    /// JSON: `{"columns": […], "rows": [[…], …]}`.
    Json,
}

/// Where samples go: a CSV writer, or JSON rows written one by one.
enum Sink<'a> {
    Csv(Box<csv::Writer<&'a mut dyn Write>>),
    Json(std::io::BufWriter<&'a mut dyn Write>, bool),
}

impl Sink<'_> {
    /// Write the header (before the first sample) and one sample.
    fn sample(&mut self, header: Option<Vec<String>>, s: &Sample) -> Result<(), Halt> {
        match self {
            Sink::Csv(csv) => {
                if let Some(h) = header {
                    csv.write_record(h).map_err(csv_halt)?;
                }
                csv.write_record(sample_row(s)).map_err(csv_halt)
            }
            Sink::Json(out, any) => {
                if let Some(h) = header {
                    write!(out, "{{\"columns\": ").map_err(Halt::Io)?;
                    serde_json::to_writer(&mut *out, &h).map_err(|e| Halt::Io(e.into()))?;
                    write!(out, ", \"rows\": [").map_err(Halt::Io)?;
                }
                let row: Vec<f64> = [s.t, s.energy]
                    .into_iter()
                    .chain(s.positions.iter().chain(&s.modal).flatten().copied())
                    .collect();
                out.write_all(if *any { b",\n" } else { b"\n" })
                    .map_err(Halt::Io)?;
                *any = true;
                serde_json::to_writer(&mut *out, &row).map_err(|e| Halt::Io(e.into()))
            }
        }
    }

    /// Close the document and flush.
    fn finish(self) -> std::io::Result<()> {
        match self {
            Sink::Csv(mut csv) => csv.flush(),
            Sink::Json(mut out, any) => {
                if any {
                    out.write_all(b"\n]}\n")?;
                }
                out.flush()
            }
        }
    }
}

fn csv_halt(e: csv::Error) -> Halt {
    match e.into_kind() {
        csv::ErrorKind::Io(io) => Halt::Io(io),
        other => Halt::Fail(format!("{other:?}")),
    }
}

/// Comma-separated finite numbers, or why not.
fn numbers(values: &str) -> Result<Vec<f64>, &'static str> {
    let values = values
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<f64>, _>>()
        .map_err(|_| "values must be numbers")?;
    if values.iter().any(|v| !v.is_finite()) {
        return Err("values must be finite");
    }
    Ok(values)
}

/// `FIELD:MODE=values`: the field, the mode and the comma-separated numbers, with `counts` the
/// numbers of values allowed.
fn modal_assignment(
    text: &str,
    what: &str,
    counts: std::ops::RangeInclusive<usize>,
    hint: &str,
) -> Result<(String, usize, Vec<f64>), CliError> {
    let bad = |why: &str| CliError::Usage(format!("{what} {text:?}: {why}"));
    let (target, values) = text
        .split_once('=')
        .ok_or_else(|| bad("expected FIELD:MODE=VALUE"))?;
    let (field, mode) = target
        .split_once(':')
        .ok_or_else(|| bad("expected FIELD:MODE before '='"))?;
    let mode: usize = mode
        .trim()
        .parse()
        .map_err(|_| bad("the mode must be a whole number"))?;
    let values = numbers(values).map_err(&bad)?;
    if !counts.contains(&values.len()) {
        return Err(bad(hint));
    }
    Ok((field.trim().to_string(), mode, values))
}

/// The initial state and forces the arguments give.
fn state(args: &Args) -> Result<(Vec<Initial>, Vec<Forcing>), CliError> {
    super::check_list("--initial", args.initial.len())?;
    super::check_list("--force", args.force.len())?;
    super::check_list("--drive", args.drive.len())?;
    let mut initial = Vec::new();
    for text in args.initial.iter().filter(|t| !is_uniform(t)) {
        let (field, mode, v) = modal_assignment(text, "--initial", 1..=2, "give Q or Q,V")?;
        initial.push(Initial {
            field,
            mode,
            displacement: v[0],
            velocity: v.get(1).copied().unwrap_or(0.0),
        });
    }
    let mut forcing = Vec::new();
    for text in &args.force {
        let (field, mode, v) = modal_assignment(text, "--force", 1..=1, "give one value")?;
        forcing.push(Forcing {
            field,
            mode,
            constant: v[0],
            amplitude: 0.0,
            frequency: 0.0,
            phase: 0.0,
        });
    }
    for text in &args.drive {
        let (field, mode, v) =
            modal_assignment(text, "--drive", 2..=3, "give F0,OMEGA or F0,OMEGA,PHASE")?;
        forcing.push(Forcing {
            field,
            mode,
            constant: 0.0,
            amplitude: v[0],
            frequency: v[1],
            phase: v.get(2).copied().unwrap_or(0.0),
        });
    }
    Ok((initial, forcing))
}

/// `FIELD=Q[,V]`: the same displacement (and velocity) at every point.
fn is_uniform(text: &str) -> bool {
    text.split_once('=')
        .is_some_and(|(target, _)| !target.contains(':'))
}

/// The uniform initial states `FIELD=Q[,V]` among the `--initial` values.
fn uniform_state(args: &Args) -> Result<Vec<(String, f64, f64)>, CliError> {
    let mut out = Vec::new();
    for text in args.initial.iter().filter(|t| is_uniform(t)) {
        let bad = |why: &str| CliError::Usage(format!("--initial {text:?}: {why}"));
        let (field, values) = text
            .split_once('=')
            .ok_or_else(|| bad("expected FIELD=Q"))?;
        let v = numbers(values).map_err(&bad)?;
        if v.len() > 2 {
            return Err(bad("give Q or Q,V"));
        }
        out.push((
            field.trim().to_string(),
            v[0],
            v.get(1).copied().unwrap_or(0.0),
        ));
    }
    Ok(out)
}

/// A body whose surviving terms are not all squares: integrated by `dynamics::nonlinear`, each
/// coefficient settable by `--param` under its printed name.
fn run_nonlinear(
    args: &Args,
    model: &crate::model::Model,
    out: &mut dyn Write,
) -> Result<(), CliError> {
    let body = super::coefficients::nonlinear_body(
        &args.params,
        model,
        args.model.order,
        args.points as usize,
    )?;
    let (initial, forcing) = state(args)?;
    let config = config(args, initial, forcing);
    let uniform = uniform_state(args)?;
    let ids: Vec<String> = body.fields.iter().map(|f| f.id.clone()).collect();
    let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
    stream(args, out, &ids, |sink| body.run(&config, &uniform, sink))
}

fn config(args: &Args, initial: Vec<Initial>, forcing: Vec<Forcing>) -> Config {
    Config {
        points: args.points as usize,
        order: args.model.order,
        dt: args.dt,
        steps: args.steps,
        every: args.every,
        temperature: args.temperature,
        seed: args.seed,
        initial,
        forcing,
    }
}

/// Run and stream the CSV.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let quadratic =
        crate::dynamics::is_quadratic(&model, args.model.order).map_err(CliError::usage)?;
    if !quadratic {
        return run_nonlinear(args, &model, out);
    }
    if let Some(text) = args.initial.iter().find(|t| is_uniform(t)) {
        return Err(CliError::Usage(format!(
            "--initial {text:?}: the same displacement at every point is for a nonlinear body; this one is linear and takes FIELD:MODE=Q[,V]"
        )));
    }
    let params = super::coefficients::linear_params(&args.params, &model, args.model.order)?;
    let (initial, forcing) = state(args)?;
    let config = config(args, initial, forcing);
    let ids: Vec<&str> = model.fields.iter().map(|f| f.id.as_str()).collect();
    stream(args, out, &ids, |sink| {
        simulate(&model, &params, &config, sink)
    })
}

/// The sink a run writes to (the file or `out`), the run itself, and its errors as the CLI's.
fn stream(
    args: &Args,
    out: &mut dyn Write,
    ids: &[&str],
    run: impl FnOnce(&mut dyn FnMut(&Sample) -> Result<(), Halt>) -> Result<(), DynamicsError>,
) -> Result<(), CliError> {
    let mut file;
    let sink: &mut dyn Write = match &args.out {
        Some(path) => {
            file =
                std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| {
                    CliError::Output(format!("cannot create {}: {e}", path.display()))
                })?);
            &mut file
        }
        None => out,
    };
    let mut sink = match args.format {
        SeriesFormat::Csv => Sink::Csv(Box::new(csv::Writer::from_writer(sink))),
        SeriesFormat::Json => Sink::Json(std::io::BufWriter::new(sink), false),
    };
    let mut first = true;
    let result = run(&mut |s| {
        let header = first.then(|| sample_header(ids, s));
        first = false;
        sink.sample(header, s)
    });
    let flushed = sink.finish();
    match result {
        // A closed pipe (`| head`) ends the run quietly.
        Err(DynamicsError::Output(std::io::ErrorKind::BrokenPipe, _)) => Ok(()),
        Err(DynamicsError::Output(_, e)) => Err(CliError::Output(format!(
            "cannot write {}: {e}",
            where_to(&args.out)
        ))),
        Err(e) => Err(CliError::usage(e)),
        Ok(()) => match flushed {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Output(format!(
                "cannot write {}: {e}",
                where_to(&args.out)
            ))),
            _ => Ok(()),
        },
    }
}

/// Where the CSV goes, for messages.
fn where_to(out: &Option<PathBuf>) -> String {
    out.as_ref()
        .map_or("standard output".into(), |p| p.display().to_string())
}
