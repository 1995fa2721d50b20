//! `theory-search stats`: statistical mechanics of the modes.

use std::io::Write;

use super::{emit, BodyArgs, CliError, PairArgs, SampleArgs};
use crate::behaviour::{equipartition_from_dynamics, explore, PairReport};
use crate::report::Output;

/// Arguments of `stats`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: StatsCommand,
}

#[derive(Debug, clap::Subcommand)]
enum StatsCommand {
    /// Unbiased exploration: Gaussian planar postures of the lateral field, the 3-point bend
    /// distribution, β refitted.
    Explore {
        /// Inverse temperature β of the whole body, in units where ω_b = 1 and the body length
        /// is 1 (the default is cold enough for small-angle postures; `stats pair` takes the β
        /// of one pair in its own units, default 1).
        #[arg(long, default_value_t = 10_000.0, allow_hyphen_values = true)]
        beta: f64,
        #[command(flatten)]
        sample: SampleArgs,
        #[command(flatten)]
        body: BodyArgs,
        /// Output format (csv: one bend angle per sample).
        #[arg(long, value_enum, default_value_t = Output::Text)]
        format: Output,
    },
    /// Langevin run, PCA of one field's postures, and the modes beside it (paper App. B).
    Equipartition {
        /// The field (id); default: the model's lateral field.
        #[arg(long)]
        field: Option<String>,
        /// Time steps of 0.5 (a tenth are burn-in).
        #[arg(long, default_value_t = 200_000)]
        steps: u64,
        /// Thermal energy kT.
        #[arg(long, default_value_t = 0.5, allow_hyphen_values = true)]
        temperature: f64,
        /// Seed of the noise.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[command(flatten)]
        body: BodyArgs,
        /// Output format (csv: one row per mode).
        #[arg(long, value_enum, default_value_t = Output::Text)]
        format: Output,
    },
    /// A degenerate pair at fixed momentum M: Z, F, A*, ⟨A⟩; with --samples also a Metropolis run.
    Pair {
        /// Inverse temperature β of the pair, in units of its energy scale (the whole body's β
        /// of `stats explore` is another quantity).
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
        beta: f64,
        /// Conserved momentum M (default 0, the resting ensemble; `behave peristalsis` and
        /// `rolling` default to 0.1, since an orbit at M = 0 does not move).
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        momentum: f64,
        /// Draw this many Metropolis samples.
        #[arg(long)]
        samples: Option<usize>,
        /// Seed of the sampler.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[command(flatten)]
        pair: PairArgs,
        /// Output format (csv: one row per sample, or the statistics).
        #[arg(long, value_enum, default_value_t = Output::Text)]
        format: Output,
    },
}

/// Run one statistic.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    match &args.what {
        StatsCommand::Explore {
            beta,
            sample,
            body,
            format,
        } => {
            let e = explore(
                &body.theory("stats explore")?,
                *beta,
                sample.samples,
                sample.seed,
            )?;
            emit(out, &e, *format)
        }
        StatsCommand::Equipartition {
            field,
            steps,
            temperature,
            seed,
            body,
            format,
        } => {
            let theory = body.theory("stats equipartition")?;
            let c = equipartition_from_dynamics(
                &theory,
                field.as_deref(),
                *steps,
                *temperature,
                *seed,
            )?;
            emit(out, &c, *format)
        }
        StatsCommand::Pair {
            beta,
            momentum,
            samples,
            seed,
            pair,
            format,
        } => {
            let omega = pair.omega("stats pair")?;
            let r = PairReport::new(omega, *beta, *momentum, *samples, *seed)?;
            emit(out, &r, *format)
        }
    }
}
