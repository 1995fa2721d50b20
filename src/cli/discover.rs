//! `theory-search discover`: the recording chooses the terms of its field's equation.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, CliError, ModelArgs};
use crate::discover::{discover, DiscoverError, DiscoverSettings, Source};
use crate::recording::Setting;
use crate::report::Output;

/// Arguments of `discover`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The recordings (`-` for standard input), as `fit` reads them; several are several animals.
    #[arg(value_name = "FILE", required = true)]
    input: Vec<PathBuf>,
    #[command(flatten)]
    recording: super::recording::RecordingArgs,
    /// Put the model's `[active]` forces (active and gyroscopic) in the library.
    #[arg(long)]
    active: bool,
    /// Moving-block bootstrap draws for intervals and inclusion frequencies (0: none).
    #[arg(long, value_name = "B", default_value_t = 200)]
    bootstrap: usize,
    /// Seed of the bootstrap draws (same seed, same intervals).
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
    /// auto: the exact likelihood on the body's continuum modes where every candidate is
    /// linear and diagonal on the modes (continuum coefficients, any frame rate, gaps), else the
    /// weak form; weak: the weak form on the grid's modes (the grid's coefficients); exact: the
    /// exact likelihood or a refusal saying why not.
    #[arg(long, value_name = "E", default_value = "auto", value_parser = ["auto", "weak", "exact"])]
    estimator: String,
    /// Also simulate the discovered equation and write the figure comparing its modal spectra
    /// and variances with the recording's into this directory.
    #[arg(long, value_name = "DIR")]
    figures: Option<PathBuf>,
    #[command(flatten)]
    page: super::options::FitPageArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format (csv: one row per library term).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Discover and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let page = args.page.page()?;
    let model = args.model.load()?;
    let mut pairs = args.recording.pairs(args.model.order);
    pairs.extend([
        ("active", Setting::Bool(args.active)),
        ("bootstrap", super::recording::count(args.bootstrap)),
        ("seed", Setting::Int(args.seed.into())),
        ("estimator", Setting::Text(args.estimator.clone())),
    ]);
    let mut settings = DiscoverSettings::from_pairs(pairs)?;
    settings.replay = args.figures.is_some();
    let sources = crate::recording::recordings(&args.input)?
        .into_iter()
        .map(|p| {
            if p.as_os_str() == "-" {
                Source::Reader(
                    "-".into(),
                    Box::new(std::io::BufReader::new(std::io::stdin())),
                )
            } else {
                Source::File(p)
            }
        })
        .collect();
    let mut report = discover(sources, &model, &settings).map_err(CliError::from)?;
    report.model_argument = args.model.model.as_ref().map(|p| p.display().to_string());
    report.inputs = super::recording::inputs(&args.input, &args.recording);
    // An equation `simulate` refuses has no replay to draw: the report says why instead.
    if let (Some(dir), None) = (&args.figures, &report.onward_refused) {
        crate::figures::write_discover(dir, &report, &page).map_err(super::figures::usage)?;
    }
    emit(out, &report, args.format)
}

impl From<DiscoverError> for CliError {
    fn from(e: DiscoverError) -> Self {
        CliError::Discover(Box::new(e))
    }
}
