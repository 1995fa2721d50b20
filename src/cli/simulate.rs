//! `theory-search simulate`: the modal dynamics, streamed as CSV.

use std::io::Write;
use std::path::PathBuf;

use super::{CliError, ModelArgs, ParamArgs};
use crate::body::{BodyError, Start};
use crate::dynamics::{
    sample_header, sample_row, sample_values, Config, DynamicsError, Halt, Sample,
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
                let row = sample_values(s);
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
        // The csv writer's other errors are serialisation failures of our own rows.
        other => Halt::Io(std::io::Error::other(format!("{other:?}"))),
    }
}

/// Run and stream the series.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let body = args.params.body(&args.model)?;
    let start = Start::parse(&args.initial, &args.force, &args.drive)?;
    let config = Config {
        points: args.points as usize,
        order: body.order(),
        dt: args.dt,
        steps: args.steps,
        every: args.every,
        temperature: args.temperature,
        seed: args.seed,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    stream(args, out, |sink| body.simulate(&config, &start, sink))?;
    if body.is_modal() && start.is_empty() && args.temperature == 0.0 {
        eprintln!(
            "warning: no --initial, --force, --drive or --temperature: the body started at rest and stayed there"
        );
    }
    Ok(())
}

/// The sink a run writes to (the file or `out`), the run itself, and its errors as the CLI's.
fn stream(
    args: &Args,
    out: &mut dyn Write,
    run: impl FnOnce(&mut dyn FnMut(&[String], &Sample) -> Result<(), Halt>) -> Result<(), BodyError>,
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
    let result = run(&mut |ids, s| {
        let header = first.then(|| {
            let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
            sample_header(&ids, s)
        });
        first = false;
        sink.sample(header, s)
    });
    let flushed = sink.finish();
    match result {
        // A closed pipe (`| head`) ends the run quietly.
        Err(BodyError::Dynamics(DynamicsError::Output(std::io::ErrorKind::BrokenPipe, _))) => {
            Ok(())
        }
        Err(BodyError::Dynamics(DynamicsError::Output(_, e))) => Err(CliError::Output(format!(
            "cannot write {}: {e}",
            where_to(&args.out)
        ))),
        Err(e) => Err(e.into()),
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
