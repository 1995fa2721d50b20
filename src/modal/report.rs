//! The `modes` result in text, JSON and CSV, each written to the output as it is formatted: at
//! N = 10⁶ the tables have millions of cells, so no format builds its whole output first (JSON
//! is serialized without a value tree; text formats one field's cells once into an arena, fits
//! the columns, and writes the lines).

use std::cell::Cell;
use std::fmt::Write as _;
use std::io::{self, Write};

use serde::ser::{Serialize, SerializeMap, Serializer};

use super::{BeamComparison, FieldModes, Mode};
use crate::model::Model;
use crate::report::{Aligned, Chunked, NonFinite, Report};

/// `modes`: every field's modes on N points, with shapes when asked.
pub struct ModesReport<'a> {
    /// The model.
    pub model: &'a Model,
    /// Points along the body.
    pub points: usize,
    /// The modes of each field.
    pub modes: &'a [FieldModes],
    /// Whether the shapes go into the CSV.
    pub shapes: bool,
}

/// `0.1234` style: 6 significant digits, scientific outside 1e-4…1e6.
fn num(out: &mut String, v: f64) {
    if v == 0.0 {
        out.push('0');
    } else if v.abs() >= 1e-4 && v.abs() < 1e6 {
        let digits = (5 - v.abs().log10().floor() as i32).clamp(0, 10) as usize;
        let start = out.len();
        let _ = write!(out, "{v:.digits$}");
        if out[start..].contains('.') {
            let kept = out.trim_end_matches('0').trim_end_matches('.').len();
            out.truncate(kept);
        }
    } else {
        let _ = write!(out, "{v:.5e}");
    }
}

fn num_string(v: f64) -> String {
    let mut s = String::new();
    num(&mut s, v);
    s
}

/// Cells of a table kept in one string: each cell is a range of it (no string per cell).
struct Arena {
    text: String,
    ends: Vec<usize>,
}

impl Arena {
    /// End the cell being written.
    fn cut(&mut self) {
        self.ends.push(self.text.len());
    }

    /// The cells of row `r` of `width` cells.
    fn row<'a>(&'a self, r: usize, width: usize, cells: &mut Vec<&'a str>) {
        cells.clear();
        let first = r * width;
        let mut start = if first == 0 { 0 } else { self.ends[first - 1] };
        for &end in &self.ends[first..first + width] {
            cells.push(&self.text[start..end]);
            start = end;
        }
    }
}

/// One mode's row of the text table into `arena`: `width` cells.
fn text_row(arena: &mut Arena, m: &Mode, beam: Option<&BeamComparison>, columns: (bool, bool)) {
    let (eq17, with_beam) = columns;
    let a = arena;
    let _ = write!(a.text, "{}", m.index);
    a.cut();
    for v in [m.eigenvalue, m.frequency, m.damping_ratio] {
        num(&mut a.text, v);
        a.cut();
    }
    match m.damped_frequency {
        Some(v) => num(&mut a.text, v),
        None => a.text.push('—'),
    }
    a.cut();
    match &m.zero_mode {
        Some(z) => {
            let _ = write!(a.text, "zero mode: {z}");
        }
        None => a.text.push_str(m.regime.name()),
    }
    a.cut();
    for v in [m.variance_share, m.cumulative_share] {
        let _ = write!(a.text, "{:.2} %", 100.0 * v);
        a.cut();
    }
    if !with_beam {
        return;
    }
    match beam {
        Some(b) => {
            let off = |text: &mut String, x: f64| {
                let r = 100.0 * (x - b.eigenvalue) / b.eigenvalue;
                let _ = if r.abs() >= 0.01 {
                    write!(text, "{r:+.2} %")
                } else {
                    write!(text, "{r:+.1e} %")
                };
            };
            let mut pair = |x: f64| {
                num(&mut a.text, x);
                a.cut();
                off(&mut a.text, x);
                a.cut();
            };
            if let Some(e) = b.seed_eq17 {
                pair(e);
            }
            pair(b.continuum);
        }
        None => {
            for _ in 0..if eq17 { 4 } else { 2 } {
                a.cut();
            }
        }
    }
}

/// One field's table and notes.
fn text_field(f: &FieldModes, out: &mut Chunked) -> io::Result<()> {
    let sp = &f.spectrum;
    let scale = f.field.scale();
    out.say(format_args!(
        "\n{} ({}) · {} boundary\n  Δ{} operator, {} modes ({}) · ω_{scale} = {}, ζ_{scale} = {} · Σλ⁻¹ = {}",
        f.field.id,
        f.field.meaning,
        f.field.boundary.name(),
        crate::term::superscript(f.k),
        sp.size,
        sp.method.name(),
        num_string(f.omega),
        num_string(f.zeta),
        num_string(sp.inverse_trace),
    ));
    if let Some(other) = &f.same_frequencies_as {
        // A twin's table would repeat the other's row for row (z is y's twin): say so instead.
        out.say(format_args!(
            "  same operator, ends and scales as {other}: the same modes (the table above; JSON and CSV list them)"
        ));
        return Ok(());
    }
    let with_beam = !f.beam.is_empty();
    let eq17 = f.beam.iter().any(|b| b.seed_eq17.is_some());
    let mut header = vec![
        "i",
        "λᵢ",
        "ωᵢ",
        "ζᵢ",
        "ω_d",
        "regime",
        "share",
        "cumulative",
    ];
    if eq17 {
        header.extend(["Eq. 17", "off"]);
    }
    if with_beam {
        header.extend(["beam limit", "off"]);
    }
    // Each mode's beam comparison by index: one lookup per row, not a scan (O(N²) at N = 10⁵).
    let beams: std::collections::HashMap<usize, &BeamComparison> =
        f.beam.iter().map(|b| (b.index, b)).collect();
    let mut arena = Arena {
        text: String::new(),
        ends: Vec::with_capacity(f.modes.len() * header.len()),
    };
    for m in &f.modes {
        text_row(
            &mut arena,
            m,
            beams.get(&m.index).copied(),
            (eq17, with_beam),
        );
    }
    let mut layout = Aligned::new(&header);
    let mut cells = Vec::with_capacity(header.len());
    for r in 0..f.modes.len() {
        arena.row(r, header.len(), &mut cells);
        layout.fit(&cells);
    }
    layout.line(&header, out.buf());
    layout.rule(out.buf());
    for r in 0..f.modes.len() {
        arena.row(r, header.len(), &mut cells);
        layout.line(&cells, out.buf());
        out.spill()?;
    }
    drop(arena);
    text_notes(f, eq17, with_beam, out)
}

fn text_notes(f: &FieldModes, eq17: bool, with_beam: bool, out: &mut Chunked) -> io::Result<()> {
    if !f.degenerate_pairs.is_empty() {
        // A ring of N points has N/2 pairs: one long line, written in chunks too.
        out.buf().push_str("  degenerate pairs:");
        for (i, j) in &f.degenerate_pairs {
            let _ = write!(out.buf(), " ({i}, {j})");
            out.spill()?;
        }
        out.buf().push('\n');
    }
    if eq17 {
        // Eq. 17's limit (iπ)⁴ against the beam's (β₁L)⁴, for the first mode.
        let gap = 100.0 * ((std::f64::consts::PI / super::beam_beta(1)).powi(4) - 1.0);
        out.say(format_args!("  Eq. 17 is the paper's 16 sin⁴(πi/(2(N−1))); the beam limit is (βᵢL)⁴/(N−1)⁴ with cos βL cosh βL = 1."));
        out.say(format_args!("{}", format!("  As N grows the numerics converge to the beam limit; Eq. 17 tends to (iπ)⁴/(N−1)⁴ and stays off\n  ({gap:+.1} % for the first mode): the paper's claim that it becomes exact is false.").replace('-', "−")));
    } else if with_beam {
        out.say(format_args!(
            "  The beam limit is (βᵢL)⁴/(N−1)⁴ of the continuous Euler–Bernoulli beam with these ends ({}).",
            f.field.boundary.name()
        ));
    }
    if let Some(v) = &f.spectrum.shapes {
        out.say(format_args!("  shapes (columns = modes):"));
        for i in 0..v.nrows() {
            let buf = out.buf();
            buf.push(' ');
            for c in 0..v.ncols() {
                let _ = write!(buf, " {:>9.5}", v[(i, c)]);
            }
            buf.push('\n');
            out.spill()?;
        }
    }
    Ok(())
}

/// The modes of every field, a table each, readable at a glance.
fn write_text(r: &ModesReport, out: &mut dyn Write) -> io::Result<()> {
    let mut out = Chunked::new(out);
    out.say(format_args!(
        "Modes of the {} model on N = {} points",
        r.model.name, r.points
    ));
    out.say(format_args!("ωᵢ = ω√λᵢ, ζᵢ = ζ√λᵢ, ω_d = ωᵢ√(1−ζᵢ²); share = λᵢ⁻¹/Σλⱼ⁻¹ over all non-zero modes (equipartition)."));
    for f in r.modes {
        text_field(f, &mut out)?;
    }
    out.finish()
}

/// A sequence serialized from an iterator as it is written (taken once).
struct Seq<I>(Cell<Option<I>>);

fn seq<I>(items: I) -> Seq<I> {
    Seq(Cell::new(Some(items)))
}

impl<I: Iterator<Item = T>, T: Serialize> Serialize for Seq<I> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.0.take().into_iter().flatten())
    }
}

/// One field of the JSON contract of `modes`.
struct JsonField<'a>(&'a FieldModes);

impl Serialize for JsonField<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let f = self.0;
        let modes = || f.modes.iter();
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("field", &f.field.id)?;
        m.serialize_entry("boundary", &f.field.boundary.name())?;
        m.serialize_entry("size", &f.spectrum.size)?;
        m.serialize_entry("method", &f.spectrum.method.name())?;
        m.serialize_entry("omega", &f.omega)?;
        m.serialize_entry("zeta", &f.zeta)?;
        m.serialize_entry("eigenvalues", &seq(modes().map(|m| m.eigenvalue)))?;
        m.serialize_entry("frequencies", &seq(modes().map(|m| m.frequency)))?;
        m.serialize_entry("damping_ratios", &seq(modes().map(|m| m.damping_ratio)))?;
        m.serialize_entry(
            "damped_frequencies",
            &seq(modes().map(|m| m.damped_frequency)),
        )?;
        m.serialize_entry("regimes", &seq(modes().map(|m| m.regime.name())))?;
        m.serialize_entry("variance_share", &seq(modes().map(|m| m.variance_share)))?;
        m.serialize_entry(
            "cumulative_share",
            &seq(modes().map(|m| m.cumulative_share)),
        )?;
        m.serialize_entry("inverse_eigenvalue_sum", &f.spectrum.inverse_trace)?;
        let zero = || modes().filter(|m| m.zero_mode.is_some());
        m.serialize_entry("zero_modes", &seq(zero().map(|m| m.index)))?;
        m.serialize_entry(
            "zero_mode_names",
            &seq(modes().filter_map(|m| m.zero_mode.as_deref())),
        )?;
        m.serialize_entry(
            "degenerate_pairs",
            &seq(f.degenerate_pairs.iter().map(|&(i, j)| [i, j])),
        )?;
        m.serialize_entry("same_frequencies_as", &f.same_frequencies_as)?;
        if !f.beam.is_empty() {
            m.serialize_entry("beam_comparison", &seq(f.beam.iter().map(JsonBeam)))?;
        }
        if let Some(v) = &f.spectrum.shapes {
            let column = |c: usize| seq((0..v.nrows()).map(move |i| v[(i, c)]));
            m.serialize_entry("shapes", &seq((0..v.ncols()).map(column)))?;
        }
        m.end()
    }
}

struct JsonBeam<'a>(&'a BeamComparison);

impl Serialize for JsonBeam<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let b = self.0;
        let mut m = s.serialize_map(Some(4))?;
        m.serialize_entry("index", &b.index)?;
        m.serialize_entry("eigenvalue", &b.eigenvalue)?;
        m.serialize_entry("seed_eq17", &b.seed_eq17)?;
        m.serialize_entry("continuum", &b.continuum)?;
        m.end()
    }
}

/// The JSON contract of `modes`: `{"points": N, "fields": [...]}`.
struct Json<'a>(&'a ModesReport<'a>);

impl Serialize for Json<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("points", &self.0.points)?;
        m.serialize_entry("fields", &seq(self.0.modes.iter().map(JsonField)))?;
        m.end()
    }
}

/// One CSV row per mode (and, with shapes, the shape's components on the body's points as
/// `v0 … v(n−1)`), written row by row with the `csv` crate (zero-mode names come from the model
/// file, so they are quoted where they need it).
fn write_csv(r: &ModesReport, out: &mut dyn Write) -> io::Result<()> {
    csv_rows(r, out).map_err(crate::report::csv_io)
}

fn csv_rows(r: &ModesReport, out: &mut dyn Write) -> csv::Result<()> {
    let mut header: Vec<String> = [
        "field",
        "index",
        "eigenvalue",
        "frequency",
        "damping_ratio",
        "damped_frequency",
        "regime",
        "variance_share",
        "cumulative_share",
        "zero_mode",
    ]
    .map(String::from)
    .to_vec();
    let width = r
        .modes
        .iter()
        .filter_map(|f| f.spectrum.shapes.as_ref().map(|s| s.nrows()))
        .max()
        .unwrap_or(0);
    if r.shapes {
        header.extend((0..width).map(|i| format!("v{i}")));
    }
    let mut w = csv::Writer::from_writer(io::BufWriter::with_capacity(1 << 16, out));
    w.write_record(&header)?;
    let mut cell = String::new();
    for f in r.modes {
        for m in &f.modes {
            w.write_field(&f.field.id)?;
            let mut number = |w: &mut csv::Writer<_>, v: Option<f64>| {
                cell.clear();
                if let Some(v) = v {
                    let _ = write!(cell, "{v}");
                }
                w.write_field(&cell)
            };
            number(&mut w, Some(m.index as f64))?;
            for v in [m.eigenvalue, m.frequency, m.damping_ratio] {
                number(&mut w, Some(v))?;
            }
            number(&mut w, m.damped_frequency)?;
            w.write_field(m.regime.name())?;
            number(&mut w, Some(m.variance_share))?;
            number(&mut w, Some(m.cumulative_share))?;
            w.write_field(m.zero_mode.as_deref().unwrap_or(""))?;
            if let Some(s) = f.spectrum.shapes.as_ref().filter(|_| r.shapes) {
                for i in 0..width {
                    number(&mut w, (i < s.nrows()).then(|| s[(i, m.index)]))?;
                }
            }
            w.write_record(None::<&[u8]>)?;
        }
    }
    Ok(w.flush()?)
}

impl Report for ModesReport<'_> {
    fn check(&self) -> Result<(), NonFinite> {
        for f in self.modes {
            let numbers: Vec<[f64; 4]> = f
                .modes
                .iter()
                .map(|m| [m.eigenvalue, m.frequency, m.damping_ratio, m.variance_share])
                .collect();
            crate::report::check_finite(&(&f.field.id, numbers, f.spectrum.inverse_trace))?;
        }
        Ok(())
    }

    fn text(&self) -> String {
        crate::report::to_string(|out| write_text(self, out))
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(Json(self)).unwrap_or_default()
    }

    fn csv(&self) -> Option<String> {
        Some(crate::report::to_string(|out| write_csv(self, out)))
    }

    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        write_text(self, out)
    }

    fn write_json(&self, out: &mut dyn Write) -> io::Result<()> {
        crate::report::json_to(out, &Json(self))
    }

    fn write_csv(&self, out: &mut dyn Write) -> Option<io::Result<()>> {
        Some(write_csv(self, out))
    }
}
