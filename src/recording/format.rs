//! Which layout a stream holds, from its first bytes (HDF5's signature, WCON's `{`, else text
//! whose DeepLabCut header rows the line reader recognises), the units that layout implies,
//! and a file read whole within a bound (WCON and HDF5 are not read line by line).

use std::io::BufRead;

use super::read::MAX_WHOLE_FILE;
use super::{InputFormat, RecordingError};

/// The format of a stream from its first bytes: HDF5's signature, `{` opens WCON; DeepLabCut's header rows are
/// recognised by the line reader; anything else is plain CSV.
pub(crate) fn sniff(
    reader: &mut Box<dyn BufRead + Send + '_>,
) -> Result<InputFormat, RecordingError> {
    loop {
        let buf = reader.fill_buf().map_err(RecordingError::Io)?;
        let Some(&first) = buf.iter().find(|b| !b.is_ascii_whitespace()) else {
            if buf.is_empty() {
                return Ok(InputFormat::Csv);
            }
            let n = buf.len();
            reader.consume(n);
            continue;
        };
        if buf.starts_with(super::hdf5::SIGNATURE) {
            return Ok(InputFormat::Hdf5);
        }
        return Ok(if first == b'{' {
            InputFormat::Wcon
        } else {
            InputFormat::Csv
        });
    }
}

/// The first cells of DeepLabCut's three header rows; an export opens with the first.
pub(crate) const DLC_HEADERS: [&str; 3] = ["scorer", "bodyparts", "coords"];

/// The time unit of a DeepLabCut export read without `--fps`: its rows hold frame indices.
pub const FRAME_UNIT: &str = "frame";

/// The units a CSV stream's own layout implies: [`FRAME_UNIT`] for a DeepLabCut export (it
/// opens with `scorer`) read without `--fps`, none otherwise. Only peeks.
pub(crate) fn layout_units(
    reader: &mut Box<dyn BufRead + Send + '_>,
    settings: &super::RecordingSettings,
) -> Result<super::Units, RecordingError> {
    let buf = reader.fill_buf().map_err(RecordingError::Io)?;
    let text = String::from_utf8_lossy(&buf[..buf.len().min(64)]);
    let first = text.trim_start().split([',', '\t', ' ', '\n']).next();
    Ok(if first.is_some_and(|c| c.trim() == DLC_HEADERS[0]) {
        frame_units(settings)
    } else {
        super::Units::default()
    })
}

/// The units of a file whose rows hold frame indices (DeepLabCut, SLEAP): [`FRAME_UNIT`]
/// without `--fps`, seconds with it (frames per second).
pub(crate) fn frame_units(settings: &super::RecordingSettings) -> super::Units {
    let unit = if settings.fps.is_some() {
        "s"
    } else {
        FRAME_UNIT
    };
    super::Units {
        time: Some(unit.to_string()),
        length: None,
    }
}

/// A whole stream as text, at most [`MAX_WHOLE_FILE`] bytes (a WCON file).
pub(crate) fn whole(reader: Box<dyn BufRead + Send + '_>) -> Result<String, RecordingError> {
    String::from_utf8(whole_bytes(reader, "a WCON file")?)
        .map_err(|e| RecordingError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// A whole stream, at most [`MAX_WHOLE_FILE`] bytes; `what` names it in the refusal.
pub(crate) fn whole_bytes(
    reader: Box<dyn BufRead + Send + '_>,
    what: &str,
) -> Result<Vec<u8>, RecordingError> {
    use std::io::Read as _;
    let mut bytes = Vec::new();
    std::io::Read::take(reader, MAX_WHOLE_FILE + 1)
        .read_to_end(&mut bytes)
        .map_err(RecordingError::Io)?;
    if bytes.len() as u64 > MAX_WHOLE_FILE {
        return Err(RecordingError::Invalid(format!(
            "{what} is read whole; this one is larger than {MAX_WHOLE_FILE} bytes (split it into chunks)"
        )));
    }
    Ok(bytes)
}
