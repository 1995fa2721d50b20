//! `theory-search active`: the active forces a model's `[active]` section allows.

use std::io::Write;

use super::options::ModelArgs;
use super::{emit, CliError};
use crate::active::{active_forces, ActiveReport};
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
    let (model, order) = (args.model.load()?, args.model.order);
    let fields = active_forces(&model, order)
        .map_err(CliError::usage)?
        .ok_or_else(|| {
            CliError::Usage(format!(
                "the {} model has no [active] section: add one (bound, columns, requirements per field, as [rayleigh]) to enumerate active forces",
                crate::markup::clip(&model.name)
            ))
        })?;
    let report = ActiveReport {
        model: model.name.clone(),
        order,
        fields,
    };
    emit(out, &report, args.format)
}
