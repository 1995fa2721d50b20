//! `theory-search equations`: the equations of motion of the surviving densities.

use std::io::Write;

use super::{emit, write_out, CliError, ModelArgs};
use crate::enumerate::Basis;
use crate::equations::{
    derive_basis, derive_nonlinear, EquationError, EquationReport, NonlinearReport,
};
use crate::report::{Output, Report};

/// Arguments of `equations`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Candidate terms: pure powers (the paper's) or every monomial.
    #[arg(long, value_enum, default_value_t = Basis::Powers)]
    basis: Basis,
    /// Output format.
    #[arg(long, value_enum, default_value_t = EquationFormat::Text)]
    format: EquationFormat,
}

/// Output formats of `equations`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum EquationFormat {
    /// Aligned text for reading.
    Text,
    /// LaTeX `align*` lines.
    Latex,
    /// JSON (serde).
    Json,
    /// CSV: one row per right-hand-side term.
    Csv,
}

/// Write an equations report in `format`.
fn write(
    out: &mut dyn Write,
    report: &dyn Report,
    latex: impl FnOnce() -> String,
    format: EquationFormat,
) -> Result<(), CliError> {
    match format {
        EquationFormat::Latex => write_out(out, &latex()),
        EquationFormat::Text => emit(out, report, Output::Text),
        EquationFormat::Json => emit(out, report, Output::Json),
        EquationFormat::Csv => emit(out, report, Output::Csv),
    }
}

/// Derive and print the equations.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let order = args.model.order;
    let (equations, notes) = match derive_basis(&model, order, args.basis) {
        Err(EquationError::NotQuadratic { .. }) => {
            // Not all quadratic: the exact nonlinear equations instead.
            let (equations, notes) =
                derive_nonlinear(&model, order, args.basis).map_err(CliError::usage)?;
            let r = NonlinearReport {
                model: model.name.clone(),
                order,
                equations,
                notes,
            };
            return write(out, &r, || r.latex(), args.format);
        }
        other => other.map_err(CliError::usage)?,
    };
    let r = EquationReport {
        model: model.name.clone(),
        order: args.model.order,
        equations,
        notes,
    };
    write(out, &r, || r.latex(), args.format)
}
