//! Trees xtask builds once and keeps under the cache directory: the Monado root ([`crate::monado`])
//! and the Adreno compiler ([`crate::turnip`]). One rule for both ([`CachedTree::ensure`]):
//!
//! * `<cache>/<name>/` is the tree and `<cache>/<name>.tar.zst` a tarball of it, where `<cache>`
//!   is `$VR_OCEAN_CACHE` or `/var/cache/vr-ocean`.
//! * A stamp file in the tree records what it was made from. A tree whose stamp differs from the
//!   wanted one is rebuilt.
//! * A missing tree is restored from the tarball when the tarball's stamp matches (seconds);
//!   otherwise it is built and the tarball is rewritten.
//! * Everything is built in `<cache>/<name>.partial` and renamed into place at the end, so a
//!   killed run never leaves a tree that looks complete. A lock file serializes xtask runs.

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use crate::process::{on_path, show};
use crate::{Failure, Result};

/// The directory holding the trees, their tarballs and locks: `$VR_OCEAN_CACHE` when set,
/// otherwise `/var/cache/vr-ocean`.
pub fn cache_dir() -> PathBuf {
    std::env::var_os("VR_OCEAN_CACHE")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/var/cache/vr-ocean"))
}

/// A tree kept under [`cache_dir`] (see the module docs).
pub struct CachedTree {
    /// What it is, for messages ("the Monado root").
    pub what: &'static str,
    /// Its directory name under the cache (`monado-trixie`, `turnip`).
    pub name: String,
    /// The stamp file's name inside the tree.
    pub stamp_file: &'static str,
    /// What the stamp of an up-to-date tree says.
    pub stamp: String,
}

impl CachedTree {
    /// The tree: `<cache>/<name>`.
    pub fn path(&self) -> PathBuf {
        cache_dir().join(&self.name)
    }

    /// Its tarball: `<cache>/<name>.tar.zst`.
    pub fn tarball(&self) -> PathBuf {
        cache_dir().join(format!("{}.tar.zst", self.name))
    }

    /// The stamp the tree at `dir` carries, if any.
    pub fn read_stamp(&self, dir: &Path) -> Option<String> {
        fs::read_to_string(dir.join(self.stamp_file)).ok()
    }

    /// Makes sure the tree exists and is up to date; `build` fills a fresh, empty directory
    /// (the `.partial` one) with it, the stamp written by [`CachedTree::ensure`] afterwards.
    /// Returns the tree's path.
    pub fn ensure(&self, build: impl FnOnce(&Path) -> Result<()>) -> Result<PathBuf> {
        let root = self.path();
        let cache = cache_dir();
        mkdir(&cache)?;

        // One xtask at a time: two concurrent builds would share `.partial`.
        let lock_path = cache.join(format!("{}.lock", self.name));
        let lock = File::create(&lock_path)
            .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", lock_path.display())))?;
        if lock.try_lock().is_err() {
            note(&format!(
                "waiting for {} (another xtask is preparing {})",
                lock_path.display(),
                self.what
            ));
            lock.lock()
                .map_err(|e| Failure::Msg(format!("cannot lock {}: {e}", lock_path.display())))?;
        }

        if root.exists() {
            if self.read_stamp(&root).as_deref() == Some(self.stamp.as_str()) {
                note(&format!("{} up to date: {}", self.what, root.display()));
                return Ok(root);
            }
            note(&format!(
                "{} {} is outdated or incomplete (its {} differs): rebuilding",
                self.what,
                root.display(),
                self.stamp_file
            ));
            let old = cache.join(format!("{}.old", self.name));
            remove_tree(&old)?;
            rename(&root, &old)?;
            remove_tree(&old)?;
        }

        let partial = cache.join(format!("{}.partial", self.name));
        remove_tree(&partial)?;

        let tarball = self.tarball();
        if tarball.exists() && self.restore(&tarball, &partial)? {
            rename(&partial, &root)?;
            return Ok(root);
        }

        mkdir(&partial)?;
        build(&partial)?;
        fs::write(partial.join(self.stamp_file), &self.stamp)
            .map_err(|e| Failure::Msg(format!("cannot write the stamp: {e}")))?;
        rename(&partial, &root)?;
        // The tarball is only a cache: failing to write it does not fail the step.
        if let Err(Failure::Msg(msg)) = write_tarball(&root, &tarball) {
            note(&format!("warning: could not write the tarball: {msg}"));
        }
        Ok(root)
    }

    /// Unpacks `tarball` into `partial`. Returns false (and leaves nothing behind) when the
    /// tarball is unreadable or holds a tree of another stamp.
    fn restore(&self, tarball: &Path, partial: &Path) -> Result<bool> {
        need_tool("zstd")?;
        note(&format!(
            "restoring {} from {}",
            self.what,
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
        let stamp = self.read_stamp(partial);
        if ok && stamp.as_deref() == Some(self.stamp.as_str()) {
            note(&format!(
                "restored {} in {:.1} s",
                self.what,
                start.elapsed().as_secs_f64()
            ));
            return Ok(true);
        }
        if ok {
            note("the tarball holds a tree of another stamp: ignoring it");
        } else {
            note("the tarball could not be unpacked: ignoring it");
        }
        remove_tree(partial)?;
        Ok(false)
    }
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

/// A progress line on stderr (so that `cargo xtask monado-root` and `turnip` print only the
/// path on stdout).
pub fn note(msg: &str) {
    eprintln!("xtask: {msg}");
}

/// Fails naming the package to install when `tool` is not on `PATH`.
pub fn need_tool(tool: &str) -> Result<()> {
    if on_path(tool) {
        return Ok(());
    }
    Err(Failure::Msg(format!(
        "{tool} not found: install it (apt-get install {tool}), or run `cargo xtask test` \
         without --no-setup so that it is installed"
    )))
}

/// `mkdir -p`.
pub fn mkdir(path: &Path) -> Result<()> {
    fs::create_dir_all(path)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", path.display())))
}

/// `mv`, with the paths in the error.
pub fn rename(from: &Path, to: &Path) -> Result<()> {
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
pub fn mounts_below(dir: &Path) -> Vec<PathBuf> {
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
pub fn remove_tree(dir: &Path) -> Result<()> {
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

/// `du -sm` of `dir`, for messages.
pub fn size_mb(dir: &Path) -> String {
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

/// The last `lines` lines of `text`.
pub fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

/// Runs `cmd` with its output into `log`; on failure, the error quotes the log's end.
pub fn run_logged(cmd: &mut Command, log: &Path, what: &str) -> Result<()> {
    let file = File::create(log)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", log.display())))?;
    let err = file
        .try_clone()
        .map_err(|e| Failure::Msg(format!("cannot reopen {}: {e}", log.display())))?;
    cmd.stdin(Stdio::null()).stdout(file).stderr(err);
    let status = cmd
        .status()
        .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(cmd))))?;
    if status.success() {
        return Ok(());
    }
    let text = fs::read_to_string(log).unwrap_or_default();
    Err(Failure::Msg(format!(
        "{what} failed ({status}): `{}`; the end of {}:\n{}",
        show(cmd),
        log.display(),
        tail(&text, 30)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mountinfo_paths_are_unescaped() {
        assert_eq!(unescape_mount_path(r"/a\040b/c"), "/a b/c");
        assert_eq!(unescape_mount_path(r"/x\134y"), r"/x\y");
        assert_eq!(unescape_mount_path("/plain"), "/plain");
    }

    #[test]
    fn a_tree_is_built_once_then_kept_and_restored_from_its_tarball() {
        if !on_path("zstd") {
            // The tarball needs zstd; `cargo xtask test` installs it before the tests run.
            assert!(
                std::env::var_os("CI").is_none(),
                "zstd is missing (apt-get install zstd)"
            );
            return;
        }
        let dir = std::env::temp_dir().join(format!("xtask-cache-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        // xtask's tests touch VR_OCEAN_CACHE only here.
        std::env::set_var("VR_OCEAN_CACHE", &dir);
        let tree = CachedTree {
            what: "a test tree",
            name: "tree".into(),
            stamp_file: "stamp.txt",
            stamp: "one\n".into(),
        };
        let builds = std::cell::Cell::new(0);
        let build = |p: &Path| {
            builds.set(builds.get() + 1);
            fs::write(p.join("payload"), "x").map_err(|e| Failure::Msg(e.to_string()))
        };
        let root = tree.ensure(build).unwrap();
        assert_eq!(fs::read_to_string(root.join("payload")).unwrap(), "x");
        tree.ensure(build).unwrap();
        fs::remove_dir_all(&root).unwrap();
        tree.ensure(build).unwrap();
        assert_eq!(builds.get(), 1, "kept, then restored from the tarball");
        let newer = CachedTree {
            stamp: "two\n".into(),
            ..tree
        };
        newer.ensure(build).unwrap();
        assert_eq!(builds.get(), 2, "another stamp is rebuilt");
        assert_eq!(newer.read_stamp(&root).as_deref(), Some("two\n"));
        fs::remove_dir_all(&dir).unwrap();
    }
}
