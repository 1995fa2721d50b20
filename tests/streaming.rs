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
