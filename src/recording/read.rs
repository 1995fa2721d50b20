//! Reading recordings: one frame per line (plain CSV or white space, or DeepLabCut exports),
//! optionally led by a track id; lost frames (missing values, skipped time steps) as rows
//! without values; lines and files bounded. Every source of frames (a text stream, a track held
//! in memory) answers the same [`Source`] questions.

use std::io::BufRead;

use super::clock::Clock;
pub use super::error::LineError;
use super::format::DLC_HEADERS;
use super::number::plain_row;
use super::{FrameError, InputKind, LineWhy, RecordingError, RecordingSettings};
use crate::markup::clip;

/// One frame of a track held in memory: time and values, `None` when the tracker lost it.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Time.
    pub t: f64,
    /// The values after time (`x₁ y₁ …` or `ℓ₁ …`); `None`, or any non-finite value, is lost.
    pub values: Option<Vec<f64>>,
}

/// One animal's frames, in time order, with a name for its reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Name in reports (file, and id within it).
    pub name: String,
    /// Frames in time order.
    pub frames: Vec<Frame>,
}

/// A stream of rows of one animal.
pub(crate) trait Source {
    /// The next row, or `None` at the end; it borrows the source until the next call.
    fn next_row(&mut self) -> Result<Option<Row<'_>>, RecordingError>;
    /// The sampling interval seen (the first time step).
    fn interval(&self) -> Option<f64>;
}

/// One row of a recording, lent by its [`Source`].
pub(crate) struct Row<'a> {
    pub(crate) t: f64,
    /// The frame's values after t; `None` when the tracker lost it.
    pub(crate) values: Option<&'a [f64]>,
    /// Frames missing from the file just before this row (from the time step).
    pub(crate) missing_before: usize,
    /// Where the row came from (line or frame, 1-based), for messages.
    pub(crate) line: usize,
    /// The frame's modal coordinates and point spacing, when a parsing worker already
    /// projected it (or why it could not).
    pub(crate) projected: Option<Result<(&'a [f64], f64), FrameError>>,
}

/// A DeepLabCut row that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DlcError {
    /// Not a whole number of (x, y, likelihood) triples.
    #[error(
        "{0} values after the frame index: DeepLabCut rows hold x, y, likelihood per body part"
    )]
    Width(usize),
    /// The frame index is not a number.
    #[error("frame index {} is not a number", clip(.0))]
    Frame(String),
}

/// A track in memory as a [`Source`].
pub(crate) struct TrackSource {
    frames: std::vec::IntoIter<Frame>,
    index: usize,
    clock: Clock,
    /// The frame last lent.
    current: Option<Frame>,
}

impl TrackSource {
    pub(crate) fn new(track: Track) -> TrackSource {
        let mut clock = Clock::default();
        clock.seed(track.frames.iter().map(|f| f.t).filter(|t| t.is_finite()));
        TrackSource {
            frames: track.frames.into_iter(),
            index: 0,
            clock,
            current: None,
        }
    }
}

impl Source for TrackSource {
    fn next_row(&mut self) -> Result<Option<Row<'_>>, RecordingError> {
        let Some(frame) = self.frames.next() else {
            return Ok(None);
        };
        self.index += 1;
        let bad = |why: LineWhy| RecordingError::Line {
            line: self.index,
            why,
        };
        if !frame.t.is_finite() {
            return Err(bad(
                format!("frame {}: time is not finite", self.index).into()
            ));
        }
        let missing_before = self.clock.step(frame.t).map_err(|e| bad(e.into()))?;
        let frame = self.current.insert(frame);
        let values = frame
            .values
            .as_deref()
            .filter(|v| v.iter().all(|x| x.is_finite()));
        Ok(Some(Row {
            t: frame.t,
            values,
            missing_before,
            line: self.index,
            projected: None,
        }))
    }

    fn interval(&self) -> Option<f64> {
        self.clock.dt
    }
}

/// The largest file read whole (WCON, or a file of interleaved tracks).
pub const MAX_WHOLE_FILE: u64 = 1 << 30;

/// The longest line a recording may have: a frame of thousands of points fits many times over;
/// `/dev/zero` or a binary file does not.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Streams frames out of text.
pub(crate) struct FrameReader<R> {
    reader: R,
    buf: Vec<u8>,
    /// The line last read (1-based).
    pub(crate) line: usize,
    width: Option<usize>,
    /// The header line, if it names every column: its line number and how many it names.
    header: Option<(usize, usize)>,
    /// Midlines (`x y` pairs after time) or lengths: how a width is counted in messages.
    kind: InputKind,
    seen_data: bool,
    clock: Clock,
    /// The first column is a track id (rows of several animals, in any order): time steps are
    /// checked per track, by the caller.
    track: bool,
    /// DeepLabCut layout: seen its `scorer`/`bodyparts`/`coords` header rows.
    dlc: bool,
    /// Frames per second, to turn DeepLabCut frame indices into time.
    fps: Option<f64>,
    /// DeepLabCut points below this likelihood are lost.
    min_likelihood: f64,
    /// The values of the row last read.
    pub(crate) values: Vec<f64>,
    /// The track id of the row last read, with `track`.
    pub(crate) track_id: Option<String>,
}

impl<R: BufRead> FrameReader<R> {
    pub(crate) fn new(reader: R, settings: &RecordingSettings) -> Self {
        FrameReader {
            reader,
            buf: Vec::new(),
            line: 0,
            width: None,
            header: None,
            kind: settings.kind,
            seen_data: false,
            clock: Clock::default(),
            track: settings.track_column,
            dlc: false,
            fps: settings.fps,
            min_likelihood: settings.min_likelihood,
            values: Vec::new(),
            track_id: None,
        }
    }

    /// A DeepLabCut row (frame, then x, y, likelihood per body part) as `t, x₁, y₁, …`, with
    /// NaN for a point tracked below the likelihood threshold.
    fn dlc_row(&self, cells: &[&str]) -> Result<Vec<String>, DlcError> {
        if (cells.len() - 1) % 3 != 0 {
            return Err(DlcError::Width(cells.len() - 1));
        }
        let frame: f64 = cells[0]
            .parse()
            .map_err(|_| DlcError::Frame(cells[0].to_string()))?;
        let mut out = vec![(frame / self.fps.unwrap_or(1.0)).to_string()];
        for part in cells[1..].chunks(3) {
            let likely = part[2]
                .parse::<f64>()
                .is_ok_and(|l| l >= self.min_likelihood);
            for v in &part[..2] {
                out.push(if likely { v.to_string() } else { "NaN".into() });
            }
        }
        Ok(out)
    }

    /// The next line into `self.buf`, read at most [`MAX_LINE_BYTES`] + 1 bytes at a time;
    /// `false` at the end.
    fn next_line(&mut self) -> Result<bool, RecordingError> {
        use std::io::Read;
        self.buf.clear();
        let read = (&mut self.reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut self.buf)
            .map_err(RecordingError::Io)?;
        self.line += usize::from(read > 0);
        Ok(read > 0)
    }

    /// The next row: a frame, or a frame the tracker lost (a missing or non-finite value), with
    /// the frames the time step says are missing before it. The values are left in
    /// `self.values`, the track id in `self.track_id`.
    pub(crate) fn advance(&mut self) -> Result<Option<Parsed>, RecordingError> {
        loop {
            if !self.next_line()? {
                return Ok(None);
            }
            let line = self.line;
            let bad = |why: LineWhy| RecordingError::Line { line, why };
            let row = match self.plain_width() {
                // The common row, once the layout is known.
                Some(width) => {
                    self.values.clear();
                    plain_line(&self.buf, width, &mut self.values).map_err(|e| bad(e.into()))?
                }
                None => {
                    let buf = std::mem::take(&mut self.buf);
                    let row = match line_text(&buf).map_err(|e| bad(e.into()))?.trim() {
                        "" => None,
                        text if text.starts_with('#') => None,
                        text => self.first_rows(text)?,
                    };
                    self.buf = buf;
                    row
                }
            };
            let Some((t, lost)) = row else {
                continue;
            };
            let missing_before = if self.track {
                0
            } else {
                // The interval from the rows already buffered, before the first step
                // (DeepLabCut's rows hold frame indices: over --fps, as `dlc_row` reads them).
                if self.clock.dt.is_none() {
                    let per = if self.dlc {
                        self.fps.unwrap_or(1.0)
                    } else {
                        1.0
                    };
                    let ahead = buffered_times(&mut self.reader)
                        .into_iter()
                        .map(|i| i / per);
                    self.clock.seed(std::iter::once(t).chain(ahead));
                }
                self.clock.step(t).map_err(|e| bad(e.into()))?
            };
            return Ok(Some(Parsed {
                t,
                lost,
                missing_before,
            }));
        }
    }

    /// A row read cell by cell: the header rows, DeepLabCut's layout, a track id. `None` for a
    /// header row.
    fn first_rows(&mut self, text: &str) -> Result<Option<(f64, bool)>, RecordingError> {
        let line = self.line;
        let bad = |why: LineWhy| RecordingError::Line { line, why };
        let mut cells: Vec<&str> = cells(text).collect();
        // DeepLabCut's three header rows; otherwise only the first line may be a header.
        if !self.seen_data && cells[0] == "individuals" {
            return Err(bad("a multi-animal DeepLabCut export: export one file per individual (each is one animal)".into()));
        }
        if !self.seen_data && DLC_HEADERS.contains(&cells[0]) {
            self.dlc = true;
            return Ok(None);
        }
        let time = usize::from(self.track).min(cells.len() - 1);
        let header = !self.seen_data && !self.dlc && cells[time].parse::<f64>().is_err();
        // The first line of any other layout holds, or names, a column of time.
        if !self.seen_data && !self.dlc && self.fps.is_some() {
            let (column, cell) = (time + 1, clip(cells[time]));
            return Err(RecordingError::Fps {
                has: if header {
                    format!("column {column}, headed {cell} (line {line})")
                } else {
                    format!("column {column}, time {cell} on line {line}")
                },
            });
        }
        self.seen_data = true;
        if header {
            // A header of one cell is a title, one ending in an ellipsis (`t,x1,y1,…`) names
            // the first columns only; any other names every column the rows hold.
            let last = cells[cells.len() - 1];
            let abridged = last.ends_with("...") || last.ends_with('…');
            self.header = (cells.len() > 1 && !abridged).then_some((line, cells.len()));
            return Ok(None);
        }
        if let Some((header, names)) = self.header.take() {
            if cells.len() != names {
                let lead = 1 + usize::from(self.track);
                let points = (self.kind == InputKind::Midline)
                    .then(|| [cells.len(), names].map(|n| n.saturating_sub(lead)))
                    .filter(|v| v.iter().all(|v| v % 2 == 0))
                    .map(|v| (v[0] / 2, v[1] / 2));
                return Err(bad(LineError::Header {
                    count: cells.len(),
                    names,
                    header,
                    points,
                }
                .into()));
            }
        }
        self.track_id = if self.track {
            if cells.len() < 2 {
                return Err(bad("a track id and then time are needed".into()));
            }
            Some(super::checked_name(cells.remove(0)).map_err(|e| bad(e.into()))?)
        } else {
            None
        };
        let converted;
        let cells: Vec<&str> = if self.dlc {
            converted = self.dlc_row(&cells).map_err(|e| bad(e.into()))?;
            converted.iter().map(String::as_str).collect()
        } else {
            cells
        };
        let width = *self.width.get_or_insert(cells.len());
        data_row(cells.into_iter(), width, &mut self.values)
            .map(Some)
            .map_err(|e| bad(e.into()))
    }

    /// The layout found in the first rows, once a data row has been read: the row width, and
    /// whether every later row is plain (no DeepLabCut conversion, no track id).
    pub(crate) fn plain_width(&self) -> Option<usize> {
        self.width.filter(|_| !self.dlc && !self.track)
    }

    /// The stream after the rows read so far, and the clock and line count to carry on with.
    pub(crate) fn into_rest(self) -> (R, Clock, usize) {
        (self.reader, self.clock, self.line)
    }
}

/// What [`FrameReader::advance`] read besides the values.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Parsed {
    pub(crate) t: f64,
    /// A value is missing or not finite: the tracker lost the frame.
    pub(crate) lost: bool,
    /// Frames the time step says are missing before this one.
    pub(crate) missing_before: usize,
}

/// A line's text (its bytes, the line end included), checked: not too long, UTF-8.
fn line_text(bytes: &[u8]) -> Result<&str, LineError> {
    if bytes.len() > MAX_LINE_BYTES {
        return Err(LineError::TooLong);
    }
    std::str::from_utf8(bytes).map_err(|_| LineError::NotUtf8)
}

/// One line (its bytes, the line end included) once the layout is known: plain rows of
/// `width` cells. `None` for a blank or comment line; else the row's time, values (appended to
/// `values`: a parsing worker keeps a chunk's rows one after the other) and whether one is
/// lost.
pub(crate) fn plain_line(
    bytes: &[u8],
    width: usize,
    values: &mut Vec<f64>,
) -> Result<Option<(f64, bool)>, LineError> {
    if bytes.len() <= MAX_LINE_BYTES {
        if let Some(t) = plain_row(bytes, width, values) {
            return Ok(Some((t, false)));
        }
    }
    match line_text(bytes)?.trim() {
        "" => Ok(None),
        text if text.starts_with('#') => Ok(None),
        text => {
            let mut row = Vec::with_capacity(width);
            let done = data_row(cells(text), width, &mut row)?;
            values.extend_from_slice(&row);
            Ok(Some(done))
        }
    }
}

/// The times of the complete plain rows `reader` has already buffered (at most
/// [`LOOK_AHEAD`](super::clock::LOOK_AHEAD)), without consuming them; reading stops at the
/// first line that is not such a row.
fn buffered_times(reader: &mut impl BufRead) -> Vec<f64> {
    let Ok(buffered) = reader.fill_buf() else {
        return Vec::new();
    };
    let mut times = Vec::new();
    let mut lines = buffered.split(|&b| b == b'\n');
    // The last piece may be a line cut by the buffer's end.
    let complete = buffered.iter().filter(|&&b| b == b'\n').count();
    for line in lines.by_ref().take(complete.min(super::clock::LOOK_AHEAD)) {
        let Some(t) = std::str::from_utf8(line)
            .ok()
            .and_then(|text| cells(text.trim()).next())
            .and_then(|cell| cell.parse::<f64>().ok())
            .filter(|t| t.is_finite())
        else {
            break;
        };
        times.push(t);
    }
    times
}

/// A line's cells: split at commas (each trimmed) when it has one, else at white space.
pub(crate) fn cells(text: &str) -> impl Iterator<Item = &str> {
    if text.contains(',') {
        itertools::Either::Left(text.split(',').map(str::trim))
    } else {
        itertools::Either::Right(text.split_whitespace())
    }
}

/// A data row of `width` cells (time first) into `values`: its time and whether a value is
/// lost (an empty cell, NaN or ±inf). A wrong width is reported before a bad cell, a bad time
/// before a bad value, the first bad value before later ones.
pub(crate) fn data_row<'t>(
    mut cells: impl Iterator<Item = &'t str>,
    width: usize,
    values: &mut Vec<f64>,
) -> Result<(f64, bool), LineError> {
    values.clear();
    let time = cells.next().unwrap_or_default();
    let (mut count, mut lost, mut error) = (1, false, None);
    for cell in cells {
        count += 1;
        if error.is_some() || count > width {
            continue;
        }
        let v = if cell.is_empty() {
            f64::NAN
        } else if let Ok(v) = cell.parse() {
            v
        } else {
            error = Some(LineError::Cell {
                column: count,
                text: cell.to_string(),
            });
            continue;
        };
        lost |= !v.is_finite();
        values.push(v);
    }
    if count != width {
        return Err(LineError::Width { count, width });
    }
    let t = time
        .parse()
        .ok()
        .filter(|t: &f64| t.is_finite())
        .ok_or_else(|| LineError::Time(time.to_string()))?;
    match error {
        Some(e) => Err(e),
        None => Ok((t, lost)),
    }
}

impl<R: BufRead> Source for FrameReader<R> {
    fn next_row(&mut self) -> Result<Option<Row<'_>>, RecordingError> {
        Ok(self.advance()?.map(|p| Row {
            t: p.t,
            values: (!p.lost).then_some(self.values.as_slice()),
            missing_before: p.missing_before,
            line: self.line,
            projected: None,
        }))
    }

    fn interval(&self) -> Option<f64> {
        self.clock.dt
    }
}

/// The tracks of a file whose first column is a track id, each in time order (rows of one
/// track may be interleaved with others'). Every value is held: the caller bounds the file.
pub(crate) fn read_tracks<R: BufRead>(
    reader: R,
    name: &str,
    settings: &RecordingSettings,
) -> Result<Vec<Track>, RecordingError> {
    let mut frames = FrameReader::new(reader, settings);
    let mut tracks: Vec<Track> = Vec::new();
    let mut index = std::collections::HashMap::new();
    while let Some(row) = frames.advance()? {
        let id = frames.track_id.take().unwrap_or_default();
        let k = *index.entry(id.clone()).or_insert_with(|| {
            tracks.push(Track {
                name: format!("{name}#{id}"),
                frames: Vec::new(),
            });
            tracks.len() - 1
        });
        tracks[k].frames.push(Frame {
            t: row.t,
            values: (!row.lost).then(|| frames.values.clone()),
        });
    }
    for t in &mut tracks {
        t.frames.sort_by(|a, b| a.t.total_cmp(&b.t));
    }
    Ok(tracks)
}
