//! The recordings a list of paths names, as the command line and Python take them: a file as
//! given, a directory's recordings (.csv, .txt, .wcon, .json, .h5) and a pattern's matches
//! (`*`, `?` in the file name), each in name order.

use std::path::{Path, PathBuf};

use super::RecordingError;

/// Files a directory holds recordings in.
const EXTENSIONS: [&str; 5] = ["csv", "txt", "wcon", "json", "h5"];

/// The files of `dir` whose names `keep` accepts, in name order.
fn files_in(dir: &Path, keep: &dyn Fn(&str) -> bool) -> Result<Vec<PathBuf>, RecordingError> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| {
            RecordingError::Open(std::io::Error::new(
                e.kind(),
                format!("cannot read {}: {e}", dir.display()),
            ))
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.file_name().and_then(|n| n.to_str()).is_some_and(keep))
        .collect();
    files.sort();
    Ok(files)
}

/// Whether `name` matches `pattern` (`*` any run of characters, `?` one), in O(p·n).
fn matches(pattern: &[char], name: &[char]) -> bool {
    // ok[j]: the pattern so far matches name[..j].
    let mut ok = vec![false; name.len() + 1];
    ok[0] = true;
    for &c in pattern {
        let mut next = vec![false; name.len() + 1];
        for j in 0..=name.len() {
            next[j] = match c {
                '*' => ok[j] || (j > 0 && next[j - 1]),
                '?' => j > 0 && ok[j - 1],
                c => j > 0 && ok[j - 1] && name[j - 1] == c,
            };
        }
        ok = next;
    }
    ok[name.len()]
}

/// The recordings named: files as given, a directory's recordings and a pattern's matches in
/// name order.
pub fn recordings(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, RecordingError> {
    let mut out = Vec::new();
    for path in inputs {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let files = if path.is_dir() {
            let ext = |n: &str| EXTENSIONS.iter().any(|e| n.ends_with(&format!(".{e}")));
            files_in(path, &ext)?
        } else if !path.exists() && name.contains(['*', '?']) && name.len() <= 256 {
            let pattern: Vec<char> = name.chars().collect();
            let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
            files_in(dir.unwrap_or(Path::new(".")), &|n: &str| {
                matches(&pattern, &n.chars().collect::<Vec<_>>())
            })?
        } else {
            out.push(path.clone());
            continue;
        };
        if files.is_empty() {
            return Err(RecordingError::In {
                name: path.display().to_string(),
                why: Box::new(RecordingError::Io(std::io::Error::other(
                    "no recordings there (.csv, .txt, .wcon, .json or .h5 files)",
                ))),
            });
        }
        out.extend(files);
    }
    if out.len() > 1 && out.iter().any(|p| p.as_os_str() == "-") {
        return Err(RecordingError::Invalid(
            "standard input (-) is one recording: give files instead to pool several".into(),
        ));
    }
    Ok(out)
}
