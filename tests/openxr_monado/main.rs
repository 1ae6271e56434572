//! The OpenXR backend against a real runtime: Monado's null compositor with a simulated HMD, in
//! the Debian trixie root that `cargo xtask test` prepares (see `tests/common/monado.rs`).
//! `vr-ocean xr` runs the same code a Quest runs: enable2 Vulkan on lavapipe, multiview into a
//! 2-layer swapchain, depth submitted, the full session lifecycle.
//!
//! These need root (chroot) and the root's path in `VR_OCEAN_MONADO_ROOT`, so they are ignored
//! by a plain `cargo test`; the `openxr (Monado)` step of `cargo xtask test` runs them.
//!
//! - [`session`]: a whole session's life: focused and ended cleanly, the focus taken by a
//!   second client, a minute of sound keeping time.
//! - [`runtime_gone`]: the runtime killed mid-session, not running, not installed.
//! - [`faults`]: the runtime misbehaving through the fault-injection layer
//!   (`tests/fixtures/xr-fault-layer`).
//! - [`float`]: the float mode riding the sea.
//! - [`panel`]: the control panel's quad layer.

#[path = "../common/mod.rs"]
mod common;

mod faults;
mod float;
mod panel;
mod runtime_gone;
mod session;

use common::monado::ClientRun;

/// The `vr-ocean` binary Cargo built for this test.
pub const EXE: &str = env!("CARGO_BIN_EXE_vr-ocean");

/// `key=value` from the `openxr summary:` line of stdout.
pub fn summary_value<'a>(run: &'a ClientRun, key: &str) -> &'a str {
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("openxr summary: "))
        .unwrap_or_else(|| panic!("no `openxr summary:` line\n{run}"));
    let prefix = format!("{key}=");
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(prefix.as_str()))
        .unwrap_or_else(|| panic!("no {key} in {line}"))
}
