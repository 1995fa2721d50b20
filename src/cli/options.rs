//! Option groups shared by several commands (flattened into their arguments): the model and
//! order, the scales and coefficients, a body on N points, the draws of a sampled result, a
//! degenerate pair's frequency, the densities of the tables, and `fit`'s figure page.

use std::path::PathBuf;

use clap::Args;

use super::{base_params, check_list, load_model, points_parser, CliError};
use crate::body::Body;
use crate::enumerate::MAX_ORDER;
use crate::figures::{Format, Page};
use crate::model::{Density, Model};
use crate::theory::Theory;

/// Which model, at which order.
#[derive(Debug, Args)]
pub(super) struct ModelArgs {
    /// Order of the expansion: candidates have δ ≤ N and ε ≤ N, and τ+σ ≤ N (Lagrangian) or
    /// τ ≤ N and σ ≤ N (Rayleigh). From 1 to 32.
    #[arg(long, short, default_value_t = crate::model::DEFAULT_ORDER, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=MAX_ORDER as i64))]
    pub(super) order: u32,
    /// A model file (TOML) instead of the embedded larva model.
    #[arg(long, value_name = "FILE")]
    pub(super) model: Option<PathBuf>,
    /// Keep K orders beyond the leading one in both densities (1: the next-to-leading order):
    /// the first 1 + K layers of the admitted terms, each the lowest order of what the layers
    /// before it left. Default: the model's own `beyond_leading` (0 for the larva).
    #[arg(long, value_name = "K",
          value_parser = clap::value_parser!(u32).range(0..=crate::model::MAX_BEYOND_LEADING as i64))]
    pub(super) beyond_leading: Option<u32>,
}

impl ModelArgs {
    pub(super) fn load(&self) -> Result<Model, CliError> {
        let mut model = load_model(&self.model)?;
        if let Some(k) = self.beyond_leading {
            model.set_beyond_leading(k);
        }
        Ok(model)
    }
}

/// Scales of the frequencies and damping.
#[derive(Debug, Args)]
pub(super) struct ParamArgs {
    /// Set a scale, e.g. `--param omega_b=2.5 --param zeta_s=0.3` (defaults: ω = 1, ζ = 0.1).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub(super) params: Vec<String>,
    /// Read scales from a TOML file of `omega_s = 1.0` lines (before any --param).
    #[arg(long = "params", value_name = "FILE")]
    pub(super) params_file: Option<PathBuf>,
}

impl ParamArgs {
    /// The body these coefficients and scales set, of the model `model` names.
    pub(super) fn body(&self, model: &ModelArgs) -> Result<Body, CliError> {
        check_list("--param", self.params.len())?;
        let base = base_params(self)?;
        let assignments = self
            .params
            .iter()
            .map(|p| crate::body::assignment(p))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Body::new(
            model.load()?,
            model.order,
            None,
            base,
            &assignments,
        )?)
    }

    /// Whether any coefficient or scale is given.
    pub(super) fn any(&self) -> bool {
        !self.params.is_empty() || self.params_file.is_some()
    }
}

/// A body to run behaviours on: model, order, points and scales, turned into one [`Theory`].
#[derive(Debug, Args)]
pub(super) struct BodyArgs {
    #[command(flatten)]
    pub(super) model: ModelArgs,
    /// Points along the body, from the least the model's operators take (3 for the larva; the
    /// error names it) to 2000.
    #[arg(long, short, default_value_t = 12, value_name = "N",
          value_parser = points_parser(1..=crate::dynamics::MAX_SIM_POINTS as u64))]
    pub(super) points: usize,
    #[command(flatten)]
    pub(super) params: ParamArgs,
}

impl BodyArgs {
    /// The theory of this body (every field's modes, once) for `what`.
    pub(super) fn theory(&self, what: &'static str) -> Result<Theory, CliError> {
        Ok(self.params.body(&self.model)?.theory(self.points, what)?)
    }
}

/// Draws of a sampled result: how many, and the seed (same seed, same draws).
#[derive(Debug, Args)]
pub(super) struct SampleArgs {
    /// Samples to draw.
    #[arg(long, default_value_t = 100_000)]
    pub(super) samples: usize,
    /// Seed of the sampler.
    #[arg(long, default_value_t = 1)]
    pub(super) seed: u64,
}

/// The frequency ω of a degenerate pair: given, or the first axial pair of a named body.
#[derive(Debug, Args)]
pub(super) struct PairArgs {
    /// The pair's frequency ω. Default: with --model, --points, --param or --params, the
    /// frequency of that body's first axial pair; otherwise 1 (the unit of frequency).
    #[arg(long, allow_hyphen_values = true)]
    pub(super) omega: Option<f64>,
    #[command(flatten)]
    pub(super) model: ModelArgs,
    /// Points along the body whose axial pair sets ω (default 12 with --model): at least what
    /// the model's operators need (3 for the larva), up to 2000.
    #[arg(long, short, value_name = "N",
          value_parser = points_parser(1..=crate::dynamics::MAX_SIM_POINTS as u64))]
    pub(super) points: Option<usize>,
    #[command(flatten)]
    pub(super) params: ParamArgs,
}

impl PairArgs {
    /// ω for `behaviour` (which names the role it needs in errors).
    pub(super) fn omega(&self, behaviour: &'static str) -> Result<f64, CliError> {
        let scales_given = self.params.any();
        if let Some(w) = self.omega {
            return Ok(crate::behaviour::given_pair_frequency(w, scales_given)?);
        }
        if self.model.model.is_none() && self.points.is_none() && !scales_given {
            return Ok(1.0);
        }
        let theory = self
            .params
            .body(&self.model)?
            .theory(self.points.unwrap_or(12), behaviour)?;
        Ok(crate::behaviour::pair_frequency(&theory, behaviour)?)
    }
}

/// Which densities to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DensityChoice {
    /// The Lagrangian density only.
    Lagrangian,
    /// The Rayleigh density only.
    Rayleigh,
    /// Both, Lagrangian first.
    Both,
}

impl DensityChoice {
    /// The densities chosen.
    pub fn densities(self) -> &'static [Density] {
        match self {
            DensityChoice::Lagrangian => &[Density::Lagrangian],
            DensityChoice::Rayleigh => &[Density::Rayleigh],
            DensityChoice::Both => &Density::ALL,
        }
    }
}

/// `fit`'s figure options: the format and printed width of `--figures DIR`.
#[derive(Debug, clap::Args)]
pub struct FitPageArgs {
    /// File format of the `--figures` files.
    #[arg(long, value_enum, default_value_t = Format::Svg, requires = "figures")]
    pub(super) figure_format: Format,
    /// Printed width of the `--figures` files in millimetres (60 to 600).
    #[arg(long, value_name = "MM", default_value_t = 180.0, requires = "figures")]
    pub(super) figure_width: f64,
    /// Resolution of PNG `--figures`, dots per inch (30 to 1200).
    #[arg(
        long,
        value_name = "DPI",
        default_value_t = 300.0,
        requires = "figures"
    )]
    pub(super) figure_dpi: f64,
}

impl FitPageArgs {
    /// The page, checked.
    pub fn page(&self) -> Result<Page, CliError> {
        let page = Page {
            format: self.figure_format,
            width_mm: self.figure_width,
            dpi: self.figure_dpi,
        };
        page.check().map_err(super::figures::usage)?;
        Ok(page)
    }
}
