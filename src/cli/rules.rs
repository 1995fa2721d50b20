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
    /// Output format (text: Markdown; csv: the registry).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
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
    emit(out, &report, args.format)
}
