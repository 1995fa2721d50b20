//! Helpers the integration tests share: the command line run as a user runs it (the binary) or
//! in this process (the library's `cli::run`). Each test target uses what it needs.
#![allow(dead_code)]

use std::process::Command;

/// The binary with `args`: (exit code, stdout, stderr).
pub fn binary(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The command line run in this process: Ok(stdout) or Err((exit code, message)).
pub fn in_process(args: &[&str]) -> Result<String, (u8, String)> {
    let mut all = vec!["theory-search"];
    all.extend_from_slice(args);
    let mut out = Vec::new();
    match theory_search::cli::run(all, &mut out) {
        Ok(()) => Ok(String::from_utf8(out).expect("UTF-8 output")),
        Err(e) => Err((e.exit_code(), e.to_string())),
    }
}

/// [`in_process`] with the message alone as the error.
pub fn cli(args: &[&str]) -> Result<String, String> {
    in_process(args).map_err(|(_, message)| message)
}

/// A JSON array of arrays of numbers (a printed matrix) as rows.
pub fn matrix(v: &serde_json::Value) -> Vec<Vec<f64>> {
    v.as_array()
        .expect("an array of rows")
        .iter()
        .map(|r| {
            r.as_array()
                .expect("a row")
                .iter()
                .map(|x| x.as_f64().expect("a number"))
                .collect()
        })
        .collect()
}
pub mod beam;
pub mod continuum;

/// A scratch directory (`ts-{tag}-…` in the system's temporary directory), removed when
/// dropped, also when the test fails.
pub fn scratch(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("ts-{tag}-"))
        .tempdir()
        .expect("a scratch directory")
}

/// A scratch file named `ts-{tag}-…{suffix}`, removed when dropped.
pub fn scratch_file(tag: &str, suffix: &str) -> tempfile::NamedTempFile {
    tempfile::Builder::new()
        .prefix(&format!("ts-{tag}-"))
        .suffix(suffix)
        .tempfile()
        .expect("a scratch file")
}

/// The binary run with `args` and `--figures` a scratch directory (it must succeed): the SVG
/// files `names` it wrote, in order.
pub fn figures_written(args: &[&str], names: &[&str]) -> Vec<String> {
    let dir_held = scratch("figures-written");
    let dir = dir_held.path();
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(args)
        .arg("--figures")
        .arg(dir)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (names.iter())
        .map(|n| std::fs::read_to_string(dir.join(n)).expect("the figure was written"))
        .collect()
}

/// Each `<text>` element of `svg`: its opening tag, and its text with the scripts (`<tspan>`)
/// joined in and plotters' entities read back.
pub fn svg_texts(svg: &str) -> Vec<(&str, String)> {
    svg.split("<text")
        .skip(1)
        .map(|t| {
            let (tag, body) = t.split_once('>').unwrap_or((t, ""));
            let body = body.split("</text>").next().unwrap_or("");
            let mut plain = String::new();
            let mut in_tag = false;
            for c in body.chars() {
                match c {
                    '<' => in_tag = true,
                    '>' => in_tag = false,
                    c if !in_tag => plain.push(c),
                    _ => {}
                }
            }
            let plain = (plain.trim())
                .replace("&apos;", "'")
                .replace("&quot;", "\"")
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&");
            (tag, plain)
        })
        .collect()
}
