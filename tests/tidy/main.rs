//! Tidy tests in the manner of rust-analyzer's: they read the sources and fail on structure that
//! would otherwise only live in ARCHITECTURE.md.
//!
//! - [`layers`]: data flows `sim → lod → render → xr → app → android`, with `base` (vocabulary
//!   shared by all) underneath; a module may name only the layers below it.
//! - [`loops`]: inside a layer, no file's imports lead back to it (no import loops).
//! - [`size`]: no Rust file in the repository over 600 lines unless listed with a reason.
//! - [`arch`]: code per CPU architecture only in the layers CI's aarch64 step tests.

mod arch;
mod layers;
mod loops;
mod paths;
mod size;

use std::path::{Path, PathBuf};

/// The repository's root (the main crate's manifest directory).
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The main crate's sources.
fn src() -> PathBuf {
    repo().join("src")
}

/// Every `.rs` file under `dir`, sorted, skipping build outputs and other trees that are not ours.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if p.is_dir() {
            if !matches!(name, "target" | ".git" | "corpus" | "artifacts") && !name.starts_with('.')
            {
                rust_files(&p, out);
            }
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}
