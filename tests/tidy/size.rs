//! Size: no Rust file in the repository (the app, xtask, tests, fixtures, benches, fuzz targets)
//! over [`MAX_LINES`] lines unless listed in [`LONG_FILES`] with the reason one algorithm needs
//! the room. A file past the cap is split by job, not at the line where it crossed.

use crate::{repo, rust_files};

/// Longest file (lines) allowed without a listed reason.
const MAX_LINES: usize = 600;

/// Files allowed above [`MAX_LINES`] (paths from the repository's root), each with why.
const LONG_FILES: &[(&str, &str)] = &[];

#[test]
fn no_rust_file_is_too_long_to_read() {
    let root = repo();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    for must in ["src/lib.rs", "xtask/src/main.rs", "tests/tidy/main.rs"] {
        assert!(
            files.iter().any(|f| f.ends_with(must)),
            "the walk missed {must}: is the file walk broken?"
        );
    }
    let mut long = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap().display().to_string();
        let lines = std::fs::read_to_string(file).unwrap().lines().count();
        let listed = LONG_FILES.iter().any(|(f, _)| *f == rel);
        if lines > MAX_LINES && !listed {
            long.push(format!(
                "{rel}: {lines} lines (over {MAX_LINES}): split it by job, or list it in \
                 LONG_FILES with the reason"
            ));
        }
    }
    assert!(long.is_empty(), "{}", long.join("\n"));
}
