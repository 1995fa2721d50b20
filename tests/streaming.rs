//! Large results are written as they are formatted: no single write to the output carries more
//! than a chunk, and what arrives in pieces is the same as the whole-string form.

use std::io::Write;

/// An output that records the size of each write.
#[derive(Default)]
struct Spy {
    bytes: Vec<u8>,
    largest: usize,
    writes: usize,
}

impl Write for Spy {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.largest = self.largest.max(buf.len());
        self.writes += 1;
        self.bytes.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn run(args: &[&str]) -> Spy {
    let mut spy = Spy::default();
    let argv = std::iter::once("theory-search").chain(args.iter().copied());
    theory_search::cli::run(argv, &mut spy).unwrap_or_else(|e| panic!("{args:?}: {e}"));
    spy
}

/// The most one write may carry: the 64 KiB chunk plus one line or record.
const CHUNK: usize = (1 << 16) + (1 << 14);

/// `spy` received more than `min` bytes, none of its writes over a chunk.
fn assert_streamed(spy: &Spy, format: &str, min: usize) {
    assert!(spy.bytes.len() > min, "{format}: {} bytes", spy.bytes.len());
    assert!(
        spy.largest <= CHUNK,
        "{format}: a write of {} bytes",
        spy.largest
    );
    assert!(spy.writes > min / CHUNK, "{format}: {} writes", spy.writes);
}

#[test]
fn modes_stream_in_every_format() {
    for format in ["text", "csv", "json"] {
        let spy = run(&["modes", "-p", "20000", "--format", format]);
        assert_streamed(&spy, format, 1 << 20);
    }
}

#[test]
fn candidate_tables_stream_in_every_format() {
    for format in ["text", "markdown", "csv", "json", "latex"] {
        let spy = run(&["--basis", "monomials", "--order", "6", "--format", format]);
        assert_streamed(&spy, format, 1 << 19);
    }
}

#[test]
fn streamed_output_is_the_string_form() {
    use theory_search::model::{Density, Model};
    use theory_search::reduce::analyse_basis;
    use theory_search::table::{render, Format};
    let model = Model::larva();
    let analyses: Vec<_> = Density::ALL
        .iter()
        .map(|&d| analyse_basis(&model, d, 4, theory_search::enumerate::Basis::Monomials).unwrap())
        .collect();
    for (format, name) in [
        (Format::Text, "text"),
        (Format::Markdown, "markdown"),
        (Format::Csv, "csv"),
        (Format::Json, "json"),
        (Format::Latex, "latex"),
    ] {
        let whole = render(&model, &analyses, format);
        let streamed = run(&["--basis", "monomials", "--order", "4", "--format", name]);
        assert_eq!(String::from_utf8(streamed.bytes).unwrap(), whole, "{name}");
        assert!(whole.ends_with('\n') && !whole.ends_with("\n\n"), "{name}");
    }
    // The JSON written as it is serialized is the value programs read.
    let v: serde_json::Value =
        serde_json::from_str(&render(&model, &analyses, Format::Json)).unwrap();
    assert_eq!(v, theory_search::table::json_report(&model, &analyses));
}

/// A table past the held limit is decided twice and never held: the streamed analysis writes
/// exactly the held one's table where both exist, and the CLI takes the monomials of order 10
/// (1.48 million Rayleigh candidates) as CSV in chunks.
#[test]
fn streamed_analyses_write_the_held_tables() {
    use theory_search::enumerate::Basis;
    use theory_search::model::{Density, Model};
    use theory_search::reduce::{analyse_basis, analyse_streamed};
    use theory_search::table::{render, Format};
    let model = Model::larva();
    for order in [3, 6] {
        let held: Vec<_> = Density::ALL
            .iter()
            .map(|&d| analyse_basis(&model, d, order, Basis::Monomials).unwrap())
            .collect();
        let streamed: Vec<_> = Density::ALL
            .iter()
            .map(|&d| analyse_streamed(&model, d, order).unwrap())
            .collect();
        for (h, s) in held.iter().zip(&streamed) {
            assert!(s.rows.is_empty() && s.candidates == h.rows.len());
            for (a, b) in h.fields.iter().zip(&s.fields) {
                assert_eq!(a.survivors, b.survivors);
                assert_eq!(a.admitted, b.admitted);
            }
        }
        for format in [Format::Text, Format::Csv, Format::Markdown, Format::Latex] {
            assert_eq!(
                render(&model, &streamed, format),
                render(&model, &held, format),
                "order {order} {format:?}"
            );
        }
    }
    let spy = run(&[
        "--basis",
        "monomials",
        "--order",
        "10",
        "--density",
        "rayleigh",
        "--format",
        "csv",
    ]);
    assert_streamed(&spy, "csv", 1 << 26);
    let lines = spy.bytes.iter().filter(|&&b| b == b'\n').count();
    assert_eq!(lines, 1 + 1_479_984);
}
