//! Scenario: the command line as a user runs it, including every error path.

use std::process::Command;

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(args)
        .output()
        .expect("binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn assert_clean_error(args: &[&str], needle: &str) {
    let (code, stdout, stderr) = run(args);
    assert_ne!(code, 0, "{args:?} succeeded");
    assert!(stdout.is_empty(), "{args:?} printed {stdout}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn default_run_prints_both_tables_and_the_densities() {
    let (code, out, err) = run(&["--order", "4"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Lagrangian density: 27 candidate terms with δ ≤ 4, ε ≤ 4, τ+σ ≤ 4"));
    assert!(out.contains("Rayleigh density: 32 candidate terms with δ ≤ 4, ε ≤ 4, τ ≤ 4, σ ≤ 4"));
    assert!(out.contains("L_x = ½(∂t x)² − ½ c_x (∂s x)²"));
    assert!(out.contains("L_y = ½(∂t y)² − ½ c_y (∂ss y)²"));
    assert!(out.contains("R_y = c'_y (∂tss y)²"));
    let (_, bare, _) = run(&[]);
    assert_eq!(bare, out, "order 4 is the default");
    let (_, sub, _) = run(&["table", "--order", "4"]);
    assert_eq!(sub, out);
}

#[test]
fn every_format_runs() {
    for (format, needle) in [
        ("text", "OST"),
        ("markdown", "| term | δ |"),
        ("csv", "density,term,delta,epsilon,tau,sigma,OST"),
        ("json", "\"lagrangian\""),
        ("latex", "\\begin{tabular}"),
    ] {
        let (code, out, err) = run(&["--order", "5", "--format", format]);
        assert_eq!(code, 0, "{format}: {err}");
        assert!(out.contains(needle), "{format}");
    }
    let (_, json, _) = run(&["--format", "json", "--density", "rayleigh"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v.get("lagrangian").is_none());
    assert_eq!(
        v["rayleigh"]["survivors"]["y"],
        serde_json::json!(["(∂tss φ)²"])
    );
}

#[test]
fn order_three_says_the_beam_has_no_potential() {
    let (code, out, _) = run(&["--order", "3", "--density", "lagrangian"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("note: L_y: no potential term survives at order 3"),
        "{out}"
    );
}

#[test]
fn bad_input_is_one_line_and_non_zero() {
    assert_clean_error(&["--order", "0"], "0 is not in 1..=32");
    assert_clean_error(&["--order", "33"], "33 is not in 1..=32");
    assert_clean_error(&["--order", "-2"], "-2");
    assert_clean_error(&["--order", "four"], "four");
    assert_clean_error(&["--format", "pdf"], "pdf");
    assert_clean_error(&["--density", "hamiltonian"], "hamiltonian");
    assert_clean_error(&["--frobnicate"], "frobnicate");
    assert_clean_error(
        &["--model", "/no/such/model.toml"],
        "cannot read /no/such/model.toml",
    );
}

#[test]
fn malformed_model_files_name_the_problem() {
    let dir = std::env::temp_dir().join(format!("theory-search-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "name = \"w\"\nfields = [\n").unwrap();
    assert_clean_error(&["--model", broken.to_str().unwrap()], "line");
    let unknown = dir.join("unknown.toml");
    let text = theory_search::model::Model::larva_toml().replace("\"SPIN\"]\n", "\"SPINX\"]\n");
    std::fs::write(&unknown, text).unwrap();
    assert_clean_error(&["--model", unknown.to_str().unwrap()], "SPINX");
    // The embedded model written out and read back gives the same output.
    let same = dir.join("larva.toml");
    std::fs::write(&same, theory_search::model::Model::larva_toml()).unwrap();
    assert_eq!(run(&["--model", same.to_str().unwrap()]).1, run(&[]).1);
}

#[test]
fn help_explains_every_option() {
    let (code, out, _) = run(&["--help"]);
    assert_eq!(code, 0);
    for opt in [
        "--order",
        "--density",
        "--format",
        "--model",
        "From 1 to 32",
        "emit",
        "rules",
    ] {
        assert!(out.contains(opt), "--help lacks {opt}");
    }
}
