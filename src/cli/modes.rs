//! `theory-search modes`: every field's modes on N points.

use std::io::Write;

use super::{emit, CliError, ModelArgs, ParamArgs};
use crate::body::BodyModes;
use crate::modal::ModesReport;
use crate::report::Output;

/// Arguments of `modes`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of points along the body (the paper uses 12): at least what the model's operators
    /// need (3 for the larva; the error names it), up to 10 000 000 with --modes K; the full
    /// spectrum up to 200 000 (about two seconds), or 2000 for a field without a closed form
    /// (clamped or mixed ends: a dense solver); a nonlinear body up to 400.
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=crate::modal::MAX_POINTS as u64))]
    points: u64,
    /// Report only the lowest K modes of each field (shares stay exact over all modes).
    #[arg(long = "modes", value_name = "K",
          value_parser = clap::value_parser!(u64).range(1..))]
    limit: Option<u64>,
    /// Also print the mode shapes on the body's points (unit norm, zero at held points, first
    /// significant component positive).
    #[arg(long)]
    shapes: bool,
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Compute and print the modes.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let body = args.params.body(&args.model)?;
    let points = args.points as usize;
    let limit = args.limit.map(|k| k as usize);
    match body.modes(points, limit, args.shapes)? {
        BodyModes::Exact(modes) => {
            let r = ModesReport {
                model: body.model(),
                points,
                modes: &modes,
                shapes: args.shapes,
            };
            emit(out, &r, args.format)
        }
        BodyModes::Linearised(mut fields) => {
            // A growing root is compared with the same body on 2N points: the grid's growth
            // changes with N (an error there leaves it uncompared, and says so).
            if fields.iter().any(|f| f.fastest_growth().is_some()) {
                let doubled = match body.modes(2 * points, None, false) {
                    Ok(BodyModes::Linearised(d)) => Some(d),
                    _ => None,
                };
                crate::dynamics::check_growth(&mut fields, 2 * points, doubled.as_deref());
            }
            let report = crate::dynamics::LinearisedReport {
                model: body.model().name.clone(),
                order: body.order(),
                points,
                linearised: true,
                nonlinear: !body.is_linear(),
                fields,
            };
            emit(out, &report, args.format)
        }
    }
}
