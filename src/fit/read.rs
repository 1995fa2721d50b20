//! Reading recordings: one frame per line (plain CSV or white space, or DeepLabCut exports),
//! optionally led by a track id; lost frames (missing values, skipped time steps) as rows
//! without values; lines and files bounded. Every source of frames (a text stream, a track held
//! in memory) answers the same [`Source`] questions.

use std::io::BufRead;

use super::{FitError, FitSettings, InputFormat};
use crate::markup::clip;
use crate::report::number;

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
pub(super) trait Source {
    /// The next row, or `None` at the end.
    fn next_row(&mut self) -> Result<Option<Row>, FitError>;
    /// Where the last row came from (line or frame, 1-based), for messages.
    fn line(&self) -> usize;
    /// The sampling interval seen (the first time step).
    fn interval(&self) -> Option<f64>;
}

/// The sampling clock: the first time step is the interval; later steps must be whole numbers
/// of it (within 1 %), the surplus being frames missing from the file.
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

/// A time column that is not a uniform clock.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClockError {
    /// Time went backwards or stood still.
    #[error("time {} does not increase (previous {})", number(*.t), number(*.last))]
    NotIncreasing {
        /// This frame's time.
        t: f64,
        /// The previous frame's time.
        last: f64,
    },
    /// A step that is not a whole number of sampling intervals.
    #[error("time step {} after t = {} is not a whole number of sampling intervals {}", number(*.gap), number(*.last), number(*.dt))]
    Uneven {
        /// The step.
        gap: f64,
        /// The previous frame's time.
        last: f64,
        /// The sampling interval (the first step).
        dt: f64,
    },
}

#[derive(Debug, Default)]
pub(super) struct Clock {
    last_t: Option<f64>,
    pub(super) dt: Option<f64>,
}

impl Clock {
    /// Check the step to `t`; returns how many frames are missing before it.
    pub(super) fn step(&mut self, t: f64) -> Result<usize, ClockError> {
        let Some(last) = self.last_t.replace(t) else {
            return Ok(0);
        };
        let gap = t - last;
        if gap <= 0.0 {
            return Err(ClockError::NotIncreasing { t, last });
        }
        let dt = *self.dt.get_or_insert(gap);
        let steps = (gap / dt).round();
        if steps >= 1.0 && (gap - steps * dt).abs() <= 0.01 * dt * steps.max(1.0) {
            // Frames missing before this one; a step of absurd length is one long gap.
            Ok((steps as usize).saturating_sub(1))
        } else {
            Err(ClockError::Uneven { gap, last, dt })
        }
    }
}

/// A track in memory as a [`Source`].
pub(super) struct TrackSource {
    frames: std::vec::IntoIter<Frame>,
    index: usize,
    clock: Clock,
}

impl TrackSource {
    pub(super) fn new(track: Track) -> TrackSource {
        TrackSource {
            frames: track.frames.into_iter(),
            index: 0,
            clock: Clock::default(),
        }
    }
}

impl Source for TrackSource {
    fn next_row(&mut self) -> Result<Option<Row>, FitError> {
        let Some(frame) = self.frames.next() else {
            return Ok(None);
        };
        self.index += 1;
        let bad = |why: String| FitError::Line {
            line: self.index,
            why,
        };
        if !frame.t.is_finite() {
            return Err(bad(format!("frame {}: time is not finite", self.index)));
        }
        let missing_before = self.clock.step(frame.t).map_err(|e| bad(e.to_string()))?;
        let values = frame.values.filter(|v| v.iter().all(|x| x.is_finite()));
        Ok(Some(Row {
            t: frame.t,
            values,
            missing_before,
            track: None,
        }))
    }

    fn line(&self) -> usize {
        self.index
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
pub(super) struct FrameReader<R> {
    reader: R,
    buf: Vec<u8>,
    /// The line last read (1-based).
    pub(super) line: usize,
    width: Option<usize>,
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
}

impl<R: BufRead> FrameReader<R> {
    pub(super) fn new(reader: R, settings: &FitSettings) -> Self {
        FrameReader {
            reader,
            buf: Vec::new(),
            line: 0,
            width: None,
            seen_data: false,
            clock: Clock::default(),
            track: settings.track_column,
            dlc: false,
            fps: settings.fps,
            min_likelihood: settings.min_likelihood,
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

    /// The next line, read at most [`MAX_LINE_BYTES`] at a time.
    fn next_line(&mut self) -> Result<Option<String>, FitError> {
        use std::io::Read;
        self.buf.clear();
        let read = (&mut self.reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut self.buf)
            .map_err(FitError::Io)?;
        if read == 0 {
            return Ok(None);
        }
        self.line += 1;
        if self.buf.len() > MAX_LINE_BYTES {
            return Err(FitError::Line {
                line: self.line,
                why: format!("longer than {MAX_LINE_BYTES} bytes: not a recording of midlines"),
            });
        }
        String::from_utf8(std::mem::take(&mut self.buf))
            .map(Some)
            .map_err(|_| FitError::Line {
                line: self.line,
                why: "is not UTF-8 text".into(),
            })
    }

    /// The next row: a frame, or a frame the tracker lost (a missing or non-finite value), with
    /// the frames the time step says are missing before it.
    pub(super) fn next_row(&mut self) -> Result<Option<Row>, FitError> {
        loop {
            let Some(text) = self.next_line()? else {
                return Ok(None);
            };
            let text = text.trim();
            if text.is_empty() || text.starts_with('#') {
                continue;
            }
            let cells: Vec<&str> = if text.contains(',') {
                text.split(',').map(str::trim).collect()
            } else {
                text.split_whitespace().collect()
            };
            // DeepLabCut's three header rows; otherwise only the first line may be a header.
            if !self.seen_data && cells[0] == "individuals" {
                return Err(FitError::Line {
                    line: self.line,
                    why: "a multi-animal DeepLabCut export: export one file per individual (each is one animal)".into(),
                });
            }
            if !self.seen_data && matches!(cells[0], "scorer" | "bodyparts" | "coords") {
                self.dlc = true;
                continue;
            }
            let first_number = cells[usize::from(self.track).min(cells.len() - 1)];
            if !self.seen_data && !self.dlc && first_number.parse::<f64>().is_err() {
                self.seen_data = true;
                continue;
            }
            self.seen_data = true;
            let line = self.line;
            let bad = |why: String| FitError::Line { line, why };
            let mut cells = cells;
            let track = if self.track {
                if cells.len() < 2 {
                    return Err(bad("a track id and then time are needed".into()));
                }
                Some(super::checked_name(cells.remove(0)).map_err(|e| bad(e.to_string()))?)
            } else {
                None
            };
            let converted;
            let cells: Vec<&str> = if self.dlc {
                converted = self.dlc_row(&cells).map_err(|e| bad(e.to_string()))?;
                converted.iter().map(String::as_str).collect()
            } else {
                cells
            };
            match self.width {
                None => self.width = Some(cells.len()),
                Some(w) if w != cells.len() => {
                    return Err(bad(format!(
                        "{} columns where the first frame had {w}",
                        cells.len()
                    )))
                }
                _ => {}
            }
            let t: f64 = cells[0]
                .parse()
                .ok()
                .filter(|t: &f64| t.is_finite())
                .ok_or_else(|| {
                    bad(format!(
                        "column 1: time {:?} is not a finite number",
                        cells[0]
                    ))
                })?;
            let mut values = Vec::with_capacity(cells.len() - 1);
            let mut lost = false;
            for (c, cell) in cells.iter().enumerate().skip(1) {
                // An empty cell, NaN or ±inf: the tracker lost this frame.
                let v: f64 = if cell.is_empty() {
                    f64::NAN
                } else {
                    cell.parse().map_err(|_| {
                        bad(format!("column {}: {} is not a number", c + 1, clip(cell)))
                    })?
                };
                lost |= !v.is_finite();
                values.push(v);
            }
            let missing_before = if self.track {
                0
            } else {
                self.clock.step(t).map_err(|e| bad(e.to_string()))?
            };
            return Ok(Some(Row {
                t,
                values: (!lost).then_some(values),
                missing_before,
                track,
            }));
        }
    }
}

impl<R: BufRead> Source for FrameReader<R> {
    fn next_row(&mut self) -> Result<Option<Row>, FitError> {
        FrameReader::next_row(self)
    }

    fn line(&self) -> usize {
        self.line
    }

    fn interval(&self) -> Option<f64> {
        self.clock.dt
    }
}

/// One row of a recording.
pub(super) struct Row {
    pub(super) t: f64,
    /// The frame's values after t; `None` when the tracker lost it.
    pub(super) values: Option<Vec<f64>>,
    /// Frames missing from the file just before this row (from the time step).
    pub(super) missing_before: usize,
    /// The row's track id, when the first column holds one.
    pub(super) track: Option<String>,
}

/// The tracks of a file whose first column is a track id, each in time order (rows of one
/// track may be interleaved with others'). Every value is held: the caller bounds the file.
pub(super) fn read_tracks<R: BufRead>(
    reader: R,
    name: &str,
    settings: &FitSettings,
) -> Result<Vec<Track>, FitError> {
    let mut frames = FrameReader::new(reader, settings);
    let mut tracks: Vec<Track> = Vec::new();
    let mut index = std::collections::HashMap::new();
    while let Some(row) = frames.next_row()? {
        let id = row.track.unwrap_or_default();
        let k = *index.entry(id.clone()).or_insert_with(|| {
            tracks.push(Track {
                name: format!("{name}#{id}"),
                frames: Vec::new(),
            });
            tracks.len() - 1
        });
        tracks[k].frames.push(Frame {
            t: row.t,
            values: row.values,
        });
    }
    for t in &mut tracks {
        t.frames.sort_by(|a, b| a.t.total_cmp(&b.t));
    }
    Ok(tracks)
}

/// The format of a stream from its first bytes: `{` opens WCON; DeepLabCut's header rows are
/// recognised by the line reader; anything else is plain CSV.
pub(super) fn sniff(reader: &mut Box<dyn BufRead + Send + '_>) -> Result<InputFormat, FitError> {
    loop {
        let buf = reader.fill_buf().map_err(FitError::Io)?;
        let Some(&first) = buf.iter().find(|b| !b.is_ascii_whitespace()) else {
            if buf.is_empty() {
                return Ok(InputFormat::Csv);
            }
            let n = buf.len();
            reader.consume(n);
            continue;
        };
        return Ok(if first == b'{' {
            InputFormat::Wcon
        } else {
            InputFormat::Csv
        });
    }
}

/// A whole stream as text, at most [`MAX_WHOLE_FILE`] bytes.
pub(super) fn whole(reader: Box<dyn BufRead + Send + '_>) -> Result<String, FitError> {
    use std::io::Read as _;
    let mut text = String::new();
    std::io::Read::take(reader, MAX_WHOLE_FILE + 1)
        .read_to_string(&mut text)
        .map_err(FitError::Io)?;
    if text.len() as u64 > MAX_WHOLE_FILE {
        return Err(FitError::Invalid(format!(
            "a WCON file is read whole; this one is larger than {MAX_WHOLE_FILE} bytes (split it into chunks)"
        )));
    }
    Ok(text)
}
