//! `cargo xtask run [--no-setup] [ARGS]`: installs what running needs, then runs the ocean.

use crate::process::{cargo, run_checked, say, workspace_root};
use crate::setup::{ensure_apt_packages, RUN_APT_PACKAGES};
use crate::Result;

/// `cargo xtask run`: `cargo run --release --bin vr-ocean -- ARGS` after the set-up (unless
/// `--no-setup` comes first).
pub fn cmd_run(args: &[String]) -> Result<()> {
    let (no_setup, args) = match args.split_first() {
        Some((first, rest)) if first == "--no-setup" => (true, rest),
        _ => (false, args),
    };
    if !no_setup {
        ensure_apt_packages(RUN_APT_PACKAGES)?;
    }
    if args.is_empty() {
        say("opening the ocean window (WASD/QE to move, mouse button held to look, Esc quits; headless PNGs if there is no display)");
    }
    let mut cmd = cargo();
    cmd.args(["run", "--release", "--bin", "vr-ocean"]);
    if !args.is_empty() {
        cmd.arg("--").args(args);
    }
    run_checked(cmd.current_dir(workspace_root()))
}
