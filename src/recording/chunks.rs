//! One large recording read on every core. The first rows (a header, the first frame) are read
//! in order and fix the layout; the rest of the file is cut into chunks of whole lines, which
//! workers read in turn and parse ([`plain_line`], the line reader's own function) and, for
//! midlines, project onto the modes, while this thread takes the chunks back in order: it runs
//! the clock and hands the rows on exactly as the line reader would, so every number and every
//! message is the same. Memory holds the chunks in flight (about 8 × workers × [`CHUNK`] of
//! text and the frames parsed from them), whatever the file's length.
//!
//! Why by hand and not rayon: rayon has no ordered map over a stream (`par_bridge` loses the
//! order, an indexed iterator needs the chunks collected first, that is the whole file in
//! memory: 233 MB for the 10⁶-frame benchmark file). Measured on two cores, this pipeline fits
//! that file in 0.62× the wall time (0.63× the CPU) of the same file read as one stream
//! (docs/benchmarks.md).

use std::io::{BufRead, Read as _};
use std::ops::Range;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::{Arc, Mutex};
use std::thread::Scope;

use super::clock::Clock;
use super::number::comma_rows;
use super::project::Work;
use super::read::{plain_line, FrameReader, LineError, Row, Source};
use super::{FrameError, InputKind, Projector, RecordingError, RecordingSettings, MAX_LINE_BYTES};

/// Bytes of text a worker parses at once (whole lines: the last one is read to its end).
pub(crate) const CHUNK: usize = 256 << 10;

/// A chunk parsed by a worker.
#[derive(Default)]
struct Parsed {
    rows: Vec<ParsedRow>,
    /// Each row's values after t, one after the other.
    values: Vec<f64>,
    /// Each projected row's modal coordinates, one after the other.
    modal: Vec<f64>,
    /// Lines in the chunk.
    lines: usize,
    /// Where parsing stopped, and why (the rows before it are good).
    error: Option<(usize, LineError)>,
}

struct ParsedRow {
    t: f64,
    lost: bool,
    /// Line within the chunk (1-based).
    line: usize,
    /// Point spacing, or why the frame does not project (`None`: not projected here).
    projected: Option<Result<f64, FrameError>>,
}

/// What the workers hand on, in order: a chunk being parsed, or why reading stopped.
type Pending = Result<Receiver<Parsed>, RecordingError>;

/// Builds the workers' projector for a frame of so many values (`None`: the rows go on
/// unprojected, and the error, if any, comes from the caller's own projector).
pub(crate) type MakeProjector<'env> = Box<dyn Fn(usize) -> Option<Projector> + 'env>;

/// The rows of one recording, the first ones from the line reader, the rest from chunks parsed
/// on worker threads.
pub(crate) struct Chunked<'scope, 'env, R: BufRead + Send + 'env> {
    head: Option<FrameReader<R>>,
    scope: &'scope Scope<'scope, 'env>,
    settings: &'env RecordingSettings,
    make_projector: MakeProjector<'env>,
    /// The first frame's values, lent once the line reader is gone.
    first: Vec<f64>,
    chunks: Option<Receiver<Pending>>,
    current: Parsed,
    /// The next row of `current`, its first value and first modal coordinate.
    next: (usize, usize, usize),
    /// Lines before `current`.
    base: usize,
    clock: Clock,
    /// Values per row (after t) and modal coordinates per projected row.
    sizes: (usize, usize),
    done: bool,
    spares: Arc<Spares>,
}

impl<'scope, 'env, R: BufRead + Send + 'env> Chunked<'scope, 'env, R> {
    /// The rows of `reader`, chunks parsed on threads of `scope`.
    pub(crate) fn new(
        reader: FrameReader<R>,
        scope: &'scope Scope<'scope, 'env>,
        settings: &'env RecordingSettings,
        make_projector: MakeProjector<'env>,
    ) -> Self {
        Chunked {
            head: Some(reader),
            scope,
            settings,
            make_projector,
            first: Vec::new(),
            chunks: None,
            current: Parsed::default(),
            next: (0, 0, 0),
            base: 0,
            clock: Clock::default(),
            sizes: (0, 0),
            done: false,
            spares: Arc::default(),
        }
    }

    /// Hand the rest of the stream to the workers, which read and parse it, rows of `width` cells.
    fn start(&mut self, head: FrameReader<R>, width: usize) {
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
        let projector = (self.settings.kind == InputKind::Midline)
            .then(|| (self.make_projector)(width - 1))
            .flatten();
        self.sizes = (width - 1, projector.as_ref().map_or(0, |p| p.rows.len()));
        self.first = head.values.clone();
        let (reader, clock, line) = head.into_rest();
        (self.clock, self.base) = (clock, line);
        // At most 8 × workers chunks wait to be taken: a worker reading the next one blocks. The
        // slack lets the workers go on while this thread transforms a batch of segments
        // (2 × workers chunks left them idle: 6 % more wall time).
        let (order, chunks) = mpsc::sync_channel(8 * workers);
        let feed = Arc::new(Mutex::new(Feed {
            reader,
            order: Some(order),
        }));
        for _ in 0..workers {
            let (feed, projector, settings) = (Arc::clone(&feed), projector.clone(), self.settings);
            let spares = Arc::clone(&self.spares);
            self.scope.spawn(move || loop {
                let job = feed.lock().ok().and_then(|mut f| f.next(&spares));
                let Some((text, parsed)) = job else {
                    return;
                };
                let _ = parsed.send(parse(&text, width, projector.as_ref(), settings, &spares));
                Spares::give(&spares.text, text);
            });
        }
        self.chunks = Some(chunks);
    }

    /// The next row of the line reader, handing over to the workers once the layout is known.
    fn next_head(&mut self) -> Result<Option<Row<'_>>, RecordingError> {
        let Some(head) = self.head.as_mut() else {
            return Ok(None);
        };
        let Some(p) = head.advance()? else {
            return Ok(None);
        };
        let line = head.line;
        let values = match head.plain_width() {
            Some(width) => {
                if let Some(head) = self.head.take() {
                    self.start(head, width);
                }
                &self.first
            }
            None => self.head.as_ref().map_or(&self.first, |h| &h.values),
        };
        Ok(Some(Row {
            t: p.t,
            values: (!p.lost).then_some(values.as_slice()),
            missing_before: p.missing_before,
            line,
            projected: None,
        }))
    }

    /// The next parsed chunk into `current`; `false` at the end.
    fn next_chunk(&mut self) -> Result<bool, RecordingError> {
        if let Some((line, why)) = self.current.error.take() {
            self.done = true;
            return Err(RecordingError::Line {
                line: self.base + line,
                why: why.into(),
            });
        }
        self.base += self.current.lines;
        let pending = self.chunks.as_ref().and_then(|c| c.recv().ok());
        let Some(pending) = pending else {
            self.done = true;
            return Ok(false);
        };
        let parsed = pending.and_then(|rx| {
            rx.recv()
                .map_err(|_| RecordingError::Io(std::io::Error::other("a parsing thread stopped")))
        });
        self.done = parsed.is_err();
        let done = std::mem::replace(&mut self.current, parsed?);
        Spares::give(&self.spares.parsed, done);
        self.next = (0, 0, 0);
        Ok(true)
    }
}

impl<'env, R: BufRead + Send + 'env> Source for Chunked<'_, 'env, R> {
    fn next_row(&mut self) -> Result<Option<Row<'_>>, RecordingError> {
        if self.head.is_some() {
            return self.next_head();
        }
        while !self.done && self.next.0 >= self.current.rows.len() {
            if !self.next_chunk()? {
                return Ok(None);
            }
        }
        if self.done {
            return Ok(None);
        }
        let (r, v, m) = self.next;
        let (width, modes) = self.sizes;
        if self.clock.dt.is_none() {
            self.clock
                .seed(self.current.rows[r..].iter().map(|row| row.t));
        }
        let row = &self.current.rows[r];
        let line = self.base + row.line;
        let missing_before = self.clock.step(row.t).map_err(|e| RecordingError::Line {
            line,
            why: e.into(),
        })?;
        let (projected, m) = match row.projected {
            Some(Ok(spacing)) => (
                Some(Ok((&self.current.modal[m..m + modes], spacing))),
                m + modes,
            ),
            Some(Err(why)) => (Some(Err(why)), m),
            None => (None, m),
        };
        self.next = (r + 1, v + width, m);
        Ok(Some(Row {
            t: row.t,
            values: (!row.lost).then_some(&self.current.values[v..v + width]),
            missing_before,
            line,
            projected,
        }))
    }

    fn interval(&self) -> Option<f64> {
        self.head.as_ref().map_or(self.clock.dt, |h| h.interval())
    }
}

/// The rest of the stream, read in chunks of whole lines by whichever worker is free (no
/// reading thread of its own: one thread fewer to wake ~900 times a 10⁶-frame file), each
/// chunk's place in line handed to `order` while the reader is held, so the chunks stay in
/// order.
struct Feed<R> {
    reader: R,
    /// Gone at the end, at an error, or once the receiver is.
    order: Option<SyncSender<Pending>>,
}

impl<R: BufRead> Feed<R> {
    /// The next chunk, and where its parsed rows go; `None` at the end, at an error (sent on
    /// in order), or when the receiver is gone.
    fn next(&mut self, spares: &Spares) -> Option<(Vec<u8>, mpsc::Sender<Parsed>)> {
        let order = self.order.as_ref()?;
        let mut text = spares
            .text()
            .unwrap_or_else(|| Vec::with_capacity(CHUNK + 256));
        let reader = &mut self.reader;
        let mut read = reader.take(CHUNK as u64).read_to_end(&mut text);
        if matches!(read, Ok(n) if n > 0) && text.last() != Some(&b'\n') {
            // The last line to its end, or past the longest line allowed (then an error).
            read = reader
                .take(MAX_LINE_BYTES as u64 + 1)
                .read_until(b'\n', &mut text);
        }
        let job = match read {
            Err(e) => {
                let _ = order.send(Err(RecordingError::Io(e)));
                None
            }
            Ok(_) if text.is_empty() => None,
            Ok(_) => {
                let (tx, rx) = mpsc::channel();
                order.send(Ok(rx)).is_ok().then_some((text, tx))
            }
        };
        if job.is_none() {
            self.order = None;
        }
        job
    }
}

/// Buffers that went round once, for the next chunks: the same few pages are reused instead of
/// new ones being mapped (and faulted in) for every chunk.
#[derive(Default)]
struct Spares {
    text: Mutex<Vec<Vec<u8>>>,
    parsed: Mutex<Vec<Parsed>>,
}

impl Spares {
    fn text(&self) -> Option<Vec<u8>> {
        let mut text = self.text.lock().ok()?.pop()?;
        text.clear();
        Some(text)
    }

    fn parsed(&self) -> Parsed {
        let mut p = self
            .parsed
            .lock()
            .ok()
            .and_then(|mut p| p.pop())
            .unwrap_or_default();
        p.rows.clear();
        p.values.clear();
        p.modal.clear();
        p.lines = 0;
        p.error = None;
        p
    }

    fn give<T>(list: &Mutex<Vec<T>>, spare: T) {
        if let Ok(mut list) = list.lock() {
            list.push(spare);
        }
    }
}

/// Parse one chunk: rows of `width` cells, projected when a projector is given. Lines are
/// read two at a time where both are plain comma-separated rows ([`comma_rows`]), else one by
/// one by the line reader's own function.
fn parse(
    text: &[u8],
    width: usize,
    projector: Option<&Projector>,
    settings: &RecordingSettings,
    spares: &Spares,
) -> Parsed {
    let mut out = spares.parsed();
    let mut work = Work::default();
    // The row (time, lost, line) whose values are `values` of `out.values`: projected when it
    // can be, and listed.
    let mut add_row = |out: &mut Parsed,
                       (t, lost, line): (f64, bool, usize),
                       values: Range<usize>| {
        let values = &out.values[values];
        let projected = match projector {
            Some(p) if !lost => {
                let done = p.project_into(values, settings.head_first, &mut work.0, &mut work.1);
                if done.is_ok() {
                    out.modal.extend_from_slice(&work.1);
                }
                Some(done)
            }
            _ => None,
        };
        out.rows.push(ParsedRow {
            t,
            lost,
            line,
            projected,
        });
    };
    let line_at = |start: usize| {
        let rest = text.get(start..).filter(|rest| !rest.is_empty())?;
        Some(&rest[..memchr::memchr(b'\n', rest).map_or(rest.len(), |end| end + 1)])
    };
    let (mut start, mut k) = (0, 0);
    while let Some(line) = line_at(start) {
        start += line.len();
        k += 1;
        out.lines = k;
        // Each row's values are parsed into place, after the chunk's earlier rows.
        let from = out.values.len();
        if let Some(next) = line_at(start).filter(|n| line.len().max(n.len()) <= MAX_LINE_BYTES) {
            if let Some([t, u]) = comma_rows([line, next], width, &mut out.values) {
                start += next.len();
                k += 1;
                out.lines = k;
                let cells = width - 1;
                add_row(&mut out, (t, false, k - 1), from..from + cells);
                add_row(&mut out, (u, false, k), from + cells..from + 2 * cells);
                continue;
            }
        }
        match plain_line(line, width, &mut out.values) {
            Ok(Some((t, lost))) => {
                let values = from..out.values.len();
                add_row(&mut out, (t, lost, k), values);
            }
            Ok(None) => {}
            Err(why) => {
                out.error = Some((k, why));
                break;
            }
        }
    }
    out
}
