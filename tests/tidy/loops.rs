//! Import loops: read from the code's own `use` lines and paths, no file's imports may lead back
//! to it. The layers rule keeps loops from crossing layers; this one looks inside each room.
//!
//! The graph's nodes are files (`src/physics/body.rs` is `physics::body`; inline modules such as
//! `mod tests` belong to their file). An edge runs from the file that names an item to the file
//! that defines it: a path through a parent's `pub use` re-export is followed to the file the
//! item comes from, so `use super::BodyKind` in `physics/world.rs` is an edge to
//! `physics/body.rs` when `physics/mod.rs` re-exports it from there. A re-export itself is the
//! room's front door, not a dependency: `physics/mod.rs` re-exporting `world::Floaters` does not
//! make `mod.rs` depend on `world.rs`. Test modules (`#[cfg(test)] mod tests { .. }`) do not
//! count: they are never part of the program, and build their fixtures from anywhere in their
//! layer. The binary (`main.rs`, `cli/`) is a crate of its own.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use crate::paths::{expand_tree, module_of, parse, Crates, ModPath};
use crate::{repo, rust_files};

/// The whole crate's modules and re-exports, to resolve a path to the file that defines its item.
struct Crate {
    /// Module → the file module holding it (itself for a file, its file for an inline module).
    modules: BTreeMap<ModPath, ModPath>,
    /// (module, name) → the path the module re-exports under that name, written in that module.
    reexports: BTreeMap<(ModPath, String), Vec<String>>,
    /// Modules with `pub use x::*`: module → the glob's source paths.
    globs: BTreeMap<ModPath, Vec<Vec<String>>>,
}

impl Crate {
    /// The file that defines what `segments` names, written in `scope`; `None` for other crates.
    fn resolve(&self, scope: &ModPath, segments: &[String], depth: usize) -> Option<ModPath> {
        if depth > 8 || segments.is_empty() {
            return None;
        }
        let mut at: ModPath;
        let mut rest = segments;
        match segments[0].as_str() {
            "crate" => {
                at = scope[..1].to_vec();
                rest = &rest[1..];
            }
            "self" => {
                at = scope.clone();
                rest = &rest[1..];
            }
            "super" => {
                at = scope.clone();
                while rest.first().is_some_and(|s| s == "super") {
                    at.pop();
                    rest = &rest[1..];
                }
            }
            first => {
                // 2018 paths: a child module of the scope, or an item re-exported into it.
                let mut child = scope.clone();
                child.push(first.to_string());
                if !self.modules.contains_key(&child)
                    && !self
                        .reexports
                        .contains_key(&(scope.clone(), first.to_string()))
                {
                    return None;
                }
                at = scope.clone();
            }
        }
        for (i, seg) in rest.iter().enumerate() {
            let mut child = at.clone();
            child.push(seg.clone());
            if self.modules.contains_key(&child) {
                at = child;
                continue;
            }
            if seg == "*" {
                break;
            }
            if let Some(target) = self.reexports.get(&(at.clone(), seg.clone())) {
                let mut path = target.clone();
                path.extend(rest[i + 1..].iter().cloned());
                return self.resolve(&at, &path, depth + 1);
            }
            if let Some(sources) = self.globs.get(&at) {
                for source in sources {
                    let mut path = source.clone();
                    path.push(seg.clone());
                    if let Some(file) = self.resolve(&at, &path, depth + 1) {
                        if &file != self.modules.get(&at)? {
                            return Some(file);
                        }
                    }
                }
            }
            break;
        }
        self.modules.get(&at).cloned()
    }
}

/// Every import loop among `files` (paths under a crate's source folder `dir` and their text):
/// each as the files in the loop and the lines that close it.
fn import_loops(dir: &str, crates: Crates, files: &[(PathBuf, String)]) -> Vec<String> {
    let mut parsed = Vec::new();
    let mut krate = Crate {
        modules: BTreeMap::new(),
        reexports: BTreeMap::new(),
        globs: BTreeMap::new(),
    };
    for (rel, text) in files {
        let module = module_of(rel, crates);
        krate.modules.insert(module.clone(), module.clone());
        let (p, inline) = parse(module.clone(), text);
        for m in inline {
            krate.modules.insert(m, module.clone());
        }
        for u in p.uses.iter().filter(|u| u.reexport) {
            let last = u.segments.last().cloned().unwrap_or_default();
            if last == "*" {
                let source = u.segments[..u.segments.len() - 1].to_vec();
                krate.globs.entry(u.scope.clone()).or_default().push(source);
            } else if last != "self" {
                krate
                    .reexports
                    .insert((u.scope.clone(), last), u.segments.clone());
            }
        }
        parsed.push((rel.clone(), p));
    }
    // Edges between files, each with one line that makes it.
    let mut edges: BTreeMap<ModPath, BTreeMap<ModPath, String>> = BTreeMap::new();
    let mut file_of: BTreeMap<ModPath, PathBuf> = BTreeMap::new();
    for (rel, p) in &parsed {
        file_of.insert(p.module.clone(), rel.clone());
        for u in p.uses.iter().filter(|u| !u.reexport) {
            let Some(target) = krate.resolve(&u.scope, &u.segments, 0) else {
                continue;
            };
            if target != p.module {
                edges
                    .entry(p.module.clone())
                    .or_default()
                    .entry(target)
                    .or_insert_with(|| format!("{dir}/{}:{}", rel.display(), u.line));
            }
        }
    }
    strongly_connected(&edges)
        .into_iter()
        .map(|component| {
            let names: Vec<String> = component
                .iter()
                .map(|m| format!("{dir}/{}", file_of[m].display()))
                .collect();
            let lines: Vec<String> = component
                .iter()
                .flat_map(|a| {
                    let edges = &edges;
                    let file_of = &file_of;
                    component.iter().filter_map(move |b| {
                        let at = edges.get(a)?.get(b)?;
                        Some(format!(
                            "{at} uses {dir}/{}",
                            file_of.get(b).map(|f| f.display().to_string())?
                        ))
                    })
                })
                .collect();
            format!("{}:\n    {}", names.join(" <-> "), lines.join("\n    "))
        })
        .collect()
}

/// Tarjan's strongly connected components with more than one node: the loops.
fn strongly_connected(edges: &BTreeMap<ModPath, BTreeMap<ModPath, String>>) -> Vec<Vec<ModPath>> {
    struct Walk<'a> {
        edges: &'a BTreeMap<ModPath, BTreeMap<ModPath, String>>,
        index: BTreeMap<&'a ModPath, (usize, usize)>,
        stack: Vec<&'a ModPath>,
        on_stack: BTreeSet<&'a ModPath>,
        next: usize,
        out: Vec<Vec<ModPath>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, v: &'a ModPath) {
            self.index.insert(v, (self.next, self.next));
            self.next += 1;
            self.stack.push(v);
            self.on_stack.insert(v);
            let edges = self.edges;
            for w in edges.get(v).into_iter().flat_map(|e| e.keys()) {
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let low = self.index[w].1.min(self.index[v].1);
                    self.index.get_mut(v).unwrap().1 = low;
                } else if self.on_stack.contains(w) {
                    let low = self.index[w].0.min(self.index[v].1);
                    self.index.get_mut(v).unwrap().1 = low;
                }
            }
            if self.index[v].0 == self.index[v].1 {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack.remove(w);
                    component.push(w.clone());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    self.out.push(component);
                }
            }
        }
    }
    let mut walk = Walk {
        edges,
        index: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !walk.index.contains_key(v) {
            walk.visit(v);
        }
    }
    walk.out
}

#[test]
fn no_file_imports_lead_back_to_it() {
    let repo = repo();
    let mut loops = Vec::new();
    let mut seen = 0;
    for (dir, crates) in [
        ("src", Crates::LibAndBin),
        ("xtask/src", Crates::One),
        ("tests/fixtures/xr-fault-layer/src", Crates::One),
    ] {
        let root = repo.join(dir);
        let mut paths = Vec::new();
        rust_files(&root, &mut paths);
        seen += paths.len();
        let files: Vec<(PathBuf, String)> = paths
            .iter()
            .map(|p| {
                (
                    p.strip_prefix(&root).unwrap().to_path_buf(),
                    std::fs::read_to_string(p).unwrap(),
                )
            })
            .collect();
        loops.extend(import_loops(dir, crates, &files));
    }
    assert!(seen > 100, "found only {seen} source files");
    assert!(
        loops.is_empty(),
        "{} import loop(s): move the shared vocabulary into a leaf module of the room, or the \
         methods into the file of their type:\n{}",
        loops.len(),
        loops.join("\n")
    );
}

/// The checker itself: a loop through a parent's re-export is found and named; the same files
/// without the back edge are clean; comments, strings and re-exports are not edges.
#[test]
fn the_loop_finder_sees_a_loop() {
    let file = |p: &str, t: &str| (PathBuf::from(p), t.to_string());
    let room = "pub mod a;\nmod b;\npub use b::{Slot, Wide};\n";
    let a_loops = "use super::Slot;\npub struct Body;\n";
    let b_back = "use crate::physics::a::Body;\npub struct Slot;\npub struct Wide;\n";
    let b_clean = "// uses crate::physics::a::Body in prose only\nconst S: &str = \"crate::physics::a\";\npub struct Slot;\npub struct Wide;\n";
    let loops = import_loops(
        "src",
        Crates::LibAndBin,
        &[
            file("lib.rs", "pub mod physics;\n"),
            file("physics/mod.rs", room),
            file("physics/a.rs", a_loops),
            file("physics/b.rs", b_back),
        ],
    );
    assert_eq!(loops.len(), 1, "{loops:?}");
    assert!(
        loops[0].starts_with("src/physics/a.rs <-> src/physics/b.rs")
            && loops[0].contains("src/physics/a.rs:1 uses src/physics/b.rs")
            && loops[0].contains("src/physics/b.rs:1 uses src/physics/a.rs"),
        "{}",
        loops[0]
    );
    let clean = import_loops(
        "src",
        Crates::LibAndBin,
        &[
            file("lib.rs", "pub mod physics;\n"),
            file("physics/mod.rs", room),
            file("physics/a.rs", a_loops),
            file("physics/b.rs", b_clean),
        ],
    );
    assert!(clean.is_empty(), "{clean:?}");
    // A multi-line grouped `use`, an inline path and a plain `use` close a loop of three; the
    // same back edge in a test module does not.
    let three = import_loops("src", Crates::LibAndBin, &[
        file("lib.rs", "pub mod sim;\n"),
        file("sim/mod.rs", "mod x;\nmod y;\nmod z;\n"),
        file("sim/x.rs", "use super::{\n    y::Y,\n    other,\n};\npub struct X;\n"),
        file("sim/y.rs", "pub struct Y;\nfn f() { crate::sim::z::go() }\n"),
        file(
            "sim/z.rs",
            "use crate::sim::x::X;\npub fn go() {}\n#[cfg(test)]\nmod tests {\n    use super::*;\n}\n",
        ),
    ]);
    assert_eq!(three.len(), 1, "{three:?}");
    assert!(
        three[0].starts_with("src/sim/x.rs <-> src/sim/y.rs <-> src/sim/z.rs"),
        "{}",
        three[0]
    );
    let tested = import_loops(
        "src",
        Crates::LibAndBin,
        &[
            file("lib.rs", "pub mod sim;\n"),
            file("sim/mod.rs", "mod x;\nmod y;\n"),
            file("sim/x.rs", "use super::y::Y;\npub struct X;\n"),
            file(
                "sim/y.rs",
                "pub struct Y;\n#[cfg(test)]\nmod tests {\n    use crate::sim::x::X;\n}\n",
            ),
        ],
    );
    assert!(tested.is_empty(), "{tested:?}");
    assert_eq!(
        expand_tree("a::{b, c::{d, self}, e as f}"),
        [
            vec!["a", "b"],
            vec!["a", "c", "d"],
            vec!["a", "c"],
            vec!["a", "e"]
        ]
    );
}
