//! The fuzz step of `cargo xtask test` (issue 31): each cargo-fuzz target in `fuzz/` (the
//! settings file, camera paths, parameter validation and the sound's input) runs under
//! libFuzzer for a bounded time, starting from its kept corpus (`fuzz/corpus/<target>/`, where
//! every crash found is kept once fixed). cargo-fuzz needs a nightly toolchain (sanitizers);
//! [`prepare_step`] installs it and cargo-fuzz when missing.

use std::path::Path;
use std::process::Command;

use crate::process::{capture, on_path, run_checked, run_status, say, show};
use crate::Result;

/// The targets, as `fuzz/Cargo.toml` names them.
pub const TARGETS: &[&str] = &["settings", "camera_path", "sound_params"];

/// Seconds each target runs in CI.
pub const CI_SECONDS: u32 = 60;

/// Makes sure the nightly toolchain and cargo-fuzz are installed.
pub fn prepare_step() -> Result<Vec<(String, String)>> {
    let toolchains = capture(Command::new("rustup").args(["toolchain", "list"]))?;
    if !toolchains.lines().any(|l| l.starts_with("nightly")) {
        say("installing the nightly toolchain (cargo-fuzz builds with sanitizers)");
        run_checked(Command::new("rustup").args([
            "toolchain",
            "install",
            "nightly",
            "--profile",
            "minimal",
        ]))?;
    }
    if on_path("cargo-fuzz") {
        say("cargo-fuzz already installed, skipping");
    } else {
        say("installing cargo-fuzz (cargo install cargo-fuzz --locked)");
        run_checked(Command::new("rustup").args([
            "run",
            "stable",
            "cargo",
            "install",
            "cargo-fuzz",
            "--locked",
        ]))?;
    }
    Ok(Vec::new())
}

/// Runs every target for `seconds` from `root` (the workspace); the first that fails (a crash
/// found, or a build error) ends the step, naming where its input was written.
pub fn run_all(root: &Path, seconds: u32) -> std::result::Result<(), String> {
    for target in TARGETS {
        let mut cmd = Command::new("rustup");
        cmd.args(["run", "nightly", "cargo", "fuzz", "run", target])
            .arg("--")
            .arg(format!("-max_total_time={seconds}"))
            // Settings files and camera paths are short; longer inputs only slow the search.
            .arg("-max_len=4096")
            .current_dir(root)
            // The nightly cargo, not the one running xtask.
            .env_remove("RUSTUP_TOOLCHAIN")
            .env_remove("CARGO");
        say(&format!(
            "fuzzing `{target}` for {seconds} s: {}",
            show(&cmd)
        ));
        let status = run_status(&mut cmd).map_err(|_| format!("cannot start {}", show(&cmd)))?;
        if !status.success() {
            return Err(format!(
                "fuzz target `{target}` failed: a crash's input is in fuzz/artifacts/{target}/ \
                 (reproduce: cargo +nightly fuzz run {target} fuzz/artifacts/{target}/<file>)"
            ));
        }
    }
    Ok(())
}
