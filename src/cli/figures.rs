//! `theory-search figures`: the SVG figures of a body.

use std::io::Write;
use std::path::PathBuf;

use super::{write_out, BodyArgs, CliError, SampleArgs};
use crate::figures::{write_figures, FigureError, FigureSettings, FIGURES};

/// Arguments of `figures`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory to write the SVG files into (created if missing); `fit --figures DIR` names
    /// its figure folder the same way. `--out` is an alias.
    #[arg(long, value_name = "DIR", visible_alias = "out")]
    figures: PathBuf,
    /// Only this figure (e.g. `mode_shapes.svg`; the `.svg` may be left off).
    #[arg(long, value_name = "NAME")]
    only: Option<String>,
    /// Draws of the sampled figures (pair density, 3-point bend).
    #[command(flatten)]
    sample: SampleArgs,
    #[command(flatten)]
    body: BodyArgs,
}

/// Write the figures, with a progress bar on a terminal (indicatif hides it when stderr is not
/// one); a figure whose behaviour needs a role the model lacks is skipped and said so.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    let theory = args.body.theory()?;
    let settings = FigureSettings {
        points: args.body.points,
        seed: args.sample.seed,
        samples: args.sample.samples,
    };
    let only = args.only.as_ref().map(|name| {
        if name.ends_with(".svg") {
            name.clone()
        } else {
            format!("{name}.svg")
        }
    });
    let names: Vec<&str> = match &only {
        Some(name) => vec![name.as_str()],
        None => FIGURES.to_vec(),
    };
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(names.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let written = write_figures(&args.figures, &names, &theory, &settings, |name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    });
    bar.finish_and_clear();
    let written = written.map_err(|e| match e {
        e @ FigureError::Io { .. } => CliError::Output(e.to_string()),
        FigureError::Body(m) => CliError::Usage(m),
        FigureError::Invalid(m) => CliError::Usage(m),
    })?;
    let mut t = String::new();
    for p in &written.written {
        t += &format!("wrote {}\n", p.display());
    }
    for (name, why) in &written.skipped {
        t += &format!("skipped {name}: {why}\n");
    }
    write_out(out, &t)
}
