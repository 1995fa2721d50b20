//! `theory-search rules`: the rule registry, and with a model what it requires.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, load_model, CliError};
use crate::catalogue::{Requirements, RulesReport};
use crate::enumerate::MAX_ORDER;
use crate::report::Output;

/// Arguments of `rules`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Also list what each field of this model (TOML) requires, and what each rule strikes out.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Count the candidates each rule strikes out at this order (default 4; implies the
    /// embedded larva when --model is not given).
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
    order: Option<u32>,
    /// Output format (csv: the registry).
    #[arg(long, value_enum, default_value_t = RulesFormat::Text)]
    format: RulesFormat,
}

/// The forms `rules` takes: the common ones and Markdown (the page `emit` keeps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum RulesFormat {
    /// Aligned text for reading.
    Text,
    /// Markdown tables.
    Markdown,
    /// JSON: one document.
    Json,
    /// CSV: the registry, one rule per row.
    Csv,
}

/// Print the registry (and the model's requirements).
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let requirements = if args.model.is_some() || args.order.is_some() {
        let model = load_model(&args.model)?;
        let order = args.order.unwrap_or(crate::model::DEFAULT_ORDER);
        Some(Requirements::new(&model, order).map_err(CliError::usage)?)
    } else {
        None
    };
    let report = RulesReport {
        header: crate::codegen::header("<!--", " -->"),
        requirements,
    };
    let format = match args.format {
        RulesFormat::Markdown => {
            return out
                .write_all(report.markdown().as_bytes())
                .map_err(|e| CliError::Output(format!("cannot write output: {e}")));
        }
        RulesFormat::Text => Output::Text,
        RulesFormat::Json => Output::Json,
        RulesFormat::Csv => Output::Csv,
    };
    emit(out, &report, format)
}
