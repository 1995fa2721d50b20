//! Bridging (`--fill-gaps K`): lost frames in gaps of up to K frames drawn as straight lines
//! between the usable frames around them. The share it synthesised is s = (frames bridged) /
//! (frames used); the recording line says it whenever bridging ran, and above
//! [`BRIDGED_SHARE`] it is a warning, since the spectra then lean on straight lines.
//!
//! A larger K joins runs: with the runs r₀, g₁, r₁, g₂, … (run and gap lengths, in frames, in
//! time order) bridging every gap gᵢ ≤ K gives runs of Σ(rᵢ + gᵢ) over each stretch of bridged
//! gaps. [`smallest`] scans K upward over the gap lengths present for the first that makes a
//! run as long as asked.

use super::report::{FitReport, Recording};
use super::timedomain::Series;
use crate::report::fixed;

/// Above this share of synthesised frames, bridging is a warning: the spectra lean on it.
const BRIDGED_SHARE: f64 = 0.05;

/// The share of the frames used that bridging synthesised.
fn share(rec: &Recording, frames: usize) -> f64 {
    rec.frames_filled as f64 / frames.max(1) as f64
}

/// The recording line's words on bridging: how many frames, their share when any, the K used.
pub(super) fn clause(rec: &Recording, frames: usize) -> String {
    let of = match rec.frames_filled {
        0 => String::new(),
        _ => format!(
            ", {} % of the frames used",
            fixed(100.0 * share(rec, frames), 1)
        ),
    };
    format!(
        "{} bridged{of}: gaps of ≤ {} frames, --fill-gaps",
        rec.frames_filled, rec.fill_gaps
    )
}

/// The warning that more than [`BRIDGED_SHARE`] of the frames used were bridged, with the share.
pub(super) fn warning(report: &FitReport) -> Option<String> {
    let (r, s) = (&report.recording, share(&report.recording, report.frames));
    (s > BRIDGED_SHARE).then(|| {
        format!(
            "{} of the {} frames used ({} %) were synthesised by bridging gaps of up to {} frames (--fill-gaps): the spectra lean on straight lines; --fill-gaps 0 fits the runs alone",
            r.frames_filled,
            report.frames,
            fixed(100.0 * s, 1),
            r.fill_gaps
        )
    })
}

/// What bridging more would give: the least K, the longest run it makes, and the share of the
/// frames used it would synthesise in all (the frames already bridged included).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Bridge {
    pub(super) fill_gaps: usize,
    pub(super) longest: usize,
    pub(super) share: f64,
}

/// Each animal's runs and gaps in time order, from its series (none when it keeps none).
fn pieces(series: &[Series]) -> Vec<Vec<(bool, usize)>> {
    (series.iter())
        .filter_map(|s| {
            let c = s.whole().coordinate(0)?.to_vec();
            let mut out: Vec<(bool, usize)> = Vec::new();
            for v in c {
                match out.last_mut() {
                    Some((lost, n)) if *lost == v.is_nan() => *n += 1,
                    _ => out.push((v.is_nan(), 1)),
                }
            }
            Some(out)
        })
        .collect()
}

/// The least K beyond the recording's that makes a run of at least `run` frames, or `None`
/// when no K does (or the series were not kept).
pub(super) fn smallest(
    series: &[Series],
    rec: &Recording,
    frames: usize,
    run: usize,
) -> Option<Bridge> {
    let animals = pieces(series);
    let mut ks: Vec<usize> = (animals.iter().flatten())
        .filter(|(lost, _)| *lost)
        .map(|&(_, n)| n)
        .collect();
    ks.sort_unstable();
    ks.dedup();
    ks.into_iter().filter(|&k| k > rec.fill_gaps).find_map(|k| {
        let (mut longest, mut filled) = (0, 0);
        for animal in &animals {
            let mut now = 0;
            for &(lost, n) in animal {
                if !lost || n <= k {
                    now += n;
                    filled += if lost { n } else { 0 };
                } else {
                    now = 0;
                }
                longest = longest.max(now);
            }
        }
        let used = frames + filled;
        (longest >= run).then(|| Bridge {
            fill_gaps: k,
            longest,
            share: (rec.frames_filled + filled) as f64 / used.max(1) as f64,
        })
    })
}
