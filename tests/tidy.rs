//! Tidy tests in the manner of rust-analyzer's: they read the sources and fail on structure that
//! would otherwise only live in ARCHITECTURE.md.
//!
//! - Layering: data flows `sim → lod → render → xr → app → android`, with `base` (vocabulary
//!   shared by all) underneath; a module may name only the layers below it. A back edge fails
//!   with the file, the line and the rule it breaks.
//! - Size: no source file over [`MAX_LINES`] lines unless it is listed in [`LONG_FILES`] with the
//!   reason one algorithm needs the room.

use std::path::{Path, PathBuf};

/// The crate's top-level modules and what each may use (besides itself).
const LAYERS: &[(&str, &[&str])] = &[
    ("base", &[]),
    ("sim", &["base"]),
    ("lod", &["base"]),
    // Floating bodies: read the simulation's heights, beside `lod`.
    ("physics", &["base", "sim"]),
    // Sound: made from the simulation's sea, beside `physics` (the app hands it the impacts).
    ("audio", &["base", "sim"]),
    // The user's choices and how they are kept: above the sea, below what draws and runs.
    ("ui", &["base", "sim", "lod", "physics"]),
    ("render", &["base", "sim", "lod", "physics", "ui"]),
    ("xr", &["base", "sim", "lod", "render", "physics", "ui"]),
    (
        "app",
        &[
            "base", "sim", "lod", "render", "xr", "physics", "audio", "ui",
        ],
    ),
    (
        "android",
        &[
            "base", "sim", "lod", "render", "xr", "app", "physics", "audio", "ui",
        ],
    ),
    // Tools of the command line, beside the layers: they read the simulation only.
    ("bench", &["base", "sim"]),
    ("export", &["base", "sim"]),
];

/// Longest file (lines) allowed without a listed reason.
const MAX_LINES: usize = 600;

/// Files allowed above [`MAX_LINES`], each with why.
const LONG_FILES: &[(&str, &str)] = &[];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The layer a source file belongs to (its first path component under `src/`, without `.rs`);
/// `None` for the crate root, the binary and its `cli` module, which may use everything.
fn layer_of(rel: &Path) -> Option<String> {
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    let name = first.strip_suffix(".rs").unwrap_or(&first).to_string();
    match name.as_str() {
        "lib" | "main" | "cli" => None,
        _ => Some(name),
    }
}

/// Every `crate::name` in code (comments skipped), with `crate::{a, b}` groups expanded.
fn crate_paths(line: &str) -> Vec<String> {
    let code = line.split("//").next().unwrap_or("");
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let after = &rest[at + "crate::".len()..];
        // `vr_ocean_crate::` or `some_crate::` are other names: require a boundary before.
        let boundary = rest[..at]
            .chars()
            .last()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
        if boundary {
            if let Some(group) = after.strip_prefix('{') {
                let end = group.find('}').unwrap_or(group.len());
                for item in group[..end].split(',') {
                    let name: String = item
                        .trim()
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if !name.is_empty() {
                        out.push(name);
                    }
                }
            } else {
                let name: String = after
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                out.push(name);
            }
        }
        rest = after;
    }
    out
}

#[test]
fn layers_only_use_the_layers_below_them() {
    let root = src();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    assert!(files.len() > 50, "found only {} source files", files.len());
    let known: Vec<&str> = LAYERS.iter().map(|(l, _)| *l).collect();
    let mut problems = Vec::new();
    let mut checked = 0;
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap();
        let Some(layer) = layer_of(rel) else {
            continue;
        };
        let Some((_, allowed)) = LAYERS.iter().find(|(l, _)| *l == layer) else {
            problems.push(format!(
                "src/{}: top-level module `{layer}` is not in tidy.rs's LAYERS: say where it \
                 sits in the data flow",
                rel.display()
            ));
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            for used in crate_paths(line) {
                checked += 1;
                if used == layer || !known.contains(&used.as_str()) {
                    continue;
                }
                if !allowed.contains(&used.as_str()) {
                    problems.push(format!(
                        "src/{}:{}: `{layer}` uses `crate::{used}`, but {layer} may use only {:?} \
                         (data flows sim → lod → render → xr → app): {}",
                        rel.display(),
                        i + 1,
                        allowed,
                        line.trim()
                    ));
                }
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} crate paths seen: is the parser broken?"
    );
    assert!(problems.is_empty(), "back edges:\n{}", problems.join("\n"));
}

#[test]
fn the_layer_parser_sees_back_edges() {
    // The checker itself: a `use` that runs back up is found, grouped or not; comments are not.
    assert_eq!(crate_paths("use crate::render::GpuContext;"), ["render"]);
    assert_eq!(
        crate_paths("use crate::{render::X, xr::Y};"),
        ["render", "xr"]
    );
    assert_eq!(
        crate_paths("let x = crate::lod::frustum::MAX; // crate::app"),
        ["lod"]
    );
    assert!(crate_paths("use other_crate::render;").is_empty());
    assert_eq!(
        layer_of(Path::new("sim/fft/x86.rs")).as_deref(),
        Some("sim")
    );
    assert_eq!(layer_of(Path::new("export.rs")).as_deref(), Some("export"));
    assert_eq!(layer_of(Path::new("main.rs")), None);
}

#[test]
fn no_source_file_is_too_long_to_read() {
    let root = src();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut long = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap().display().to_string();
        let lines = std::fs::read_to_string(file).unwrap().lines().count();
        let listed = LONG_FILES.iter().any(|(f, _)| *f == rel);
        if lines > MAX_LINES && !listed {
            long.push(format!(
                "src/{rel}: {lines} lines (over {MAX_LINES}): split it by job, or list it in \
                 LONG_FILES with the reason"
            ));
        }
    }
    assert!(long.is_empty(), "{}", long.join("\n"));
}
