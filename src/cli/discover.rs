//! `theory-search discover`: the recording chooses the terms of its field's equation.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, CliError, ModelArgs};
use crate::discover::{discover, DiscoverError, DiscoverSettings, Source, MAX_DRAWS};
use crate::fit::{FitSettings, InputKind};
use crate::report::Output;

/// Arguments of `discover`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The recordings (`-` for standard input), as `fit` reads them; several are several animals.
    #[arg(value_name = "FILE", required = true)]
    input: Vec<PathBuf>,
    /// What the columns after time hold.
    #[arg(long, value_enum, default_value_t = Kind::Midline)]
    kind: Kind,
    /// The model field the data observe (default: the lateral field for midlines, the axial
    /// one for lengths).
    #[arg(long)]
    field: Option<String>,
    /// Model points N for midlines (resampled by arc length), from 3 to 500.
    #[arg(long, short, default_value_t = 12, value_name = "N")]
    points: usize,
    /// Put the model's `[active]` forces (active and gyroscopic) in the library.
    #[arg(long)]
    active: bool,
    /// Bridge gaps of at most K lost frames linearly (0: none); longer gaps split the runs.
    #[arg(long, value_name = "K", default_value_t = crate::fit::DEFAULT_FILL_GAPS)]
    fill_gaps: usize,
    /// Frames per second of a DeepLabCut file (its rows hold frame indices; without it the
    /// time unit is one frame). Refused for a file with a time column.
    #[arg(allow_hyphen_values = true, long, value_name = "F")]
    fps: Option<f64>,
    /// Moving-block bootstrap draws for intervals and inclusion frequencies (0: none).
    #[arg(long, value_name = "B", default_value_t = 200)]
    bootstrap: usize,
    /// Seed of the bootstrap draws (same seed, same intervals).
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
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

/// Input kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Kind {
    Midline,
    Lengths,
}

/// Discover and print.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    if args.bootstrap > MAX_DRAWS {
        return Err(CliError::Usage(format!(
            "--bootstrap takes at most {MAX_DRAWS} draws, not {}",
            args.bootstrap
        )));
    }
    let page = args.page.page()?;
    let model = args.model.load()?;
    let mut fit = FitSettings::new(match args.kind {
        Kind::Midline => InputKind::Midline,
        Kind::Lengths => InputKind::Lengths,
    });
    fit.field = args.field.clone();
    fit.order = args.model.order;
    fit.points = args.points;
    fit.fill_gaps = args.fill_gaps;
    fit.fps = args.fps;
    let settings = DiscoverSettings {
        fit,
        active: args.active,
        bootstrap: args.bootstrap,
        seed: args.seed,
        replay: args.figures.is_some(),
    };
    let sources = crate::fit::recordings(&args.input)?
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
