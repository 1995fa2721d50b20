//! The command line: a thin layer that parses arguments, calls the library and formats errors.
//!
//! Every failure is one line on stderr (`error: …`) and a non-zero exit: 2 for bad usage, 1 for a
//! file that cannot be read or a model that is invalid.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::codegen;
use crate::discretise::{operators, Operator};
use crate::enumerate::Basis;
use crate::enumerate::MAX_ORDER;
use crate::equations::{self, derive_basis};
use crate::modal::{field_modes, Params};
use crate::model::{Density, Model};
use crate::reduce::analyse_basis;
use crate::table as report;
use crate::table::{render, Format};

/// The most points `operators` prints as dense matrices.
pub const MAX_PRINT_POINTS: usize = 2000;

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
    /// Derive the continuum equations of motion from the surviving densities.
    Equations {
        #[command(flatten)]
        model: ModelArgs,
        /// Candidate terms: pure powers (the seed's) or every monomial.
        #[arg(long, value_enum, default_value_t = Basis::Powers)]
        basis: Basis,
        /// Output format.
        #[arg(long, value_enum, default_value_t = EquationFormat::Text)]
        format: EquationFormat,
    },
    /// Print the difference operators the surviving terms give on N points.
    Operators {
        /// Number of points along the body (the seed uses 12). Dense matrices are printed up to
        /// 2000 points.
        #[arg(long, short, value_name = "N",
              value_parser = clap::value_parser!(u64).range(1..=MAX_PRINT_POINTS as u64))]
        points: u64,
        #[command(flatten)]
        model: ModelArgs,
        /// Output format.
        #[arg(long, value_enum, default_value_t = OperatorFormat::Text)]
        format: OperatorFormat,
    },
    /// Modes of every field: eigenvalues, frequencies, damping ratios, variance shares.
    Modes(ModesArgs),
    /// Integrate the dissipative Hamilton's equations mode by mode (exact propagators); CSV out.
    Simulate(SimulateArgs),
    /// The interaction table: which terms could couple each pair of fields, and whether any
    /// survives at long wavelengths.
    Interactions {
        #[command(flatten)]
        model: ModelArgs,
        /// Which density.
        #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
        density: DensityChoice,
    },
    /// Reduce each field's admitted monomials modulo total derivatives: the independent terms
    /// and the relations used.
    Parts {
        #[command(flatten)]
        model: ModelArgs,
        /// Which density.
        #[arg(long, value_enum, default_value_t = DensityChoice::Lagrangian)]
        density: DensityChoice,
    },
    /// Forward/backward wave frequencies of the self-interacting axial pair (seed App. C).
    Asymmetry {
        /// Coupling constant c of the cubic dissipative interaction.
        #[arg(long, allow_negative_numbers = true)]
        coupling: f64,
        /// Wave amplitude A.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        amplitude: f64,
        /// Free-field frequency ω.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        omega: f64,
        /// Output format.
        #[arg(long, value_enum, default_value_t = BehaveFormat::Text)]
        format: BehaveFormat,
    },
    /// Floquet stability chart of the Mathieu equation Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0 (seed App. D).
    Mathieu {
        /// Natural frequency λ of the transverse mode.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        lambda: f64,
        /// Lowest ω/λ of the chart.
        #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
        ratio_min: f64,
        /// Highest ω/λ of the chart.
        #[arg(long, default_value_t = 4.5, allow_negative_numbers = true)]
        ratio_max: f64,
        /// Largest ε of the chart.
        #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
        epsilon_max: f64,
        /// Grid points along ω/λ.
        #[arg(long, default_value_t = 81)]
        columns: usize,
        /// Grid points along ε.
        #[arg(long, default_value_t = 21)]
        rows: usize,
        /// Output format (csv: one row per grid point).
        #[arg(long, value_enum, default_value_t = ModesFormat::Text)]
        format: ModesFormat,
    },
    /// Peristalsis or rolling (the minimum-energy orbit of a degenerate pair, seed App. I),
    /// rearing or hunching (a constant force on the first dorsoventral or axial mode, §3.3.2), or
    /// self-righting (twist, mouth-hook attachment, release and relaxation, §3.3.1, App. H).
    Behave {
        /// Which behaviour.
        #[arg(value_enum)]
        kind: BehaveKind,
        /// The constant modal force (rearing, hunching).
        #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
        force: f64,
        /// How long to follow the transient (rearing, hunching).
        #[arg(long, default_value_t = 2000.0)]
        duration: f64,
        /// Conserved momentum M (its sign sets the direction).
        #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
        momentum: f64,
        /// Points along the body.
        #[arg(long, default_value_t = 12)]
        points: usize,
        /// Periods to run.
        #[arg(long, default_value_t = 100.0)]
        periods: f64,
        /// Tolerance δ in radians for mouth-hook attachment and alignment (self-righting).
        #[arg(long, default_value_t = 0.01)]
        tolerance: f64,
        /// Damping ratio ζ₁ of the first torsional mode (self-righting; default 1, critical,
        /// unless `--param zeta_t=…` is given).
        #[arg(long, value_name = "ZETA")]
        mode_damping: Option<f64>,
        /// Initial orientation of the body in radians (self-righting; π is upside down).
        #[arg(long, default_value_t = std::f64::consts::PI, allow_negative_numbers = true)]
        theta0: f64,
        /// Relaxation after attachment (self-righting): the seed's two-degree-of-freedom model,
        /// or the whole chain with the head held.
        #[arg(long, value_enum, default_value_t = AttachmentKind::Seed)]
        attachment: AttachmentKind,
        /// Also run these first-mode damping ratios and tabulate their righting times.
        #[arg(long, value_delimiter = ',', value_name = "ZETA,…")]
        sweep: Vec<f64>,
        #[command(flatten)]
        params: ParamArgs,
        /// Output format (csv: the time series).
        #[arg(long, value_enum, default_value_t = BehaveFormat::Text)]
        format: BehaveFormat,
    },
    /// Statistical mechanics of the modes (seed App. J).
    Stats {
        #[command(subcommand)]
        what: StatsCommand,
    },
    /// Write the SVG figures (mode shapes, spectrum, self-righting, peristalsis, rolling, free
    /// energy, 3-point bend, Mathieu chart) of the embedded larva into a directory.
    Figures {
        /// Directory to write into (created if missing).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Only this figure (e.g. `mode_shapes.svg`).
        #[arg(long, value_name = "NAME")]
        only: Option<String>,
        /// Points along the body.
        #[arg(long, default_value_t = 12)]
        points: usize,
        /// Samples of the sampled figures.
        #[arg(long, default_value_t = 100_000)]
        samples: usize,
        /// Seed of the sampled figures.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[command(flatten)]
        params: ParamArgs,
    },
    /// Fit the theory to tracked midlines or segment lengths: modal projection, PCA, spectra,
    /// ω and β (seed §2.4, Fig. 2).
    Fit {
        /// The data file (`-` for standard input): `t x₁ y₁ … x_K y_K` or `t ℓ₁ … ℓ_K` per line.
        #[arg(value_name = "FILE")]
        input: PathBuf,
        /// What the columns after time hold.
        #[arg(long, value_enum, default_value_t = FitKind::Midline)]
        kind: FitKind,
        /// The model field the data observe (default: y for midlines, x for lengths).
        #[arg(long)]
        field: Option<String>,
        /// Model points N for midlines (resampled by arc length when the data have another K).
        #[arg(long, default_value_t = 12)]
        points: usize,
        /// Welch window in frames.
        #[arg(long, default_value_t = 256)]
        window: usize,
        /// Frequency estimator: peak (rhythmic behaviour) or centroid (aperiodic).
        #[arg(long, value_enum, default_value_t = FitEstimator::Peak)]
        estimator: FitEstimator,
        /// Non-zero modes used to fit ω and β.
        #[arg(long, default_value_t = 4)]
        fit_modes: usize,
        /// Fix ω instead of fitting it.
        #[arg(long)]
        omega: Option<f64>,
        /// Lengths only: the number of segments around the whole body when only the first K
        /// were measured (fits the lowest whole modes by least squares).
        #[arg(long, value_name = "R")]
        ring: Option<usize>,
        /// Also write the fit's SVG figures into this directory.
        #[arg(long, value_name = "DIR")]
        figures: Option<PathBuf>,
        /// Also write every frame's modal coordinates to this CSV file (t, q_<mode>, …).
        #[arg(long, value_name = "FILE")]
        series: Option<PathBuf>,
        /// A model file (TOML) instead of the embedded larva model.
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// Output format (csv: one row per mode).
        #[arg(long, value_enum, default_value_t = BehaveFormat::Text)]
        format: BehaveFormat,
    },
    /// Count the candidate terms of each density at every order up to a maximum.
    Count {
        /// Candidate terms: pure powers or every monomial.
        #[arg(long, value_enum, default_value_t = Basis::Powers)]
        basis: Basis,
        /// Count orders 1 … N.
        #[arg(long, default_value_t = 8, value_name = "N",
              value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
        max_order: u32,
        /// A model file (TOML) instead of the embedded larva model.
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
    },
    /// List the rules the engine knows (generated from the registry).
    Rules,
    /// Regenerate every generated file (src/generated/, tables/) under a directory.
    Emit {
        /// Directory to write into: the crate root.
        #[arg(long, default_value = ".")]
        out: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
}

#[derive(Debug, Subcommand)]
enum StatsCommand {
    /// Unbiased exploration: Gaussian planar postures, the 3-point bend distribution, β refitted.
    Explore {
        /// Inverse temperature β (in units where ω_b = 1 and the body length is 1).
        #[arg(long, default_value_t = 10_000.0, allow_negative_numbers = true)]
        beta: f64,
        /// Postures to sample.
        #[arg(long, default_value_t = 100_000)]
        samples: usize,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Points along the body.
        #[arg(long, default_value_t = 12)]
        points: usize,
        #[command(flatten)]
        params: ParamArgs,
        /// Output format (csv: one bend angle per sample).
        #[arg(long, value_enum, default_value_t = ModesFormat::Text)]
        format: ModesFormat,
    },
    /// Langevin run, PCA of one field's postures, and the modes beside it (seed App. B).
    Equipartition {
        /// The field (id).
        #[arg(long, default_value = "y")]
        field: String,
        /// Points along the body.
        #[arg(long, default_value_t = 12)]
        points: usize,
        /// Time steps of 0.5 (a tenth are burn-in).
        #[arg(long, default_value_t = 200_000)]
        steps: u64,
        /// Thermal energy kT.
        #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
        temperature: f64,
        /// Seed of the noise.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[command(flatten)]
        params: ParamArgs,
        /// Output format (csv: one row per sample, or per mode).
        #[arg(long, value_enum, default_value_t = BehaveFormat::Text)]
        format: BehaveFormat,
    },
    /// A degenerate pair at fixed momentum M: Z, F, A*, ⟨A⟩; with --samples also a Metropolis run.
    Pair {
        /// The pair's frequency ω.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        omega: f64,
        /// Inverse temperature β.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        beta: f64,
        /// Conserved momentum M.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        momentum: f64,
        /// Draw this many Metropolis samples.
        #[arg(long)]
        samples: Option<usize>,
        /// Seed of the sampler.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output format (csv: one row per sample, or per mode).
        #[arg(long, value_enum, default_value_t = BehaveFormat::Text)]
        format: BehaveFormat,
    },
}

/// Which densities to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum DensityChoice {
    Lagrangian,
    Rayleigh,
    Both,
}

/// Output formats of `equations`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum EquationFormat {
    Text,
    Latex,
    Json,
}

/// The behaviours of `behave`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BehaveKind {
    Peristalsis,
    Rolling,
    Rearing,
    Hunching,
    SelfRighting,
}

/// Relaxation models of `behave self-righting`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AttachmentKind {
    Seed,
    Pinned,
}

/// Input kinds of `fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum FitKind {
    Midline,
    Lengths,
}

/// Frequency estimators of `fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum FitEstimator {
    Peak,
    Centroid,
}

/// Output formats of `behave` (csv: the time series).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BehaveFormat {
    Text,
    Json,
    Csv,
}

/// Output formats of `modes`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ModesFormat {
    Text,
    Json,
    Csv,
}

/// Scales of the frequencies and damping.
#[derive(Debug, Args)]
struct ParamArgs {
    /// Set a scale, e.g. `--param omega_b=2.5 --param zeta_s=0.3` (defaults: ω = 1, ζ = 0.1).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Read scales from a TOML file of `omega_s = 1.0` lines (before any --param).
    #[arg(long = "params", value_name = "FILE")]
    params_file: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct SimulateArgs {
    /// Number of points along the body (the seed uses 12), up to 2000.
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=crate::dynamics::MAX_SIM_POINTS as u64))]
    points: u64,
    /// Time step.
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 1000)]
    steps: u64,
    /// Write a row every K steps (the initial state is always written).
    #[arg(long, default_value_t = 1, value_name = "K")]
    every: u64,
    /// Initial modal state FIELD:MODE=Q[,Q̇], e.g. `theta:1=3.14` or `y:2=0,0.5` (repeatable).
    #[arg(long = "initial", value_name = "FIELD:MODE=Q[,V]")]
    initial: Vec<String>,
    /// Constant modal force FIELD:MODE=F (repeatable).
    #[arg(long = "force", value_name = "FIELD:MODE=F")]
    force: Vec<String>,
    /// Sinusoidal modal force FIELD:MODE=F0,OMEGA[,PHASE]: F0·cos(OMEGA·t + PHASE) (repeatable).
    #[arg(long = "drive", value_name = "FIELD:MODE=F0,OMEGA[,PHASE]")]
    drive: Vec<String>,
    /// Thermal energy kT of the Langevin noise (0: none).
    #[arg(long, default_value_t = 0.0)]
    temperature: f64,
    /// Seed of the noise (same seed, same run).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the CSV here instead of standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    model: ModelArgs,
}

#[derive(Debug, Args)]
struct ModesArgs {
    /// Number of points along the body (the seed uses 12), up to 10 000 000.
    #[arg(long, short, value_name = "N",
          value_parser = clap::value_parser!(u64).range(1..=crate::modal::MAX_POINTS as u64))]
    points: u64,
    /// Report only the lowest K modes of each field (shares stay exact over all modes).
    #[arg(long = "modes", value_name = "K",
          value_parser = clap::value_parser!(u64).range(1..))]
    limit: Option<u64>,
    /// Also print the mode shapes (unit norm, first significant component positive).
    #[arg(long)]
    shapes: bool,
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = ModesFormat::Text)]
    format: ModesFormat,
}

/// Output formats of `operators`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum OperatorFormat {
    Text,
    Json,
}

/// Which model, at which order.
#[derive(Debug, Args)]
struct ModelArgs {
    /// Order of the expansion: candidates have δ ≤ N and ε ≤ N, and τ+σ ≤ N (Lagrangian) or
    /// τ ≤ N and σ ≤ N (Rayleigh). From 1 to 32.
    #[arg(long, short, default_value_t = 4, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
    order: u32,
    /// A model file (TOML) instead of the embedded larva model.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct TableArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Candidate terms: pure powers (the seed's Table 1) or every monomial (products of factors).
    #[arg(long, value_enum, default_value_t = Basis::Powers)]
    basis: Basis,
    /// Which density to print.
    #[arg(long, value_enum, default_value_t = DensityChoice::Both)]
    density: DensityChoice,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

fn densities_of(choice: DensityChoice) -> &'static [Density] {
    match choice {
        DensityChoice::Lagrangian => &[Density::Lagrangian],
        DensityChoice::Rayleigh => &[Density::Rayleigh],
        DensityChoice::Both => &Density::ALL,
    }
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
    let model = load_model(&args.model.model)?;
    let densities = densities_of(args.density);
    let analyses = densities
        .iter()
        .map(|&d| analyse_basis(&model, d, args.model.order, args.basis))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| CliError::new(2, e.to_string()))?;
    Ok(render(&model, &analyses, args.format))
}

fn equations_command(
    args: &ModelArgs,
    basis: Basis,
    format: EquationFormat,
) -> Result<String, CliError> {
    let model = load_model(&args.model)?;
    let (eqs, notes) =
        derive_basis(&model, args.order, basis).map_err(|e| CliError::new(2, e.to_string()))?;
    Ok(match format {
        EquationFormat::Json => {
            let v = equations::json(args.order, &eqs, &notes);
            serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
        }
        EquationFormat::Latex => {
            let lines: Vec<String> = eqs.iter().map(|e| e.latex()).collect();
            format!(
                "\\begin{{align*}}\n{}\n\\end{{align*}}\n",
                lines.join(" \\\\\n")
            )
        }
        EquationFormat::Text => {
            let mut out = format!(
                "Equations of motion of the {} model at order {} (δL/δφ = δR/δ(∂tφ)):\n",
                model.name, args.order
            );
            for e in &eqs {
                out += &format!("  {}\n", e.text());
            }
            let folds: Vec<String> = eqs.iter().flat_map(|e| e.folds()).collect();
            if !folds.is_empty() {
                out += &format!(
                    "Coefficients are positive free parameters; {}.\n",
                    folds.join(", ")
                );
            }
            for n in notes {
                out += &format!("note: {n}\n");
            }
            out
        }
    })
}

fn operators_text(ops: &[Operator], model: &Model, points: usize) -> String {
    let mut out = format!(
        "Difference operators of the {} model on N = {points} points:\n",
        model.name
    );
    for op in ops {
        let symbol = model.symbol(&op.field);
        let term: crate::term::Term = op.term.parse().expect("operators carry canonical terms");
        out += &format!(
            "\n{} · {} · {} · {} boundary · {}×{} · D = Σ (Δ{}{symbol})²{}\n",
            op.field,
            op.density,
            term.render(&|_| symbol.clone()),
            op.boundary,
            op.size,
            op.size,
            crate::term::superscript(op.k),
            op.seed_name.map(|n| format!(" = {n}")).unwrap_or_default(),
        );
        let width = op
            .matrix
            .iter()
            .flatten()
            .map(|v| v.to_string().len())
            .max()
            .unwrap_or(1);
        for row in &op.matrix {
            let cells: Vec<String> = row.iter().map(|v| format!("{v:>width$}")).collect();
            out += &format!("  {}\n", cells.join(" "));
        }
    }
    out
}

fn operators_command(
    args: &ModelArgs,
    points: usize,
    format: OperatorFormat,
) -> Result<String, CliError> {
    let model = load_model(&args.model)?;
    let ops = operators(&model, args.order, points).map_err(|e| CliError::new(2, e.to_string()))?;
    Ok(match format {
        OperatorFormat::Json => {
            let v = serde_json::json!({"points": points, "order": args.order, "operators": ops});
            serde_json::to_string(&v).unwrap_or_default() + "\n"
        }
        OperatorFormat::Text => operators_text(&ops, &model, points),
    })
}

/// The embedded larva with the given scales, for a run on `points` points.
fn larva_run(params: &ParamArgs, points: usize) -> Result<(Model, Params), CliError> {
    let model = Model::larva();
    let params = load_params(params, &model)?;
    if points > crate::dynamics::MAX_SIM_POINTS {
        return Err(CliError::new(
            2,
            format!("at most {} points", crate::dynamics::MAX_SIM_POINTS),
        ));
    }
    Ok((model, params))
}

fn step_text(
    kind: BehaveKind,
    field: &str,
    force: f64,
    r: &crate::behaviour::StepResponse,
    format: BehaveFormat,
) -> String {
    match format {
        BehaveFormat::Json => return serde_json::to_string_pretty(r).unwrap_or_default() + "\n",
        BehaveFormat::Csv => {
            return csv(&["t", "q"], r.transient.iter().map(|&(t, q)| vec![t, q]));
        }
        BehaveFormat::Text => {}
    }
    let shape: Vec<String> = r.shape.iter().map(|v| format!("{v:.5}")).collect();
    let mut t = format!(
        "{kind:?}: force {force} on mode {} of {field}; equilibrium Q* = F/ω² = {:.9}\n  shifted shape: {}\n  transient agrees with the analytic step response to {:.1e}\n  t, Q(t):\n",
        r.mode,
        r.equilibrium,
        shape.join(" "),
        r.max_error
    );
    for (tt, q) in r.transient.iter().step_by(40) {
        t += &format!("  {tt:>10.2}  {q:.9}\n");
    }
    t
}

/// A CSV table of numbers under `header`.
fn csv(header: &[&str], rows: impl IntoIterator<Item = Vec<f64>>) -> String {
    let mut t = header.join(",") + "\n";
    for r in rows {
        let cells: Vec<String> = r.iter().map(|v| v.to_string()).collect();
        t += &(cells.join(",") + "\n");
    }
    t
}

/// Run the fit on a file or standard input, streaming the modal series to `series` if asked.
fn fit_command(
    input: &std::path::Path,
    series: Option<&std::path::Path>,
    model: &Model,
    settings: &crate::fit::FitSettings,
) -> Result<crate::fit::FitReport, CliError> {
    use crate::fit::{fit_each, FitError};
    let params = Params::default();
    let mut sink =
        match series {
            None => None,
            Some(path) => Some((
                path,
                std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| {
                    CliError::new(1, format!("cannot write {}: {e}", path.display()))
                })?),
                false,
            )),
        };
    let mut each = |p: &crate::fit::Projector, t: f64, q: &[f64]| -> Result<(), String> {
        let Some((path, out, started)) = sink.as_mut() else {
            return Ok(());
        };
        let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
        if !*started {
            let names: Vec<String> = (0..q.len())
                .map(|j| format!("q_{}", p.first_mode + j))
                .collect();
            writeln!(out, "t,{}", names.join(",")).map_err(fail)?;
            *started = true;
        }
        let cells: Vec<String> = q.iter().map(|v| v.to_string()).collect();
        writeln!(out, "{t},{}", cells.join(",")).map_err(fail)
    };
    let result = if input.as_os_str() == "-" {
        fit_each(std::io::stdin().lock(), model, &params, settings, &mut each)
    } else {
        let file = std::fs::File::open(input)
            .map_err(|e| CliError::new(1, format!("cannot open {}: {e}", input.display())))?;
        fit_each(
            std::io::BufReader::new(file),
            model,
            &params,
            settings,
            &mut each,
        )
    };
    if let Some((path, mut out, _)) = sink {
        out.flush()
            .map_err(|e| CliError::new(1, format!("cannot write {}: {e}", path.display())))?;
    }
    result.map_err(|e| match e {
        FitError::Invalid(m) => CliError::new(2, m),
        FitError::Output(m) => CliError::new(1, m),
        other => CliError::new(1, format!("{}: {other}", input.display())),
    })
}

/// The fit report as text, JSON or CSV.
fn fit_text(r: &crate::fit::FitReport, format: BehaveFormat) -> String {
    match format {
        BehaveFormat::Json => serde_json::to_string_pretty(r).unwrap_or_default() + "\n",
        BehaveFormat::Csv => csv(
            &[
                "mode",
                "eigenvalue",
                "pca_share",
                "theory_share",
                "overlap",
                "variance",
                "peak_frequency",
                "centroid_frequency",
                "angular_frequency",
                "theory_angular_frequency",
            ],
            r.modes.iter().enumerate().map(|(k, m)| {
                vec![
                    m.index as f64,
                    m.eigenvalue,
                    r.pca_variance_share[k],
                    r.theory_variance_share[k],
                    r.overlap[k][k],
                    m.variance,
                    m.peak_frequency,
                    m.centroid_frequency,
                    m.angular_frequency,
                    m.theory_angular_frequency,
                ]
            }),
        ),
        BehaveFormat::Text => {
            let what = match r.kind {
                crate::fit::InputKind::Midline => format!("{}-point midlines", r.points),
                crate::fit::InputKind::Lengths => format!("{} segment lengths", r.points),
            };
            let mut t = format!(
                "Fit of {} frames of {what} (sampling interval {}) to field {} on N = {}\n\
                 \x20 ω = {:.6} (least squares over modes {}–{}), β = {:.6} (lengths in units of the point spacing)\n\
                 \x20 Welch: window {} frames, {} segments\n\
                 \x20 mode        λ   PCA share  equipartition  overlap with mode   peak f  centroid f   measured ω  theory ω√λ\n",
                r.frames,
                (r.sample_interval * 1e9).round() / 1e9,
                r.field,
                r.model_points,
                r.omega,
                r.modes[0].index,
                r.modes[r.fitted_modes - 1].index,
                r.beta,
                r.welch.0,
                r.welch.1,
            );
            for (k, m) in r.modes.iter().enumerate() {
                t += &format!(
                    "  {:>4} {:>8.5} {:>9.3} % {:>12.3} % {:>18.5} {:>8.5} {:>11.5} {:>12.5} {:>11.5}\n",
                    m.index,
                    m.eigenvalue,
                    100.0 * r.pca_variance_share[k],
                    100.0 * r.theory_variance_share[k],
                    r.mode_overlap[k],
                    m.peak_frequency,
                    m.centroid_frequency,
                    m.angular_frequency,
                    m.theory_angular_frequency,
                );
            }
            let shares: Vec<String> = r
                .angle_pca_variance_share
                .iter()
                .map(|s| format!("{:.1}", 100.0 * s))
                .collect();
            t += "  overlap: |cos(PCₖ, vₖ)|, or the projection onto the pair's plane when λₖ is degenerate\n";
            t += &format!(
                "  PCA of the plain angles (%, the seed's eigenmaggots; equipartition makes them equal): {}\n",
                shares.join(" ")
            );
            t
        }
    }
}

/// Write the figures, with a progress bar on a terminal (indicatif hides it when stderr is not
/// one).
fn figures_command(
    dir: &std::path::Path,
    only: Option<&str>,
    model: &Model,
    params: &Params,
    settings: &crate::figures::FigureSettings,
) -> Result<Vec<PathBuf>, CliError> {
    use crate::figures::{write_figures, FIGURES};
    let fail = |e: crate::figures::FigureError| {
        let code = if e.0.starts_with("cannot") { 1 } else { 2 };
        CliError::new(code, e.0)
    };
    let names: Vec<&str> = match only {
        Some(name) => vec![name],
        None => FIGURES.to_vec(),
    };
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(names.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let written = write_figures(dir, &names, model, params, settings, |name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    });
    bar.finish_and_clear();
    written.map_err(fail)
}

/// The self-righting report, with an optional sweep over the first mode's damping ratio.
fn righting_text(
    model: &Model,
    params: &Params,
    settings: &crate::behaviour::RightingSettings,
    sweep: &[f64],
    format: BehaveFormat,
) -> Result<String, CliError> {
    use crate::behaviour::{righting_sweep, self_righting};
    let fail = |e: crate::behaviour::BehaviourError| CliError::new(2, e.to_string());
    let r = self_righting(model, params, settings).map_err(fail)?;
    let rows = righting_sweep(model, params, settings, sweep).map_err(fail)?;
    Ok(match format {
        BehaveFormat::Json => {
            let mut v = serde_json::to_value(&r).unwrap_or_default();
            if !rows.is_empty() {
                v["sweep"] = serde_json::to_value(&rows).unwrap_or_default();
            }
            serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
        }
        BehaveFormat::Csv => {
            let mut header: Vec<String> = ["t", "torque", "mode", "mean_rotation"]
                .iter()
                .map(|h| h.to_string())
                .collect();
            header.extend((0..r.points).map(|j| format!("theta_{j}")));
            let header: Vec<&str> = header.iter().map(String::as_str).collect();
            csv(
                &header,
                r.frames.iter().map(|f| {
                    let mut row = vec![f.t, f.torque, f.mode, f.mean_rotation];
                    row.extend(&f.angles);
                    row
                }),
            )
        }
        BehaveFormat::Text => {
            let regime = if (r.damping_ratio - 1.0).abs() <= 1e-9 {
                "critical"
            } else if r.damping_ratio < 1.0 {
                "underdamped"
            } else {
                "overdamped"
            };
            let mut t = format!(
                "Self-righting on N = {}: first torsional mode ω₁ = {:.9}, ζ₁ = {:.6} ({regime}), a = v₁(head) = {:.9}\n\
                 \x20 stage 1: constant torque Q = −ω₁²θ₀/a = {:.9} on Θ₁ from θ₀ = {:.6}\n\
                 \x20   the head follows Eq. 20 to {:.1e}; the mean rotation moves by {:.1e}\n\
                 \x20   mouth hooks attach at t = {:.4} (head within δ = {} rad)\n\
                 \x20 stage 2 ({:?}): torque released; slowest relaxing mode ω = {:.6}, ζ = {:.4}; overshoot {:.4}\n\
                 \x20   body aligned within δ at t = {:.4}\n\
                 \x20 alignment time per segment (0 = tail … {} = head):\n",
                r.points,
                r.frequency,
                r.damping_ratio,
                r.head_coefficient,
                r.torque,
                r.theta0,
                r.head_error,
                r.rotation_before_attachment,
                r.attachment_time,
                r.tolerance,
                r.attachment,
                r.relaxation.0,
                r.relaxation.1,
                r.overshoot,
                r.righting_time,
                r.points - 1,
            );
            for (j, a) in r.alignment_times.iter().enumerate() {
                t += &format!("  {j:>6}  {a:.4}\n");
            }
            if !rows.is_empty() {
                t += "  sweep of ζ₁:\n      ζ₁   attach   righted  overshoot  decay rate\n";
                for p in &rows {
                    t += &format!(
                        "  {:>6.3}  {:>7.3}  {:>8.3}  {:>9.4}  {:>10.6}\n",
                        p.mode_damping,
                        p.attachment_time,
                        p.righting_time,
                        p.overshoot,
                        p.decay_rate,
                    );
                }
            }
            t
        }
    })
}

/// The most numbers `--shapes` prints.
const MAX_SHAPE_VALUES: usize = 20_000_000;

fn load_params(args: &ParamArgs, model: &Model) -> Result<Params, CliError> {
    let mut params = Params::default();
    if let Some(path) = &args.params_file {
        let text = std::fs::read_to_string(path)
            .map_err(|e| CliError::new(1, format!("cannot read {}: {e}", path.display())))?;
        params
            .set_from_toml(&text)
            .map_err(|e| CliError::new(2, format!("{}: {e}", path.display())))?;
    }
    for p in &args.params {
        params
            .set_assignment(p)
            .map_err(|e| CliError::new(2, e.to_string()))?;
    }
    let scales: Vec<&str> = model.fields.iter().map(|f| f.scale()).collect();
    if let Some(name) = params.unused(&scales).first() {
        return Err(CliError::new(
            2,
            format!(
                "parameter {name}: no field of the {} model uses it (scales: {})",
                model.name,
                scales.join(", ")
            ),
        ));
    }
    Ok(params)
}

/// `FIELD:MODE=values`: the field, the mode and the comma-separated numbers.
fn modal_assignment(text: &str, what: &str) -> Result<(String, usize, Vec<f64>), CliError> {
    let bad = |why: &str| CliError::new(2, format!("{what} {text:?}: {why}"));
    let (target, values) = text
        .split_once('=')
        .ok_or_else(|| bad("expected FIELD:MODE=VALUE"))?;
    let (field, mode) = target
        .split_once(':')
        .ok_or_else(|| bad("expected FIELD:MODE before '='"))?;
    let mode: usize = mode
        .trim()
        .parse()
        .map_err(|_| bad("the mode must be a whole number"))?;
    let values = values
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<f64>, _>>()
        .map_err(|_| bad("values must be numbers"))?;
    if values.iter().any(|v| !v.is_finite()) {
        return Err(bad("values must be finite"));
    }
    Ok((field.trim().to_string(), mode, values))
}

fn simulate_command(args: &SimulateArgs, out: &mut dyn Write) -> Result<(), CliError> {
    use crate::dynamics::{csv_header, csv_row, simulate, Config, Forcing, Initial};
    let model = load_model(&args.model.model)?;
    let params = load_params(&args.params, &model)?;
    let mut initial = Vec::new();
    for text in &args.initial {
        let (field, mode, v) = modal_assignment(text, "--initial")?;
        if v.is_empty() || v.len() > 2 {
            return Err(CliError::new(
                2,
                format!("--initial {text:?}: give Q or Q,V"),
            ));
        }
        initial.push(Initial {
            field,
            mode,
            displacement: v[0],
            velocity: v.get(1).copied().unwrap_or(0.0),
        });
    }
    let mut forcing = Vec::new();
    for text in &args.force {
        let (field, mode, v) = modal_assignment(text, "--force")?;
        if v.len() != 1 {
            return Err(CliError::new(
                2,
                format!("--force {text:?}: give one value"),
            ));
        }
        forcing.push(Forcing {
            field,
            mode,
            constant: v[0],
            amplitude: 0.0,
            frequency: 0.0,
            phase: 0.0,
        });
    }
    for text in &args.drive {
        let (field, mode, v) = modal_assignment(text, "--drive")?;
        if !(2..=3).contains(&v.len()) {
            return Err(CliError::new(
                2,
                format!("--drive {text:?}: give F0,OMEGA or F0,OMEGA,PHASE"),
            ));
        }
        forcing.push(Forcing {
            field,
            mode,
            constant: 0.0,
            amplitude: v[0],
            frequency: v[1],
            phase: v.get(2).copied().unwrap_or(0.0),
        });
    }
    let config = Config {
        points: args.points as usize,
        order: args.model.order,
        dt: args.dt,
        steps: args.steps,
        every: args.every,
        temperature: args.temperature,
        seed: args.seed,
        initial,
        forcing,
    };
    let mut file;
    let sink: &mut dyn Write = match &args.out {
        Some(path) => {
            file =
                std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| {
                    CliError::new(1, format!("cannot create {}: {e}", path.display()))
                })?);
            &mut file
        }
        None => out,
    };
    let ids: Vec<&str> = model.fields.iter().map(|f| f.id.as_str()).collect();
    let mut first = true;
    let result = simulate(&model, &params, &config, |s| {
        if first {
            writeln!(sink, "{}", csv_header(&ids, s)).map_err(|e| e.to_string())?;
            first = false;
        }
        writeln!(sink, "{}", csv_row(s)).map_err(|e| e.to_string())
    });
    match result {
        Ok(()) => sink
            .flush()
            .map_err(|e| CliError::new(1, format!("cannot write: {e}"))),
        // A closed pipe (`| head`) ends the run quietly.
        Err(crate::dynamics::DynamicsError::Invalid(m)) if m.contains("Broken pipe") => Ok(()),
        Err(e) => Err(CliError::new(2, e.to_string())),
    }
}

fn modes_command(args: &ModesArgs) -> Result<String, CliError> {
    let model = load_model(&args.model.model)?;
    let params = load_params(&args.params, &model)?;
    let points = args.points as usize;
    let limit = args.limit.map(|k| k as usize);
    if args.shapes && points.saturating_mul(limit.unwrap_or(points)) > MAX_SHAPE_VALUES {
        return Err(CliError::new(
            2,
            format!("--shapes at {points} points would print more than {MAX_SHAPE_VALUES} numbers; add --modes K"),
        ));
    }
    let modes = field_modes(
        &model,
        args.model.order,
        points,
        &params,
        limit,
        args.shapes,
    )
    .map_err(|e| CliError::new(2, e.to_string()))?;
    Ok(match args.format {
        ModesFormat::Text => report::modes_text(&model, points, &modes),
        ModesFormat::Json => {
            serde_json::to_string_pretty(&report::modes_json(points, &modes)).unwrap_or_default()
                + "\n"
        }
        ModesFormat::Csv => report::modes_csv(&modes, args.shapes),
    })
}

/// Parse `args` (program name first), run, and write the output to `out`.
pub fn run<I, T>(args: I, out: &mut dyn Write) -> Result<(), CliError>
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
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => write_out(out, &rendered),
                _ => {
                    // Clap's message runs up to the first blank line; keep it, on one line.
                    let head: Vec<&str> = rendered
                        .lines()
                        .take_while(|l| !l.trim().is_empty())
                        .map(str::trim)
                        .collect();
                    let joined = head.join(" ");
                    let msg = joined.strip_prefix("error: ").unwrap_or(&joined);
                    Err(CliError::new(2, format!("{msg} (see --help)")))
                }
            };
        }
    };
    let text = match &cli.command {
        None => table(&cli.table),
        Some(Command::Table(args)) => table(args),
        Some(Command::Equations {
            model,
            basis,
            format,
        }) => equations_command(model, *basis, *format),
        Some(Command::Operators {
            points,
            model,
            format,
        }) => operators_command(model, *points as usize, *format),
        Some(Command::Modes(args)) => modes_command(args),
        Some(Command::Simulate(args)) => return simulate_command(args, out),
        Some(Command::Parts { model, density }) => {
            let loaded = load_model(&model.model)?;
            let mut text = String::new();
            for &d in densities_of(*density) {
                let fields = crate::parts::reduce_model(&loaded, d, model.order)
                    .map_err(|e| CliError::new(2, e.to_string()))?;
                text += &crate::parts::text(&loaded, d, model.order, &fields);
                text.push('\n');
            }
            Ok(text)
        }
        Some(Command::Interactions { model, density }) => {
            let loaded = load_model(&model.model)?;
            let mut text = String::new();
            for &d in densities_of(*density) {
                let i = crate::interaction::interactions(&loaded, d, model.order)
                    .map_err(|e| CliError::new(2, e.to_string()))?;
                text += &i.text(&loaded);
                text.push('\n');
            }
            Ok(text)
        }
        Some(Command::Asymmetry {
            coupling,
            amplitude,
            omega,
            format,
        }) => {
            let a = crate::behaviour::asymmetry(*coupling, *amplitude, *omega)
                .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                BehaveFormat::Json => serde_json::to_string_pretty(&a).unwrap_or_default() + "\n",
                BehaveFormat::Csv => csv(
                    &["forward", "backward", "ratio", "simulated_forward", "simulated_backward"],
                    [vec![a.forward, a.backward, a.ratio, a.simulated_forward, a.simulated_backward]],
                ),
                BehaveFormat::Text => format!(
                    "ω_s² + cA²ω_s − ω² = 0 with c = {coupling}, A = {amplitude}, ω = {omega}\n  forward  ω₊ = {:.12}  (simulated {:.12})\n  backward ω₋ = {:.12}  (simulated {:.12})\n  |ω₋/ω₊| = {:.12}\n",
                    a.forward, a.simulated_forward, a.backward, a.simulated_backward, a.ratio
                ),
            })
        }
        Some(Command::Mathieu {
            lambda,
            ratio_min,
            ratio_max,
            epsilon_max,
            columns,
            rows,
            format,
        }) => {
            let chart = crate::behaviour::stability_chart(
                *lambda,
                (*ratio_min, *ratio_max),
                *epsilon_max,
                (*columns, *rows),
            )
            .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                ModesFormat::Json => serde_json::to_string(&chart).unwrap_or_default() + "\n",
                ModesFormat::Csv => {
                    let mut t = String::from("frequency_ratio,epsilon,trace,multiplier,stable\n");
                    for p in &chart {
                        t += &format!(
                            "{},{},{},{},{}\n",
                            p.frequency_ratio, p.epsilon, p.trace, p.multiplier, p.stable
                        );
                    }
                    t
                }
                ModesFormat::Text => {
                    let mut t = format!("Mathieu stability chart, λ = {lambda}: '#' unstable (|tr M| > 2), '.' stable; ε up, ω/λ across\n");
                    for row in chart.chunks(*columns).rev() {
                        let cells: String = row
                            .iter()
                            .map(|p| if p.stable { '.' } else { '#' })
                            .collect();
                        t += &format!("ε = {:<6.3} {cells}\n", row[0].epsilon);
                    }
                    t += &format!("           ω/λ from {ratio_min} to {ratio_max}; the first tongue is at ω/λ = 2\n");
                    t
                }
            })
        }
        Some(Command::Fit {
            input,
            kind,
            field,
            points,
            window,
            estimator,
            fit_modes,
            omega,
            ring,
            figures,
            series,
            model,
            format,
        }) => {
            use crate::fit::{Estimator, FitSettings, InputKind};
            let model = load_model(model)?;
            let mut settings = FitSettings::new(match kind {
                FitKind::Midline => InputKind::Midline,
                FitKind::Lengths => InputKind::Lengths,
            });
            if let Some(f) = field {
                settings.field = f.clone();
            }
            settings.points = *points;
            settings.window = *window;
            settings.estimator = match estimator {
                FitEstimator::Peak => Estimator::Peak,
                FitEstimator::Centroid => Estimator::Centroid,
            };
            settings.fit_modes = *fit_modes;
            settings.omega = *omega;
            if ring.is_some() && *kind != FitKind::Lengths {
                return Err(CliError::new(2, "--ring applies to --kind lengths only"));
            }
            settings.ring = *ring;
            let report = fit_command(input, series.as_deref(), &model, &settings)?;
            if let Some(dir) = figures {
                crate::figures::write_fit(dir, &report).map_err(|e| CliError::new(1, e.0))?;
            }
            Ok(fit_text(&report, *format))
        }
        Some(Command::Figures {
            out: dir,
            only,
            points,
            samples,
            seed,
            params,
        }) => {
            let (model, params) = larva_run(params, *points)?;
            let settings = crate::figures::FigureSettings {
                points: *points,
                seed: *seed,
                samples: *samples,
            };
            let written = figures_command(dir, only.as_deref(), &model, &params, &settings)?;
            let mut t = String::new();
            for p in written {
                t += &format!("wrote {}\n", p.display());
            }
            Ok(t)
        }
        Some(Command::Stats {
            what:
                StatsCommand::Pair {
                    omega,
                    beta,
                    momentum,
                    samples,
                    seed,
                    format,
                },
        }) => {
            let stats = crate::behaviour::pair_statistics(*omega, *beta, *momentum)
                .map_err(|e| CliError::new(2, e.to_string()))?;
            let sampled = samples
                .map(|k| crate::behaviour::sample_pair(*omega, *beta, *momentum, k, *seed))
                .transpose()
                .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                BehaveFormat::Csv => match &sampled {
                    Some(s) => csv(
                        &["amplitude", "phase", "momentum_a"],
                        (0..s.amplitude.len())
                            .map(|i| vec![s.amplitude[i], s.phase[i], s.momentum[i]]),
                    ),
                    None => csv(
                        &[
                            "partition_function",
                            "free_energy",
                            "amplitude_at_minimum",
                            "mean_amplitude",
                        ],
                        [vec![
                            stats.partition_function,
                            stats.free_energy,
                            stats.amplitude_at_minimum,
                            stats.mean_amplitude,
                        ]],
                    ),
                },
                BehaveFormat::Json => {
                    let mut v = serde_json::to_value(stats).unwrap_or_default();
                    if let Some(s) = &sampled {
                        v["samples"] = serde_json::to_value(s).unwrap_or_default();
                    }
                    serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
                }
                _ => {
                    let mut t = format!(
                        "Degenerate pair, ω = {omega}, β = {beta}, M = {momentum}\n  Z = 2π²/(βω)·e^(−β|M|ω) = {:.12} (quadrature {:.12})\n  F = −ln Z/β = {:.12}, ∂F/∂M = {} (kink at M = 0: ∓ω)\n  A* = √(|M|/ω) = {:.12}, ⟨A⟩ = {:.12}\n",
                        stats.partition_function, stats.partition_function_quadrature, stats.free_energy,
                        stats.free_energy_slope, stats.amplitude_at_minimum, stats.mean_amplitude
                    );
                    if let Some(s) = &sampled {
                        t += &format!(
                            "  Metropolis ({} samples, seed {seed}): ⟨A⟩ = {:.6}, acceptance {:.3}, effective sample size {:.0}\n",
                            s.amplitude.len(), s.mean_amplitude, s.acceptance_rate, s.effective_sample_size
                        );
                    }
                    t
                }
            })
        }
        Some(Command::Stats {
            what:
                StatsCommand::Equipartition {
                    field,
                    points,
                    steps,
                    temperature,
                    seed,
                    params,
                    format,
                },
        }) => {
            let (model, params) = larva_run(params, *points)?;
            let c = crate::behaviour::equipartition_from_dynamics(
                &model,
                &params,
                field,
                *points,
                *steps,
                *temperature,
                *seed,
            )
            .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                BehaveFormat::Json => serde_json::to_string_pretty(&c).unwrap_or_default() + "\n",
                BehaveFormat::Csv => csv(
                    &[
                        "k",
                        "pca_variance_share",
                        "theory_variance_share",
                        "overlap",
                    ],
                    (0..c.overlap.len()).map(|k| {
                        vec![
                            (k + 1) as f64,
                            c.pca_variance_share[k],
                            c.theory_variance_share[k],
                            c.overlap[k],
                        ]
                    }),
                ),
                BehaveFormat::Text => {
                    let mut t = format!(
                        "PCA of {} simulated postures of {} (N = {points}, kT = {temperature}) beside its non-zero modes\n   k   PCA share   equipartition   |cos(PC, mode)|\n",
                        c.frames, c.field
                    );
                    for k in 0..c.overlap.len() {
                        t += &format!(
                            "  {:>2}   {:>8.4} %   {:>10.4} %   {:>10.5}\n",
                            k + 1,
                            100.0 * c.pca_variance_share[k],
                            100.0 * c.theory_variance_share[k],
                            c.overlap[k]
                        );
                    }
                    t
                }
            })
        }
        Some(Command::Behave {
            kind,
            force,
            duration,
            momentum,
            points,
            periods,
            tolerance,
            mode_damping,
            theta0,
            attachment,
            sweep,
            params: param_args,
            format,
        }) => {
            let (model, params) = larva_run(param_args, *points)?;
            let pair = match kind {
                BehaveKind::Peristalsis => crate::behaviour::PairKind::Peristalsis,
                BehaveKind::Rolling => crate::behaviour::PairKind::Rolling,
                BehaveKind::Rearing | BehaveKind::Hunching => {
                    let field = if *kind == BehaveKind::Rearing {
                        "z"
                    } else {
                        "x"
                    };
                    let r = crate::behaviour::step_response(
                        &model, &params, *points, field, *force, *duration,
                    )
                    .map_err(|e| CliError::new(2, e.to_string()))?;
                    return write_out(out, &step_text(*kind, field, *force, &r, *format));
                }
                BehaveKind::SelfRighting => {
                    let explicit = param_args
                        .params
                        .iter()
                        .any(|p| p.trim().starts_with("zeta_t"))
                        || param_args.params_file.is_some();
                    let settings = crate::behaviour::RightingSettings {
                        points: *points,
                        theta0: *theta0,
                        tolerance: *tolerance,
                        mode_damping: mode_damping.or(if explicit { None } else { Some(1.0) }),
                        attachment: match attachment {
                            AttachmentKind::Seed => crate::behaviour::Attachment::Seed,
                            AttachmentKind::Pinned => crate::behaviour::Attachment::Pinned,
                        },
                        ..Default::default()
                    };
                    let text = righting_text(&model, &params, &settings, sweep, *format)?;
                    return write_out(out, &text);
                }
            };
            let o =
                crate::behaviour::pair_orbit(&model, &params, *points, pair, *momentum, *periods)
                    .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                BehaveFormat::Json => serde_json::to_string_pretty(&o).unwrap_or_default() + "\n",
                BehaveFormat::Csv => csv(
                    &["t", "q_a", "q_b"],
                    o.trajectory.iter().map(|&(t, a, b)| vec![t, a, b]),
                ),
                BehaveFormat::Text => {
                    let what = match pair {
                        crate::behaviour::PairKind::Peristalsis => format!(
                            "the compression wave travels {:.9} body lengths per unit time",
                            o.body_rate
                        ),
                        crate::behaviour::PairKind::Rolling => format!(
                            "the C-bend at the head turns at {:.9} rad per unit time",
                            o.body_rate
                        ),
                    };
                    format!(
                        "{:?} on N = {points}: pair frequency ω = {:.9}, M = {momentum}\n  minimum-energy orbit A* = √(|M|/ω) = {:.9}\n  phase advances at {:.9} (ω·sign M); M conserved to {:.1e} relative over {periods} periods\n  {what}\n",
                        kind, o.omega, o.amplitude, o.angular_velocity, o.momentum_drift
                    )
                }
            })
        }
        Some(Command::Stats {
            what:
                StatsCommand::Explore {
                    beta,
                    samples,
                    seed,
                    points,
                    params,
                    format,
                },
        }) => {
            let (model, params) = larva_run(params, *points)?;
            let e = crate::behaviour::explore(&model, &params, *points, *beta, *samples, *seed)
                .map_err(|e| CliError::new(2, e.to_string()))?;
            Ok(match format {
                ModesFormat::Json => serde_json::to_string_pretty(&e).unwrap_or_default() + "\n",
                ModesFormat::Csv => {
                    std::iter::once("bend".to_string())
                        .chain(e.bend.iter().map(|b| b.to_string()))
                        .collect::<Vec<_>>()
                        .join("\n")
                        + "\n"
                }
                ModesFormat::Text => {
                    let mut t = format!(
                        "Unbiased exploration, β = {beta}, N = {points}, {samples} postures\n  3-point bend: sd {:.6} rad (small-amplitude prediction {:.6})\n  β refitted from the modal variances: {:.6}\n  histogram of the bend angle:\n",
                        e.bend_sd, e.bend_sd_linear, e.fitted_beta
                    );
                    let lim = 4.0 * e.bend_sd;
                    let bins = 21usize;
                    let mut counts = vec![0usize; bins];
                    for b in &e.bend {
                        let k = ((b + lim) / (2.0 * lim) * bins as f64).floor();
                        if k >= 0.0 && (k as usize) < bins {
                            counts[k as usize] += 1;
                        }
                    }
                    let top = counts.iter().copied().max().unwrap_or(1).max(1);
                    for (k, c) in counts.iter().enumerate() {
                        let centre = -lim + (k as f64 + 0.5) * 2.0 * lim / bins as f64;
                        t += &format!("  {centre:>+9.4}  {}\n", "█".repeat(c * 50 / top));
                    }
                    t
                }
            })
        }
        Some(Command::Count {
            basis,
            max_order,
            model,
        }) => {
            let model = load_model(model)?;
            let name = match basis {
                Basis::Powers => "powers",
                Basis::Monomials => "monomials",
            };
            let mut text = format!(
                "order  lagrangian  rayleigh   ({name} basis, model {})\n",
                model.name
            );
            for order in 1..=*max_order {
                let count = |d: Density| {
                    crate::enumerate::candidates(
                        *basis,
                        &crate::enumerate::Bounds::for_order(model.density(d).bound, order),
                    )
                    .len()
                };
                text += &format!(
                    "{order:>5}  {:>10}  {:>8}\n",
                    count(Density::Lagrangian),
                    count(Density::Rayleigh)
                );
            }
            Ok(text)
        }
        Some(Command::Rules) => Ok(codegen::rules_markdown()),
        Some(Command::Emit { out: dir, model }) => {
            let loaded = load_model(&model.model)?;
            let written =
                codegen::emit(dir, &loaded, model.order).map_err(|e| CliError::new(1, e))?;
            Ok(written
                .iter()
                .map(|p| format!("wrote {}\n", p.display()))
                .collect())
        }
    }?;
    write_out(out, &text)
}

/// Write `text`; a closed pipe (`| head`) is not an error.
fn write_out(out: &mut dyn Write, text: &str) -> Result<(), CliError> {
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(CliError::new(1, format!("cannot write output: {e}")))
        }
        _ => Ok(()),
    }
}
