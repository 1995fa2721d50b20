//! `theory-search figures`: the figures of a body, as SVG, PNG or PDF at a printed width.

use std::io::Write;
use std::path::PathBuf;

use super::{write_out, BodyArgs, CliError, SampleArgs};
use crate::figures::{figure_names, write_figures, FigureError, FigureSettings, Format, Page};

/// Arguments of `figures`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory to write the figures into (created if missing); `fit --figures DIR` names
    /// its figure folder the same way. `--out` is an alias.
    #[arg(long, value_name = "DIR", visible_alias = "out")]
    figures: PathBuf,
    /// Only this figure (e.g. `mode_shapes`; an extension is ignored).
    #[arg(long, value_name = "NAME")]
    only: Option<String>,
    /// File format of the figures.
    #[arg(long, value_enum, default_value_t = Format::Svg, visible_alias = "figure-format")]
    format: Format,
    /// Printed width in millimetres, 60 to 600 (180: a journal's full width). The layout
    /// follows the width, so text is 7.4 pt at any width.
    #[arg(
        long,
        value_name = "MM",
        default_value_t = 180.0,
        visible_alias = "figure-width"
    )]
    width: f64,
    /// Resolution of PNG figures, dots per inch (30 to 1200).
    #[arg(
        long,
        value_name = "DPI",
        default_value_t = 300.0,
        visible_alias = "figure-dpi"
    )]
    dpi: f64,
    /// Draws of the sampled figures (pair density, 3-point bend).
    #[command(flatten)]
    sample: SampleArgs,
    #[command(flatten)]
    body: BodyArgs,
}

/// Write the figures, with a progress bar on a terminal (indicatif hides it when stderr is not
/// one); a figure whose behaviour needs a role the model lacks is skipped and said so.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let settings = FigureSettings {
        points: args.body.points,
        seed: args.sample.seed,
        samples: args.sample.samples,
        page: Page {
            format: args.format,
            width_mm: args.width,
            dpi: args.dpi,
        },
    };
    settings.check().map_err(usage)?;
    let theory = args.body.theory("figures")?;
    let names = figure_names(args.only.as_deref());
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(names.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let written = write_figures(&args.figures, &names, &theory, &settings, |name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    });
    bar.finish_and_clear();
    let written = written.map_err(usage)?;
    let mut t = String::new();
    for p in &written.written {
        t += &format!("wrote {}\n", p.display());
    }
    for (name, why) in &written.skipped {
        t += &format!("skipped {name}: {why}\n");
    }
    write_out(out, &t)
}

/// A figure error as the CLI reports it: unwritable files are output errors, the rest usage.
pub(super) fn usage(e: FigureError) -> CliError {
    match e {
        e @ FigureError::Io { .. } => CliError::Output(e.to_string()),
        FigureError::Behaviour(b) => CliError::Behaviour(b),
        FigureError::Invalid(m) => CliError::Usage(m),
    }
}
