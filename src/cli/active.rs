//! `theory-search active`: the active forces a model's `[active]` section allows.

use std::io::Write;

use super::options::ModelArgs;
use super::{emit, CliError};
use crate::active::ActiveReport;
use crate::report::Output;

/// Arguments of `active`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Enumerate, decide, classify and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let report = ActiveReport::of(&model, args.model.order).map_err(CliError::usage)?;
    emit(out, &report, args.format)
}
