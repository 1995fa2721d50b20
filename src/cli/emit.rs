//! `theory-search emit`: regenerate the generated files.

use std::io::Write;
use std::path::PathBuf;

use super::{write_out, CliError, ModelArgs};

/// Arguments of `emit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory to write into: the crate root.
    #[arg(long, default_value = ".")]
    out: PathBuf,
    #[command(flatten)]
    model: ModelArgs,
}

/// Write every generated file under `--out`.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let written =
        crate::codegen::emit(&args.out, &model, args.model.order).map_err(CliError::Output)?;
    let text: String = written
        .iter()
        .map(|p| format!("wrote {}\n", p.display()))
        .collect();
    write_out(out, &text)
}
