//! One animal's frames into its statistics, as a worker reads them: each frame oriented head
//! last, projected, handed to the per-frame sink and added to its run; lost frames split the
//! runs unless `--fill-gaps` bridges them.

use super::read::Source;
use super::stats::Ladder;
use super::stats::{Run, Stats};
use super::{animal::Animal, FitError, FitSettings, InputKind, Projector, Recording};
use crate::modal::Params;
use crate::model::Model;

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
    pub(super) ladder: Ladder,
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
        if ctx.settings.kind == InputKind::Lengths {
            if let Some(&(w, _)) = self.by_width.first().filter(|(w, _)| *w != width) {
                return Err(FitError::Invalid(format!(
                    "{width} segments where the first animal has {w}: rings of another K are another body"
                )));
            }
        }
        let k = match self.by_width.iter().position(|(w, _)| *w == width) {
            Some(k) => k,
            None => {
                let p = Projector::new(ctx.model, ctx.params, ctx.settings, width)?;
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
    };
    let mut run: Option<Run> = None;
    let mut previous: Option<(f64, Vec<f64>)> = None;
    let mut reference: Option<f64> = None;
    let mut pending = 0usize;
    while let Some(row) = source.next_row()? {
        counts.frames_read += 1;
        pending += row.missing_before;
        let Some(values) = row.values else {
            pending += 1;
            continue;
        };
        let line = source.line();
        let proj = projs.get(ctx, values.len()).map_err(|e| match e {
            FitError::Line { why, .. } => FitError::Line { line, why },
            other => other,
        })?;
        if settings.kind == InputKind::Lengths && reference.is_none() {
            // Each animal's own rest length: a constant offset in the strains only shifts the
            // means, which the covariance and the spectra remove.
            reference = Some(values.iter().sum::<f64>() / values.len() as f64);
        }
        proj.reference_length = reference;
        if pending > 0 {
            counts.frames_lost += pending;
            match &previous {
                Some(prev) if pending <= settings.fill_gaps => {
                    for k in 1..=pending {
                        let w = k as f64 / (pending + 1) as f64;
                        let t = prev.0 + w * (row.t - prev.0);
                        let v: Vec<f64> = prev
                            .1
                            .iter()
                            .zip(&values)
                            .map(|(a, b)| a + w * (b - a))
                            .collect();
                        counts.frames_filled += 1;
                        feed(proj, ctx, &mut run, each, (t, &v, line))?;
                    }
                }
                Some(_) => {
                    counts.gaps += 1;
                    close(&mut run, &mut animal, &mut counts, ctx);
                }
                // Lost before the animal's first usable frame: nothing to split.
                None => {}
            }
            pending = 0;
        }
        feed(proj, ctx, &mut run, each, (row.t, &values, line))?;
        previous = Some((row.t, values));
    }
    counts.frames_lost += pending;
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
        animal.stats = Stats::new(piece.mean.len(), &ctx.ladder);
    }
    animal.stats.absorb(&piece, 1.0);
    animal.pieces.extend(blocks);
}

/// Project one frame (oriented head last), hand it to `each`, add it to the run.
fn feed(
    proj: &Projector,
    ctx: &Context<'_>,
    run: &mut Option<Run>,
    each: &mut Option<Each<'_>>,
    (t, values, line): (f64, &[f64], usize),
) -> Result<(), FitError> {
    let oriented;
    let values = if ctx.settings.head_first {
        oriented = head_last(ctx.settings.kind, values);
        &oriented
    } else {
        values
    };
    let q = proj.modal(values).map_err(|why| FitError::Line {
        line,
        why: why.to_string(),
    })?;
    if let Some(each) = each {
        each(proj, t, &q).map_err(FitError::Output)?;
    }
    let spacing = proj.spacing(values);
    run.get_or_insert_with(|| Run::new(q.len(), &ctx.ladder, ctx.settings.bootstrap > 0))
        .push(q, spacing);
    Ok(())
}

/// A frame listed head first, reordered head last (the model's orientation): points (x, y)
/// pairs for midlines, segments for lengths.
fn head_last(kind: InputKind, values: &[f64]) -> Vec<f64> {
    match kind {
        InputKind::Midline => values.chunks(2).rev().flatten().copied().collect(),
        InputKind::Lengths => values.iter().rev().copied().collect(),
    }
}
