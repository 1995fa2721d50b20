//! One animal: its pooled moments, its blocks of frames, and the units a bootstrap resamples.

use super::stats::Stats;
use super::timedomain::{Series, Span};
use super::Recording;

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

/// The frames of its series each bootstrap unit of [`units`] covers (an animal's whole series,
/// or one block's frames), and the spans of a resample's draws (first unit, how many).
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
                    .map(|frames| Span { series: one, frames })
                    .collect()
            }
            _ => Vec::new(),
        };
        UnitFrames(spans)
    }

    /// The spans of `draws`; none when the units' frames are not known.
    pub(super) fn drawn(&self, draws: &[(usize, usize)]) -> Vec<Span<'a>> {
        (draws.iter())
            .filter_map(|&(start, length)| {
                let (first, last) = (self.0.get(start)?, self.0.get(start + length - 1)?);
                Some(Span {
                    series: first.series,
                    frames: first.frames.start..last.frames.end,
                })
            })
            .collect()
    }
}
