//! The README cannot rot: every `cargo run --release -- …` line it shows is run, and every line
//! of the Table 1 excerpt it prints (but the "…" elisions) is in what the engine prints now.

fn readme() -> String {
    std::fs::read_to_string(format!("{}/README.md", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The fenced blocks of the README with their info strings.
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
    out
}

fn run(args: &[String]) -> String {
    let mut all = vec!["theory-search".to_string()];
    all.extend(args.iter().cloned());
    let mut out = Vec::new();
    theory_search::cli::run(all.clone(), &mut out).unwrap_or_else(|e| panic!("{all:?}: {e}"));
    String::from_utf8(out).unwrap()
}

#[test]
fn every_command_the_readme_shows_runs() {
    let dir = std::env::temp_dir().join(format!("ts-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut ran = 0;
    for (info, body) in blocks(&readme()) {
        if info != "sh" {
            continue;
        }
        // Join continued lines, drop comments.
        let joined = body.replace("\\\n", " ");
        for line in joined.lines() {
            let line = line.split(" #").next().unwrap().trim();
            let Some(rest) = line.strip_prefix("cargo run --release -- ") else {
                continue;
            };
            let args: Vec<String> = rest
                .split_whitespace()
                .map(|a| match a {
                    // Output directories go to a scratch place.
                    "figs" => dir.join("figs").display().to_string(),
                    _ => a.to_string(),
                })
                .collect();
            run(&args);
            ran += 1;
        }
    }
    assert!(ran >= 7, "{ran} commands");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_table_the_readme_prints_is_what_the_engine_prints() {
    let shown = blocks(&readme())
        .into_iter()
        .find(|(info, body)| info.is_empty() && body.contains("Lagrangian density:"))
        .expect("the Table 1 excerpt")
        .1;
    let printed = run(&["--order".into(), "4".into()]);
    let lines: Vec<&str> = printed.lines().map(str::trim_end).collect();
    for line in shown
        .lines()
        .filter(|l| !l.trim().is_empty() && l.trim() != "…")
    {
        assert!(
            lines.contains(&line.trim_end()),
            "the README shows {line:?}, which the engine no longer prints"
        );
    }
}

/// Every `$ cargo run --release -- …` example in docs/: the command runs, and every line shown
/// under it (but the "…" elisions) is a line of what it prints now.
#[test]
fn the_examples_in_docs_print_what_they_show() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("ts-docs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut checked = 0;
    let mut stale = Vec::new();
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        for (_, body) in blocks(&text) {
            let joined = body.replace("\\\n", " ");
            let mut lines = joined.lines();
            let Some(command) = lines
                .next()
                .and_then(|l| l.strip_prefix("$ cargo run --release -- "))
            else {
                continue;
            };
            // The directory after --out or --figures goes to a scratch place.
            let words: Vec<&str> = command.split_whitespace().collect();
            let args: Vec<String> = words
                .iter()
                .enumerate()
                .map(|(i, a)| match i.checked_sub(1).map(|j| words[j]) {
                    Some("--out" | "--figures") => dir.join(a).display().to_string(),
                    _ => a.to_string(),
                })
                .collect();
            // Paths in what it prints name the directory as the example does.
            let mut printed = run(&args);
            for (i, a) in words.iter().enumerate().skip(1) {
                if matches!(words[i - 1], "--out" | "--figures") {
                    printed = printed.replace(&dir.join(a).display().to_string(), a);
                }
            }
            let printed: std::collections::HashSet<&str> = printed.lines().map(str::trim).collect();
            for shown in lines
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.contains('…'))
            {
                if !printed.contains(shown) {
                    stale.push(format!(
                        "{}: `{command}` no longer prints {shown:?}",
                        path.display()
                    ));
                }
            }
            checked += 1;
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(checked >= 10, "{checked} examples");
    assert!(stale.is_empty(), "{}", stale.join("\n"));
}

/// Every command written inline in running text (`` `theory-search rules` ``, `` `cargo run
/// --release -- --order 4` ``) runs; a synopsis with placeholders (`[--order N]`, `…`, `FILE`)
/// names a subcommand whose `--help` runs. Output directories go to a scratch place.
#[test]
fn every_inline_command_in_the_readme_and_docs_runs() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("ts-inline-{}", std::process::id()));
    let mut texts = vec![(root.join("README.md"), readme())];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        texts.push((path.clone(), std::fs::read_to_string(&path).unwrap()));
    }
    let mut ran = 0;
    for (path, text) in &texts {
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
    std::fs::remove_dir_all(&dir).ok();
    assert!(ran >= 10, "{ran} inline commands");
}
