//! Scenario: the house stands. Every module of `src/` sits in a layer of docs/layout.md's
//! table; a module refers (`crate::x`) only to its own layer or those below (no arrow up), the
//! references between modules form no circle, and no hand-written source file is over 600
//! lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The longest hand-written source file.
const MAX_LINES: usize = 600;

/// Module → layer, from the table of docs/layout.md (the backticked names of its second column).
fn layers() -> BTreeMap<String, u32> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("docs/layout.md")).unwrap();
    let mut out = BTreeMap::new();
    for line in text.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(layer) = cells.get(1).and_then(|c| c.parse::<u32>().ok()) else {
            continue;
        };
        for name in cells[2].split('`').skip(1).step_by(2) {
            out.insert(name.trim_end_matches('/').to_string(), layer);
        }
    }
    out
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a file of `src/` belongs to (`None` for the crate roots).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    let name = first.trim_end_matches(".rs").to_string();
    (!matches!(name.as_str(), "lib" | "main")).then_some(name)
}

/// The modules `text` refers to as `crate::name`.
fn references(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in text.match_indices("crate::") {
        // `theory_search::` from outside is not this; `crate::` inside a word is not either.
        if text[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &text[i + "crate::".len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if rest[name.len()..].starts_with("::") || rest[name.len()..].starts_with(['{', ';', ',']) {
            out.insert(name);
        }
    }
    // `use crate::{a, b::c}`.
    for (i, _) in text.match_indices("crate::{") {
        let rest = &text[i + "crate::{".len()..];
        let group = &rest[..rest.find('}').unwrap_or(rest.len())];
        for part in group.split(',') {
            let name: String = part
                .trim()
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

#[test]
fn no_arrow_up_no_circle_no_long_file() {
    let layers = layers();
    let src = Path::new(ROOT).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut problems = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let generated = file.starts_with(src.join("generated"));
        let lines = text.lines().count();
        if !generated && lines > MAX_LINES {
            problems.push(format!("{} has {lines} lines", file.display()));
        }
        let Some(module) = module_of(&src, file) else {
            continue;
        };
        let Some(&own) = layers.get(&module) else {
            problems.push(format!("module {module} is in no layer of docs/layout.md"));
            continue;
        };
        for target in references(&text) {
            if target == module {
                continue;
            }
            match layers.get(&target) {
                None => problems.push(format!("{module} refers to {target}, in no layer")),
                Some(&layer) if layer > own => problems.push(format!(
                    "arrow up: {module} (layer {own}) refers to {target} (layer {layer}) in {}",
                    file.display()
                )),
                Some(_) => {
                    graph.entry(module.clone()).or_default().insert(target);
                }
            }
        }
    }
    // A circle: a module that reaches itself.
    for start in graph.keys() {
        let mut seen = BTreeSet::new();
        let mut stack: Vec<&String> = graph[start].iter().collect();
        while let Some(m) = stack.pop() {
            if m == start {
                problems.push(format!("circle through {start}"));
                break;
            }
            if seen.insert(m.clone()) {
                stack.extend(graph.get(m).into_iter().flatten());
            }
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
    // The check sees the code: the CLI refers to modules below it.
    assert!(graph["cli"].contains("body"), "{graph:?}");
}

#[test]
fn the_layout_names_the_error_types_and_test_files_there_are() {
    let layout = std::fs::read_to_string(Path::new(ROOT).join("docs/layout.md")).unwrap();
    let mut missing: Vec<String> = Vec::new();
    for entry in std::fs::read_dir(Path::new(ROOT).join("tests")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "rs") {
            let stem = path.file_stem().unwrap().to_str().unwrap();
            if !layout.contains(&format!("`{stem}`")) {
                missing.push(format!("tests/{stem}.rs"));
            }
        }
    }
    let mut files = Vec::new();
    sources(&Path::new(ROOT).join("src"), &mut files);
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (i, _) in text.match_indices("pub enum ") {
            let name: String = text[i + 9..]
                .chars()
                .take_while(|c| c.is_alphanumeric())
                .collect();
            if name.ends_with("Error") && !layout.contains(&format!("`{name}`")) {
                missing.push(name);
            }
        }
    }
    assert!(
        missing.is_empty(),
        "docs/layout.md does not name {missing:?}"
    );
}
