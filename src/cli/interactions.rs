//! `theory-search interactions`: which terms could couple each pair of fields.

use std::io::Write;

use super::options::DensityChoice;
use super::{emit, CliError, ModelArgs};
use crate::interaction::InteractionsReport;
use crate::report::Output;

/// Arguments of `interactions`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Which density.
    #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
    density: DensityChoice,
    /// Output format (csv: one row per verdict).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Decide and print the interaction tables.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let report = InteractionsReport::new(&model, args.density.densities(), args.model.order)
        .map_err(CliError::usage)?;
    emit(out, &report, args.format)
}
