//! `theory-search emit`: regenerate the generated files.

use std::io::Write;
use std::path::PathBuf;

use super::{write_out, CliError, ModelArgs};

/// Arguments of `emit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory to write `src/generated/` and `tables/` into (default: the current directory,
    /// which must then be a theory-search checkout).
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    model: ModelArgs,
}

/// Write every generated file under `--out`.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let dir = match &args.out {
        Some(dir) => dir.clone(),
        None => {
            // Without --out, only a checkout of this crate: never scatter files elsewhere.
            let manifest = std::fs::read_to_string("Cargo.toml").unwrap_or_default();
            if !manifest.contains("name = \"theory-search\"") {
                return Err(CliError::Usage(
                    "emit writes src/generated/ and tables/ of a theory-search checkout: run it at the crate root, or give --out DIR".into(),
                ));
            }
            PathBuf::from(".")
        }
    };
    let written =
        crate::artifacts::emit(&dir, &model, args.model.order).map_err(|e| match e.failure() {
            crate::failure::Failure::Usage => CliError::Usage(e.to_string()),
            _ => CliError::Output(e.to_string()),
        })?;
    let text: String = written
        .iter()
        .map(|p| format!("wrote {}\n", p.display()))
        .collect();
    write_out(out, &text)
}
