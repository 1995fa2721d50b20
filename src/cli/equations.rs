//! `theory-search equations`: the equations of motion of the surviving densities.

use std::io::Write;

use super::{emit, write_out, CliError, ModelArgs};
use crate::enumerate::Basis;
use crate::equations::{derive_any, Derivation, Derived, EquationError, EquationReport, Shown};
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
    /// JSON: one document.
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

/// Derive and print the equations: every field that has one; each other field's reason is a
/// note, and then the command fails (exit 2) saying how many fields have none.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let order = args.model.order;
    let underived = match derive_any(&model, order, args.basis).map_err(CliError::usage)? {
        Derived::Linear(d) => print(out, &model, order, d, args.format)?,
        Derived::Nonlinear(d) => print(out, &model, order, d, args.format)?,
    };
    match underived.as_slice() {
        [] => Ok(()),
        some => Err(CliError::Usage(format!(
            "{} of the {} fields have no equation of motion (the notes say why): {}",
            some.len(),
            model.fields.len(),
            some.iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        ))),
    }
}

/// Print a derivation's report (nothing when no field has an equation: the first reason is
/// then the whole answer); the reasons of the fields without one.
fn print<E>(
    out: &mut dyn Write,
    model: &crate::model::Model,
    order: u32,
    d: Derivation<E>,
    format: EquationFormat,
) -> Result<Vec<EquationError>, CliError>
where
    EquationReport<E>: Report,
    E: Shown,
{
    none_derived(&d.equations, &d.underived)?;
    let r = EquationReport {
        model: model.name.clone(),
        order,
        equations: d.equations,
        notes: with_reasons(d.notes, &d.underived),
    };
    write(out, &r, || r.latex(), format)?;
    Ok(d.underived)
}

/// When no field has an equation, the first reason is the whole answer (nothing is printed).
fn none_derived<E>(equations: &[E], underived: &[EquationError]) -> Result<(), CliError> {
    match underived.first() {
        Some(e) if equations.is_empty() => Err(CliError::usage(e)),
        _ => Ok(()),
    }
}

/// The notes, then one line per field without an equation.
fn with_reasons(mut notes: Vec<String>, underived: &[EquationError]) -> Vec<String> {
    notes.extend(underived.iter().map(|e| e.to_string()));
    notes
}
