//! Reading the named paths out of Rust source as text, for the loop rule ([`crate::loops`]):
//! `use` trees expanded, paths in running code that start at `crate`, `super` or `self`,
//! comments and strings blanked, inline modules found by rustfmt's indentation, test modules
//! left out; and which module each file declares.

use std::path::Path;

/// A module's path from its crate's root, with the crate (`lib` or `bin`) first.
pub(crate) type ModPath = Vec<String>;

/// One named path in a file: where it is, whether it is a re-export, and its segments.
pub(crate) struct Use {
    pub(crate) line: usize,
    /// The module the path is written in (the file's, or an inline module's inside it).
    pub(crate) scope: ModPath,
    pub(crate) reexport: bool,
    pub(crate) segments: Vec<String>,
}

/// What the walk learns of one file.
pub(crate) struct Parsed {
    pub(crate) module: ModPath,
    pub(crate) uses: Vec<Use>,
}

/// How a source folder's files divide into crates.
#[derive(Clone, Copy)]
pub(crate) enum Crates {
    /// The app's `src/`: the library, and the binary (`main.rs`, `cli/`) as a crate of its own.
    LibAndBin,
    /// One crate (xtask's binary, the fault layer's library).
    One,
}

/// The module a file under a crate's `src/` declares, with its crate first.
pub(crate) fn module_of(rel: &Path, crates: Crates) -> ModPath {
    let parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let bin = parts[0] == "main.rs" || parts[0] == "cli" || parts[0] == "cli.rs";
    let name = match crates {
        Crates::LibAndBin if bin => "bin",
        Crates::LibAndBin => "lib",
        Crates::One => "crate",
    };
    let mut module = vec![name.to_string()];
    for (i, p) in parts.iter().enumerate() {
        let last = i + 1 == parts.len();
        let name = p.strip_suffix(".rs").unwrap_or(p);
        if last && matches!(name, "mod" | "lib" | "main") {
            break;
        }
        module.push(name.to_string());
    }
    module
}

/// `a::b::{c, d::{e, self}, *}` expanded into its leaf paths.
pub(crate) fn expand_tree(tree: &str) -> Vec<Vec<String>> {
    fn split_top(s: &str) -> Vec<&str> {
        let (mut depth, mut start, mut out) = (0, 0, Vec::new());
        for (i, ch) in s.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.push(&s[start..i]);
                    start = i + 1;
                }
                _ => {}
            }
        }
        out.push(&s[start..]);
        out
    }
    let tree = tree.trim();
    if tree.is_empty() {
        return Vec::new();
    }
    if let Some(open) = tree.find('{') {
        let prefix: Vec<String> = tree[..open]
            .split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let close = tree.rfind('}').unwrap_or(tree.len());
        let mut out = Vec::new();
        for item in split_top(&tree[open + 1..close]) {
            for rest in expand_tree(item) {
                let mut path = prefix.clone();
                if rest != ["self"] {
                    path.extend(rest);
                }
                out.push(path);
            }
        }
        return out;
    }
    // `x as y`: the path is `x`.
    let path = tree.split(" as ").next().unwrap_or(tree);
    vec![path.split("::").map(|s| s.trim().to_string()).collect()]
}

/// Code only: a line's `//` comment and string literals blanked, so paths in prose don't count.
fn code_of(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut in_str = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        if in_str {
            if c == '\\' {
                chars.next();
            } else if c == '"' {
                in_str = false;
            }
            out.push(' ');
        } else if c == '"' {
            in_str = true;
            out.push(' ');
        } else if c == '/' && chars.peek() == Some(&'/') {
            break;
        } else {
            out.push(c);
        }
    }
    out
}

/// Paths in running code that start at `crate`, `super` or `self` (`crate::sim::GRAVITY * x`).
fn inline_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for root in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(at) = code[from..].find(root) {
            let at = from + at;
            from = at + root.len();
            let boundary = code[..at]
                .chars()
                .last()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_' || c == ':'));
            if !boundary {
                continue;
            }
            let chain: String = code[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            out.push(
                chain
                    .split("::")
                    .filter(|s| !s.is_empty())
                    .map(String::from)
                    .collect(),
            );
        }
    }
    out
}

/// A file's named paths, with the inline modules it opens (found by rustfmt's indentation: an
/// inline `mod name {` closes at the `}` with the same indent).
pub(crate) fn parse(module: ModPath, text: &str) -> (Parsed, Vec<ModPath>) {
    let mut uses = Vec::new();
    let mut inline = Vec::new();
    // Open inline modules: indent, name, whether it is a test module.
    let mut stack: Vec<(usize, String, bool)> = Vec::new();
    let mut pending: Option<(usize, bool, String)> = None;
    let mut after_cfg_test = false;
    for (i, raw) in text.lines().enumerate() {
        let indent = raw.len() - raw.trim_start().len();
        let trimmed = raw.trim();
        if let Some((open_indent, _, _)) = stack.last() {
            if trimmed == "}" && indent == *open_indent {
                stack.pop();
                continue;
            }
        }
        let cfg_test = std::mem::replace(&mut after_cfg_test, trimmed == "#[cfg(test)]");
        let mut scope = module.clone();
        scope.extend(stack.iter().map(|(_, n, _)| n.clone()));
        let in_test = stack.iter().any(|(_, _, test)| *test);
        let code = code_of(raw);
        let words: Vec<&str> = code.split_whitespace().collect();
        let mod_at = words.iter().position(|w| *w == "mod");
        if let Some(at) = mod_at {
            if words.get(at + 2) == Some(&"{") && words[..at].iter().all(|w| w.starts_with("pub")) {
                let name = words[at + 1].to_string();
                let mut m = scope.clone();
                m.push(name.clone());
                inline.push(m);
                stack.push((indent, name, cfg_test));
                continue;
            }
        }
        if in_test {
            continue;
        }
        if let Some((line, reexport, mut acc)) = pending.take() {
            acc.push(' ');
            acc.push_str(&code);
            if let Some(end) = acc.find(';') {
                for segments in expand_tree(&acc[..end]) {
                    uses.push(Use {
                        line,
                        scope: scope.clone(),
                        reexport,
                        segments,
                    });
                }
            } else {
                pending = Some((line, reexport, acc));
            }
            continue;
        }
        let use_at = words.iter().position(|w| *w == "use");
        if let Some(at) = use_at {
            if words[..at]
                .iter()
                .all(|w| w.starts_with("pub") || w.starts_with("#["))
            {
                let reexport = words[..at].iter().any(|w| w.starts_with("pub"));
                let start = code.find("use ").unwrap() + 4;
                let acc = code[start..].to_string();
                if let Some(end) = acc.find(';') {
                    for segments in expand_tree(&acc[..end]) {
                        uses.push(Use {
                            line: i + 1,
                            scope: scope.clone(),
                            reexport,
                            segments,
                        });
                    }
                } else {
                    pending = Some((i + 1, reexport, acc));
                }
                continue;
            }
        }
        for segments in inline_paths(&code) {
            uses.push(Use {
                line: i + 1,
                scope: scope.clone(),
                reexport: false,
                segments,
            });
        }
    }
    (Parsed { module, uses }, inline)
}
