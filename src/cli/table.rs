//! `theory-search [table]`: the candidate tables and surviving densities.

use std::io::Write;

use super::{written, CliError, ModelArgs};
use crate::enumerate::Basis;
use crate::model::Density;
use crate::reduce::analyse_basis;
use crate::table::{write, Format};

/// Arguments of the table (the default command).
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Candidate terms: pure powers (the paper's Table 1) or every monomial (products of factors).
    #[arg(long, value_enum, default_value_t = Basis::Powers)]
    basis: Basis,
    /// Which density to print.
    #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
    density: DensityChoice,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

/// Which densities to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DensityChoice {
    /// The Lagrangian density only.
    Lagrangian,
    /// The Rayleigh density only.
    Rayleigh,
    /// Both, Lagrangian first.
    Both,
}

impl DensityChoice {
    /// The densities chosen.
    pub fn densities(self) -> &'static [Density] {
        match self {
            DensityChoice::Lagrangian => &[Density::Lagrangian],
            DensityChoice::Rayleigh => &[Density::Rayleigh],
            DensityChoice::Both => &Density::ALL,
        }
    }
}

/// Print the tables.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    crate::reduce::check_work(
        &model,
        args.density.densities(),
        args.model.order,
        args.basis,
    )
    .map_err(CliError::usage)?;
    let analyses = args
        .density
        .densities()
        .iter()
        .map(|&d| analyse_basis(&model, d, args.model.order, args.basis))
        .collect::<Result<Vec<_>, _>>()
        .map_err(CliError::usage)?;
    written(write(&model, &analyses, args.format, out))
}
