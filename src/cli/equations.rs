//! `theory-search equations`: the equations of motion of the surviving densities.

use std::io::Write;

use super::{write_out, CliError, ModelArgs};
use crate::enumerate::Basis;
use crate::equations::{derive_basis, EquationReport};
use crate::report::Report;

/// Arguments of `equations`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Candidate terms: pure powers (the seed's) or every monomial.
    #[arg(long, value_enum, default_value_t = Basis::Powers)]
    basis: Basis,
    /// Output format.
    #[arg(long, value_enum, default_value_t = EquationFormat::Text)]
    format: EquationFormat,
}

/// Output formats of `equations`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum EquationFormat {
    Text,
    Latex,
    Json,
}

/// Derive and print the equations.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let (equations, notes) =
        derive_basis(&model, args.model.order, args.basis).map_err(CliError::usage)?;
    let r = EquationReport {
        model: model.name.clone(),
        order: args.model.order,
        equations,
        notes,
    };
    let text = match args.format {
        EquationFormat::Text => r.text(),
        EquationFormat::Latex => r.latex(),
        EquationFormat::Json => serde_json::to_string_pretty(&r.json()).unwrap_or_default() + "\n",
    };
    write_out(out, &text)
}
