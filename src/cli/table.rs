//! `theory-search [table]`: the candidate tables and surviving densities.

use std::io::Write;

use super::options::DensityChoice;
use super::{written, CliError, ModelArgs};
use crate::enumerate::Basis;
use crate::enumerate::MAX_CANDIDATES;
use crate::reduce::{
    analyse_basis, analyse_streamed, check_work, check_work_within, OrderError, MAX_STREAMED,
};
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

/// Print the tables.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let model = args.model.load()?;
    let order = args.model.order;
    // Monomial tables past the held limit are decided twice and never held (all but JSON).
    let streams = args.basis == Basis::Monomials && !matches!(args.format, Format::Json);
    let limit = if streams {
        MAX_STREAMED
    } else {
        MAX_CANDIDATES
    };
    check_work_within(&model, args.density.densities(), order, args.basis, limit)
        .map_err(|e| match e {
            // Held formats stop earlier than the streamed ones: say so.
            OrderError::TooManyCandidates {
                what,
                order,
                count,
                limit,
                ..
            } if !streams && args.basis == Basis::Monomials && count <= MAX_STREAMED => {
                OrderError::TooManyCandidates {
                    what,
                    advice: ", another --format (text, csv, markdown and latex stream), or --basis powers",
                    order,
                    count,
                    limit,
                }
            }
            e => e,
        })
        .map_err(CliError::usage)?;
    let analyses = args
        .density
        .densities()
        .iter()
        .map(|&d| match check_work(&model, &[d], order, args.basis) {
            Err(OrderError::TooManyCandidates { .. }) if streams => {
                analyse_streamed(&model, d, order)
            }
            _ => analyse_basis(&model, d, order, args.basis),
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(CliError::usage)?;
    written(write(&model, &analyses, args.format, out))
}
