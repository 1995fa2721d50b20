//! Figures of the modes and the behaviour models (the paper's Figs. 2, 3, 6, 7, 8 and the
//! Mathieu chart of App. D), drawn as SVG with plotters' SVG backend and written as SVG, PNG or
//! PDF at a chosen printed width ([`Page`]).
//!
//! Text goes into the SVG as `<text>` elements (plotters' own font features stay off); PNG and
//! PDF render it with an embedded DejaVu Sans. No text is smaller than 7 pt in print. Every figure is computed here from the library, never
//! read from a file; all quantities are dimensionless (time in units of the field's 1/ω, the
//! default scales ω = 1, ζ = 0.1 unless `params` says otherwise) and each axis says so.

use std::path::{Path, PathBuf};

mod behaviour;
mod compare;
mod discover;
mod fit;
mod key;
mod modes;
mod page;
mod plot;
mod script;
mod series;

use crate::behaviour::PairKind;
use crate::theory::Theory;
use behaviour::{
    asymmetry, bend_angle, equipartition, forward_backward, free_energy, mathieu, pair,
    rearing_hunching, self_righting,
};
pub use fit::fit_figures;
use modes::{mode_shapes, spectrum};
pub use page::{Format, Page, DPI, PX_PER_MM, WIDTH_MM};

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// A setting out of range, an unknown figure, or a model that cannot make it.
    #[error("{0}")]
    Invalid(String),
    /// The figure's behaviour cannot run on this body (a missing role or structure, or a
    /// failed run).
    #[error(transparent)]
    Behaviour(#[from] crate::behaviour::BehaviourError),
    /// A file or directory could not be written.
    #[error("cannot {action} {}: {source}", .path.display())]
    Io {
        /// `create` (a directory) or `write` (a file).
        action: &'static str,
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

impl FigureError {
    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        match self {
            FigureError::Invalid(_) => crate::failure::Failure::Usage,
            FigureError::Behaviour(b) => b.failure(),
            FigureError::Io { .. } => crate::failure::Failure::Output,
        }
    }
}

pub(super) fn err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Invalid(e.to_string())
}

/// Settings shared by the figures.
#[derive(Debug, Clone)]
pub struct FigureSettings {
    /// Points along the body.
    pub points: usize,
    /// Seed of the sampled figures.
    pub seed: u64,
    /// Samples of the sampled figures (pair density, 3-point bend).
    pub samples: usize,
    /// Format and printed width (the layout follows the width).
    pub page: Page,
}

/// The most points the figures are drawn for: every behaviour is run on the body, about six
/// seconds at 500 points (five of them the fixed cost of the figures themselves), nine at 1000.
pub const MAX_FIGURE_POINTS: usize = 500;

impl FigureSettings {
    /// The points and the page, checked before any work.
    pub fn check(&self) -> Result<(), FigureError> {
        if self.points > MAX_FIGURE_POINTS {
            return Err(FigureError::Invalid(format!(
                "the figures are drawn for at most {MAX_FIGURE_POINTS} points (about six seconds), not {}",
                self.points
            )));
        }
        self.page.check()
    }
}

impl Default for FigureSettings {
    fn default() -> Self {
        FigureSettings {
            points: 12,
            seed: 1,
            samples: 100_000,
            page: Page::default(),
        }
    }
}

/// The figures, by file name, in the order they are made.
pub const FIGURES: [&str; 12] = [
    "mode_shapes.svg",
    "spectrum.svg",
    "self_righting.svg",
    "rearing_hunching.svg",
    "asymmetry.svg",
    "equipartition.svg",
    "peristalsis.svg",
    "rolling.svg",
    "free_energy.svg",
    "bend_angle.svg",
    "mathieu.svg",
    "forward_backward.svg",
];

/// Make figure `name` (one of [`FIGURES`]) as SVG text.
pub fn figure(
    name: &str,
    theory: &Theory,
    settings: &FigureSettings,
) -> Result<String, FigureError> {
    settings.page.check()?;
    let width = settings.page.canvas_width();
    match name {
        "mode_shapes.svg" => mode_shapes(theory, width),
        "spectrum.svg" => spectrum(theory, width),
        "self_righting.svg" => self_righting(theory, width),
        "rearing_hunching.svg" => rearing_hunching(theory, width),
        "asymmetry.svg" => asymmetry(width),
        "equipartition.svg" => equipartition(theory, settings),
        "peristalsis.svg" => pair(theory, PairKind::Peristalsis, settings),
        "rolling.svg" => pair(theory, PairKind::Rolling, settings),
        "free_energy.svg" => free_energy(theory, width),
        "bend_angle.svg" => bend_angle(theory, settings),
        "mathieu.svg" => mathieu(width),
        "forward_backward.svg" => forward_backward(theory, width),
        _ => Err(FigureError::Invalid(format!(
            "unknown figure {name:?} (figures: {})",
            FIGURES.join(", ")
        ))),
    }
}

/// What [`write_figures`] did: the files written, and the figures skipped because the model
/// lacks a role they need (with the reason).
#[derive(Debug, Default)]
pub struct Written {
    /// Paths written.
    pub written: Vec<PathBuf>,
    /// (figure, why) of each figure the body cannot make.
    pub skipped: Vec<(String, String)>,
}

/// The figures `only` names (any of the three extensions names the same figure, by its SVG
/// file), or all of [`FIGURES`].
pub fn figure_names(only: Option<&str>) -> Vec<String> {
    match only {
        Some(name) => {
            let stem = [".svg", ".png", ".pdf"]
                .iter()
                .find_map(|e| name.strip_suffix(e))
                .unwrap_or(name);
            vec![format!("{stem}.svg")]
        }
        None => FIGURES.iter().map(|n| n.to_string()).collect(),
    }
}

/// Write the figures `names` (from [`FIGURES`]) into `dir` (created if missing), calling
/// `progress` before each one. Unknown names are refused before anything is written. When
/// several are asked, a figure the body cannot make (a missing role, no degenerate pair, …) is
/// skipped and reported; a single one asked for is an error.
pub fn write_figures(
    dir: &Path,
    names: &[&str],
    theory: &Theory,
    settings: &FigureSettings,
    mut progress: impl FnMut(&str),
) -> Result<Written, FigureError> {
    if let Some(bad) = names.iter().find(|n| !FIGURES.contains(n)) {
        return Err(FigureError::Invalid(format!(
            "unknown figure {bad:?} (figures: {})",
            FIGURES.join(", ")
        )));
    }
    settings.page.check()?;
    create_dir(dir)?;
    let mut out = Written::default();
    for name in names {
        progress(name);
        match figure(name, theory, settings) {
            Ok(svg) => out
                .written
                .push(write_figure(dir, name, &svg, &settings.page)?),
            Err(FigureError::Behaviour(why)) if names.len() > 1 && why.is_missing_structure() => {
                // Named as the file it would have been, in the format asked for.
                out.skipped
                    .push((file_name(name, &settings.page), why.to_string()))
            }
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

fn create_dir(dir: &Path) -> Result<(), FigureError> {
    std::fs::create_dir_all(dir).map_err(|source| FigureError::Io {
        action: "create",
        path: dir.to_path_buf(),
        source,
    })
}

/// Figure `name`'s (`….svg`) file name in `page`'s format.
fn file_name(name: &str, page: &Page) -> String {
    Path::new(name)
        .with_extension(page.format.extension())
        .display()
        .to_string()
}

/// Write figure `name` (`….svg`) as `page` says: the file takes the format's extension.
fn write_figure(dir: &Path, name: &str, svg: &str, page: &Page) -> Result<PathBuf, FigureError> {
    let path = dir.join(file_name(name, page));
    let bytes = page.encode(svg)?;
    std::fs::write(&path, bytes).map_err(|source| FigureError::Io {
        action: "write",
        path: path.clone(),
        source,
    })?;
    Ok(path)
}

/// Write `discover`'s figure (`discover_spectra`) into `dir`: the report must hold its replay.
pub fn write_discover(
    dir: &Path,
    r: &crate::discover::DiscoverReport,
    page: &Page,
) -> Result<PathBuf, FigureError> {
    page.check()?;
    let replay = r
        .replay
        .as_ref()
        .ok_or_else(|| err("the report holds no replay to draw"))?;
    let svg = discover::discover_spectra(r, replay, page.canvas_width())?;
    create_dir(dir)?;
    write_figure(dir, "discover_spectra.svg", &svg, page)
}

/// Write `compare`'s figure (`compare_groups`) into `dir`, laid out and encoded as `page` says.
pub fn write_compare(
    dir: &Path,
    r: &crate::compare::CompareReport,
    page: &Page,
) -> Result<PathBuf, FigureError> {
    page.check()?;
    let svg = compare::compare_groups(r, page.canvas_width())?;
    create_dir(dir)?;
    write_figure(dir, "compare_groups.svg", &svg, page)
}

/// Write [`fit_figures`] into `dir`, laid out and encoded as `page` says.
pub fn write_fit(
    dir: &Path,
    r: &crate::fit::FitReport,
    page: &Page,
) -> Result<Vec<PathBuf>, FigureError> {
    page.check()?;
    create_dir(dir)?;
    fit_figures(r, page)?
        .iter()
        .map(|(name, svg)| write_figure(dir, name, svg, page))
        .collect()
}
