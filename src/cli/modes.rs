//! `theory-search modes`: every field's modes on N points.

use std::io::Write;

use super::{emit, CliError, ModelArgs, ParamArgs};
use crate::modal::{field_modes, ModesReport};
use crate::report::Output;

/// The most points whose every mode `modes` computes and prints.
const MAX_FULL_SPECTRUM: usize = 1_000_000;

/// The most numbers `--shapes` prints.
const MAX_SHAPE_VALUES: usize = 20_000_000;

/// Arguments of `modes`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of points along the body (the paper uses 12): at least what the model's operators
    /// need (3 for the larva; the error names it), up to 10 000 000 with --modes K; the full
    /// spectrum up to 1 000 000 (about ten seconds).
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
    let model = args.model.load()?;
    let points = args.points as usize;
    let quadratic =
        crate::dynamics::is_quadratic(&model, args.model.order).map_err(CliError::usage)?;
    if !quadratic {
        return linearised(args, &model, points, out);
    }
    let params = super::coefficients::linear_params(&args.params, &model, args.model.order)?;
    let limit = args.limit.map(|k| k as usize);
    if limit.is_none() && points > MAX_FULL_SPECTRUM {
        return Err(CliError::Usage(format!(
            "the full spectrum takes at most {MAX_FULL_SPECTRUM} points (about ten seconds); at {points} add --modes K"
        )));
    }
    if args.shapes && points.saturating_mul(limit.unwrap_or(points)) > MAX_SHAPE_VALUES {
        return Err(CliError::Usage(format!(
            "--shapes at {points} points would print more than {MAX_SHAPE_VALUES} numbers; add --modes K"
        )));
    }
    let modes = field_modes(
        &model,
        args.model.order,
        points,
        &params,
        limit,
        args.shapes,
    )
    .map_err(CliError::usage)?;
    let r = ModesReport {
        model: &model,
        points,
        modes: &modes,
        shapes: args.shapes,
    };
    emit(out, &r, args.format)
}

/// The most points a linearisation takes: a dense eigendecomposition per field, and a dense
/// least-squares Newton step per iteration towards the equilibrium (about a second at 400).
const MAX_LINEARISED_POINTS: usize = 400;

/// A nonlinear body to linearise, on at most [`MAX_LINEARISED_POINTS`] points.
pub(super) fn linearisable(
    params: &super::ParamArgs,
    model: &crate::model::Model,
    order: u32,
    points: usize,
) -> Result<crate::dynamics::nonlinear::NonlinearBody, CliError> {
    if points > MAX_LINEARISED_POINTS {
        return Err(CliError::Usage(format!(
            "a nonlinear body is linearised on at most {MAX_LINEARISED_POINTS} points, not {points}"
        )));
    }
    super::coefficients::nonlinear_body(params, model, order, points)
}

/// `modes` of a nonlinear body: the modes of its linearisation about each field's equilibrium.
fn linearised(
    args: &Args,
    model: &crate::model::Model,
    points: usize,
    out: &mut dyn Write,
) -> Result<(), CliError> {
    let body = linearisable(&args.params, model, args.model.order, points)?;
    let mut fields = body.linearise(args.shapes).map_err(CliError::usage)?;
    if let Some(k) = args.limit {
        for f in &mut fields {
            let k = (k as usize).min(f.eigenvalues.len());
            f.eigenvalues.truncate(k);
            f.frequencies.truncate(k);
            if let Some(s) = &mut f.shapes {
                s.truncate(k);
            }
        }
    }
    let report = crate::dynamics::LinearisedReport {
        model: model.name.clone(),
        order: args.model.order,
        points,
        linearised: true,
        fields,
    };
    emit(out, &report, args.format)
}
