//! Render analyses as the paper's Table 1 and its Rayleigh twin: aligned Unicode text, Markdown,
//! CSV, JSON (the contract other tools read) and a LaTeX `tabular`.
//!
//! Every cell comes from an [`Analysis`]; nothing here decides anything. A mark `x` means the term
//! satisfies the requirement (rule columns) or survives in that field's density (field columns),
//! as in the paper.

use std::io::{self, Write};

use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::Value;

use crate::markup::{latex_symbol, markdown_cell};
use crate::report::{Aligned, Chunked};

use crate::model::{Density, Model};
use crate::reduce::{for_each_row, prefactor_text, sign_joiner, Analysis, FieldResult, Row};
use crate::term::Term;

/// An output format of the table command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Aligned Unicode text for the terminal.
    Text,
    /// Markdown tables, as in `tables/`.
    Markdown,
    /// One CSV table, one row per candidate and density.
    Csv,
    /// The JSON contract.
    Json,
    /// LaTeX `tabular` environments and an `align*` of the densities.
    Latex,
}

const MARK: &str = "x";

fn mark(b: bool) -> &'static str {
    if b {
        MARK
    } else {
        ""
    }
}

/// One density's table as cells, row by row through [`for_each_row`] (held rows, or a streamed
/// analysis decided again): the header, numbers from a small table, marks static, each term
/// rendered by `term` into one reused string. No string per cell: the monomial tables run to
/// 10⁷ rows.
struct Cells<'a> {
    model: &'a Model,
    analysis: &'a Analysis,
    header: Vec<String>,
    numbers: Vec<String>,
    term: fn(&Term, &mut String),
}

impl<'a> Cells<'a> {
    fn new(model: &'a Model, a: &'a Analysis, term: fn(&Term, &mut String)) -> Self {
        let mut header: Vec<String> = ["term", "δ", "ε", "τ", "σ"].map(String::from).to_vec();
        header.extend(a.columns.iter().map(|r| r.code.to_string()));
        header.extend(model.fields.iter().map(|f| f.symbol.clone()));
        // δ, ε and τ, σ (at most ε·δ) of any candidate within the bounds.
        let top = a.bounds.epsilon * a.bounds.delta.max(1);
        Cells {
            model,
            analysis: a,
            header,
            numbers: (0..=top).map(|v| v.to_string()).collect(),
            term,
        }
    }

    /// Each row's cells, in order, to `f`.
    fn each(&self, f: &mut dyn FnMut(&Row, &[&str]) -> io::Result<()>) -> io::Result<()> {
        let mut text = String::new();
        for_each_row(self.model, self.analysis, &mut |r| {
            text.clear();
            (self.term)(&r.term, &mut text);
            let o = r.orders;
            let mut row: Vec<&str> = Vec::with_capacity(self.header.len());
            row.push(&text);
            for v in [o.delta, o.epsilon, o.tau, o.sigma] {
                row.push(&self.numbers[v as usize]);
            }
            for b in r.passed.iter().chain(r.included.iter()) {
                row.push(mark(b));
            }
            f(r, &row)
        })
    }

    /// Every row as one line: `open`, the cells joined by `sep`, `close`.
    fn joined(&self, out: &mut Chunked, (open, sep, close): (&str, &str, &str)) -> io::Result<()> {
        self.each(&mut |_, row| {
            out.say(format_args!("{open}{}{close}", row.join(sep)));
            out.spill()
        })
    }
}

/// A term in LaTeX math, `$…$`.
fn latex_term(t: &Term, out: &mut String) {
    out.push('$');
    out.push_str(&t.render_latex(&|_| "\\phi".to_string()));
    out.push('$');
}

/// A term's text form (what `Display` writes).
fn plain(t: &Term, out: &mut String) {
    // Writing to a String cannot fail.
    let _ = t.write_text(out);
}

fn title(a: &Analysis) -> String {
    let kind = match a.basis {
        crate::enumerate::Basis::Powers => "candidate terms",
        crate::enumerate::Basis::Monomials => "candidate monomials",
    };
    format!(
        "{} density: {} {kind} with {}",
        a.density, a.candidates, a.bounds
    )
}

fn requirement_line(model: &Model, a: &Analysis) -> String {
    // Group fields with the same requirements, as the paper does ("x, θ: …; y, z: …").
    let mut groups: Vec<(Vec<String>, Vec<&str>)> = Vec::new();
    for f in &model.fields {
        let codes: Vec<&str> = model
            .requirements(a.density, &f.id)
            .iter()
            .map(|r| r.code)
            .collect();
        match groups.iter_mut().find(|(_, c)| *c == codes) {
            Some((names, _)) => names.push(f.symbol.clone()),
            None => groups.push((vec![f.symbol.clone()], codes)),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(names, codes)| {
            let codes = if codes.is_empty() {
                "none".to_string()
            } else {
                codes.join(" ")
            };
            format!("{}: {codes}", names.join(", "))
        })
        .collect();
    format!("Required: {}", parts.join("; "))
}

fn notes(a: &Analysis) -> Vec<String> {
    a.fields.iter().flat_map(|f| f.missing.clone()).collect()
}

/// The candidate tables in text: the title, the requirements, the aligned table, then each
/// density's survivors and notes; written line by line to `out`.
fn text(model: &Model, analyses: &[Analysis], out: &mut Chunked) -> io::Result<()> {
    // Which body the tables are of: a model file's name is validated text (one line, no controls).
    if let Some(a) = analyses.first() {
        out.say(format_args!(
            "Candidate terms of the {} model at order {}\n",
            model.name, a.order
        ));
    }
    for a in analyses {
        let cells = Cells::new(model, a, plain);
        out.say(format_args!(
            "{}\n{}\n",
            title(a),
            requirement_line(model, a)
        ));
        // Two passes over the rows: the column widths, then the lines.
        let mut layout = Aligned::new(&cells.header);
        cells.each(&mut |_, row| {
            layout.fit(row);
            Ok(())
        })?;
        layout.line(&cells.header, out.buf());
        layout.rule(out.buf());
        cells.each(&mut |_, row| {
            layout.line(row, out.buf());
            out.spill()
        })?;
        out.buf().push('\n');
    }
    for (k, a) in analyses.iter().enumerate() {
        out.say(format_args!(
            "Surviving {} densities ({}):",
            a.density,
            kept(model, a)
        ));
        for f in &a.fields {
            out.say(format_args!("  {}", f.formula(a.density)));
        }
        for n in notes(a) {
            out.say(format_args!("  note: {n}"));
        }
        if k + 1 < analyses.len() {
            out.buf().push('\n');
        }
    }
    out.finish()
}

/// Which terms a surviving density keeps: the lowest order, and the layers beyond it.
fn kept(model: &Model, a: &Analysis) -> String {
    match model.density(a.density).beyond_leading {
        0 => "lowest order in τ and σ".into(),
        1 => "lowest order in τ and σ, and the next".into(),
        k => format!("lowest order in τ and σ, and the next {k}"),
    }
}

fn markdown(model: &Model, analyses: &[Analysis], out: &mut Chunked) -> io::Result<()> {
    for (k, a) in analyses.iter().enumerate() {
        let cells = Cells::new(model, a, plain);
        out.say(format_args!(
            "## {}\n\n{}.\n",
            title(a),
            requirement_line(model, a)
        ));
        let header: Vec<String> = cells.header.iter().map(|h| markdown_cell(h)).collect();
        out.say(format_args!("| {} |", header.join(" | ")));
        out.say(format_args!("|{}", "---|".repeat(cells.header.len())));
        cells.joined(out, ("| ", " | ", " |"))?;
        out.say(format_args!(
            "\nSurviving {} densities ({}):\n",
            a.density,
            kept(model, a)
        ));
        for f in &a.fields {
            out.say(format_args!("- `{}`", f.formula(a.density)));
        }
        for n in notes(a) {
            out.say(format_args!("- note: {n}"));
        }
        if k + 1 < analyses.len() {
            out.buf().push('\n');
        }
    }
    out.finish()
}

/// One CSV table for all densities, row by row through the `csv` crate's writer.
fn csv(model: &Model, analyses: &[Analysis], out: &mut dyn io::Write) -> io::Result<()> {
    csv_rows(model, analyses, out).map_err(crate::report::csv_io)
}

fn csv_rows(model: &Model, analyses: &[Analysis], out: &mut dyn io::Write) -> csv::Result<()> {
    // The union of rule columns, empty where a rule is not a requirement column of that
    // density; 1/0 for satisfied/failed and included/not.
    let mut codes: Vec<&str> = Vec::new();
    for a in analyses {
        for r in &a.columns {
            if !codes.contains(&r.code) {
                codes.push(r.code);
            }
        }
    }
    let mut header: Vec<String> = ["density", "term", "delta", "epsilon", "tau", "sigma"]
        .map(String::from)
        .to_vec();
    header.extend(codes.iter().map(|c| c.to_string()));
    header.extend(model.fields.iter().map(|f| f.id.clone()));
    let mut w = csv::Writer::from_writer(io::BufWriter::with_capacity(1 << 16, out));
    w.write_record(&header)?;
    let bit = |b: bool| -> &'static str {
        if b {
            "1"
        } else {
            "0"
        }
    };
    for a in analyses {
        let cells = Cells::new(model, a, plain);
        let column: Vec<Option<usize>> = codes
            .iter()
            .map(|code| a.columns.iter().position(|c| c.code == *code))
            .collect();
        cells
            .each(&mut |r, cells| {
                // The density, the term and its four orders, then 1/0 marks.
                let mut row: Vec<&str> = vec![a.density.key()];
                row.extend_from_slice(&cells[..5]);
                for c in &column {
                    row.push(c.map_or("", |i| bit(r.passed[i])));
                }
                for b in r.included.iter() {
                    row.push(bit(b));
                }
                w.write_record(&row).map_err(crate::report::csv_io)
            })
            .map_err(csv::Error::from)?;
    }
    Ok(w.flush()?)
}

/// Serialize `f(i, field)` for each field as a map keyed by field id, in model order.
struct FieldMap<'a, F> {
    fields: &'a [FieldResult],
    value: F,
}

impl<T: Serialize, F: Fn(usize, &FieldResult) -> T> Serialize for FieldMap<'_, F> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(
            self.fields
                .iter()
                .enumerate()
                .map(|(i, f)| (f.field.id.as_str(), (self.value)(i, f))),
        )
    }
}

fn field_map<T: Serialize, F: Fn(usize, &FieldResult) -> T>(
    fields: &[FieldResult],
    value: F,
) -> FieldMap<'_, F> {
    FieldMap { fields, value }
}

/// One factor of a term in the JSON contract: `{"t", "s", "power"}`, and `"field"` in products
/// of several fields.
struct JsonFactor<'a>(&'a crate::term::Factor);

impl Serialize for JsonFactor<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let f = self.0;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("t", &f.deriv.t)?;
        m.serialize_entry("s", &f.deriv.s)?;
        m.serialize_entry("power", &f.power)?;
        if f.field != 0 {
            m.serialize_entry("field", &f.field)?;
        }
        m.end()
    }
}

/// One candidate row of the JSON contract, serialized as it is written (no value tree).
struct JsonRow<'a> {
    a: &'a Analysis,
    i: usize,
}

impl Serialize for JsonRow<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (a, r) = (self.a, &self.a.rows[self.i]);
        let o = r.orders;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("term", &r.term.to_string())?;
        let factors: Vec<JsonFactor> = r.term.factors().iter().map(JsonFactor).collect();
        m.serialize_entry("factors", &factors)?;
        m.serialize_entry("delta", &o.delta)?;
        m.serialize_entry("epsilon", &o.epsilon)?;
        m.serialize_entry("tau", &o.tau)?;
        m.serialize_entry("sigma", &o.sigma)?;
        let codes = || a.columns.iter().map(|c| c.code);
        m.serialize_entry("satisfies", &Pairs(codes().zip(r.passed.iter()).collect()))?;
        m.serialize_entry("included", &field_map(&a.fields, |i, _| r.included[i]))?;
        m.serialize_entry("admitted", &field_map(&a.fields, |i, _| r.admitted[i]))?;
        // The reasons come from the full verdict (the explanation path), for failed rules only.
        let rejected: Vec<(&str, String)> = codes()
            .enumerate()
            .filter(|&(i, _)| !r.passed[i])
            .filter_map(|(i, code)| r.why(a, i).map(|why| (code, why)))
            .collect();
        m.serialize_entry("rejected", &Pairs(rejected))?;
        m.end()
    }
}

/// Key–value pairs serialized as a JSON object in their order.
struct Pairs<K, V>(Vec<(K, V)>);

impl<K: Serialize, V: Serialize> Serialize for Pairs<K, V> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

/// The JSON of one density (the contract's `"lagrangian"` / `"rayleigh"` object).
struct JsonDensity<'a> {
    model: &'a Model,
    a: &'a Analysis,
}

impl Serialize for JsonDensity<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, a) = (self.model, self.a);
        let mut m = s.serialize_map(None)?;
        m.serialize_entry(
            "basis",
            match a.basis {
                crate::enumerate::Basis::Powers => "powers",
                crate::enumerate::Basis::Monomials => "monomials",
            },
        )?;
        m.serialize_entry("bound", &a.bounds.to_string())?;
        let codes: Vec<&str> = a.columns.iter().map(|r| r.code).collect();
        m.serialize_entry("requirements", &codes)?;
        let ids: Vec<&str> = model.fields.iter().map(|f| f.id.as_str()).collect();
        m.serialize_entry("fields", &ids)?;
        let rows = (0..a.rows.len()).map(|i| JsonRow { a, i });
        m.serialize_entry("rows", &Seq(std::cell::Cell::new(Some(rows))))?;
        m.serialize_entry(
            "survivors",
            &field_map(&a.fields, |_, f| {
                f.survivors
                    .iter()
                    .map(|t| t.to_string())
                    .collect::<Vec<_>>()
            }),
        )?;
        m.serialize_entry(
            "field_requirements",
            &field_map(&a.fields, |_, f| {
                model
                    .requirements(a.density, &f.field.id)
                    .iter()
                    .map(|r| r.code)
                    .collect::<Vec<_>>()
            }),
        )?;
        m.serialize_entry(
            "densities",
            &field_map(&a.fields, |_, f| f.formula(a.density)),
        )?;
        m.serialize_entry("notes", &notes(a))?;
        m.end()
    }
}

/// A sequence serialized from an iterator, item by item (taken once).
struct Seq<I>(std::cell::Cell<Option<I>>);

impl<I: Iterator<Item = T>, T: Serialize> Serialize for Seq<I> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.0.take().into_iter().flatten())
    }
}

/// The JSON report: `{"order": N, "model": …, "lagrangian": {…}, "rayleigh": {…}}`, with only
/// the densities analysed.
struct JsonReport<'a> {
    model: &'a Model,
    analyses: &'a [Analysis],
}

impl Serialize for JsonReport<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("order", &self.analyses.first().map_or(0, |a| a.order))?;
        m.serialize_entry("model", &self.model.name)?;
        for a in self.analyses {
            m.serialize_entry(
                a.density.key(),
                &JsonDensity {
                    model: self.model,
                    a,
                },
            )?;
        }
        m.end()
    }
}

/// The JSON report as a value (for programs that inspect it; the command streams it).
pub fn json_report(model: &Model, analyses: &[Analysis]) -> Value {
    serde_json::to_value(JsonReport { model, analyses }).unwrap_or_default()
}

/// The JSON report written to `out` as it is serialized, pretty-printed.
pub fn write_json(model: &Model, analyses: &[Analysis], out: &mut dyn io::Write) -> io::Result<()> {
    let mut w = io::BufWriter::with_capacity(1 << 16, out);
    serde_json::to_writer_pretty(&mut w, &JsonReport { model, analyses })?;
    w.write_all(b"\n")?;
    w.flush()
}

fn latex_formula(density: Density, f: &FieldResult) -> String {
    let sym = latex_symbol(&f.field.symbol);
    let mut out = format!("{}_{{{sym}}} &=", density.letter());
    if f.density.is_empty() {
        return out + " 0";
    }
    for (i, dt) in f.density.iter().enumerate() {
        out += &sign_joiner(i, dt.sign < 0, "-");
        let p = prefactor_text(dt.prefactor);
        let mut pieces: Vec<String> = Vec::new();
        if let Some((n, d)) = p.split_once('/') {
            pieces.push(format!("\\tfrac{{{n}}}{{{d}}}"));
        } else if p == "½" {
            pieces.push("\\tfrac{1}{2}".to_string());
        } else if !p.is_empty() {
            pieces.push(p);
        }
        if let Some(param) = &dt.parameter {
            let (base, _) = param.split_once('_').unwrap_or((param, ""));
            pieces.push(format!("{base}_{{{sym}}}"));
        }
        pieces.push(dt.term.render_latex(&|_| sym.clone()));
        out += &pieces.join(" ");
    }
    out
}

fn latex(model: &Model, analyses: &[Analysis], out: &mut Chunked) -> io::Result<()> {
    out.say(format_args!(
        "% Generated by theory-search; needs no package beyond LaTeX itself."
    ));
    for (k, a) in analyses.iter().enumerate() {
        let cells = Cells::new(model, a, latex_term);
        out.say(format_args!("% {}", title(a)));
        out.say(format_args!(
            "\\begin{{tabular}}{{l|cccc|{}|{}}}\n\\hline",
            "c".repeat(a.columns.len()),
            "c".repeat(model.fields.len())
        ));
        let mut header: Vec<String> = ["Term", "$\\delta$", "$\\epsilon$", "$\\tau$", "$\\sigma$"]
            .map(String::from)
            .to_vec();
        header.extend(a.columns.iter().map(|r| r.code.to_string()));
        header.extend(
            model
                .fields
                .iter()
                .map(|f| format!("${}$", latex_symbol(&f.symbol))),
        );
        out.say(format_args!("{} \\\\\n\\hline", header.join(" & ")));
        cells.joined(out, ("", " & ", " \\\\"))?;
        out.say(format_args!(
            "\\hline\n\\end{{tabular}}\n\n\\begin{{align*}}"
        ));
        let lines: Vec<String> = a
            .fields
            .iter()
            .map(|f| latex_formula(a.density, f))
            .collect();
        out.say(format_args!("{}\n\\end{{align*}}", lines.join(" \\\\\n")));
        for n in notes(a) {
            out.say(format_args!("% note: {n}"));
        }
        if k + 1 < analyses.len() {
            out.buf().push('\n');
        }
    }
    out.finish()
}

/// Write `analyses` (one per density, same order) of `model` in `format` to `out`, row by row.
pub fn write(
    model: &Model,
    analyses: &[Analysis],
    format: Format,
    out: &mut dyn io::Write,
) -> io::Result<()> {
    match format {
        Format::Text => text(model, analyses, &mut Chunked::new(out)),
        Format::Markdown => markdown(model, analyses, &mut Chunked::new(out)),
        Format::Csv => csv(model, analyses, out),
        Format::Json => write_json(model, analyses, out),
        Format::Latex => latex(model, analyses, &mut Chunked::new(out)),
    }
}

/// [`write`] into a string (for generated files and tests).
pub fn render(model: &Model, analyses: &[Analysis], format: Format) -> String {
    let mut out = Vec::new();
    // Writing to memory cannot fail.
    let _ = write(model, analyses, format, &mut out);
    String::from_utf8(out).unwrap_or_default()
}
