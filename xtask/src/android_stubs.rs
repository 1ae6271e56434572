//! Stub Android system libraries for linking `libvr_ocean.so` without the NDK.
//!
//! AOSP's symbol maps (`xtask/android-api/*.map.txt`, copied from `shared/android-api/`) list
//! what libc, libm, libdl, liblog and libandroid export to apps, per architecture and API
//! level. [`parse_map`] keeps what an arm64 app may use at a given minimum API (the rules of
//! the NDK's own stub generator: no `_PRIVATE`/`_PLATFORM` versions, nothing tagged
//! `platform-only`, `llndk`, `apex`, `systemapi` or `future`, nothing introduced later or for
//! other architectures); [`build_stubs`] writes each library as an assembly file of empty
//! functions (`var` symbols as 8-byte objects) plus a version script, and builds it with
//! Debian's clang and lld (`--target=aarch64-linux-android29 -shared -nostdlib`). Linking
//! against these with `-z defs` fails on any import Android 10 does not have.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::process::{capture, workspace_root};
use crate::{Failure, Result};

/// The libraries stubbed, by map file stem (the stub is `<stem>.so`).
pub const LIBRARIES: &[&str] = &["libc", "libm", "libdl", "liblog", "libandroid", "libaaudio"];

/// The architecture tag of arm64 in the maps.
const ARCH: &str = "arm64";

/// Every architecture tag the maps use (a symbol with any of them exists only there).
const ARCH_TAGS: &[&str] = &["arm", "arm64", "x86", "x86_64", "riscv64", "mips", "mips64"];

/// Tags that keep a symbol or version out of the app-facing (NDK) stubs.
const NOT_FOR_APPS: &[&str] = &["platform-only", "llndk", "apex", "systemapi", "future"];

/// One exported symbol.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Symbol {
    /// Its name.
    pub name: String,
    /// A data object (`# var`) rather than a function.
    pub object: bool,
    /// Weak (`# weak`).
    pub weak: bool,
}

/// A symbol version node (`LIBC_N { ... } LIBC;`) and what it keeps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Version {
    /// Version name, e.g. `LIBC_N`.
    pub name: String,
    /// Symbols of this version available to the app.
    pub symbols: Vec<Symbol>,
    /// Symbols listed under this version that are exported unversioned at the chosen API
    /// (`versioned=N` above it).
    pub unversioned: Vec<Symbol>,
}

/// The API level a tag value names (`29`, or a codename); `None` for codenames not known to
/// be released (treated as the future).
fn api_of(value: &str) -> Option<u32> {
    match value {
        "Tiramisu" => Some(33),
        "UpsideDownCake" => Some(34),
        "VanillaIceCream" => Some(35),
        "Baklava" => Some(36),
        v => v.parse().ok(),
    }
}

/// Whether an item with `tags` exists for arm64 at `api` (arch tags, `introduced`,
/// `introduced-arm64`, the not-for-apps tags). Errors name a malformed tag.
fn available(tags: &[&str], api: u32) -> std::result::Result<bool, String> {
    let arches: Vec<&str> = tags
        .iter()
        .copied()
        .filter(|t| ARCH_TAGS.contains(t))
        .collect();
    if !arches.is_empty() && !arches.contains(&ARCH) {
        return Ok(false);
    }
    if tags.iter().any(|t| NOT_FOR_APPS.contains(t)) {
        return Ok(false);
    }
    let mut introduced = None;
    let mut introduced_arch = None;
    for tag in tags {
        if let Some(v) = tag.strip_prefix("introduced=") {
            introduced = Some(api_of(v));
        } else if let Some(v) = tag.strip_prefix(&format!("introduced-{ARCH}=")) {
            introduced_arch = Some(api_of(v));
        } else if tag.starts_with("introduced") && !tag.contains('=') {
            return Err(format!("tag `{tag}` has no value"));
        }
    }
    Ok(match introduced_arch.or(introduced) {
        None => true,
        Some(None) => false,
        Some(Some(level)) => level <= api,
    })
}

/// The API level from which a symbol is versioned (`versioned=N`), if tagged.
fn versioned_from(tags: &[&str]) -> Option<u32> {
    tags.iter()
        .find_map(|t| t.strip_prefix("versioned="))
        .and_then(api_of)
}

/// Splits `text # tags` into the code and its tags.
fn split_comment(line: &str) -> (&str, Vec<&str>) {
    match line.split_once('#') {
        Some((code, tags)) => (code.trim(), tags.split_whitespace().collect()),
        None => (line.trim(), Vec::new()),
    }
}

/// Parses one map file and keeps what arm64 apps may use at `api`. `name` is for errors.
pub fn parse_map(name: &str, text: &str, api: u32) -> Result<Vec<Version>> {
    let err = |line: usize, msg: String| Failure::Msg(format!("{name}:{line}: {msg}"));
    let mut versions = Vec::new();
    // (version, kept) while inside a `{ ... }` block.
    let mut current: Option<(Version, bool)> = None;
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let (code, tags) = split_comment(raw);
        if code.is_empty() {
            continue;
        }
        if let Some(head) = code.strip_suffix('{') {
            if current.is_some() {
                return Err(err(line_no, "a version block inside another".into()));
            }
            let vname = head.trim();
            if vname.is_empty() || vname.contains(char::is_whitespace) {
                return Err(err(line_no, format!("bad version name `{vname}`")));
            }
            let private = vname.ends_with("_PRIVATE") || vname.ends_with("_PLATFORM");
            let keep = !private && available(&tags, api).map_err(|m| err(line_no, m))?;
            current = Some((
                Version {
                    name: vname.to_string(),
                    symbols: Vec::new(),
                    unversioned: Vec::new(),
                },
                keep,
            ));
            continue;
        }
        if code.starts_with('}') {
            let Some((version, keep)) = current.take() else {
                return Err(err(line_no, "`}` without an open version block".into()));
            };
            if keep && !(version.symbols.is_empty() && version.unversioned.is_empty()) {
                versions.push(version);
            }
            continue;
        }
        let Some((version, keep)) = current.as_mut() else {
            return Err(err(line_no, format!("`{code}` outside a version block")));
        };
        if code == "global:" || code == "local:" || code == "*;" {
            continue;
        }
        let Some(sym) = code.strip_suffix(';') else {
            return Err(err(line_no, format!("expected `symbol;`, found `{code}`")));
        };
        if sym.is_empty() || !sym.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(err(line_no, format!("bad symbol name `{sym}`")));
        }
        if !*keep || !available(&tags, api).map_err(|m| err(line_no, m))? {
            continue;
        }
        let symbol = Symbol {
            name: sym.to_string(),
            object: tags.contains(&"var"),
            weak: tags.contains(&"weak"),
        };
        if versioned_from(&tags).is_some_and(|from| from > api) {
            version.unversioned.push(symbol);
        } else {
            version.symbols.push(symbol);
        }
    }
    if let Some((version, _)) = current {
        return Err(Failure::Msg(format!(
            "{name}: version block `{}` is not closed",
            version.name
        )));
    }
    Ok(versions)
}

/// The stub's assembly: an empty function (`ret`) or an 8-byte object per symbol.
pub fn stub_assembly(versions: &[Version]) -> String {
    let mut s =
        String::from("// Generated by cargo xtask (android_stubs.rs): link-time stub only.\n");
    let mut seen = std::collections::BTreeSet::new();
    for sym in versions
        .iter()
        .flat_map(|v| v.symbols.iter().chain(&v.unversioned))
    {
        // A symbol listed under two versions (e.g. moved) is defined once.
        if !seen.insert(sym.name.as_str()) {
            continue;
        }
        let bind = if sym.weak { ".weak" } else { ".globl" };
        let n = &sym.name;
        if sym.object {
            let _ = writeln!(
                s,
                ".data\n.balign 8\n{bind} {n}\n.type {n}, %object\n.size {n}, 8\n{n}:\n.quad 0"
            );
        } else {
            let _ = writeln!(
                s,
                ".text\n.balign 4\n{bind} {n}\n.type {n}, %function\n{n}:\nret"
            );
        }
    }
    s
}

/// The version script giving each symbol its version, as in the real library.
pub fn version_script(versions: &[Version]) -> String {
    let mut s = String::new();
    for v in versions.iter().filter(|v| !v.symbols.is_empty()) {
        let _ = writeln!(s, "{} {{\n  global:", v.name);
        for sym in &v.symbols {
            let _ = writeln!(s, "    {};", sym.name);
        }
        s.push_str("};\n");
    }
    s
}

/// The directory with the maps.
pub fn maps_dir() -> PathBuf {
    workspace_root().join("xtask").join("android-api")
}

/// Writes and builds every stub library for arm64 at `api` into `out` (created), plus an
/// empty `libunwind.a` (Rust's std for Android links `-lunwind`; the `unwinding` crate
/// provides the symbols). Returns how many symbols each library got.
pub fn build_stubs(out: &Path, api: u32) -> Result<Vec<(String, usize)>> {
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", out.display())))?;
    let mut counts = Vec::new();
    for lib in LIBRARIES {
        let map = maps_dir().join(format!("{lib}.map.txt"));
        let text = std::fs::read_to_string(&map)
            .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", map.display())))?;
        let versions = parse_map(&map.display().to_string(), &text, api)?;
        let n: usize = versions
            .iter()
            .map(|v| v.symbols.len() + v.unversioned.len())
            .sum();
        let asm = out.join(format!("{lib}.S"));
        let script = out.join(format!("{lib}.map"));
        let so = out.join(format!("{lib}.so"));
        write(&asm, &stub_assembly(&versions))?;
        write(&script, &version_script(&versions))?;
        link_shared(api, &asm, Some(&script), &format!("{lib}.so"), &so)?;
        counts.push((lib.to_string(), n));
    }
    // An empty ar archive: the 8-byte global header and no members.
    write(&out.join("libunwind.a"), "!<arch>\n")?;
    Ok(counts)
}

/// Assembles `asm` into an arm64 Android (`api`) shared object `out` named `soname`, with an
/// optional version script (Debian's clang and lld).
pub fn link_shared(
    api: u32,
    asm: &Path,
    script: Option<&Path>,
    soname: &str,
    out: &Path,
) -> Result<()> {
    let mut cmd = Command::new("clang");
    cmd.arg(format!("--target=aarch64-linux-android{api}"))
        .args(["-shared", "-nostdlib", "-fuse-ld=lld"])
        .arg(format!("-Wl,-soname,{soname}"));
    if let Some(script) = script {
        cmd.arg(format!("-Wl,--version-script={}", script.display()));
    }
    capture(cmd.arg("-o").arg(out).arg(asm)).map(|_| ())
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text)
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAP: &str = "\
LIBC {
  global:
    plain;
    armonly; # arm
    arm64too; # arm arm64
    later; # introduced=30
    now; # introduced=29
    archlater; # introduced=21 introduced-arm64=31
    archnow; # introduced=31 introduced-arm64=24
    environ; # var
    weakling; # weak
    vendor; # llndk
    inapex; # apex
    soon; # introduced=UpsideDownCake
  local:
    *;
};

LIBC_N { # introduced-arm64=24 introduced-x86=24
  global:
    n_sym; # introduced=24
    late_version; # introduced=24 versioned=30
} LIBC;

LIBC_R { # introduced=30
  global:
    r_sym;
} LIBC_N;

LIBC_PRIVATE {
  global:
    private_sym;
} LIBC_R;

LIBC_DEPRECATED { # arm platform-only
  global: # arm
    old; # arm
} LIBC_O; # arm
";

    fn names(v: &Version) -> Vec<&str> {
        v.symbols.iter().map(|s| s.name.as_str()).collect()
    }

    #[test]
    fn keeps_what_arm64_has_at_api_29() {
        let versions = parse_map("test", MAP, 29).unwrap();
        assert_eq!(versions.len(), 2, "{versions:?}");
        assert_eq!(versions[0].name, "LIBC");
        assert_eq!(
            names(&versions[0]),
            ["plain", "arm64too", "now", "archnow", "environ", "weakling"]
        );
        assert!(versions[0].symbols[4].object && !versions[0].symbols[0].object);
        assert!(versions[0].symbols[5].weak);
        assert_eq!(versions[1].name, "LIBC_N");
        assert_eq!(names(&versions[1]), ["n_sym"]);
        assert_eq!(versions[1].unversioned[0].name, "late_version");
        // At API 30 the R version and `later` appear, and `late_version` gets its version.
        let v30 = parse_map("test", MAP, 30).unwrap();
        assert_eq!(v30.len(), 3);
        assert!(names(&v30[0]).contains(&"later"));
        assert_eq!(names(&v30[1]), ["n_sym", "late_version"]);
        assert_eq!(names(&v30[2]), ["r_sym"]);
    }

    #[test]
    fn malformed_maps_are_errors_naming_the_line() {
        for (bad, line) in [
            ("LIBC {\n  global:\n    foo\n};\n", 3),
            ("  foo;\n", 1),
            ("LIBC {\n  global:\n    foo;\n", 0),
            ("LIBC {\n    foo bar;\n};\n", 2),
            ("};\n", 1),
        ] {
            match parse_map("m.txt", bad, 29) {
                Err(Failure::Msg(msg)) => {
                    if line > 0 {
                        assert!(msg.starts_with(&format!("m.txt:{line}:")), "{msg}");
                    } else {
                        assert!(msg.contains("not closed"), "{msg}");
                    }
                }
                other => panic!("{bad:?} gave {other:?}"),
            }
        }
    }

    #[test]
    fn assembly_and_script_agree() {
        let versions = parse_map("test", MAP, 29).unwrap();
        let asm = stub_assembly(&versions);
        assert!(asm.contains(".globl plain\n.type plain, %function\nplain:\nret"));
        assert!(asm.contains(".type environ, %object\n.size environ, 8"));
        assert!(asm.contains(".weak weakling"));
        assert!(asm.contains(".globl late_version"));
        assert!(!asm.contains("later") && !asm.contains("private_sym"));
        let script = version_script(&versions);
        assert_eq!(
            script,
            "LIBC {\n  global:\n    plain;\n    arm64too;\n    now;\n    archnow;\n    \
             environ;\n    weakling;\n};\nLIBC_N {\n  global:\n    n_sym;\n};\n"
        );
    }

    #[test]
    fn real_maps_parse_and_have_the_basics() {
        for lib in LIBRARIES {
            let path = maps_dir().join(format!("{lib}.map.txt"));
            let text = std::fs::read_to_string(&path).unwrap();
            let versions = parse_map(lib, &text, 29).unwrap();
            let all: Vec<&str> = versions
                .iter()
                .flat_map(|v| v.symbols.iter().map(|s| s.name.as_str()))
                .collect();
            let expect: &[&str] = match *lib {
                "libc" => &[
                    "malloc",
                    "pthread_create",
                    "__cxa_thread_atexit_impl",
                    "getauxval",
                ],
                "libm" => &["sinf", "fmaf"],
                "libdl" => &["dlopen", "dl_iterate_phdr"],
                "liblog" => &["__android_log_write"],
                "libaaudio" => &["AAudio_createStreamBuilder", "AAudioStream_getXRunCount"],
                _ => &["ANativeWindow_release", "ALooper_pollOnce"],
            };
            for e in expect {
                assert!(all.contains(e), "{lib} lacks {e}");
            }
        }
        // bionic's `_Unwind_*` and API 30+ symbols are not there at 29.
        let libc = std::fs::read_to_string(maps_dir().join("libc.map.txt")).unwrap();
        let all: Vec<String> = parse_map("libc", &libc, 29)
            .unwrap()
            .into_iter()
            .flat_map(|v| v.symbols.into_iter().map(|s| s.name))
            .collect();
        assert!(!all.iter().any(|s| s.starts_with("_Unwind_")));
        assert!(!all.iter().any(|s| s == "memfd_create"), "API 30");
        // AAudio's API 30 additions are not there at 29 either.
        let aaudio = std::fs::read_to_string(maps_dir().join("libaaudio.map.txt")).unwrap();
        let all: Vec<String> = parse_map("libaaudio", &aaudio, 29)
            .unwrap()
            .into_iter()
            .flat_map(|v| v.symbols.into_iter().map(|s| s.name))
            .collect();
        assert!(all
            .iter()
            .any(|s| s == "AAudioStream_getAllowedCapturePolicy"));
        assert!(!all.iter().any(|s| s == "AAudioStream_release"), "API 30");
    }
}
