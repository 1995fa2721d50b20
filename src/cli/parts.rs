//! `theory-search parts`: admitted monomials modulo total derivatives.

use std::io::Write;

use super::options::DensityChoice;
use super::{emit, CliError, ModelArgs};
use crate::parts::PartsReport;
use crate::report::Output;

/// Arguments of `parts`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Which density.
    #[arg(long, value_enum, default_value_t = DensityChoice::Lagrangian)]
    density: DensityChoice,
    /// Output format (csv: one row per admitted monomial).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Reduce and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let report = PartsReport::new(&model, args.density.densities(), args.model.order)
        .map_err(CliError::usage)?;
    emit(out, &report, args.format)
}
