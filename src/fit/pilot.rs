//! A long file's window foretold by its first frames. Without `--window` a pass keeps the
//! Welch sums at every window of the ladder, for every mode, so that the fit can choose once
//! the lowest mode's frequency is known; only the chosen window is fitted. A pilot reads the
//! first [`PILOT_FRAMES`] frames of a file at least [`WORTH`] times as long (on a thread beside
//! the pass, whose workers parse meanwhile), makes the same choice on them
//! ([`likely_windows`]), and the pass keeps every mode only there (and at a neighbour the
//! choice could still move to), the longest window only the lead modes whose frequency
//! chooses, the other windows none (their segments are counted). Every number is the same as
//! without the pilot: when the whole recording chooses a window the pass kept partially
//! ([`super::FitError::Pruned`]), the file is read again with the whole ladder.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use super::accumulate::{accumulate, Context, Forecast, PassLadder, ProjectorCache, Projectors};
use super::welch::{Ladder, LADDER};
use super::window::{likely_windows, lowest_frequency};
use super::FitSettings;
use crate::modal::Params;
use crate::model::Model;
use crate::recording::{sniff, FrameReader};
use crate::recording::{InputFormat, MAX_LINE_BYTES};

/// Frames the pilot reads: 4 segments of the ladder's longest window (at half overlap), which
/// is the one the choice measures the lowest mode's frequency at.
pub(super) const PILOT_FRAMES: usize = 5 << (*LADDER.end() - 1);

/// The most text the pilot reads (frames of thousands of points, lines up to
/// [`MAX_LINE_BYTES`]): past it, no pilot.
const MAX_PILOT_BYTES: usize = 64 << 20;

/// How many times the pilot's text a file must hold for the pilot to pay: below, the pass keeps
/// the whole ladder.
const WORTH: u64 = 8;

/// The ladder a pass over the file at `path` keeps, pruned when a pilot over its first frames
/// foretells the window; `None` keeps the whole ladder.
pub(super) fn ladder(path: &Path, ctx: &Context<'_>) -> Option<Ladder> {
    windows(path, ctx).map(|full| ctx.ladder().pruned(&full))
}

/// `pass` run with the ladder a pilot over the file at `path` foretells, the pilot on a thread
/// of its own while the pass's workers start to parse (its rows wait on the forecast); the
/// whole ladder when none is foretold (a short file, a layout the pilot cannot read).
pub(super) fn beside<T>(
    path: &Path,
    ctx: &Context<'_>,
    whole: &Ladder,
    pass: impl FnOnce(&Context<'_>) -> T,
) -> T {
    let foretold = Forecast::default();
    let piloted = Context {
        ladder: PassLadder::Foretold(&foretold),
        ..*ctx
    };
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let _whole = Fallback(&foretold, whole);
            if let Some(ladder) = ladder(path, ctx) {
                foretold.set(ladder);
            }
        });
        pass(&piloted)
    })
}

/// Sets its forecast to its ladder when dropped (a forecast already made stays): a pass waiting
/// on a pilot never waits forever.
struct Fallback<'a>(&'a Forecast, &'a Ladder);

impl Drop for Fallback<'_> {
    fn drop(&mut self) {
        self.0.set(self.1.clone());
    }
}

/// The windows at which `fit` of the file at `path` alone keeps every mode's Welch sums, as
/// a pilot over its first frames foretells them; `None` when it keeps every window (a short
/// file, a window given, a track column, a layout the pilot cannot read: the pass then says
/// what is wrong). Whatever the forecast, the fit's numbers are the whole ladder's.
pub fn foretold_windows(
    path: &Path,
    model: &Model,
    params: &Params,
    settings: &FitSettings,
) -> Option<Vec<usize>> {
    let made = ProjectorCache::default();
    let ctx = Context {
        model,
        params,
        settings,
        ladder: PassLadder::Known(Ladder::new(settings.window)),
        alone: true,
        noise: true,
        made: &made,
    };
    windows(path, &ctx)
}

/// The pilot's forecast (see [`foretold_windows`]), `ctx` holding the whole ladder.
fn windows(path: &Path, ctx: &Context<'_>) -> Option<Vec<usize>> {
    let settings = ctx.settings;
    if settings.window.is_some()
        || settings.recording.track_column
        || !matches!(
            settings.recording.format,
            InputFormat::Auto | InputFormat::Csv
        )
    {
        return None;
    }
    let file = std::fs::File::open(path).ok()?;
    let meta = file.metadata().ok()?;
    // Nothing is read from what is not a regular file of some length (a pipe's text would be
    // gone for the pass).
    let size = meta.len();
    if !meta.is_file() || size < WORTH * PILOT_FRAMES as u64 {
        return None;
    }
    let mut reader = BufReader::new(file);
    let mut head = Vec::new();
    for _ in 0..PILOT_FRAMES + 8 {
        let before = head.len();
        let read = (&mut reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut head)
            .ok()?;
        if read == 0 || head.len() - before > MAX_LINE_BYTES || head.len() > MAX_PILOT_BYTES {
            return None;
        }
        if before == 0 {
            // Room for the frames at about the first line's length, instead of doubling.
            head.reserve((read * (PILOT_FRAMES + 8) * 5 / 4).min(MAX_PILOT_BYTES));
        }
    }
    if size < WORTH * head.len() as u64 {
        return None;
    }
    let mut text: Box<dyn BufRead + Send + '_> = Box::new(head.as_slice());
    if sniff(&mut text).ok()? != InputFormat::Csv {
        return None;
    }
    // Read on this thread: for so few frames the workers save nothing (measured).
    let source = FrameReader::new(text, &settings.recording);
    let mut projs = Projectors { by_width: vec![] };
    // The choice reads the lead modes at the longest window, the others' segment counts.
    let ctx = Context {
        ladder: PassLadder::Known(ctx.ladder().pruned(&[])),
        noise: false,
        ..*ctx
    };
    let animal = accumulate(&mut { source }, String::new(), &ctx, &mut projs, &mut None).ok()?;
    let proj = projs.first()?;
    let fs = 1.0 / animal.interval?;
    let cov = animal.stats.covariance();
    let spectra = animal.stats.spectra(ctx.ladder(), fs);
    likely_windows(&spectra, |s| lowest_frequency(&proj, &cov, s, fs), fs)
}
