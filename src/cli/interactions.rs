//! `theory-search interactions`: which terms could couple each pair of fields.

use std::io::Write;

use super::table::DensityChoice;
use super::{write_out, CliError, ModelArgs};

/// Arguments of `interactions`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Which density.
    #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
    density: DensityChoice,
}

/// Decide and print the interaction tables.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    // Every density's budget before any density's work.
    for &d in args.density.densities() {
        crate::interaction::check_interaction_work(&model, d, args.model.order)
            .map_err(CliError::usage)?;
    }
    let mut text = String::new();
    for &d in args.density.densities() {
        let i = crate::interaction::interactions(&model, d, args.model.order)
            .map_err(CliError::usage)?;
        text += &i.text(&model);
        text.push('\n');
    }
    write_out(out, &text)
}
