//! `theory-search operators`: the difference operators on N points.

use std::io::Write;

use super::{write_out, CliError, ModelArgs, ParamArgs};
use crate::discretise::{operators, OperatorReport};
use crate::report::Report;

/// The most points `operators` prints as dense matrices.
pub const MAX_PRINT_POINTS: usize = 2000;

/// Arguments of `operators`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of points along the body (the paper uses 12): at least what the model's operators
    /// need (3 for the larva; the error names it), up to 2000 (dense matrices are printed).
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=MAX_PRINT_POINTS as u64))]
    points: u64,
    /// Coefficients of a nonlinear body's terms (`c2_u=1`, `cp_u=0.1`) and the scales ω, ζ its
    /// leading squares take by default; a linear body's operators have none.
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OperatorFormat::Text)]
    format: OperatorFormat,
}

/// Output formats of `operators`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum OperatorFormat {
    /// Aligned text: each dense matrix.
    Text,
    /// JSON, streamed from the operators.
    Json,
    /// CSV: one row per non-zero entry.
    Csv,
}

/// Print the operators.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let points = args.points as usize;
    if !crate::dynamics::is_quadratic(&model, args.model.order).map_err(CliError::usage)? {
        return linearised(args, &model, points, out);
    }
    if !args.params.params.is_empty() || args.params.params_file.is_some() {
        return Err(CliError::Usage(
            "the operators of a linear body have no coefficients: --param is for a nonlinear one (its linearisation)".into(),
        ));
    }
    let r = OperatorReport {
        model: &model,
        order: args.model.order,
        points,
        operators: operators(&model, args.model.order, points).map_err(CliError::usage)?,
    };
    match args.format {
        OperatorFormat::Text => write_out(out, &r.text()),
        OperatorFormat::Csv => super::emit(out, &r, crate::report::Output::Csv),
        // Streamed from the operators themselves: no JSON value tree of N² numbers in memory.
        OperatorFormat::Json => {
            let doc = crate::discretise::OperatorsJson {
                points,
                order: args.model.order,
                operators: &r.operators,
            };
            let mut w = std::io::BufWriter::new(out);
            let written = serde_json::to_writer(&mut w, &doc)
                .map_err(std::io::Error::from)
                .and_then(|_| w.write_all(b"\n"))
                .and_then(|_| w.flush());
            match written {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    Err(CliError::Output(format!("cannot write output: {e}")))
                }
                _ => Ok(()),
            }
        }
    }
}

/// `operators` of a nonlinear body: the operators of its linearisation about the equilibrium.
fn linearised(
    args: &Args,
    model: &crate::model::Model,
    points: usize,
    out: &mut dyn Write,
) -> Result<(), CliError> {
    let body = super::modes::linearisable(&args.params, model, args.model.order, points)?;
    let report = crate::dynamics::LinearisedOperatorsReport {
        model: model.name.clone(),
        order: args.model.order,
        points,
        linearised: true,
        fields: body.linearised_operators().map_err(CliError::usage)?,
    };
    let format = match args.format {
        OperatorFormat::Text => crate::report::Output::Text,
        OperatorFormat::Json => crate::report::Output::Json,
        OperatorFormat::Csv => crate::report::Output::Csv,
    };
    super::emit(out, &report, format)
}
