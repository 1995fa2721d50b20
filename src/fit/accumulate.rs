//! One animal's frames into its statistics, as a worker reads them: each frame oriented head
//! last, projected, handed to the per-frame sink and added to its run; lost frames split the
//! runs unless `--fill-gaps` bridges them.

use super::stats::{Run, Stats};
use super::timedomain::Series;
use super::welch::Ladder;
use super::{animal::Animal, FitError, FitSettings, Recording};
use crate::modal::Params;
use crate::model::Model;
use crate::recording::Jitter;
use crate::recording::Source;
use crate::recording::Work;
use crate::recording::{FrameError, InputKind, Projector, RecordingError};

/// The per-frame callback of a streaming fit: projector, time, modal coordinates.
pub type Each<'a> = &'a mut dyn FnMut(&Projector, f64, &[f64]) -> Result<(), SinkError>;

/// Why the per-frame sink of [`super::fit_each`] failed (kept as the source of
/// [`FitError::Output`]).
pub type SinkError = Box<dyn std::error::Error + Send + Sync>;

/// Shared, read-only context of the workers.
pub(super) struct Context<'a> {
    pub(super) model: &'a Model,
    pub(super) params: &'a Params,
    pub(super) settings: &'a FitSettings,
    /// The Welch windows the pass keeps (see [`Context::ladder`]).
    pub(super) ladder: PassLadder<'a>,
    /// One input only: a file may be parsed on every core.
    pub(super) alone: bool,
    /// Measure the tracking noise (a pilot does not: the pass reads its frames again).
    pub(super) noise: bool,
    /// Projectors made so far, by frame width: the pilot's, the parsing workers' and each
    /// animal's are one (made once, a few milliseconds each).
    pub(super) made: &'a ProjectorCache,
}

/// The ladder of a pass: known, or foretold by a pilot on another thread while the pass's
/// workers already parse (its rows wait for it).
pub(super) enum PassLadder<'a> {
    Known(Ladder),
    Foretold(&'a Forecast),
}

/// A ladder set once by one thread and awaited by another.
#[derive(Default)]
pub(super) struct Forecast {
    ladder: std::sync::OnceLock<Ladder>,
    ready: (std::sync::Mutex<()>, std::sync::Condvar),
}

impl Forecast {
    /// Set the ladder (the first one set stays) and wake whoever waits.
    pub(super) fn set(&self, ladder: Ladder) {
        let _ = self.ladder.set(ladder);
        let (lock, ready) = &self.ready;
        let _held = lock.lock().unwrap_or_else(|e| e.into_inner());
        ready.notify_all();
    }

    /// The ladder, once set.
    fn wait(&self) -> &Ladder {
        let (lock, ready) = &self.ready;
        let mut held = lock.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if let Some(ladder) = self.ladder.get() {
                return ladder;
            }
            held = ready.wait(held).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// Projectors made for one fit, by frame width.
pub(super) type ProjectorCache = std::sync::Mutex<Vec<(usize, Projector)>>;

impl Context<'_> {
    /// The Welch windows the pass keeps: once a pilot has foretold them, if one runs.
    pub(super) fn ladder(&self) -> &Ladder {
        match &self.ladder {
            PassLadder::Known(ladder) => ladder,
            PassLadder::Foretold(cell) => cell.wait(),
        }
    }

    /// The projector of frames of `width` values: made once per fit, then copied.
    pub(super) fn projector(&self, width: usize) -> Result<Projector, FitError> {
        let mut made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, p)) = made.iter().find(|(w, _)| *w == width) {
            return Ok(p.clone());
        }
        let p = Projector::new(self.model, self.params, &self.settings.recording, width)?;
        made.push((width, p.clone()));
        Ok(p)
    }
}

/// Projectors by frame width (midlines of another K resample to the same N modes).
pub(super) struct Projectors {
    pub(super) by_width: Vec<(usize, Projector)>,
}

impl Projectors {
    pub(super) fn get(
        &mut self,
        ctx: &Context<'_>,
        width: usize,
    ) -> Result<&mut Projector, FitError> {
        if ctx.settings.recording.kind == InputKind::Lengths {
            if let Some(&(w, _)) = self.by_width.first().filter(|(w, _)| *w != width) {
                return Err(FitError::Invalid(format!(
                    "{width} segments where the first animal has {w}: rings of another K are another body"
                )));
            }
        }
        let k = match self.by_width.iter().position(|(w, _)| *w == width) {
            Some(k) => k,
            None => {
                let p = ctx.projector(width)?;
                self.by_width.push((width, p));
                self.by_width.len() - 1
            }
        };
        Ok(&mut self.by_width[k].1)
    }

    pub(super) fn first(&self) -> Option<Projector> {
        self.by_width.first().map(|(_, p)| p.clone())
    }
}

/// One animal's frames into its statistics: lost frames split the runs unless a gap is short
/// enough to bridge linearly.
pub(super) fn accumulate(
    source: &mut dyn Source,
    name: String,
    ctx: &Context<'_>,
    projs: &mut Projectors,
    each: &mut Option<Each<'_>>,
) -> Result<Animal, FitError> {
    let settings = ctx.settings;
    let mut counts = Recording {
        recordings: 1,
        ..Recording::default()
    };
    let mut animal = Animal {
        name,
        stats: Stats::default(),
        pieces: Vec::new(),
        counts: Recording::default(),
        interval: None,
        own: None,
        jitter: None,
        movement: None,
        series: Default::default(),
    };
    let mut run: Option<Run> = None;
    // The last usable frame's time, and its values when gaps may be bridged.
    let mut previous: Option<f64> = None;
    let mut previous_values: Vec<f64> = Vec::new();
    let mut reference: Option<f64> = None;
    let mut holding = false;
    let mut pending = 0usize;
    let mut work = Work::default();
    while let Some(row) = source.next_row()? {
        counts.frames_read += 1;
        pending = pending.saturating_add(row.missing_before);
        let Some(values) = row.values else {
            pending += 1;
            continue;
        };
        let line = row.line;
        let proj = projs.get(ctx, values.len()).map_err(|e| match e {
            FitError::Recording(RecordingError::Line { why, .. }) => {
                RecordingError::Line { line, why }.into()
            }
            other => other,
        })?;
        if settings.recording.kind == InputKind::Lengths && reference.is_none() {
            // Each animal's own rest length: a constant offset in the strains only shifts the
            // means, which the covariance and the spectra remove.
            reference = Some(values.iter().sum::<f64>() / values.len() as f64);
        }
        proj.reference_length = reference;
        if proj.holds() && !holding {
            // The animal's held points, from its first usable frame (the lab holds them).
            proj.hold(values, settings.recording.head_first);
            holding = proj.holding();
            animal.movement = proj.movement(values, settings.recording.head_first);
        }
        if let Some(m) = animal.movement.as_mut() {
            m.frame(values);
        }
        if settings.recording.kind == InputKind::Midline && ctx.noise {
            if animal.jitter.is_none() {
                animal.jitter = Jitter::new(values.len() / 2);
            }
            if let Some(j) = animal.jitter.as_mut() {
                j.frame(values, pending == 0 && previous.is_some());
            }
        }
        if pending > 0 {
            counts.frames_lost = counts.frames_lost.saturating_add(pending);
            match previous {
                Some(t0) if pending <= settings.recording.fill_gaps => {
                    for k in 1..=pending {
                        let w = k as f64 / (pending + 1) as f64;
                        let t = t0 + w * (row.t - t0);
                        let v: Vec<f64> = previous_values
                            .iter()
                            .zip(values)
                            .map(|(a, b)| a + w * (b - a))
                            .collect();
                        counts.frames_filled += 1;
                        let kept = (&mut run, &mut work, &mut animal.series);
                        feed(proj, ctx, kept, each, (t, &v, line), None)?;
                    }
                }
                Some(_) => {
                    counts.gaps += 1;
                    animal.series.gap(pending);
                    close(&mut run, &mut animal, &mut counts, ctx);
                }
                // Lost before the animal's first usable frame: nothing to split.
                None => {}
            }
            pending = 0;
        }
        feed(
            proj,
            ctx,
            (&mut run, &mut work, &mut animal.series),
            each,
            (row.t, values, line),
            row.projected,
        )?;
        previous = Some(row.t);
        if settings.recording.fill_gaps > 0 {
            previous_values.clear();
            previous_values.extend_from_slice(values);
        }
    }
    counts.frames_lost = counts.frames_lost.saturating_add(pending);
    close(&mut run, &mut animal, &mut counts, ctx);
    animal.counts = counts;
    animal.interval = source.interval();
    Ok(animal)
}

/// End the current run: into the animal's total, its blocks kept for a bootstrap over time.
fn close(run: &mut Option<Run>, animal: &mut Animal, counts: &mut Recording, ctx: &Context<'_>) {
    let Some(r) = run.take() else {
        return;
    };
    counts.runs += 1;
    counts.longest_run = counts.longest_run.max(r.len());
    let (piece, blocks) = r.finish();
    if animal.stats.mean.is_empty() {
        animal.stats = Stats::new(piece.mean.len(), ctx.ladder());
    }
    animal.stats.absorb(&piece, 1.0);
    animal.pieces.extend(blocks);
}

/// Project one frame (oriented head last) unless a parsing worker did, hand it to `each`, add
/// it to the run and the series.
fn feed(
    proj: &Projector,
    ctx: &Context<'_>,
    (run, work, series): (&mut Option<Run>, &mut Work, &mut Series),
    each: &mut Option<Each<'_>>,
    (t, values, line): (f64, &[f64], usize),
    projected: Option<Result<(&[f64], f64), FrameError>>,
) -> Result<(), FitError> {
    let bad = |why: FrameError| {
        FitError::from(RecordingError::Line {
            line,
            why: why.into(),
        })
    };
    let (q, spacing) = match projected {
        Some(done) => done.map_err(bad)?,
        None => {
            let head_first = ctx.settings.recording.head_first;
            let spacing = proj
                .project_into(values, head_first, &mut work.0, &mut work.1)
                .map_err(bad)?;
            (work.1.as_slice(), spacing)
        }
    };
    if let Some(each) = each {
        each(proj, t, q).map_err(FitError::Output)?;
    }
    series.push(q);
    run.get_or_insert_with(|| Run::new(q.len(), ctx.ladder(), ctx.settings.bootstrap > 0))
        .push(q, spacing);
    Ok(())
}
