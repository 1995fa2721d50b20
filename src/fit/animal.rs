//! One animal: its pooled moments, its blocks of frames, and the units a bootstrap resamples.

use super::stats::Stats;
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
