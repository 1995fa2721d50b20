//! `theory-search operators`: the difference operators on N points.

use std::io::Write;

use super::{write_out, CliError, ModelArgs, ParamArgs};
use crate::body::BodyOperators;
use crate::discretise::OperatorReport;
use crate::report::Report;

/// Arguments of `operators`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of points along the body (the paper uses 12): at least what the model's operators
    /// need (3 for the larva; the error names it), up to 2000 (dense matrices are printed).
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=crate::body::MAX_OPERATOR_POINTS as u64))]
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
    let body = args.params.body(&args.model)?;
    let points = args.points as usize;
    let operators = match body.operators(points)? {
        BodyOperators::Exact(operators) => operators,
        BodyOperators::Linearised(fields) => {
            let report = crate::dynamics::LinearisedOperatorsReport {
                model: body.model().name.clone(),
                order: body.order(),
                points,
                linearised: true,
                fields,
            };
            let format = match args.format {
                OperatorFormat::Text => crate::report::Output::Text,
                OperatorFormat::Json => crate::report::Output::Json,
                OperatorFormat::Csv => crate::report::Output::Csv,
            };
            return super::emit(out, &report, format);
        }
    };
    let r = OperatorReport {
        model: body.model(),
        order: body.order(),
        points,
        operators,
    };
    match args.format {
        OperatorFormat::Text => write_out(out, &r.text()),
        OperatorFormat::Csv => super::emit(out, &r, crate::report::Output::Csv),
        // Streamed from the operators themselves: no JSON value tree of N² numbers in memory.
        OperatorFormat::Json => {
            let doc = crate::discretise::OperatorsJson {
                points,
                order: body.order(),
                operators: &r.operators,
            };
            let mut w = std::io::BufWriter::new(out);
            let written = serde_json::to_writer(&mut w, &doc)
                .map_err(std::io::Error::from)
                .and_then(|_| w.write_all(b"\n"))
                .and_then(|_| w.flush());
            super::written(written)
        }
    }
}
