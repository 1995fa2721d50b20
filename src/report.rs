//! One small trait for every result the tool prints: text for people, JSON for programs, and
//! CSV for the results that are tables. Each result type implements it beside its own
//! definition; the command line only picks the format.

use std::io::{self, Write};

use clap::ValueEnum;

/// How a result is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Output {
    /// Aligned text for reading.
    Text,
    /// JSON: one document.
    Json,
    /// CSV: a header, then one row per record (fields quoted where needed).
    Csv,
}

/// A printable result.
pub trait Report {
    /// Text for people.
    fn text(&self) -> String;
    /// The JSON value.
    fn json(&self) -> serde_json::Value;
    /// The result as one CSV table, if it is one.
    fn csv(&self) -> Option<String> {
        None
    }
    /// Every number the result holds is finite (checked before any format is written); a
    /// result type that serializes implements it as [`check_finite`]`(self)`.
    fn check(&self) -> Result<(), NonFinite> {
        Ok(())
    }
    /// Write the text to `out`; a large result streams it instead of building it.
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        out.write_all(self.text().as_bytes())
    }
    /// Write the JSON (pretty, one trailing newline) to `out`; a large result serializes
    /// itself as it writes instead of building a value.
    fn write_json(&self, out: &mut dyn Write) -> io::Result<()> {
        json_to(out, &self.json())
    }
    /// Write the CSV to `out`, if the result is a table.
    fn write_csv(&self, out: &mut dyn Write) -> Option<io::Result<()>> {
        self.csv().map(|s| out.write_all(s.as_bytes()))
    }
}

/// Why a result was not written.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    /// The result cannot take this form (a non-finite number, no CSV form).
    #[error("{0}")]
    Refused(String),
    /// The output failed.
    #[error("cannot write output: {0}")]
    Io(#[from] io::Error),
}

/// Write `report` in `format` to `out` as it is formatted.
pub fn emit(report: &dyn Report, format: Output, out: &mut dyn Write) -> Result<(), EmitError> {
    report.check().map_err(|e| EmitError::Refused(e.0))?;
    match format {
        Output::Text => report.write_text(out)?,
        Output::Json => report.write_json(out)?,
        Output::Csv => report.write_csv(out).ok_or_else(|| {
            EmitError::Refused("this result has no CSV form: use --format text or json".into())
        })??,
    }
    Ok(out.flush()?)
}

/// `report` in `format` as a string, or why it has no such form.
pub fn render(report: &dyn Report, format: Output) -> Result<String, EmitError> {
    let mut out = Vec::new();
    emit(report, format, &mut out)?;
    Ok(String::from_utf8(out).unwrap_or_default())
}

/// `value` as pretty JSON and a newline, serialized straight to `out` (buffered).
pub fn json_to(out: &mut dyn Write, value: &impl serde::Serialize) -> io::Result<()> {
    let mut w = io::BufWriter::with_capacity(1 << 16, out);
    serde_json::to_writer_pretty(&mut w, value)?;
    w.write_all(b"\n")?;
    w.flush()
}

/// A `csv` crate error as the I/O error it wraps, kind kept (a closed pipe stays one).
pub fn csv_io(e: csv::Error) -> io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(e) => e,
        other => io::Error::other(format!("{other:?}")),
    }
}

/// What a streaming writer writes, as a string (for the `String` forms and tests).
pub fn to_string(write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> String {
    let mut out = Vec::new();
    // Writing to memory cannot fail.
    let _ = write(&mut out);
    String::from_utf8(out).unwrap_or_default()
}

/// A CSV table of `header` and `rows` of cells, written with the `csv` crate (so a cell with a
/// comma, quote or newline is quoted).
pub fn csv_table<H: AsRef<str>, C: AsRef<str>>(
    header: &[H],
    rows: impl IntoIterator<Item = Vec<C>>,
) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    // Writing to memory cannot fail.
    let _ = w.write_record(header.iter().map(|h| h.as_ref()));
    for row in rows {
        let _ = w.write_record(row.iter().map(|c| c.as_ref()));
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// A CSV table of numbers (each written as Rust's shortest round-trip form).
pub fn csv_numbers<H: AsRef<str>>(
    header: &[H],
    rows: impl IntoIterator<Item = Vec<f64>>,
) -> String {
    csv_table(
        header,
        rows.into_iter()
            .map(|r| r.iter().map(|v| v.to_string()).collect::<Vec<_>>()),
    )
}

/// The longest line a text report prints before it wraps ([`wrap_long`]).
pub const MAX_LINE: usize = 160;

/// Each line of `text` longer than `width` characters broken at spaces, the continuation lines
/// indented four spaces past the line's own indent. A line holding a command to copy
/// (`theory-search …`) is left whole.
pub fn wrap_long(text: &str, width: usize) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches('\n');
        if body.chars().count() <= width || body.contains("theory-search ") {
            out.push_str(line);
            continue;
        }
        let indent = body.len() - body.trim_start().len();
        let pad = " ".repeat(indent + 4);
        let mut rest = body;
        let mut first = true;
        loop {
            let room = if first { width } else { width - pad.len() };
            let prefix = if first { "" } else { pad.as_str() };
            if rest.chars().count() <= room {
                out.push_str(prefix);
                out.push_str(rest);
                break;
            }
            // The last space within `room` characters (past the indent), else the first after.
            let cut = rest
                .char_indices()
                .take(room + 1)
                .filter(|&(i, c)| c == ' ' && i > indent)
                .map(|(i, _)| i)
                .last()
                .or_else(|| {
                    rest.char_indices()
                        .skip(room)
                        .find(|&(_, c)| c == ' ')
                        .map(|(i, _)| i)
                });
            let Some(cut) = cut else {
                out.push_str(prefix);
                out.push_str(rest);
                break;
            };
            out.push_str(prefix);
            out.push_str(rest[..cut].trim_end());
            out.push('\n');
            rest = rest[cut..].trim_start();
            first = false;
        }
        if line.ends_with('\n') {
            out.push('\n');
        }
    }
    out
}

/// `v` with `digits` decimals (`{:.6}`) for ordinary magnitudes, and in exponent form with as
/// many significant decimals where that would print hundreds of digits or only zeros.
pub fn fixed(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e12).contains(&v.abs()) {
        format!("{v:.digits$}")
    } else {
        format!("{v:.digits$e}")
    }
}

/// A number as the user typed it: plain for ordinary magnitudes, exponent form (`1e300`) where
/// plain would print hundreds of digits.
pub fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-6..1e15).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `v` to five significant digits, as [`number`] prints it (`0.025165`, `1.2346e-7`).
pub fn short(v: f64) -> String {
    number(format!("{v:.4e}").parse().unwrap_or(v))
}

/// Serialize `value` to a JSON value (every result type is plain data).
pub fn to_json(value: &impl serde::Serialize) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or_default()
}

/// Text written to an output in chunks: lines gather in a buffer that goes out every 64 KiB,
/// so a table of 10⁵ rows never sits whole in memory.
pub struct Chunked<'a> {
    buf: String,
    out: &'a mut dyn std::io::Write,
}

impl<'a> Chunked<'a> {
    const CHUNK: usize = 1 << 16;

    /// Chunks to `out`.
    pub fn new(out: &'a mut dyn std::io::Write) -> Self {
        Chunked {
            buf: String::with_capacity(Self::CHUNK + 1024),
            out,
        }
    }

    /// The buffer to append to.
    pub fn buf(&mut self) -> &mut String {
        &mut self.buf
    }

    /// Append one formatted line.
    pub fn say(&mut self, line: std::fmt::Arguments) {
        // Formatting into a String cannot fail.
        let _ = std::fmt::Write::write_fmt(&mut self.buf, line);
        self.buf.push('\n');
    }

    /// Send the buffer on once it is a chunk long.
    pub fn spill(&mut self) -> std::io::Result<()> {
        if self.buf.len() >= Self::CHUNK {
            self.out.write_all(self.buf.as_bytes())?;
            self.buf.clear();
        }
        Ok(())
    }

    /// Send what is left and flush.
    pub fn finish(&mut self) -> std::io::Result<()> {
        self.out.write_all(self.buf.as_bytes())?;
        self.buf.clear();
        self.out.flush()
    }
}

/// Columns padded to their widest cell: the first (a term, a label) left-aligned, the others
/// centred under their headers, two spaces between, no trailing spaces. Widths are fitted to
/// every row first ([`Aligned::fit`]); rows are then written one at a time.
pub struct Aligned {
    widths: Vec<usize>,
}

/// Display width of a cell: one column per character (the tables use no wide characters).
fn width(s: &str) -> usize {
    if s.is_ascii() {
        s.len()
    } else {
        s.chars().count()
    }
}

fn spaces(out: &mut String, n: usize) {
    out.extend(std::iter::repeat_n(' ', n));
}

impl Aligned {
    /// Columns as wide as the header's cells.
    pub fn new<S: AsRef<str>>(header: &[S]) -> Aligned {
        Aligned {
            widths: header.iter().map(|h| width(h.as_ref())).collect(),
        }
    }

    /// Widen the columns to hold `cells`.
    pub fn fit<S: AsRef<str>>(&mut self, cells: &[S]) {
        for (w, c) in self.widths.iter_mut().zip(cells) {
            *w = (*w).max(width(c.as_ref()));
        }
    }

    /// Append one line of `cells`.
    pub fn line<S: AsRef<str>>(&self, cells: &[S], out: &mut String) {
        out.push_str("  ");
        for (i, (c, &w)) in cells.iter().zip(&self.widths).enumerate() {
            let c = c.as_ref();
            let pad = w.saturating_sub(width(c));
            if i == 0 {
                out.push_str(c);
                spaces(out, pad);
            } else {
                out.push_str("  ");
                spaces(out, pad / 2);
                out.push_str(c);
                spaces(out, pad - pad / 2);
            }
        }
        let kept = out.trim_end_matches(' ').len();
        out.truncate(kept);
        out.push('\n');
    }

    /// Append the rule under the header.
    pub fn rule(&self, out: &mut String) {
        let total = self.widths.iter().sum::<usize>() + 2 * self.widths.len().saturating_sub(1);
        out.push_str("  ");
        out.extend(std::iter::repeat_n('─', total));
        out.push('\n');
    }
}

/// Why a result cannot be printed: a number in it is not finite.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct NonFinite(pub String);

impl serde::ser::Error for NonFinite {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        NonFinite(msg.to_string())
    }
}

/// `Ok` when every number `value` serializes is finite; otherwise names the first field that
/// is not (a result with NaN or ±∞ is refused, never printed).
pub fn check_finite(value: &impl serde::Serialize) -> Result<(), NonFinite> {
    value.serialize(&mut FiniteCheck { path: Vec::new() })
}

/// A serializer that writes nothing and fails on the first non-finite float.
struct FiniteCheck {
    path: Vec<String>,
}

impl FiniteCheck {
    fn float(&self, v: f64) -> Result<(), NonFinite> {
        if v.is_finite() {
            Ok(())
        } else {
            let at = if self.path.is_empty() {
                "the result".to_string()
            } else {
                self.path.join(".")
            };
            Err(NonFinite(format!(
                "{at} came out {v}: the inputs are beyond what this computation can represent"
            )))
        }
    }
}

macro_rules! accept {
    ($($name:ident: $t:ty),*) => {
        $(fn $name(self, _: $t) -> Result<(), NonFinite> { Ok(()) })*
    };
}

impl serde::Serializer for &mut FiniteCheck {
    type Ok = ();
    type Error = NonFinite;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;

    accept!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
        serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
        serialize_u64: u64, serialize_char: char, serialize_str: &str, serialize_bytes: &[u8],
        serialize_unit_struct: &'static str);

    fn serialize_f32(self, v: f32) -> Result<(), NonFinite> {
        self.float(v as f64)
    }
    fn serialize_f64(self, v: f64) -> Result<(), NonFinite> {
        self.float(v)
    }
    fn serialize_none(self) -> Result<(), NonFinite> {
        Ok(())
    }
    fn serialize_some<T: ?Sized + serde::Serialize>(self, v: &T) -> Result<(), NonFinite> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), NonFinite> {
        Ok(())
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
    ) -> Result<(), NonFinite> {
        Ok(())
    }
    fn serialize_newtype_struct<T: ?Sized + serde::Serialize>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), NonFinite> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + serde::Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        v: &T,
    ) -> Result<(), NonFinite> {
        v.serialize(self)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_tuple(self, _: usize) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, NonFinite> {
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, NonFinite> {
        Ok(self)
    }
}

impl FiniteCheck {
    fn field<T: ?Sized + serde::Serialize>(&mut self, key: &str, v: &T) -> Result<(), NonFinite> {
        self.path.push(key.to_string());
        v.serialize(&mut *self)?;
        self.path.pop();
        Ok(())
    }
}

macro_rules! elements {
    ($($tr:ident :: $m:ident),*) => {
        $(impl serde::ser::$tr for &mut FiniteCheck {
            type Ok = ();
            type Error = NonFinite;
            fn $m<T: ?Sized + serde::Serialize>(&mut self, v: &T) -> Result<(), NonFinite> {
                v.serialize(&mut **self)
            }
            fn end(self) -> Result<(), NonFinite> {
                Ok(())
            }
        })*
    };
}

elements!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field,
    SerializeTupleVariant::serialize_field
);

impl serde::ser::SerializeMap for &mut FiniteCheck {
    type Ok = ();
    type Error = NonFinite;
    fn serialize_key<T: ?Sized + serde::Serialize>(&mut self, _: &T) -> Result<(), NonFinite> {
        Ok(())
    }
    fn serialize_value<T: ?Sized + serde::Serialize>(&mut self, v: &T) -> Result<(), NonFinite> {
        v.serialize(&mut **self)
    }
    fn end(self) -> Result<(), NonFinite> {
        Ok(())
    }
}

macro_rules! fields {
    ($($tr:ident),*) => {
        $(impl serde::ser::$tr for &mut FiniteCheck {
            type Ok = ();
            type Error = NonFinite;
            fn serialize_field<T: ?Sized + serde::Serialize>(
                &mut self,
                key: &'static str,
                v: &T,
            ) -> Result<(), NonFinite> {
                self.field(key, v)
            }
            fn end(self) -> Result<(), NonFinite> {
                Ok(())
            }
        })*
    };
}

fields!(SerializeStruct, SerializeStructVariant);

#[cfg(test)]
mod wrap_tests {
    use super::*;

    #[test]
    fn long_lines_wrap_at_spaces_and_commands_stay_whole() {
        let long = format!("  {}\n", "word ".repeat(50).trim_end());
        let wrapped = wrap_long(&long, 40);
        assert!(
            wrapped.lines().all(|l| l.chars().count() <= 40),
            "{wrapped}"
        );
        assert!(wrapped.lines().skip(1).all(|l| l.starts_with("      word")));
        assert_eq!(wrapped.split_whitespace().count(), 50);
        let command = format!("  onward: theory-search simulate {}\n", "--x 1 ".repeat(40));
        assert_eq!(wrap_long(&command, 40), command);
        assert_eq!(wrap_long("short\n", 40), "short\n");
    }
}
