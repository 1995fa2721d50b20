//! The README and docs cannot rot. Every fenced block says what it is:
//! - `sh`: commands; every `cargo run --release -- …` line is run;
//! - `console`: `$ cargo run --release -- …` and then what it prints: the command is run and what
//!   it prints now must match, line by line, where `…` alone on a line skips any number of lines
//!   and `…` inside a line stands for any text there (blank lines and the lines' outer white
//!   space aside);
//! - `toml`, `python`, `text` (a synopsis, no output): checked elsewhere or not output.
//!
//! Every inline command in running text runs too.

mod common;

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every page of docs/, with their text.
fn pages() -> Vec<(PathBuf, String)> {
    let mut pages = vec![root().join("README.md")];
    for entry in std::fs::read_dir(root().join("docs")).unwrap() {
        pages.push(entry.unwrap().path());
    }
    pages.sort();
    pages
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

/// The fenced blocks of a page with their info strings.
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut current: Option<(String, String)> = None;
    for line in text.lines() {
        if let Some(info) = line.strip_prefix("```") {
            match current.take() {
                Some(block) => out.push(block),
                None => current = Some((info.trim().to_string(), String::new())),
            }
        } else if let Some((_, body)) = current.as_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    assert!(current.is_none(), "an unclosed fence");
    out
}

/// What `theory-search args…` prints (it must succeed).
fn run(args: &[String]) -> String {
    let mut all = vec!["theory-search".to_string()];
    all.extend(args.iter().cloned());
    let mut out = Vec::new();
    theory_search::cli::run(all.clone(), &mut out).unwrap_or_else(|e| panic!("{all:?}: {e}"));
    String::from_utf8(out).unwrap()
}

/// `shown` line against `printed` line: equal, or equal around the `…` wildcards it holds.
fn line_matches(shown: &str, printed: &str) -> bool {
    if !shown.contains('…') {
        return shown == printed;
    }
    let parts: Vec<&str> = shown.split('…').collect();
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !printed.starts_with(first) || printed.len() < first.len() + last.len() {
        return false;
    }
    let mut rest = &printed[first.len()..];
    for middle in &parts[1..parts.len() - 1] {
        match rest.find(middle) {
            Some(i) => rest = &rest[i + middle.len()..],
            None => return false,
        }
    }
    rest.ends_with(last)
}

/// Whether `shown` is what `printed` holds, in order, with `…` elisions; the first line that
/// differs when not.
fn matches(shown: &str, printed: &str) -> Result<(), String> {
    let clean = |s: &str| -> Vec<String> {
        s.lines()
            .map(|l| l.trim().to_string())
            .filter(|l| !l.is_empty())
            .collect()
    };
    let (shown, printed) = (clean(shown), clean(printed));
    // Dynamic programming over (shown line, printed line): whether the rest matches.
    let (n, m) = (shown.len(), printed.len());
    let mut ok = vec![vec![false; m + 1]; n + 1];
    ok[n][m] = true;
    for i in (0..n).rev() {
        for j in (0..=m).rev() {
            ok[i][j] = if shown[i] == "…" {
                // Skip nothing, or one more printed line.
                ok[i + 1][j] || (j < m && ok[i][j + 1])
            } else {
                j < m && line_matches(&shown[i], &printed[j]) && ok[i + 1][j + 1]
            };
        }
    }
    if ok[0][0] {
        return Ok(());
    }
    // The first shown line that cannot be placed after the lines before it.
    let mut j = 0;
    for line in &shown {
        if line == "…" {
            continue;
        }
        match printed[j.min(m)..]
            .iter()
            .position(|p| line_matches(line, p))
        {
            Some(k) => j += k + 1,
            None => return Err(format!("it does not print {line:?} where shown")),
        }
    }
    Err("the lines are there, but not in the order or with the elisions shown".into())
}

#[test]
fn the_matcher_is_strict_and_honours_elisions() {
    let printed = "a\nb 1 c\nd\ne\n";
    assert!(matches("a\nb 1 c\nd\ne", printed).is_ok());
    assert!(matches("a\nb … c\n…\ne", printed).is_ok());
    assert!(matches("…\nd\ne", printed).is_ok());
    // A missing elision, a changed line, the wrong order, a line more: all fail.
    assert!(matches("a\nd\ne", printed).is_err());
    assert!(matches("a\nb 2 c\n…", printed).is_err());
    assert!(matches("…\ne\nd", printed).is_err());
    assert!(matches("a\nb 1 c\nd\ne\nf", printed).is_err());
    assert!(matches("a\n…", printed).is_ok());
    assert!(!line_matches("b … c", "b c"));
}

/// The arguments of a command line, with output directories sent to `scratch` (and how to
/// write the scratch path back as the page shows it).
fn arguments(command: &str, scratch: &Path) -> (Vec<String>, Vec<(String, String)>) {
    let words: Vec<&str> = command.split_whitespace().collect();
    let mut back = Vec::new();
    let args = words
        .iter()
        .enumerate()
        .map(|(i, a)| match i.checked_sub(1).map(|j| words[j]) {
            Some("--out" | "--figures") => {
                let moved = scratch.join(a).display().to_string();
                back.push((moved.clone(), a.to_string()));
                moved
            }
            _ => a.to_string(),
        })
        .collect();
    (args, back)
}

#[test]
fn every_block_says_what_it_is_and_shown_output_is_printed() {
    let scratch_held = common::scratch("docs");
    let scratch = scratch_held.path();
    let (mut commands, mut outputs, mut onward) = (0, 0, 0);
    let mut problems = Vec::new();
    for (path, text) in pages() {
        let page = path.strip_prefix(root()).unwrap().display().to_string();
        for (info, body) in blocks(&text) {
            let joined = body.replace("\\\n", " ");
            match info.as_str() {
                "sh" => {
                    for line in joined.lines() {
                        let line = line.split(" #").next().unwrap().trim();
                        if let Some(rest) = line.strip_prefix("cargo run --release -- ") {
                            onward += onward_lines_run(&run(&arguments(rest, scratch).0));
                            commands += 1;
                        }
                    }
                }
                "console" => {
                    let (first, shown) = joined.split_once('\n').unwrap_or((&joined, ""));
                    let Some(command) = first.strip_prefix("$ cargo run --release -- ") else {
                        problems.push(format!("{page}: a console block starts {first:?}"));
                        continue;
                    };
                    let (args, back) = arguments(command, scratch);
                    let mut printed = run(&args);
                    onward += onward_lines_run(&printed);
                    for (moved, shown_as) in back {
                        printed = printed.replace(&moved, &shown_as);
                    }
                    if shown.trim().is_empty() {
                        problems.push(format!("{page}: `{command}` shows no output"));
                    } else if let Err(why) = matches(shown, &printed) {
                        problems.push(format!("{page}: `{command}`: {why}"));
                    }
                    outputs += 1;
                }
                "toml" | "python" | "text" => {}
                other => problems.push(format!(
                    "{page}: a block marked {other:?} (sh, console, toml, python or text)"
                )),
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(commands >= 7, "{commands} commands");
    assert!(outputs >= 15, "{outputs} outputs checked");
    assert!(onward >= 1, "{onward} onward lines run");
}

/// Every onward line a command printed, run as printed (no shell quoting: the words are the
/// arguments): discover's `Onward: theory-search simulate …`, fit's `onward (…): theory-search
/// simulate …` and the verdict blocks' `next: theory-search … (why)` (fit) and `Next: …`
/// (discover); how many ran.
fn onward_lines_run(printed: &str) -> usize {
    let mut ran = 0;
    for line in printed.lines() {
        let line = line.trim();
        let onward = ["Onward: ", "onward (", "next: ", "Next: "]
            .iter()
            .any(|p| line.starts_with(p));
        let Some((_, command)) = line.split_once("theory-search ").filter(|_| onward) else {
            continue;
        };
        // A trailing `(why)` is words, not arguments.
        let command = command.split(" (").next().unwrap_or(command);
        assert!(!command.contains('\''), "a quoted onward line: {command}");
        let args: Vec<String> = command.split_whitespace().map(String::from).collect();
        run(&args);
        ran += 1;
    }
    ran
}

/// Every command written inline in running text (`` `theory-search rules` ``, `` `cargo run
/// --release -- --order 4` ``) runs; a synopsis with placeholders (`[--order N]`, `…`, `FILE`)
/// names a subcommand whose `--help` runs. Output directories go to a scratch place.
#[test]
fn every_inline_command_in_the_readme_and_docs_runs() {
    let dir_held = common::scratch("inline");
    let dir = dir_held.path();
    let mut ran = 0;
    for (path, text) in &pages() {
        for (i, piece) in text.split('`').enumerate() {
            // Odd pieces are inside backticks.
            let Some(rest) = (i % 2 == 1)
                .then(|| {
                    piece
                        .strip_prefix("theory-search ")
                        .or_else(|| piece.strip_prefix("cargo run --release -- "))
                })
                .flatten()
            else {
                continue;
            };
            let words: Vec<&str> = rest.split_whitespace().collect();
            let placeholder = |w: &&str| {
                w.contains(['[', '…']) || (w.len() > 1 && w.chars().all(|c| c.is_ascii_uppercase()))
            };
            let mut args: Vec<String> = match words.iter().position(placeholder) {
                Some(first) => {
                    let mut a: Vec<String> = words[..first]
                        .iter()
                        .take_while(|w| !w.starts_with('-'))
                        .map(|w| w.to_string())
                        .collect();
                    a.push("--help".into());
                    a
                }
                None => words.iter().map(|w| w.to_string()).collect(),
            };
            // `emit` without --out would write into this checkout.
            if args.first().map(String::as_str) == Some("emit") && !args.contains(&"--help".into())
            {
                args.extend(["--out".into(), dir.join("emit").display().to_string()]);
            }
            let mut all = vec!["theory-search".to_string()];
            all.extend(args);
            let mut out = Vec::new();
            if let Err(e) = theory_search::cli::run(all.clone(), &mut out) {
                panic!("{}: `{piece}` ({all:?}): {e}", path.display());
            }
            ran += 1;
        }
    }
    assert!(ran >= 10, "{ran} inline commands");
}

/// The README's count of shipped example models is the number of files in tables/models/.
#[test]
fn the_readme_counts_the_shipped_examples_truly() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let words = [
        "Zero", "One", "Two", "Three", "Four", "Five", "Six", "Seven", "Eight", "Nine", "Ten",
        "Eleven", "Twelve", "Thirteen", "Fourteen", "Fifteen",
    ];
    let said = readme
        .split_whitespace()
        .collect::<Vec<_>>()
        .windows(3)
        .find(|w| w[1] == "examples" && w[2] == "ship")
        .map(|w| w[0].to_string())
        .expect("README says how many examples ship");
    let shipped = std::fs::read_dir(root().join("tables/models"))
        .unwrap()
        .filter(|e| {
            let p = e.as_ref().unwrap().path();
            p.extension().is_some_and(|x| x == "toml")
        })
        .count();
    assert_eq!(said, words[shipped], "README says {said}, {shipped} ship");
}

/// What the README's and docs' own commands write (`--figures D`, `--out F`, `python -m venv
/// D`) is git-ignored, so following them leaves `git status` clean.
#[test]
fn what_the_shown_commands_write_is_git_ignored() {
    let ignore = std::fs::read_to_string(root().join(".gitignore")).unwrap();
    let ignored: Vec<&str> = ignore
        .lines()
        .map(|l| l.trim().trim_start_matches('/').trim_end_matches('/'))
        .collect();
    let mut missing = Vec::new();
    for (path, text) in pages() {
        for (info, body) in blocks(&text) {
            if !matches!(info.as_str(), "sh" | "console") {
                continue;
            }
            let joined = body.replace("\\\n", " ");
            let words: Vec<&str> = joined.split_whitespace().collect();
            for w in words.windows(2) {
                let written = match w[0] {
                    "--figures" | "--out" => w[1],
                    "venv" => w[1],
                    _ => continue,
                };
                let placeholder = written.chars().all(|c| !c.is_ascii_lowercase());
                if !placeholder && !ignored.contains(&written) {
                    missing.push(format!("{}: {written}", path.display()));
                }
            }
        }
    }
    assert!(missing.is_empty(), "not in .gitignore: {missing:?}");
}

/// The README uses the binary's name (`theory-search rules`, the onward lines the tools print)
/// and says how to put it on PATH.
#[test]
fn the_readme_says_how_to_install_the_binary() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(readme.contains("`theory-search "));
    assert!(
        readme.contains("`cargo install --path .`"),
        "no install line"
    );
}
