//! `theory-search asymmetry`: forward/backward waves of the self-interacting axial pair.

use std::io::Write;

use super::{emit, load_params, CliError, ModelArgs, ParamArgs};
use crate::report::Output;
use crate::theory::Theory;

/// Arguments of `asymmetry`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Coupling constant c of the cubic dissipative interaction.
    #[arg(long, allow_negative_numbers = true)]
    coupling: f64,
    /// Wave amplitude A.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    amplitude: f64,
    /// Free-field frequency ω. Default: with --model or --points, the frequency of that body's
    /// first axial pair; otherwise 1 (the unit of frequency).
    #[arg(long, allow_negative_numbers = true)]
    omega: Option<f64>,
    #[command(flatten)]
    model: ModelArgs,
    /// Points along the body whose axial pair sets ω (default 12 with --model).
    #[arg(long)]
    points: Option<usize>,
    #[command(flatten)]
    params: ParamArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// The frequency of the first degenerate pair of the field `behaviour` needs (axial), when the
/// user named a body; `None` otherwise.
pub(super) fn body_pair_frequency(
    model: &ModelArgs,
    points: Option<usize>,
    params: &ParamArgs,
    behaviour: &str,
) -> Result<Option<f64>, CliError> {
    if model.model.is_none() && points.is_none() {
        return Ok(None);
    }
    let m = model.load()?;
    let p = load_params(params, &m)?;
    let theory = Theory::new(m, model.order, points.unwrap_or(12), p).map_err(CliError::usage)?;
    let f = crate::behaviour::role_fields(&theory.model, behaviour)?[0];
    let fm = &theory.modes[f];
    let (i, _) = *fm.degenerate_pairs.first().ok_or_else(|| {
        CliError::Usage(format!(
            "{behaviour}: the axial field {} of model {:?} has no degenerate pair (give --omega)",
            fm.field.id, theory.model.name
        ))
    })?;
    Ok(Some(fm.modes[i].frequency))
}

/// Solve and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let omega = match args.omega {
        Some(w) => w,
        None => {
            body_pair_frequency(&args.model, args.points, &args.params, "asymmetry")?.unwrap_or(1.0)
        }
    };
    let a = crate::behaviour::asymmetry(args.coupling, args.amplitude, omega)?;
    emit(out, &a, args.format)
}
