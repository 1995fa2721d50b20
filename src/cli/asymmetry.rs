//! `theory-search asymmetry`: forward/backward waves of the self-interacting axial pair.

use std::io::Write;

use super::{emit, CliError, PairArgs};
use crate::report::Output;

/// Arguments of `asymmetry`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Coupling constant c of the cubic dissipative interaction.
    #[arg(long, allow_hyphen_values = true)]
    coupling: f64,
    /// Wave amplitude A.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    amplitude: f64,
    #[command(flatten)]
    pair: PairArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Solve and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let omega = args.pair.omega("asymmetry")?;
    let a = crate::behaviour::asymmetry(args.coupling, args.amplitude, omega)?;
    emit(out, &a, args.format)
}
