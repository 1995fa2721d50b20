//! The generated tables under `tables/` must be what the engine gives now.

use std::path::Path;
use theory_search::artifacts::{ensure_file_contents, generated_files};

#[test]
fn generated_files_are_fresh() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let stale: Vec<String> = generated_files()
        .expect("generation works")
        .into_iter()
        .filter_map(|(rel, contents)| ensure_file_contents(&root.join(rel), &contents).err())
        .map(|e| e.to_string())
        .collect();
    assert!(stale.is_empty(), "{}", stale.join("\n"));
}
