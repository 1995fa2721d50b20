//! One animal: its pooled moments, its blocks of frames, the units a bootstrap resamples, and
//! its own fit as a pooled report lists it.

use super::accumulate::Context;
use super::stats::Stats;
use super::summary::{summarise, Origin, Scope};
use super::timedomain::Exact;
use super::timedomain::{Series, Span};
use super::Recording;
use super::{FitError, FitReport};
use crate::recording::{Projector, Units};

/// One animal's accumulated frames.
pub(super) struct Animal {
    pub(super) name: String,
    pub(super) stats: Stats,
    /// Its consecutive blocks of frames (every run's, in order), kept for a bootstrap over time.
    pub(super) pieces: Vec<Stats>,
    pub(super) counts: Recording,
    pub(super) interval: Option<f64>,
    /// Its own fit, when the worker that read it made it (several inputs).
    pub(super) own: Option<super::AnimalFit>,
    /// Its tracked points' turning angles, for the tracking noise (midlines only).
    pub(super) jitter: Option<crate::recording::Jitter>,
    /// How far its held ends move (a body held in place).
    pub(super) movement: Option<crate::recording::Movement>,
    /// Its modal coordinates in time order (`timedomain`).
    pub(super) series: super::timedomain::Series,
}

/// The units a bootstrap draws: the animals, or the one animal's blocks of frames in time order
/// (drawn as moving blocks of consecutive ones).
pub(super) fn units(animals: &[Animal]) -> (Vec<&Stats>, &'static str) {
    let with_frames: Vec<&Animal> = animals.iter().filter(|a| a.stats.count > 0.0).collect();
    if with_frames.len() > 1 {
        (with_frames.iter().map(|a| &a.stats).collect(), "animals")
    } else {
        let blocks = with_frames
            .first()
            .map(|a| a.pieces.iter().filter(|p| p.count > 0.0).collect())
            .unwrap_or_default();
        (blocks, "blocks")
    }
}

/// The frames of its series each bootstrap unit of [`units`] covers: an animal's whole series,
/// or one block's frames.
pub(super) struct UnitFrames<'a>(Vec<Span<'a>>);

impl<'a> UnitFrames<'a> {
    /// Of `units`, drawn from the animals whose series are `series` (in the same order);
    /// none when they cannot be matched (a series not kept).
    pub(super) fn of(units: &(Vec<&Stats>, &'static str), series: &'a [Series]) -> Self {
        let spans = match (units.1, series) {
            ("animals", _) if units.0.len() == series.len() => {
                series.iter().map(Series::whole).collect()
            }
            ("blocks", [one]) => {
                let counts: Vec<usize> = units.0.iter().map(|u| u.count as usize).collect();
                (one.blocks(&counts).unwrap_or_default().into_iter())
                    .map(|frames| Span {
                        series: one,
                        frames,
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        UnitFrames(spans)
    }

    /// Each unit's span.
    pub(super) fn spans(&self) -> &[Span<'a>] {
        &self.0
    }
}

/// One animal's own fit, in a pooled fit of several.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AnimalFit {
    /// The animal's name (file, and track id within it).
    pub recording: String,
    /// Frames used.
    pub frames: usize,
    /// Frames lost.
    pub frames_lost: usize,
    /// Its ω (`None` when it cannot be fitted alone).
    pub omega: Option<f64>,
    /// Its β.
    pub beta: Option<f64>,
    /// Its first principal component's variance share.
    pub first_share: Option<f64>,
    /// Its PCA variance shares, descending.
    pub pca_variance_share: Vec<f64>,
    /// Its components' overlaps with their modes.
    pub mode_overlap: Vec<f64>,
    /// Its continuum constant (κ or c, as the pooled one) and that one's 95 % interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuum: Option<f64>,
    /// The interval (from its modes' errors).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuum_interval: Option<[f64; 2]>,
    /// Its own tests of the theory (`spread` combines them when the animals differ).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tests: Option<super::TheoryTests>,
    /// Why it could not be fitted alone (it still counts in the pool), or why it is not in the
    /// pool (sampled at another rate than the pool's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

impl AnimalFit {
    /// The summary of `report`, the fit of animal `name` alone.
    pub fn of(name: &str, counts: &Recording, report: &super::FitReport) -> AnimalFit {
        AnimalFit {
            recording: name.to_string(),
            frames: report.frames,
            frames_lost: counts.frames_lost,
            omega: Some(report.omega),
            beta: Some(report.beta),
            first_share: report.pca_variance_share.first().copied(),
            pca_variance_share: report.pca_variance_share.clone(),
            mode_overlap: report.mode_overlap.clone(),
            continuum: report.continuum.as_ref().map(|c| c.constant),
            continuum_interval: report.continuum.as_ref().and_then(|c| c.interval),
            tests: Some(report.tests.clone()),
            note: None,
        }
    }

    pub(super) fn failed(name: &str, stats: &Stats, counts: &Recording, why: &str) -> AnimalFit {
        AnimalFit {
            frames: stats.count as usize,
            frames_lost: counts.frames_lost,
            ..AnimalFit::unfitted(name, why)
        }
    }

    /// `name`, with no fit and the reason.
    pub(super) fn unfitted(name: &str, why: &str) -> AnimalFit {
        AnimalFit {
            recording: name.to_string(),
            frames: 0,
            frames_lost: 0,
            omega: None,
            beta: None,
            first_share: None,
            pca_variance_share: Vec::new(),
            mode_overlap: Vec::new(),
            continuum: None,
            continuum_interval: None,
            tests: None,
            note: Some(why.to_string()),
        }
    }
}

/// An animal's own fit (only the constants) from its name, counts and statistics, or why it
/// has none.
pub(super) fn own_fit(
    proj: &Projector,
    ctx: &Context<'_>,
    (name, counts, stats, series): (&str, &Recording, &Stats, &Series),
    interval: f64,
) -> AnimalFit {
    let spans = [series.whole()];
    let scope = Scope::Constants(None, Exact::Spans(&spans));
    match fit_stats(proj, ctx, stats, interval, (scope, None)) {
        Ok(r) => AnimalFit::of(name, counts, &r),
        Err(e) => AnimalFit::failed(name, stats, counts, &e.to_string()),
    }
}

/// The fit of some accumulated frames sampled every `interval`; `described` is the
/// recording's counts and units when the report is the one shown (not a resample's).
pub(super) fn fit_stats(
    proj: &Projector,
    ctx: &Context<'_>,
    stats: &Stats,
    interval: f64,
    (scope, described): (Scope<'_>, Option<(Recording, Units)>),
) -> Result<FitReport, FitError> {
    if stats.count < 8.0 {
        return Err(FitError::TooShort(format!(
            "{} usable frames; at least 8 are needed for variances and spectra",
            stats.count
        )));
    }
    let spectra = stats.spectra(ctx.ladder(), 1.0 / interval);
    if spectra.is_empty() {
        return Err(FitError::TooShort(format!(
            "no run of 8 frames between gaps for the spectra (longest {}); bridge short gaps with --fill-gaps K",
            stats.short.len()
        )));
    }
    let (recording, units) = described.unwrap_or_default();
    let origin = Origin {
        frames: stats.count as usize,
        spacing: stats.spacing / stats.count,
        recording,
        units,
    };
    summarise(
        proj,
        ctx.settings,
        stats.covariance(),
        interval,
        spectra,
        (scope, origin),
    )
}
