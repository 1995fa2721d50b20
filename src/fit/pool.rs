//! Many recordings, many animals: each input (a file, a stream, tracks in memory) is read by
//! a worker thread into per-animal [`Stats`], one piece per run between gaps; the main thread
//! takes the animals in input order, fits each alone and adds it to the pool, so the pooled
//! numbers do not depend on the number of threads. Memory holds the inputs in flight (one per
//! worker) and, for the bootstrap only, every piece's statistics.
//!
//! The workers are hand-written, not rayon's: each animal is pooled once every earlier one is
//! in (a bounded channel), so reading overlaps fitting and memory holds a few animals, where a
//! rayon `collect` would hold them all first. The per-mode fits are rayon's (`window`).

use crate::recording::{Jitter, Movement};
use std::collections::BTreeMap;
use std::io::BufRead;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex};

use super::accumulate::{accumulate, Context, Each, PassLadder, ProjectorCache, Projectors};
use super::animal::{fit_stats, own_fit, UnitFrames};
use super::stats::Stats;
use super::timedomain::{Exact, OneStep, Series, Span, MAX_POOLED};
use super::welch::Ladder;
use super::{
    animal::{units, Animal},
    bootstrap,
    summary::Scope,
    AnimalFit, FitError, FitReport, FitSettings, Recording,
};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::Chunked;
use crate::recording::{
    read_tracks, sniff, whole, FrameReader, Track, TrackSource, MAX_WHOLE_FILE,
};
use crate::recording::{InputFormat, Projector, RecordingError, Units};

/// One input of a fit.
pub enum Input<'a> {
    /// A file, opened by the worker that reads it.
    File(PathBuf),
    /// A named stream (standard input, a buffer).
    Reader {
        /// Name in messages and reports.
        name: String,
        /// The text.
        reader: Box<dyn BufRead + Send + 'a>,
    },
    /// Animals already in memory (each track one animal).
    Tracks(Vec<Track>),
}

impl Input<'_> {
    fn name(&self) -> String {
        match self {
            Input::File(p) => p.display().to_string(),
            Input::Reader { name, .. } => name.clone(),
            Input::Tracks(t) => t.first().map(|t| t.name.clone()).unwrap_or_default(),
        }
    }
}

/// What a worker hands back for one input.
struct Read {
    animals: Vec<Animal>,
    units: Units,
    /// A projector of the worker's (the pool's fits need one).
    projector: Option<Projector>,
}

/// Fit several inputs, each one animal or several (track ids, WCON ids): one pooled fit and,
/// with more than one animal, each animal's own.
pub fn fit_inputs(
    inputs: Vec<Input<'_>>,
    model: &Model,
    params: &Params,
    settings: &FitSettings,
    each: Option<Each<'_>>,
) -> Result<FitReport, FitError> {
    super::settings::check_settings(settings)?;
    if inputs.is_empty() {
        return Err(FitError::Invalid("no recordings to fit".into()));
    }
    let made = ProjectorCache::default();
    let whole = Ladder::new(settings.window);
    let ctx = Context {
        model,
        params,
        settings,
        ladder: PassLadder::Known(whole.clone()),
        alone: inputs.len() == 1,
        noise: true,
        made: &made,
    };
    // A file alone: a pilot over its first frames foretells the windows (on a thread of its own,
    // while the pass's workers start to parse); the pass keeps every mode only there, and is
    // made again with the whole ladder when the recording chooses another.
    if let (None, [Input::File(path)]) = (&each, inputs.as_slice()) {
        let path = path.clone();
        let done = super::pilot::beside(&path, &ctx, &whole, |piloted| pass(inputs, piloted, None));
        return match done {
            Err(FitError::Pruned { .. }) => pass(vec![Input::File(path)], &ctx, None),
            done => done,
        };
    }
    pass(inputs, &ctx, each)
}

/// One pass over the inputs, and the fit of what it accumulated.
fn pass(
    inputs: Vec<Input<'_>>,
    ctx: &Context<'_>,
    each: Option<Each<'_>>,
) -> Result<FitReport, FitError> {
    let mut pool = Pool::default();
    match each {
        Some(each) => {
            let mut projs = Projectors { by_width: vec![] };
            for input in inputs {
                let name = input.name();
                let read = read_input(input, ctx, &mut projs, &mut Some(&mut *each));
                pool.take(ctx, read.map_err(|e| FitError::named(e, &name))?)?;
            }
        }
        None => parallel(inputs, ctx, &mut pool)?,
    }
    pool.finish(ctx)
}

/// Read the inputs on all cores, handing the reads to `pool` in input order.
fn parallel(inputs: Vec<Input<'_>>, ctx: &Context<'_>, pool: &mut Pool) -> Result<(), FitError> {
    let total = inputs.len();
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(total);
    let queue: Vec<Mutex<Option<Input<'_>>>> =
        inputs.into_iter().map(|i| Mutex::new(Some(i))).collect();
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    // At most 2 × threads reads wait for an earlier one: workers block on the channel.
    let (tx, rx) = mpsc::sync_channel::<(usize, String, Result<Read, FitError>)>(2 * threads);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let tx = tx.clone();
            let (queue, next, stop) = (&queue, &next, &stop);
            scope.spawn(move || {
                let mut projs = Projectors { by_width: vec![] };
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= total || stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let Some(input) = queue[i].lock().ok().and_then(|mut q| q.take()) else {
                        break;
                    };
                    let name = input.name();
                    let mut read = read_input(input, ctx, &mut projs, &mut None);
                    // With several inputs every animal is fitted alone: here, on all cores.
                    if let Ok(r) = &mut read {
                        if let (true, Some(proj)) = (total > 1, r.projector.as_ref()) {
                            for a in r.animals.iter_mut().filter(|a| a.stats.count > 0.0) {
                                let interval = a.interval.unwrap_or(1.0);
                                let parts = (a.name.as_str(), &a.counts, &a.stats, &a.series);
                                a.own = Some(own_fit(proj, ctx, parts, interval));
                            }
                        }
                    }
                    if tx.send((i, name, read)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        let mut waiting = BTreeMap::new();
        let mut want = 0;
        let mut outcome = Ok(());
        for (i, name, read) in rx.iter() {
            waiting.insert(i, (name, read));
            while let Some((name, read)) = waiting.remove(&want) {
                want += 1;
                if outcome.is_ok() {
                    outcome = read
                        .map_err(|e| FitError::named(e, &name))
                        .and_then(|r| pool.take(ctx, r));
                    if outcome.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
        }
        outcome
    })
}

/// Open and read one input into its animals.
fn read_input(
    input: Input<'_>,
    ctx: &Context<'_>,
    projs: &mut Projectors,
    each: &mut Option<Each<'_>>,
) -> Result<Read, FitError> {
    let settings = ctx.settings;
    // Only a DeepLabCut export takes --fps (its rows hold frame indices); the line reader
    // refuses it for a CSV, whose first column is time.
    let fps = |has: &str| match settings.recording.fps {
        Some(_) => Err(RecordingError::Fps { has: has.into() }),
        None => Ok(()),
    };
    // A file alone is parsed on every core (a stream is not: its reader could wait forever).
    let mut chunked = false;
    let (name, mut reader): (String, Box<dyn BufRead + Send + '_>) = match input {
        Input::Tracks(tracks) => {
            fps("each frame's t (tracks held in memory)")?;
            return read_tracks_of(tracks, ctx, projs, each, Units::default());
        }
        Input::Reader { name, reader } => (name, reader),
        Input::File(path) => {
            let file = std::fs::File::open(&path).map_err(RecordingError::Open)?;
            chunked = ctx.alone;
            (
                path.display().to_string(),
                Box::new(std::io::BufReader::new(file)),
            )
        }
    };
    let format = match settings.recording.format {
        InputFormat::Auto => sniff(&mut reader)?,
        forced => forced,
    };
    if format == InputFormat::Wcon {
        fps("its records' \"t\" (WCON)")?;
        let text = whole(reader)?;
        let w = crate::recording::parse_wcon(&text, &name, settings.recording.head_first)?;
        let units = Units {
            time: Some(w.time_unit),
            length: Some(w.length_unit),
        };
        return read_tracks_of(w.tracks, ctx, projs, each, units);
    }
    if format == InputFormat::Hdf5 {
        let bytes = crate::recording::whole_bytes(reader, "an HDF5 file")?;
        let tracks = crate::recording::parse_hdf5(bytes, &name, &settings.recording)?;
        let units = crate::recording::frame_units(&settings.recording);
        return read_tracks_of(tracks, ctx, projs, each, units);
    }
    if settings.recording.track_column {
        let tracks = read_tracks(
            std::io::Read::take(reader, MAX_WHOLE_FILE),
            &name,
            &settings.recording,
        )?;
        return read_tracks_of(tracks, ctx, projs, each, Units::default());
    }
    let units = crate::recording::layout_units(&mut reader, &settings.recording)?;
    let source = FrameReader::new(reader, &settings.recording);
    let animal = if chunked {
        std::thread::scope(|scope| {
            // A body held in place is observed with each animal's reference frame, which
            // the caller's projector keeps: the workers leave its rows unprojected.
            let make = Box::new(|width| ctx.projector(width).ok().filter(|p| !p.holds()));
            let mut source = Chunked::new(source, scope, &settings.recording, make);
            accumulate(&mut source, name, ctx, projs, each)
        })?
    } else {
        accumulate(&mut { source }, name, ctx, projs, each)?
    };
    Ok(Read {
        animals: vec![animal],
        units,
        projector: projs.first(),
    })
}

fn read_tracks_of(
    tracks: Vec<Track>,
    ctx: &Context<'_>,
    projs: &mut Projectors,
    each: &mut Option<Each<'_>>,
    units: Units,
) -> Result<Read, FitError> {
    let mut animals = Vec::with_capacity(tracks.len());
    for track in tracks {
        let name = track.name.clone();
        let mut source = TrackSource::new(track);
        animals.push(
            accumulate(&mut source, name.clone(), ctx, projs, each).map_err(|e| match e {
                FitError::Recording(RecordingError::Line { .. }) => FitError::In {
                    name,
                    why: Box::new(e),
                },
                other => other,
            })?,
        );
    }
    Ok(Read {
        animals,
        units,
        projector: projs.first(),
    })
}

/// The animals taken so far, in input order.
#[derive(Default)]
struct Pool {
    stats: Option<Stats>,
    /// The tracked points' angles of the animals with the first animal's K.
    jitter: Option<Jitter>,
    movement: Option<Movement>,
    counts: Recording,
    interval: Option<f64>,
    units: Option<Units>,
    projector: Option<Projector>,
    /// Each animal's own fit.
    fits: Vec<AnimalFit>,
    /// Each animal's statistics and runs (bootstrap only).
    kept: Vec<Animal>,
    /// The first animal's name, counts, statistics and interval, fitted alone only once a
    /// second arrives (alone, its own fit would be the pooled one).
    first: Option<(String, Recording, Stats, f64)>,
    /// Each pooled animal's modal coordinates in time order (`timedomain`).
    series: Vec<super::timedomain::Series>,
    /// The animals sampled at other rates, one pool per rate (`rates`).
    others: Vec<Pool>,
}

impl Pool {
    /// Add one input's animals.
    fn take(&mut self, ctx: &Context<'_>, read: Read) -> Result<(), FitError> {
        match (&self.units, read.units.time.is_some()) {
            (Some(u), true) if *u != read.units => {
                return Err(FitError::Invalid(format!(
                    "{}: its units ({}) differ from the first file's ({}): fit recordings of one unit together",
                    read.animals.first().map_or("", |a| a.name.as_str()),
                    read.units,
                    u
                )))
            }
            (None, true) => self.units = Some(read.units),
            _ => {}
        }
        if self.projector.is_none() {
            self.projector = read.projector;
        }
        for animal in read.animals {
            self.take_animal(ctx, animal)?;
        }
        Ok(())
    }

    /// The deferred first animal's own fit, now that it is not the only one.
    fn fit_first(&mut self, ctx: &Context<'_>) {
        let (Some((name, counts, stats, interval)), Some(proj)) =
            (self.first.take(), self.projector.as_ref())
        else {
            return;
        };
        let none = Series::default();
        let series = self.series.first().unwrap_or(&none);
        let fit = own_fit(proj, ctx, (&name, &counts, &stats, series), interval);
        self.fits.push(fit);
    }

    fn take_animal(&mut self, ctx: &Context<'_>, mut animal: Animal) -> Result<(), FitError> {
        if let (Some(a), Some(b)) = (self.interval, animal.interval) {
            if (a - b).abs() > 0.01 * a {
                self.fit_first(ctx);
                return self.other_rate(ctx, animal, b);
            }
        }
        let c = &animal.counts;
        let total = &mut self.counts;
        total.recordings += 1;
        total.frames_read += c.frames_read;
        total.frames_lost = total.frames_lost.saturating_add(c.frames_lost);
        total.frames_filled += c.frames_filled;
        total.gaps += c.gaps;
        total.runs += c.runs;
        total.longest_run = total.longest_run.max(c.longest_run);
        if self.interval.is_none() {
            self.interval = animal.interval;
        }
        if animal.stats.count == 0.0 {
            self.fit_first(ctx);
            self.fits.push(AnimalFit::failed(
                &animal.name,
                &animal.stats,
                &animal.counts,
                "no usable frame",
            ));
            return Ok(());
        }
        if self.projector.is_none() {
            return Err(FitError::Invalid(
                "an animal with frames but no projector".into(),
            ));
        }
        let interval = animal.interval.unwrap_or(1.0);
        if let Some(own) = animal.own.clone() {
            self.fit_first(ctx);
            self.fits.push(own);
        } else if self.fits.is_empty() && self.first.is_none() {
            self.first = Some((
                animal.name.clone(),
                animal.counts.clone(),
                animal.stats.clone(),
                interval,
            ));
        } else {
            self.fit_first(ctx);
            if let Some(proj) = self.projector.as_ref() {
                let parts = (animal.name.as_str(), &animal.counts, &animal.stats);
                let parts = (parts.0, parts.1, parts.2, &animal.series);
                self.fits.push(own_fit(proj, ctx, parts, interval));
            }
        }
        self.stats
            .get_or_insert_with(|| Stats::new(animal.stats.mean.len(), ctx.ladder()))
            .absorb(&animal.stats, 1.0);
        self.series.push(std::mem::take(&mut animal.series));
        if self.series.iter().map(Series::values).sum::<usize>() > MAX_POOLED {
            self.series.iter_mut().for_each(Series::drop_frames);
        }
        if let Some(j) = animal.jitter.take() {
            match &mut self.jitter {
                Some(pooled) => pooled.absorb(&j),
                None => self.jitter = Some(j),
            }
        }
        if let Some(m) = animal.movement.take() {
            match &mut self.movement {
                Some(pooled) => pooled.absorb(&m),
                None => self.movement = Some(m),
            }
        }
        if ctx.settings.bootstrap > 0 {
            // Two animals are resampled whole: nobody's blocks are needed any more.
            if !self.kept.is_empty() {
                animal.pieces = Vec::new();
                self.kept.iter_mut().for_each(|a| a.pieces = Vec::new());
            }
            self.kept.push(animal);
        }
        Ok(())
    }

    /// An animal sampled at another rate than the pool's (the first timed animal's): spectra
    /// in frames of different lengths cannot be summed, so it joins the pool of its own rate.
    fn other_rate(&mut self, ctx: &Context<'_>, animal: Animal, rate: f64) -> Result<(), FitError> {
        let same = |p: &Pool| p.interval.is_some_and(|a| (a - rate).abs() <= 0.01 * a);
        let i = match self.others.iter().position(same) {
            Some(i) => i,
            None => {
                self.others.push(Pool {
                    interval: Some(rate),
                    units: self.units.clone(),
                    projector: self.projector.clone(),
                    ..Pool::default()
                });
                self.others.len() - 1
            }
        };
        self.others[i].take_animal(ctx, animal)
    }

    /// The names of the animals pooled.
    fn names(&self) -> Vec<String> {
        let first = self.first.iter().map(|f| f.0.clone());
        first
            .chain(self.fits.iter().map(|f| f.recording.clone()))
            .collect()
    }

    fn finish(mut self, ctx: &Context<'_>) -> Result<FitReport, FitError> {
        let others = std::mem::take(&mut self.others);
        let names = self.names();
        let (Some(stats), Some(proj)) = (&self.stats, &self.projector) else {
            // A recording with nothing in it is a problem of the file: named, when there is one.
            let empty = FitError::from(RecordingError::NoFrames {
                read: self.counts.frames_read,
            });
            let mut names = self.fits.iter().map(|f| f.recording.as_str());
            return Err(match (names.next(), names.next()) {
                (Some(name), None) if !name.is_empty() => FitError::named(empty, name),
                _ => empty,
            });
        };
        let interval = self.interval.unwrap_or(1.0);
        let mut named = self.units.clone().unwrap_or_default();
        if let Some(u) = &ctx.settings.recording.time_unit {
            named.time = Some(u.clone());
        }
        if let Some(u) = &ctx.settings.recording.length_unit {
            named.length = Some(u.clone());
        }
        let counts = Recording {
            fill_gaps: ctx.settings.recording.fill_gaps,
            ..self.counts.clone()
        };
        let described = Some((counts, named));
        let spans: Vec<Span> = self.series.iter().map(Series::whole).collect();
        let scope = (Scope::Full(&spans), described);
        let mut report = fit_stats(proj, ctx, stats, interval, scope)?;
        report.tracking_noise = self.jitter.as_ref().and_then(Jitter::estimate);
        report
            .warnings
            .extend(self.movement.as_ref().and_then(Movement::warning));
        report.held_movement = self.movement.as_ref().and_then(Movement::share);
        report
            .warnings
            .extend(super::report::recording_notes(&report));
        report.advice = super::advice::of(&report, &self.series);
        if ctx.settings.bootstrap > 0 {
            let units = units(&self.kept);
            let frames = UnitFrames::of(&units, &self.series);
            let one = OneStep::of(&report.modes_fit, frames.spans(), 1.0 / interval);
            let pooled = report.clone();
            // A resample that would choose a window a pilot kept partially: the pass is made again.
            let pruned = AtomicBool::new(false);
            let fit = |s: &Stats, times: &[usize]| {
                let exact = Exact::Resample(&one, times);
                let scope = (Scope::Constants(Some(&pooled), exact), None);
                let fitted = fit_stats(proj, ctx, s, interval, scope);
                pruned.fetch_or(
                    matches!(fitted, Err(FitError::Pruned { .. })),
                    Ordering::Relaxed,
                );
                fitted.ok()
            };
            let span = bootstrap::span(&report, interval);
            let kappa = report.continuum.as_ref().map(|c| c.constant);
            let centre = (report.omega, report.beta, kappa);
            let ladder = (ctx.ladder(), span);
            let drawn = bootstrap::intervals(&units, ctx.settings, ladder, fit, centre);
            bootstrap::attach(&mut report, drawn);
            if pruned.load(Ordering::Relaxed) {
                return Err(FitError::Pruned {
                    window: report.window.frames,
                });
            }
        }
        if self.fits.len() > 1 || !others.is_empty() {
            report.animals = self.fits;
            super::spread::apply(&mut report);
        }
        if !others.is_empty() {
            let fitted = (others.into_iter())
                .map(|o| (o.interval.unwrap_or(1.0), o.names(), o.finish(ctx)))
                .collect();
            super::rates::attach(&mut report, (interval, names), fitted);
        }
        report.onward = report.onward_arguments();
        report.active_allowed = ctx.model.active.is_some();
        Ok(report)
    }
}
