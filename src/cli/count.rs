//! `theory-search count`: candidate terms per density at every order.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, load_model, CliError};
use crate::enumerate::{Basis, MAX_ORDER};
use crate::report::Output;

/// Arguments of `count`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Candidate terms: pure powers or every monomial.
    #[arg(long, value_enum, default_value_t = Basis::Powers)]
    basis: Basis,
    /// Count orders 1 … N.
    #[arg(long, default_value_t = 8, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
    max_order: u32,
    /// A model file (TOML) instead of the embedded larva model.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Count and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = load_model(&args.model)?;
    let counts = crate::catalogue::CountReport::new(&model, args.basis, args.max_order)
        .map_err(CliError::usage)?;
    emit(out, &counts, args.format)
}
