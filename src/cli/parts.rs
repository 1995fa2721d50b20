//! `theory-search parts`: admitted monomials modulo total derivatives.

use std::io::Write;

use super::table::DensityChoice;
use super::{write_out, CliError, ModelArgs};

/// Arguments of `parts`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Which density.
    #[arg(long, value_enum, default_value_t = DensityChoice::Lagrangian)]
    density: DensityChoice,
}

/// Reduce and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let mut text = String::new();
    for &d in args.density.densities() {
        let fields =
            crate::parts::reduce_model(&model, d, args.model.order).map_err(CliError::usage)?;
        text += &crate::parts::text(&model, d, args.model.order, &fields);
        text.push('\n');
    }
    write_out(out, &text)
}
