//! `theory-search mathieu`: the Floquet chart of a bare equation (no body).

use std::io::Write;

use super::{emit, CliError};
use crate::report::Output;

/// Arguments of `mathieu`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Natural frequency λ of the transverse mode.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    lambda: f64,
    /// Lowest ω/λ of the chart.
    #[arg(long, default_value_t = 0.5, allow_hyphen_values = true)]
    ratio_min: f64,
    /// Highest ω/λ of the chart.
    #[arg(long, default_value_t = 4.5, allow_hyphen_values = true)]
    ratio_max: f64,
    /// Largest ε of the chart.
    #[arg(long, default_value_t = 0.5, allow_hyphen_values = true)]
    epsilon_max: f64,
    /// Grid points along ω/λ.
    #[arg(long, default_value_t = 81)]
    columns: usize,
    /// Grid points along ε.
    #[arg(long, default_value_t = 21)]
    rows: usize,
    /// Output format (csv: one row per grid point).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Compute and print the chart.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let chart = crate::behaviour::chart(
        args.lambda,
        (args.ratio_min, args.ratio_max),
        args.epsilon_max,
        (args.columns, args.rows),
    )?;
    emit(out, &chart, args.format)
}
