//! The command line: a thin layer over the library. One module per subcommand owns its
//! arguments and a short `run`; results format themselves ([`crate::report::Report`]).
//!
//! Every failure is one line on stderr (`error: …`) and a non-zero exit, chosen by the kind of
//! [`CliError`]: 2 for bad usage or values, 1 for files that cannot be read or written.

use std::io::Write;
use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::body::BodyError;
use crate::failure::Failure;
use crate::modal::Params;
use crate::model::{Model, RoleError};
use crate::report::{EmitError, Output, Report};

mod active;
mod asymmetry;
mod behave;
mod compare;
mod count;
mod discover;
mod emit;
mod equations;
mod figures;
mod fit;
mod interactions;
mod mathieu;
mod modes;
mod operators;
mod options;
mod parts;
mod recording;
mod rules;
mod simulate;
mod stats;
mod table;

use options::{BodyArgs, ModelArgs, PairArgs, ParamArgs, SampleArgs};

/// Derive the physics of a soft slender body from symmetry alone.
///
/// With no subcommand, prints the candidate-term tables (the paper's Table 1 and its Rayleigh
/// twin) and the surviving densities of the embedded Drosophila larva model. Every command
/// that depends on the body takes `--model FILE` (another body) and `--order N`.
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
    table: table::Args,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print the candidate tables and surviving densities (the default command).
    Table(table::Args),
    /// Derive the continuum equations of motion from the surviving densities.
    Equations(equations::Args),
    /// Print the difference operators the surviving terms give on N points.
    Operators(operators::Args),
    /// Modes of every field: eigenvalues, frequencies, damping ratios, variance shares.
    Modes(modes::Args),
    /// Integrate the equations of motion (mode by mode with exact propagators when the damping
    /// is modal, the discretised body's implicit step otherwise), streamed as CSV or JSON.
    Simulate(simulate::Args),
    /// The interaction table: which terms could couple each pair of fields, and whether any
    /// survives at long wavelengths.
    Interactions(interactions::Args),
    /// Reduce each field's admitted monomials modulo total derivatives: the independent terms
    /// and the relations used.
    Parts(parts::Args),
    /// Forward/backward wave frequencies of the self-interacting axial pair (paper App. C).
    Asymmetry(asymmetry::Args),
    /// Floquet stability chart of the Mathieu equation Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0 (paper App. D).
    Mathieu(mathieu::Args),
    /// Peristalsis or rolling (the minimum-energy orbit of a degenerate pair, paper App. I),
    /// rearing or hunching (a constant force on the first dorsoventral or axial mode, §3.3.2), or
    /// self-righting (twist, mouth-hook attachment, release and relaxation, §3.3.1, App. H).
    Behave(behave::Args),
    /// Statistical mechanics of the modes (paper App. J).
    Stats(stats::Args),
    /// Write the figures as SVG, PNG or PDF (mode shapes, spectrum, self-righting, rearing and hunching,
    /// asymmetry, equipartition, peristalsis, rolling, free energy, 3-point bend, Mathieu
    /// chart) of a body into a directory.
    Figures(figures::Args),
    /// Fit the theory to tracked midlines or segment lengths: modal projection, PCA, spectra,
    /// ω and β (paper §2.4, Fig. 2).
    Fit(fit::Args),
    /// Discover which terms of the engine's library a recording's field needs: the modes'
    /// exact likelihood (the weak form for nonlinear forces), selection by an
    /// information criterion and the bootstrap's draws, the nested theories scored, whether the
    /// theory holds, and the onward simulate line.
    Discover(discover::Args),
    /// Compare two groups of animals (a mutant against the wild type): each animal fitted
    /// alone, the difference of the groups' κ, Ω and ζ with Welch's 95 % interval over animals
    /// and a permutation p-value, and the laws' verdicts counted per group.
    Compare(compare::Args),
    /// Count the candidate terms of each density at every order up to a maximum.
    Count(count::Args),
    /// Active forces: the force terms a model's [active] section allows that no Lagrangian or
    /// Rayleigh density gives, classified (conservative, gyroscopic, dissipative, active).
    Active(active::Args),
    /// List the rules the engine knows; with --model, what each field requires and what each
    /// rule strikes out at --order.
    Rules(rules::Args),
    /// Regenerate every generated file (src/generated/, tables/) under a directory.
    Emit(emit::Args),
}

/// Why a command failed; the kind decides the exit code, never the message text.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad arguments or values, or a computation the input cannot support (exit 2).
    #[error("{0}")]
    Usage(String),
    /// The model lacks a field role the command needs (exit 2).
    #[error("{}", bounded_text(.0))]
    Role(#[from] RoleError),
    /// A file that cannot be read, or a model file that is invalid (exit 1).
    #[error("{0}")]
    Input(String),
    /// A file that does not exist (exit 1; Python's `FileNotFoundError`).
    #[error("{0}")]
    Missing(String),
    /// Output that cannot be written (exit 1).
    #[error("{0}")]
    Output(String),
    /// The body: its coefficients, modes, operators or run (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Body(#[from] BodyError),
    /// A behaviour model (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Behaviour(#[source] crate::behaviour::BehaviourError),
    /// A recording that cannot be read (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Recording(#[from] crate::recording::RecordingError),
    /// A fit (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Fit(#[from] crate::fit::FitError),
    /// Discovery (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Discover(#[source] Box<crate::discover::DiscoverError>),
    /// A comparison of groups (exit by the kind of failure).
    #[error("{}", bounded_text(.0))]
    Compare(#[source] Box<crate::compare::CompareError>),
}

/// A library error's message as one bounded line ([`crate::markup::bound_line`]): a typed
/// error keeps its type (and so its exit code and Python exception), and the words it quotes
/// (a 100 000-character `--field`, a recording's path, a number of 301 digits) are cut or put
/// in short form wherever in the library the message was built.
fn bounded_text(e: &dyn std::fmt::Display) -> String {
    crate::markup::bound_line(&e.to_string())
}

impl CliError {
    /// The kind of failure (docs/commands.md, "Exit codes").
    pub fn failure(&self) -> Failure {
        match self {
            CliError::Usage(_) | CliError::Role(_) => Failure::Usage,
            CliError::Input(_) | CliError::Missing(_) => Failure::Input,
            CliError::Output(_) => Failure::Output,
            CliError::Body(e) => e.failure(),
            CliError::Behaviour(e) => e.failure(),
            CliError::Recording(e) => e.failure(),
            CliError::Fit(e) => e.failure(),
            CliError::Discover(e) => e.failure(),
            CliError::Compare(e) => e.failure(),
        }
    }

    /// The process exit code, by the kind of failure.
    pub fn exit_code(&self) -> u8 {
        self.failure().exit_code()
    }

    /// The same error with its message bounded ([`crate::markup::bound_line`]): input quoted
    /// in it (a 1 MB line, a 100 000-character path) is never echoed back whole.
    fn bounded(self) -> CliError {
        use crate::markup::bound_line;
        match self {
            CliError::Usage(m) => CliError::Usage(bound_line(&m)),
            CliError::Input(m) => CliError::Input(bound_line(&m)),
            CliError::Missing(m) => CliError::Missing(bound_line(&m)),
            CliError::Output(m) => CliError::Output(bound_line(&m)),
            typed => typed,
        }
    }

    /// An input error from a failed read: [`CliError::Missing`] where the file does not exist.
    pub(crate) fn read(e: &std::io::Error, message: String) -> CliError {
        match e.kind() {
            std::io::ErrorKind::NotFound => CliError::Missing(message),
            _ => CliError::Input(message),
        }
    }

    /// A usage error from any displayable library error.
    fn usage(e: impl std::fmt::Display) -> CliError {
        CliError::Usage(e.to_string())
    }
}

impl From<crate::behaviour::BehaviourError> for CliError {
    fn from(e: crate::behaviour::BehaviourError) -> CliError {
        match e {
            crate::behaviour::BehaviourError::Role(r) => CliError::Role(r),
            other => CliError::Behaviour(other),
        }
    }
}

/// A number of points in `range`, read as `usize` (clap's ranged parser reads `u64`).
fn points_parser(
    range: std::ops::RangeInclusive<u64>,
) -> impl clap::builder::TypedValueParser<Value = usize> {
    use clap::builder::TypedValueParser;
    clap::value_parser!(u64).range(range).map(|n| n as usize)
}

pub use crate::body::MAX_LIST;

/// A repeatable option given more than [`MAX_LIST`] times is refused before any work.
fn check_list(option: &str, len: usize) -> Result<(), CliError> {
    if len > MAX_LIST {
        return Err(CliError::Usage(format!(
            "{option} is given {len} times; at most {MAX_LIST}"
        )));
    }
    Ok(())
}

/// The largest model or parameter file read (a model of eight fields is a few kilobytes).
pub const MAX_TEXT_FILE: u64 = 1 << 20;

/// The text of a small input file, refusing anything larger than [`MAX_TEXT_FILE`] (such as
/// `/dev/zero`) before reading it whole.
fn read_text(path: &std::path::Path) -> Result<String, CliError> {
    use std::io::Read;
    let cannot =
        |e: std::io::Error| CliError::read(&e, format!("cannot read {}: {e}", path.display()));
    let mut text = String::new();
    std::fs::File::open(path)
        .map_err(cannot)?
        .take(MAX_TEXT_FILE + 1)
        .read_to_string(&mut text)
        .map_err(cannot)?;
    if text.len() as u64 > MAX_TEXT_FILE {
        return Err(CliError::Input(format!(
            "{}: larger than {MAX_TEXT_FILE} bytes, not a model or parameter file",
            path.display()
        )));
    }
    Ok(text)
}

fn load_model(path: &Option<PathBuf>) -> Result<Model, CliError> {
    match path {
        None => Ok(Model::larva()),
        Some(p) => {
            let text = read_text(p)?;
            Model::from_toml(&text).map_err(|e| {
                CliError::Input(format!("{}: {}", p.display(), one_line(&e.to_string())))
            })
        }
    }
}

use crate::model::one_line;

/// The scales of the `--params` file (none without one).
fn base_params(args: &ParamArgs) -> Result<Params, CliError> {
    let mut params = Params::default();
    if let Some(path) = &args.params_file {
        // A file that is not a parameter file is an input error (exit 1), like a model file.
        params
            .set_from_toml(&read_text(path)?)
            .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?;
    }
    Ok(params)
}

/// Write a result in `format`.
fn emit(out: &mut dyn Write, report: &dyn Report, format: Output) -> Result<(), CliError> {
    match crate::report::emit(report, format, out) {
        Err(EmitError::Refused(why)) => Err(CliError::Usage(why)),
        Err(EmitError::Io(e)) => written(Err(e)),
        Ok(()) => Ok(()),
    }
}

/// Write `text`; a closed pipe (`| head`) is not an error.
fn write_out(out: &mut dyn Write, text: &str) -> Result<(), CliError> {
    written(out.write_all(text.as_bytes()).and_then(|_| out.flush()))
}

/// The outcome of writing a result as it streams; a closed pipe (`| head`) is not an error.
fn written(result: std::io::Result<()>) -> Result<(), CliError> {
    match result {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(CliError::Output(format!("cannot write output: {e}")))
        }
        _ => Ok(()),
    }
}

/// For an unknown subcommand: the subcommands of the command it was given to, as
/// `commands: a, b, …` (clap suggests only a close one).
fn subcommand_choices(args: &[std::ffi::OsString]) -> Option<String> {
    use clap::CommandFactory;
    let mut cmd = Cli::command();
    for a in args.iter().skip(1) {
        let Some(next) = a.to_str().and_then(|a| cmd.find_subcommand(a)).cloned() else {
            break;
        };
        cmd = next;
    }
    let names: Vec<&str> = cmd
        .get_subcommands()
        .map(|c| c.get_name())
        .filter(|n| *n != "help")
        .collect();
    (!names.is_empty()).then(|| format!("commands: {}", names.join(", ")))
}

/// Parse `args` (program name first), run, and write the output to `out`. Every error is one
/// bounded line.
pub fn run<I, T>(args: I, out: &mut dyn Write) -> Result<(), CliError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    run_unbounded(args, out).map_err(CliError::bounded)
}

fn run_unbounded<I, T>(args: I, out: &mut dyn Write) -> Result<(), CliError>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let args: Vec<std::ffi::OsString> = args.into_iter().map(Into::into).collect();
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            let rendered = e.render().to_string();
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => write_out(out, &rendered),
                // `behave` or `stats` alone: bad usage (exit 2), naming the choices.
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    Err(CliError::Usage(format!(
                        "a subcommand is needed; {} (see --help)",
                        subcommand_choices(&args).unwrap_or_default()
                    )))
                }
                _ => {
                    // Clap's message runs up to the first blank line; keep it, on one line.
                    // Clap's suggestions ("tip: a similar subcommand exists") follow the blank
                    // line; they are kept too.
                    let head: Vec<&str> = rendered
                        .lines()
                        .take_while(|l| !l.trim().is_empty())
                        .map(str::trim)
                        .collect();
                    let tips = rendered
                        .lines()
                        .map(str::trim)
                        .filter(|l| l.starts_with("tip:"));
                    let choices = (e.kind() == ErrorKind::InvalidSubcommand)
                        .then(|| subcommand_choices(&args))
                        .flatten();
                    let joined = std::iter::once(head.join(" "))
                        .chain(tips.map(str::to_string))
                        .chain(choices)
                        .collect::<Vec<_>>()
                        .join("; ");
                    let msg = joined.strip_prefix("error: ").unwrap_or(&joined);
                    // Rust's integer parser speaks of digits; say what is wanted.
                    let msg = msg
                        .replace("invalid digit found in string", "a whole number is needed")
                        .replace(
                            "number too large to fit in target type",
                            "a whole number in range is needed",
                        );
                    Err(CliError::Usage(format!("{msg} (see --help)")))
                }
            };
        }
    };
    match &cli.command {
        None => table::run(&cli.table, out),
        Some(Command::Table(a)) => table::run(a, out),
        Some(Command::Equations(a)) => equations::run(a, out),
        Some(Command::Operators(a)) => operators::run(a, out),
        Some(Command::Modes(a)) => modes::run(a, out),
        Some(Command::Simulate(a)) => simulate::run(a, out),
        Some(Command::Interactions(a)) => interactions::run(a, out),
        Some(Command::Parts(a)) => parts::run(a, out),
        Some(Command::Asymmetry(a)) => asymmetry::run(a, out),
        Some(Command::Mathieu(a)) => mathieu::run(a, out),
        Some(Command::Behave(a)) => behave::run(a, out),
        Some(Command::Stats(a)) => stats::run(a, out),
        Some(Command::Figures(a)) => figures::run(a, out),
        Some(Command::Fit(a)) => fit::run(a, out),
        Some(Command::Discover(a)) => discover::run(a, out),
        Some(Command::Compare(a)) => compare::run(a, out),
        Some(Command::Count(a)) => count::run(a, out),
        Some(Command::Active(a)) => active::run(a, out),
        Some(Command::Rules(a)) => rules::run(a, out),
        Some(Command::Emit(a)) => emit::run(a, out),
    }
}
