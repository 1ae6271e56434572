//! Debian packages: which are installed (dpkg-query) and installing the missing ones (apt-get).

use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

use super::packages::APT_PACKAGES;
use crate::process::{is_root, on_path, run_checked, say};
use crate::{Failure, Result};

/// Set once this xtask run has run `apt-get update`.
static APT_UPDATED: AtomicBool = AtomicBool::new(false);

/// Installs the Debian packages in `wanted` that are not installed yet (one `apt-get update`
/// per xtask run at most). Needs root or sudo; otherwise fails naming the packages.
pub fn ensure_apt_packages(wanted: &[&str]) -> Result<()> {
    say(&format!("checking apt packages: {}", wanted.join(" ")));
    let mut missing = Vec::new();
    for pkg in wanted {
        if !dpkg_installed(pkg)? {
            missing.push(*pkg);
        }
    }
    if missing.is_empty() {
        say("apt packages already installed, skipping");
        return Ok(());
    }
    let list = missing.join(" ");
    // Runs apt-get directly as root, through `sudo env ...` otherwise (sudo resets the env).
    let prefix: Vec<&str> = if is_root() {
        vec![]
    } else if on_path("sudo") {
        say("not root: using sudo for apt-get");
        vec!["sudo", "env", "DEBIAN_FRONTEND=noninteractive"]
    } else {
        return Err(Failure::Msg(format!(
            "missing apt packages: {list}\n  installing them needs root and sudo is not available; \
             run as root: apt-get install -y {list}\n  (or install them yourself and pass --no-setup)"
        )));
    };
    let apt = |args: &[&str]| -> Result<()> {
        let mut all: Vec<&str> = prefix.clone();
        all.push("apt-get");
        all.extend_from_slice(args);
        let mut cmd = Command::new(all[0]);
        cmd.args(&all[1..])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .stdin(std::process::Stdio::null());
        run_checked(&mut cmd).map_err(|_| {
            Failure::Msg(format!(
                "`{}` failed (needed packages: {list})",
                all.join(" ")
            ))
        })
    };
    // Wait for a concurrent dpkg (e.g. unattended-upgrades) instead of failing at once.
    const LOCK_WAIT: &str = "-oDPkg::Lock::Timeout=600";
    if !APT_UPDATED.swap(true, Ordering::SeqCst) {
        say("apt-get update");
        apt(&["-q", LOCK_WAIT, "update"])?;
    }
    say(&format!("installing apt packages: {list}"));
    let mut args = vec!["-q", LOCK_WAIT, "install", "-y", "--no-install-recommends"];
    args.extend_from_slice(&missing);
    apt(&args)
}

/// Whether dpkg has `pkg` installed (fails when dpkg-query cannot run: not Debian/Ubuntu).
fn dpkg_installed(pkg: &str) -> Result<bool> {
    let out = Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", pkg])
        .output()
        .map_err(|e| {
            Failure::Msg(format!(
                "cannot run dpkg-query ({e}); automatic set-up supports Debian/Ubuntu only. \
                 Install the equivalents of: {} and pass --no-setup",
                APT_PACKAGES.join(" ")
            ))
        })?;
    // Exit status 1 and "no packages found" on stderr when the package is unknown.
    Ok(out.status.success() && is_installed_status(&String::from_utf8_lossy(&out.stdout)))
}

/// `${Status}` is "want flag status", e.g. `install ok installed`; `deinstall ok config-files`
/// (removed, config kept) does not count.
fn is_installed_status(status: &str) -> bool {
    status.split_whitespace().nth(2) == Some("installed")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dpkg_status() {
        assert!(is_installed_status("install ok installed"));
        assert!(!is_installed_status("deinstall ok config-files"));
        assert!(!is_installed_status(""));
    }
}
