//! Everything the tool generates into the repository, and the one helper that keeps it fresh.
//!
//! [`generated_files`] lists each generated file with the contents the engine gives *now*
//! (the operators' and the forces' Rust source from [`crate::codegen`], the tables from [`crate::table`], the
//! rule list from [`crate::catalogue`]); `theory-search emit` writes them, and the freshness
//! test calls [`ensure_file_contents`] for every one, so a checked-in table can never drift
//! from the engine that made it.

use std::fs;
use std::path::{Path, PathBuf};

use crate::codegen::{forces_source, header, operators_source, CodegenError, TABLE_ORDER};
use crate::model::{Density, Model};
use crate::reduce::{analyse, OrderError};
use crate::table::{render, Format};

/// Why the generated files could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum ArtifactError {
    /// The order is out of range or too large.
    #[error(transparent)]
    Order(#[from] OrderError),
    /// The operators' source could not be generated.
    #[error(transparent)]
    Code(#[from] CodegenError),
    /// A directory or file could not be written.
    #[error("cannot {action} {}: {source}", .path.display())]
    Io {
        /// `create` (a directory) or `write` (a file).
        action: &'static str,
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A checked-in file differed from the engine's output and has been rewritten.
    #[error("{} was not up to date with the engine and has been regenerated; review and commit it", .0.display())]
    Stale(PathBuf),
}

impl ArtifactError {
    /// The kind of failure: a model or order the generator refuses is usage; a file that
    /// cannot be written (or a formatter that fails) is output.
    pub fn failure(&self) -> crate::failure::Failure {
        use crate::failure::Failure;
        match self {
            ArtifactError::Order(_)
            | ArtifactError::Code(CodegenError::Plan(_) | CodegenError::Active(_)) => {
                Failure::Usage
            }
            _ => Failure::Output,
        }
    }
}

/// Write `contents` to `path`, creating its directory.
fn write(path: &Path, contents: &str) -> Result<(), ArtifactError> {
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir).map_err(|source| ArtifactError::Io {
            action: "create",
            path: dir.to_path_buf(),
            source,
        })?;
    }
    fs::write(path, contents).map_err(|source| ArtifactError::Io {
        action: "write",
        path: path.to_path_buf(),
        source,
    })
}

/// Every generated file, relative to the crate root, with the contents the engine gives now for
/// the embedded larva model at [`TABLE_ORDER`] (what is checked in).
pub fn generated_files() -> Result<Vec<(PathBuf, String)>, ArtifactError> {
    generated_files_for(&Model::larva(), TABLE_ORDER)
}

/// Every generated file for `model` at `order`.
pub fn generated_files_for(
    model: &Model,
    order: u32,
) -> Result<Vec<(PathBuf, String)>, ArtifactError> {
    let model = model.clone();
    let analysis = |d| analyse(&model, d, order).map(|a| vec![a]);
    let md = |d| -> Result<String, ArtifactError> {
        Ok(header("<!--", " -->") + "\n" + &render(&model, &analysis(d)?, Format::Markdown))
    };
    let mut both = analysis(Density::Lagrangian)?;
    both.extend(analysis(Density::Rayleigh)?);
    Ok(vec![
        (
            PathBuf::from("src/generated/operators.rs"),
            operators_source(&model, order)?,
        ),
        (
            PathBuf::from("src/generated/forces.rs"),
            forces_source(&model, order)?,
        ),
        (PathBuf::from("tables/table1.md"), md(Density::Lagrangian)?),
        (PathBuf::from("tables/rayleigh.md"), md(Density::Rayleigh)?),
        (
            PathBuf::from("tables/table1.json"),
            render(&model, &both, Format::Json),
        ),
        (
            PathBuf::from("tables/rules.md"),
            (header("<!--", " -->") + &crate::catalogue::rules_markdown()),
        ),
    ])
}

/// Make sure `path` holds `contents`. If it does not, write it and return an error saying so,
/// so a test fails once and the fix is to commit the regenerated file.
pub fn ensure_file_contents(path: &Path, contents: &str) -> Result<(), ArtifactError> {
    if fs::read_to_string(path).ok().as_deref() == Some(contents) {
        return Ok(());
    }
    write(path, contents)?;
    Err(ArtifactError::Stale(path.to_path_buf()))
}

/// Write every generated file for `model` at `order` under `root`; returns the paths written.
pub fn emit(root: &Path, model: &Model, order: u32) -> Result<Vec<PathBuf>, ArtifactError> {
    let mut written = Vec::new();
    for (rel, contents) in generated_files_for(model, order)? {
        let path = root.join(&rel);
        write(&path, &contents)?;
        written.push(path);
    }
    Ok(written)
}
