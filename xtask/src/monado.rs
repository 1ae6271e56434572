//! The Debian trixie root that the OpenXR tests run Monado in.
//!
//! Monado (the open-source OpenXR runtime) is not packaged for bookworm, and trixie's build needs
//! a newer glibc than the host's, so the `openxr (Monado)` step runs `monado-service` and the
//! test clients in a trixie chroot (see `docs/notes/monado-headless-ci.md`). [`ensure_root`]
//! makes sure that root exists and holds [`PACKAGES`]:
//!
//! * `<cache>/monado-trixie/` is the root and `<cache>/monado-trixie.tar.zst` a tarball of it,
//!   where `<cache>` is `$VR_OCEAN_CACHE` or `/var/cache/vr-ocean`.
//! * A stamp file in the root records the suite, mirror and package list. A root whose stamp
//!   differs from [`stamp_text`] is rebuilt.
//! * A missing root is restored from the tarball when the tarball's stamp matches (seconds);
//!   otherwise it is made with `debootstrap` (about 100 s, network) and the tarball is rewritten.
//! * Everything is built in `<cache>/monado-trixie.partial` and renamed into place at the end, so
//!   a killed run never leaves a root that looks complete. A lock file serializes xtask runs.
//!
//! It needs root: debootstrap creates device nodes and the tests `chroot`. Unprivileged
//! `unshare -r chroot` does work on the CI kernel, but debootstrap cannot `mknod` in a user
//! namespace and the root's files belong to real root, so there is no rootless path here.

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use crate::{is_root, on_path, show, Failure, Result};

/// The Debian suite of the root.
pub const SUITE: &str = "trixie";

/// Where debootstrap downloads from.
pub const MIRROR: &str = "http://deb.debian.org/debian";

/// Packages installed in the root (on top of debootstrap's minbase): the Monado service and
/// runtime library, the OpenXR loader and core validation layer, Vulkan on lavapipe with the
/// Khronos validation layer (trixie's, not the host's), and ALSA's library.
pub const PACKAGES: &[&str] = &[
    "monado-service",
    "libopenxr1-monado",
    "libopenxr-loader1",
    "openxr-layer-corevalidation",
    "mesa-vulkan-drivers",
    "libvulkan1",
    "vulkan-validationlayers",
    // The sound's output links ALSA (cpal); the chroot has no sound card, so the run goes
    // silent on its clock, as on any machine without one.
    "libasound2t64",
];

/// Name of the stamp file inside the root.
const STAMP: &str = "vr-ocean-stamp.txt";

/// The directory holding the root, its tarball and the lock: `$VR_OCEAN_CACHE` when set,
/// otherwise `/var/cache/vr-ocean`.
pub fn cache_dir() -> PathBuf {
    std::env::var_os("VR_OCEAN_CACHE")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/var/cache/vr-ocean"))
}

/// The root: `<cache>/monado-trixie`.
pub fn root_path() -> PathBuf {
    cache_dir().join(format!("monado-{SUITE}"))
}

/// The tarball of a freshly built root: `<cache>/monado-trixie.tar.zst`.
pub fn tarball_path() -> PathBuf {
    cache_dir().join(format!("monado-{SUITE}.tar.zst"))
}

/// What the stamp of an up-to-date root says. Changing the suite, mirror or package list
/// changes it and so rebuilds the root.
pub fn stamp_text() -> String {
    format!(
        "vr-ocean Monado root, made by `cargo xtask` (xtask/src/monado.rs)\n\
         suite={SUITE}\nmirror={MIRROR}\nvariant=minbase\npackages={}\n",
        PACKAGES.join(",")
    )
}

/// The `prepare` hook of the `openxr (Monado)` step: the root's path for the tests.
pub fn prepare_step() -> Result<Vec<(String, String)>> {
    let root = ensure_root()?;
    // The failure tests load the fault-injection API layer into the client
    // (`tests/common/fault_layer.rs` finds it next to the test binaries, same profile).
    note("building the OpenXR fault-injection layer (tests/fixtures/xr-fault-layer)");
    let status = crate::cargo()
        .args(["build", "-p", "xr-fault-layer"])
        .status()
        .map_err(|e| Failure::Msg(format!("cannot run cargo: {e}")))?;
    if !status.success() {
        return Err(Failure::Msg("cargo build -p xr-fault-layer failed".into()));
    }
    Ok(vec![(
        "VR_OCEAN_MONADO_ROOT".into(),
        root.to_string_lossy().into_owned(),
    )])
}

/// Makes sure the root exists and is up to date (see the module docs); returns its path.
pub fn ensure_root() -> Result<PathBuf> {
    let root = root_path();
    if !is_root() {
        return Err(Failure::Msg(format!(
            "the Monado step needs root: it builds a Debian {SUITE} chroot ({}) with debootstrap \
             and runs monado-service and the OpenXR tests in it with chroot.\n  Run as root (CI \
             does), e.g. `sudo -E env \"PATH=$PATH\" cargo xtask test`, or skip the slow steps \
             with `cargo xtask test --quick`.",
            root.display()
        )));
    }
    let cache = cache_dir();
    fs::create_dir_all(&cache)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", cache.display())))?;

    // One xtask at a time: two concurrent builds would share `.partial`.
    let lock_path = cache.join(format!("monado-{SUITE}.lock"));
    let lock = File::create(&lock_path)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", lock_path.display())))?;
    if lock.try_lock().is_err() {
        note(&format!(
            "waiting for {} (another xtask is preparing the root)",
            lock_path.display()
        ));
        lock.lock()
            .map_err(|e| Failure::Msg(format!("cannot lock {}: {e}", lock_path.display())))?;
    }

    let want = stamp_text();
    if root.exists() {
        if read_stamp(&root).as_deref() == Some(want.as_str()) {
            note(&format!("Monado root up to date: {}", root.display()));
            return Ok(root);
        }
        note(&format!(
            "Monado root {} is outdated or incomplete (its {STAMP} differs): rebuilding",
            root.display()
        ));
        let old = cache.join(format!("monado-{SUITE}.old"));
        remove_tree(&old)?;
        rename(&root, &old)?;
        remove_tree(&old)?;
    }

    let partial = cache.join(format!("monado-{SUITE}.partial"));
    remove_tree(&partial)?;

    let tarball = tarball_path();
    if tarball.exists() && restore(&tarball, &partial)? {
        rename(&partial, &root)?;
        return Ok(root);
    }

    build(&partial)?;
    rename(&partial, &root)?;
    // The tarball is only a cache: failing to write it does not fail the step.
    if let Err(Failure::Msg(msg)) = write_tarball(&root, &tarball) {
        note(&format!("warning: could not write the tarball: {msg}"));
    }
    Ok(root)
}

/// Unpacks `tarball` into `partial`. Returns false (and leaves nothing behind) when the tarball
/// is unreadable or holds a root for another package set.
fn restore(tarball: &Path, partial: &Path) -> Result<bool> {
    need_tool("zstd")?;
    note(&format!(
        "restoring the Monado root from {}",
        tarball.display()
    ));
    let start = Instant::now();
    mkdir(partial)?;
    let mut zstd = Command::new("zstd");
    zstd.args(["-d", "-c", "-q"]).arg(tarball);
    let mut tar = Command::new("tar");
    tar.arg("-C").arg(partial).args([
        "--numeric-owner",
        "--xattrs",
        "--xattrs-include=*",
        "-xpf",
        "-",
    ]);
    let ok = pipe(&mut zstd, &mut tar)?;
    let stamp = read_stamp(partial);
    if ok && stamp.as_deref() == Some(stamp_text().as_str()) {
        note(&format!(
            "restored the Monado root in {:.1} s",
            start.elapsed().as_secs_f64()
        ));
        return Ok(true);
    }
    if ok {
        note("the tarball holds a root for another package set: ignoring it");
    } else {
        note("the tarball could not be unpacked: ignoring it");
    }
    remove_tree(partial)?;
    Ok(false)
}

/// Runs debootstrap into `partial`, removes apt's caches and writes the stamp.
fn build(partial: &Path) -> Result<()> {
    let debootstrap = ["/usr/sbin/debootstrap", "/sbin/debootstrap"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
        .or_else(|| on_path("debootstrap").then(|| PathBuf::from("debootstrap")))
        .ok_or_else(|| {
            Failure::Msg(
                "debootstrap not found: install it (apt-get install debootstrap zstd), or run \
                 `cargo xtask test` without --no-setup so that it is installed"
                    .into(),
            )
        })?;
    let log_path = partial.with_extension("debootstrap.log");
    let log = File::create(&log_path)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", log_path.display())))?;
    let log_err = log
        .try_clone()
        .map_err(|e| Failure::Msg(format!("cannot reopen {}: {e}", log_path.display())))?;
    let mut cmd = Command::new(debootstrap);
    cmd.args([
        "--variant=minbase",
        &format!("--include={}", PACKAGES.join(",")),
    ])
    .arg(SUITE)
    .arg(partial)
    .arg(MIRROR)
    .stdin(Stdio::null())
    .stdout(log)
    .stderr(log_err);
    note(&format!(
        "building the Monado root (about 100 s; log: {}): {}",
        log_path.display(),
        show(&cmd)
    ));
    let start = Instant::now();
    let status = cmd
        .status()
        .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(&cmd))))?;
    if !status.success() {
        let text = fs::read_to_string(&log_path).unwrap_or_default();
        return Err(Failure::Msg(format!(
            "debootstrap failed ({status}); the end of {}:\n{}",
            log_path.display(),
            tail(&text, 30)
        )));
    }
    note(&format!(
        "debootstrap took {:.1} s",
        start.elapsed().as_secs_f64()
    ));

    let start = Instant::now();
    let before = size_mb(partial);
    for dir in [
        "var/cache/apt/archives",
        "var/cache/apt",
        "var/lib/apt/lists",
    ] {
        let Ok(entries) = fs::read_dir(partial.join(dir)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            let junk = name.ends_with(".deb")
                || name.ends_with(".bin")
                || (dir.ends_with("lists") && path.is_file() && name != "lock");
            if junk {
                fs::remove_file(&path)
                    .map_err(|e| Failure::Msg(format!("cannot remove {}: {e}", path.display())))?;
            }
        }
    }
    note(&format!(
        "removed apt's caches: {} MB -> {} MB ({:.1} s)",
        before,
        size_mb(partial),
        start.elapsed().as_secs_f64()
    ));
    if !mounts_below(partial).is_empty() {
        return Err(Failure::Msg(format!(
            "debootstrap left file systems mounted in {}",
            partial.display()
        )));
    }
    fs::write(partial.join(STAMP), stamp_text())
        .map_err(|e| Failure::Msg(format!("cannot write the stamp: {e}")))?;
    Ok(())
}

/// Writes `root` into `tarball` (via a temporary file, renamed at the end).
fn write_tarball(root: &Path, tarball: &Path) -> Result<()> {
    need_tool("zstd")?;
    let partial = tarball.with_extension("zst.partial");
    let _ = fs::remove_file(tarball);
    note(&format!("writing {}", tarball.display()));
    let start = Instant::now();
    let mut tar = Command::new("tar");
    tar.arg("-C").arg(root).args([
        "--numeric-owner",
        "--xattrs",
        "--xattrs-include=*",
        "-cf",
        "-",
        ".",
    ]);
    let mut zstd = Command::new("zstd");
    zstd.args(["-T0", "-3", "-q", "-f", "-o"]).arg(&partial);
    if !pipe(&mut tar, &mut zstd)? {
        let _ = fs::remove_file(&partial);
        return Err(Failure::Msg("tar | zstd failed".into()));
    }
    rename(&partial, tarball)?;
    let mb = fs::metadata(tarball).map(|m| m.len() >> 20).unwrap_or(0);
    note(&format!(
        "wrote the tarball ({mb} MB) in {:.1} s",
        start.elapsed().as_secs_f64()
    ));
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Helpers

fn note(msg: &str) {
    // stderr, so that `cargo xtask monado-root` prints only the path on stdout.
    eprintln!("xtask: {msg}");
}

fn read_stamp(root: &Path) -> Option<String> {
    fs::read_to_string(root.join(STAMP)).ok()
}

fn need_tool(tool: &str) -> Result<()> {
    if on_path(tool) {
        return Ok(());
    }
    Err(Failure::Msg(format!(
        "{tool} not found: install it (apt-get install debootstrap zstd), or run `cargo xtask \
         test` without --no-setup so that it is installed"
    )))
}

fn mkdir(path: &Path) -> Result<()> {
    fs::create_dir_all(path)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", path.display())))
}

fn rename(from: &Path, to: &Path) -> Result<()> {
    fs::rename(from, to).map_err(|e| {
        Failure::Msg(format!(
            "cannot rename {} to {}: {e}",
            from.display(),
            to.display()
        ))
    })
}

/// Runs `left | right`; true when both succeed.
fn pipe(left: &mut Command, right: &mut Command) -> Result<bool> {
    let start = |cmd: &mut Command| {
        cmd.spawn()
            .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(cmd))))
    };
    let mut first = start(left.stdout(Stdio::piped()))?;
    let out = first.stdout.take().expect("piped stdout");
    let second = start(right.stdin(out));
    let ok_second = match second {
        Ok(mut child) => child.wait().map(|s| s.success()).unwrap_or(false),
        Err(e) => {
            let _ = first.kill();
            let _ = first.wait();
            return Err(e);
        }
    };
    let ok_first = first.wait().map(|s| s.success()).unwrap_or(false);
    Ok(ok_first && ok_second)
}

/// Mount points at or below `dir` (deepest first).
fn mounts_below(dir: &Path) -> Vec<PathBuf> {
    let Ok(dir) = dir.canonicalize() else {
        return Vec::new();
    };
    let info = fs::read_to_string("/proc/self/mountinfo").unwrap_or_default();
    let mut found: Vec<PathBuf> = info
        .lines()
        .filter_map(|line| line.split(' ').nth(4))
        .map(|p| PathBuf::from(unescape_mount_path(p)))
        .filter(|p| p.starts_with(&dir))
        .collect();
    found.sort_by_key(|p| std::cmp::Reverse(p.as_os_str().len()));
    found
}

/// mountinfo escapes space, tab, newline and backslash as `\ooo`.
fn unescape_mount_path(p: &str) -> String {
    let mut out = String::with_capacity(p.len());
    let mut rest = p;
    while let Some(i) = rest.find('\\') {
        out.push_str(&rest[..i]);
        let code = rest
            .get(i + 1..i + 4)
            .and_then(|o| u8::from_str_radix(o, 8).ok());
        match code {
            Some(c) => {
                out.push(char::from(c));
                rest = &rest[i + 4..];
            }
            None => {
                out.push('\\');
                rest = &rest[i + 1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// Deletes `dir` recursively. A debootstrap killed mid-run leaves `proc` and `sys` mounted in
/// its target: those are unmounted first, and `rm --one-file-system` never crosses into a mount.
fn remove_tree(dir: &Path) -> Result<()> {
    if fs::symlink_metadata(dir).is_err() {
        return Ok(());
    }
    for mount in mounts_below(dir) {
        note(&format!(
            "unmounting {} (left by a killed run)",
            mount.display()
        ));
        let status = Command::new("umount").arg("-l").arg(&mount).status();
        if !status.is_ok_and(|s| s.success()) {
            return Err(Failure::Msg(format!(
                "cannot unmount {}; unmount it and delete {} by hand",
                mount.display(),
                dir.display()
            )));
        }
    }
    let start = Instant::now();
    let status = Command::new("rm")
        .args(["-rf", "--one-file-system"])
        .arg(dir)
        .status()
        .map_err(|e| Failure::Msg(format!("cannot run rm: {e}")))?;
    if !status.success() || dir.exists() {
        return Err(Failure::Msg(format!("cannot delete {}", dir.display())));
    }
    note(&format!(
        "deleted {} ({:.1} s)",
        dir.display(),
        start.elapsed().as_secs_f64()
    ));
    Ok(())
}

fn size_mb(dir: &Path) -> String {
    Command::new("du")
        .args(["-sm", "--one-file-system"])
        .arg(dir)
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .split_whitespace()
                .next()
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "?".into())
}

fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn stamp_names_every_package_and_the_suite() {
        let stamp = stamp_text();
        assert!(stamp.contains("suite=trixie\n"));
        for pkg in PACKAGES {
            assert!(stamp.contains(pkg), "{pkg}");
        }
    }

    #[test]
    fn mountinfo_paths_are_unescaped() {
        assert_eq!(unescape_mount_path(r"/a\040b/c"), "/a b/c");
        assert_eq!(unescape_mount_path(r"/x\134y"), r"/x\y");
        assert_eq!(unescape_mount_path("/plain"), "/plain");
    }

    #[test]
    fn write_stamp_roundtrip() {
        let dir = std::env::temp_dir().join(format!("xtask-stamp-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        File::create(dir.join(STAMP))
            .unwrap()
            .write_all(stamp_text().as_bytes())
            .unwrap();
        assert_eq!(read_stamp(&dir).as_deref(), Some(stamp_text().as_str()));
        fs::remove_dir_all(&dir).unwrap();
    }
}
