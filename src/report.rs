//! One small trait for every result the tool prints: text for people, JSON for programs, and
//! CSV for the results that are tables. Each result type implements it beside its own
//! definition; the command line only picks the format.

use clap::ValueEnum;

/// How a result is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Output {
    /// Aligned text for reading.
    Text,
    /// JSON (serde).
    Json,
    /// CSV (the `csv` crate's writer: quoting included).
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
}

/// `report` in `format`, or why it has no such form.
pub fn render(report: &dyn Report, format: Output) -> Result<String, String> {
    match format {
        Output::Text => Ok(report.text()),
        Output::Json => Ok(serde_json::to_string_pretty(&report.json()).unwrap_or_default() + "\n"),
        Output::Csv => report
            .csv()
            .ok_or_else(|| "this result has no CSV form: use --format text or json".into()),
    }
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

/// Serialize `value` to a JSON value (every result type is plain data).
pub fn to_json(value: &impl serde::Serialize) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or_default()
}
