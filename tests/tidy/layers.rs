//! The layers: a module may name only the layers below it; a back edge fails with the file, the
//! line and the rule it breaks.

use std::path::Path;

use crate::{rust_files, src};

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
