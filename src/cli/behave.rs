//! `theory-search behave`: the behaviour models on a body.

use std::io::Write;

use super::{emit, BodyArgs, CliError};
use crate::behaviour::{
    pair_orbit, righting_sweep, role_fields, self_righting, step_response, Attachment, PairKind,
    RightingReport, RightingSettings,
};
use crate::report::Output;

/// Arguments of `behave`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Which behaviour.
    #[arg(value_enum)]
    kind: BehaveKind,
    /// The constant modal force (rearing, hunching).
    #[arg(long, default_value_t = 0.02, allow_hyphen_values = true)]
    force: f64,
    /// How long to follow the transient (rearing, hunching).
    #[arg(long, default_value_t = 2000.0)]
    duration: f64,
    /// Conserved momentum M (its sign sets the direction).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    momentum: f64,
    /// Periods to run.
    #[arg(long, default_value_t = 100.0)]
    periods: f64,
    /// Tolerance δ in radians for mouth-hook attachment and alignment (self-righting).
    #[arg(long, default_value_t = 0.01)]
    tolerance: f64,
    /// Damping ratio ζ₁ of the first torsional mode (self-righting; default 1, critical,
    /// unless the torsion field's ζ is given by --param or --params).
    #[arg(long, value_name = "ZETA")]
    mode_damping: Option<f64>,
    /// Initial orientation of the body in radians (self-righting; π is upside down).
    #[arg(long, default_value_t = std::f64::consts::PI, allow_hyphen_values = true)]
    theta0: f64,
    /// Relaxation after attachment (self-righting): the paper's two-degree-of-freedom model,
    /// or the whole chain with the head held.
    #[arg(long, value_enum, default_value_t = AttachmentKind::Paper)]
    attachment: AttachmentKind,
    /// Also run these first-mode damping ratios and tabulate their righting times.
    #[arg(long, value_delimiter = ',', value_name = "ZETA,…")]
    sweep: Vec<f64>,
    #[command(flatten)]
    body: BodyArgs,
    /// Output format (csv: the time series).
    #[arg(long, value_enum, default_value_t = Output::Text)]
    format: Output,
}

/// The behaviours of `behave`, with the field roles each needs
/// ([`crate::behaviour::ROLE_NEEDS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum BehaveKind {
    /// The first axial pair as a travelling wave (needs an axial field).
    Peristalsis,
    /// The first lateral and dorsoventral modes in quadrature (needs both).
    Rolling,
    /// A force on the first dorsoventral mode (needs a dorsoventral field).
    Rearing,
    /// A force on the first axial mode (needs an axial field).
    Hunching,
    /// Twist, attach and relax (needs a torsion field).
    SelfRighting,
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
    let theory = args.body.theory()?;
    match args.kind {
        BehaveKind::Peristalsis | BehaveKind::Rolling => {
            let kind = if args.kind == BehaveKind::Peristalsis {
                PairKind::Peristalsis
            } else {
                PairKind::Rolling
            };
            let o = pair_orbit(&theory, kind, args.momentum, args.periods)?;
            emit(out, &o, args.format)
        }
        BehaveKind::Rearing | BehaveKind::Hunching => {
            let (name, behaviour) = if args.kind == BehaveKind::Rearing {
                ("Rearing", "behave rearing")
            } else {
                ("Hunching", "behave hunching")
            };
            let field = role_fields(&theory.model, behaviour)?[0];
            let r = step_response(&theory, name, field, args.force, args.duration)?;
            emit(out, &r, args.format)
        }
        BehaveKind::SelfRighting => {
            let torsion = role_fields(&theory.model, "behave self-righting")?[0];
            let scale = theory.model.fields[torsion].scale();
            // The model's own ζ when the user gave it, critical damping of ζ₁ otherwise.
            let explicit = args.body.params.sets_zeta(&theory.params, scale);
            let settings = RightingSettings {
                theta0: args.theta0,
                tolerance: args.tolerance,
                mode_damping: args.mode_damping.or((!explicit).then_some(1.0)),
                attachment: match args.attachment {
                    AttachmentKind::Paper => Attachment::Paper,
                    AttachmentKind::Pinned => Attachment::Pinned,
                },
                ..Default::default()
            };
            let r = RightingReport {
                righting: self_righting(&theory, &settings)?,
                sweep: righting_sweep(&theory, &settings, &args.sweep)?,
            };
            emit(out, &r, args.format)
        }
    }
}
