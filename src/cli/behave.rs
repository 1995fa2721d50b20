//! `theory-search behave`: the behaviour models on a body.

use std::io::Write;

use super::{emit, BodyArgs, CliError};
use crate::behaviour::{
    pair_orbit, righting_sweep, role_fields, self_righting, step_response, Attachment, PairKind,
    RightingReport, RightingSettings,
};
use crate::report::Output;

/// Arguments of `behave`: one subcommand per behaviour, each with its own options.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    kind: Behaviour,
}

/// The behaviours, with the field roles each needs ([`crate::behaviour::ROLE_NEEDS`]).
#[derive(Debug, clap::Subcommand)]
enum Behaviour {
    /// The first axial pair as a travelling wave (needs an axial field).
    Peristalsis(OrbitArgs),
    /// The first lateral and dorsoventral modes in quadrature (needs both).
    Rolling(OrbitArgs),
    /// A force on the first dorsoventral mode (needs a dorsoventral field).
    Rearing(StepArgs),
    /// A force on the first axial mode (needs an axial field).
    Hunching(StepArgs),
    /// Twist, attach and relax (needs a torsion field).
    SelfRighting(RightingArgs),
}

/// What every behaviour takes: the body, and how to print.
#[derive(Debug, clap::Args)]
struct Common {
    #[command(flatten)]
    body: BodyArgs,
    /// Output format (csv: the time series).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// Options of the minimum-energy orbits of a degenerate pair.
#[derive(Debug, clap::Args)]
struct OrbitArgs {
    /// Conserved momentum M (its sign sets the direction; 0 does not move, so the default is a
    /// small travelling orbit).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    momentum: f64,
    /// Periods to run.
    #[arg(allow_hyphen_values = true, long, default_value_t = 100.0)]
    periods: f64,
    #[command(flatten)]
    common: Common,
}

/// Options of a step response.
#[derive(Debug, clap::Args)]
struct StepArgs {
    /// The constant modal force.
    #[arg(long, default_value_t = 0.02, allow_hyphen_values = true)]
    force: f64,
    /// How long to follow the transient.
    #[arg(allow_hyphen_values = true, long, default_value_t = 2000.0)]
    duration: f64,
    #[command(flatten)]
    common: Common,
}

/// Options of self-righting.
#[derive(Debug, clap::Args)]
struct RightingArgs {
    /// Tolerance δ in radians for mouth-hook attachment and alignment.
    #[arg(allow_hyphen_values = true, long, default_value_t = 0.01)]
    tolerance: f64,
    /// Damping ratio ζ₁ of the first torsional mode (default 1, critical, unless the torsion
    /// field's ζ is given by --param or --params).
    #[arg(allow_hyphen_values = true, long, value_name = "ZETA")]
    mode_damping: Option<f64>,
    /// Initial orientation of the body in radians (π is upside down).
    #[arg(long, default_value_t = std::f64::consts::PI, allow_hyphen_values = true)]
    theta0: f64,
    /// Relaxation after attachment: the paper's two-degree-of-freedom model, or the whole chain
    /// with the head held.
    #[arg(long, value_enum, default_value_t = AttachmentKind::Paper)]
    attachment: AttachmentKind,
    /// Also run these first-mode damping ratios and tabulate their righting times (at most
    /// 50 values).
    #[arg(
        allow_hyphen_values = true,
        long,
        value_delimiter = ',',
        value_name = "ZETA,…"
    )]
    sweep: Vec<f64>,
    #[command(flatten)]
    common: Common,
}

/// Relaxation models of `behave self-righting`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum AttachmentKind {
    /// The paper's model (App. H); `seed` is its old name.
    #[value(alias = "seed")]
    Paper,
    /// The whole chain with the head held.
    Pinned,
}

/// Run one behaviour.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<(), CliError> {
    match &args.kind {
        Behaviour::Peristalsis(a) => orbit(a, PairKind::Peristalsis, out),
        Behaviour::Rolling(a) => orbit(a, PairKind::Rolling, out),
        Behaviour::Rearing(a) => step(a, "Rearing", "behave rearing", out),
        Behaviour::Hunching(a) => step(a, "Hunching", "behave hunching", out),
        Behaviour::SelfRighting(a) => righting(a, out),
    }
}

fn orbit(a: &OrbitArgs, kind: PairKind, out: &mut dyn Write) -> Result<(), CliError> {
    let what = match kind {
        PairKind::Peristalsis => "behave peristalsis",
        PairKind::Rolling => "behave rolling",
    };
    let theory = a.common.body.theory(what)?;
    let o = pair_orbit(&theory, kind, a.momentum, a.periods)?;
    emit(out, &o, a.common.format)
}

fn step(
    a: &StepArgs,
    name: &str,
    behaviour: &'static str,
    out: &mut dyn Write,
) -> Result<(), CliError> {
    let theory = a.common.body.theory(behaviour)?;
    let field = role_fields(&theory.model, behaviour)?[0];
    let r = step_response(&theory, name, field, a.force, a.duration)?;
    emit(out, &r, a.common.format)
}

fn righting(a: &RightingArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let theory = a.common.body.theory("behave self-righting")?;
    let settings = RightingSettings {
        theta0: a.theta0,
        tolerance: a.tolerance,
        mode_damping: RightingSettings::mode_damping_for(
            &theory,
            a.mode_damping,
            a.common.body.params.params_file.is_some(),
        )?,
        attachment: match a.attachment {
            AttachmentKind::Paper => Attachment::Paper,
            AttachmentKind::Pinned => Attachment::Pinned,
        },
        ..Default::default()
    };
    let r = RightingReport {
        righting: self_righting(&theory, &settings)?,
        sweep: righting_sweep(&theory, &settings, &a.sweep)?,
    };
    emit(out, &r, a.common.format)
}
