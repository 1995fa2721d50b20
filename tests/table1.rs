//! Scenario: the engine regenerates the seed's Table 1 (decoded in `shared/reference/table1.md`)
//! mark for mark at order 4.

use std::collections::BTreeMap;

use theory_search::model::{Density, Model};
use theory_search::reduce::analyse;
use theory_search::term::Term;

const REFERENCE: &str = include_str!("fixtures/table1_reference.md");

/// Per term: its orders and its marks in column order.
type Rows = BTreeMap<Term, (Vec<u32>, Vec<bool>)>;

/// The reference header and rows.
fn reference_rows() -> (Vec<String>, Rows) {
    let mut header = Vec::new();
    let mut rows = BTreeMap::new();
    for line in REFERENCE.lines().filter(|l| l.starts_with('|')) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells[0] == "term" {
            header = cells.iter().map(|c| c.to_string()).collect();
            continue;
        }
        if header.is_empty() || cells[0].starts_with("---") || cells.len() != header.len() {
            continue;
        }
        let term: Term = cells[0].parse().unwrap_or_else(|e| panic!("{e}"));
        let orders = cells[1..5].iter().map(|c| c.parse().unwrap()).collect();
        let marks = cells[5..].iter().map(|c| *c == "x").collect();
        assert!(
            rows.insert(term, (orders, marks)).is_none(),
            "duplicate row"
        );
    }
    (header, rows)
}

#[test]
fn fixture_is_the_shared_reference() {
    let shared = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/reference/table1.md");
    // The shared reference must be there: a check that skips itself cannot fail.
    let text = std::fs::read_to_string(shared).unwrap_or_else(|e| {
        panic!("{shared}: {e} (the Table 1 check needs ../shared beside the repository)")
    });
    assert_eq!(
        text, REFERENCE,
        "tests/fixtures/table1_reference.md is stale"
    );
}

#[test]
fn table1_matches_the_decoded_reference_mark_for_mark() {
    let (header, reference) = reference_rows();
    assert_eq!(reference.len(), 27);
    let model = Model::larva();
    let a = analyse(&model, Density::Lagrangian, 4).unwrap();

    // Same columns: the requirement codes, then the field symbols.
    let mut ours: Vec<String> = ["term", "δ", "ε", "τ", "σ"].map(String::from).to_vec();
    ours.extend(a.columns.iter().map(|r| r.code.to_string()));
    ours.extend(model.fields.iter().map(|f| f.symbol.clone()));
    assert_eq!(ours, header);

    assert_eq!(a.rows.len(), reference.len());
    for row in &a.rows {
        let (orders, marks) = reference
            .get(&row.term)
            .unwrap_or_else(|| panic!("{} is not in Table 1", row.term));
        let o = row.orders;
        assert_eq!(
            &vec![o.delta, o.epsilon, o.tau, o.sigma],
            orders,
            "{}",
            row.term
        );
        let ours: Vec<bool> = row.passed.iter().chain(row.included.iter()).collect();
        assert_eq!(&ours, marks, "marks of {}", row.term);
    }
}

#[test]
fn markdown_output_has_the_reference_shape() {
    let model = Model::larva();
    let a = analyse(&model, Density::Lagrangian, 4).unwrap();
    let md = theory_search::table::render(&model, &[a], theory_search::table::Format::Markdown);
    assert!(md.contains("| term | δ | ε | τ | σ | OST | TRAN | REF | KIN | ROT | x | θ | y | z |"));
    assert!(md.contains("| (∂t φ)² | 1 | 2 | 2 | 0 | x | x | x | x | x | x | x | x | x |"));
    assert!(md.contains("| φ | 0 | 1 | 0 | 0 | x |  |  | x |  |  |  |  |  |"));
}
