//! The command line: a thin layer that parses arguments, calls the library and formats errors.
//!
//! Every failure is one line on stderr (`error: …`) and a non-zero exit: 2 for bad usage, 1 for a
//! file that cannot be read or a model that is invalid.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::codegen;
use crate::enumerate::MAX_ORDER;
use crate::model::{Density, Model};
use crate::reduce::analyse;
use crate::table::{render, Format};

/// Derive the physics of a soft slender body from symmetry alone.
///
/// With no subcommand, prints the candidate-term tables (the seed's Table 1 and its Rayleigh
/// twin) and the surviving densities of the embedded Drosophila larva model.
#[derive(Debug, Parser)]
#[command(
    name = "theory-search",
    version,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    table: TableArgs,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print the candidate tables and surviving densities (the default command).
    Table(TableArgs),
    /// List the rules the engine knows (generated from the registry).
    Rules,
    /// Regenerate every generated file (tables/) under a directory.
    Emit {
        /// Directory to write into: the crate root.
        #[arg(long, default_value = ".")]
        out: PathBuf,
    },
}

/// Which densities to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum DensityChoice {
    Lagrangian,
    Rayleigh,
    Both,
}

#[derive(Debug, Args)]
struct TableArgs {
    /// Order of the expansion: candidates have δ ≤ N and ε ≤ N, and τ+σ ≤ N (Lagrangian) or
    /// τ ≤ N and σ ≤ N (Rayleigh). From 1 to 32.
    #[arg(long, short, default_value_t = 4, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
    order: u32,
    /// Which density to print.
    #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
    density: DensityChoice,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
    /// A model file (TOML) instead of the embedded larva model.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
}

/// A failure, with the exit code it maps to.
#[derive(Debug)]
pub struct CliError {
    /// The one-line message.
    pub message: String,
    /// Process exit code.
    pub code: u8,
}

impl CliError {
    fn new(code: u8, message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code,
        }
    }
}

fn load_model(path: &Option<PathBuf>) -> Result<Model, CliError> {
    match path {
        None => Ok(Model::larva()),
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| CliError::new(1, format!("cannot read {}: {e}", p.display())))?;
            Model::from_toml(&text).map_err(|e| {
                CliError::new(1, format!("{}: {}", p.display(), one_line(&e.to_string())))
            })
        }
    }
}

/// Fold a multi-line message (TOML errors quote the offending line) onto one line.
fn one_line(s: &str) -> String {
    s.split('\n')
        .map(str::trim)
        .filter(|l| !l.is_empty() && l.chars().any(|c| c.is_alphanumeric()))
        .collect::<Vec<_>>()
        .join("; ")
}

fn table(args: &TableArgs) -> Result<String, CliError> {
    let model = load_model(&args.model)?;
    let densities: &[Density] = match args.density {
        DensityChoice::Lagrangian => &[Density::Lagrangian],
        DensityChoice::Rayleigh => &[Density::Rayleigh],
        DensityChoice::Both => &Density::ALL,
    };
    let analyses = densities
        .iter()
        .map(|&d| analyse(&model, d, args.order))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| CliError::new(2, e.to_string()))?;
    Ok(render(&model, &analyses, args.format))
}

/// Parse `args` (program name first) and run; the output to print, or the error.
pub fn run<I, T>(args: I) -> Result<String, CliError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            let rendered = e.render().to_string();
            return match e.kind() {
                ErrorKind::DisplayHelp
                | ErrorKind::DisplayVersion
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => Ok(rendered),
                _ => {
                    let first = rendered.lines().next().unwrap_or("invalid arguments");
                    let msg = first.strip_prefix("error: ").unwrap_or(first);
                    Err(CliError::new(2, format!("{msg} (see --help)")))
                }
            };
        }
    };
    match &cli.command {
        None => table(&cli.table),
        Some(Command::Table(args)) => table(args),
        Some(Command::Rules) => Ok(codegen::rules_markdown()),
        Some(Command::Emit { out }) => {
            let written = codegen::emit(out).map_err(|e| CliError::new(1, e))?;
            Ok(written
                .iter()
                .map(|p| format!("wrote {}\n", p.display()))
                .collect())
        }
    }
}
