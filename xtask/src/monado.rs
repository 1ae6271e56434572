//! The Debian trixie root that the OpenXR tests run Monado in.
//!
//! Monado (the open-source OpenXR runtime) is not packaged for bookworm, and trixie's build needs
//! a newer glibc than the host's, so the `openxr (Monado)` step runs `monado-service` and the
//! test clients in a trixie chroot (see `docs/notes/monado-headless-ci.md`). [`ensure_root`]
//! makes sure that root exists and holds [`PACKAGES`]: `<cache>/monado-trixie/`, kept, stamped
//! and restored from its tarball by [`crate::cache::CachedTree`]; made with `debootstrap`
//! (about 100 s, network) when missing or when its package list changed.
//!
//! It needs root: debootstrap creates device nodes and the tests `chroot`. Unprivileged
//! `unshare -r chroot` does work on the CI kernel, but debootstrap cannot `mknod` in a user
//! namespace and the root's files belong to real root, so there is no rootless path here.

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use crate::cache::{mounts_below, note, size_mb, tail, CachedTree};
use crate::process::{is_root, on_path, show};
use crate::{Failure, Result};

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

/// What the stamp of an up-to-date root says. Changing the suite, mirror or package list
/// changes it and so rebuilds the root.
pub fn stamp_text() -> String {
    format!(
        "vr-ocean Monado root, made by `cargo xtask` (xtask/src/monado.rs)\n\
         suite={SUITE}\nmirror={MIRROR}\nvariant=minbase\npackages={}\n",
        PACKAGES.join(",")
    )
}

/// The root as a cached tree: `<cache>/monado-trixie`.
fn tree() -> CachedTree {
    CachedTree {
        what: "the Monado root",
        name: format!("monado-{SUITE}"),
        stamp_file: STAMP,
        stamp: stamp_text(),
    }
}

/// The `prepare` hook of the `openxr (Monado)` step: the root's path for the tests.
pub fn prepare_step() -> Result<Vec<(String, String)>> {
    let root = ensure_root()?;
    // The failure tests load the fault-injection API layer into the client
    // (`tests/common/fault_layer.rs` finds it next to the test binaries, same profile).
    note("building the OpenXR fault-injection layer (tests/fixtures/xr-fault-layer)");
    let status = crate::process::cargo()
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
    let tree = tree();
    if !is_root() {
        return Err(Failure::Msg(format!(
            "the Monado step needs root: it builds a Debian {SUITE} chroot ({}) with debootstrap \
             and runs monado-service and the OpenXR tests in it with chroot.\n  Run as root (CI \
             does), e.g. `sudo -E env \"PATH=$PATH\" cargo xtask test`, or skip the slow steps \
             with `cargo xtask test --quick`.",
            tree.path().display()
        )));
    }
    tree.ensure(build)
}

/// Runs debootstrap into `partial` and removes apt's caches.
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamp_names_every_package_and_the_suite() {
        let stamp = stamp_text();
        assert!(stamp.contains("suite=trixie\n"));
        for pkg in PACKAGES {
            assert!(stamp.contains(pkg), "{pkg}");
        }
    }
}
