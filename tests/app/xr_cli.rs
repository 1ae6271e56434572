//! `vr-ocean xr` without a usable runtime, and with bad options: a clear error and exit 1, never
//! a panic or a hang. (Against a real runtime: `tests/openxr_monado/`.)

use crate::common;

use std::process::Command;
use std::time::{Duration, Instant};

use common::assert_rejected;

#[test]
fn no_loader_or_runtime_says_what_to_install() {
    // The runtime manifest points nowhere, so even a machine with a runtime installed has none
    // here: without a loader the loader is named, with one the runtime.
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_vr-ocean"))
        .args(["xr", "--frames", "1"])
        .env("XR_RUNTIME_JSON", "/nonexistent/vr-ocean-no-runtime.json")
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        start.elapsed() < Duration::from_secs(60),
        "took {:?}",
        start.elapsed()
    );
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let no_loader = err.contains("no OpenXR loader could be loaded")
        && err.contains("apt install libopenxr-loader1");
    let no_runtime =
        err.contains("no active OpenXR runtime") && err.contains("apt install monado-service");
    assert!(no_loader || no_runtime, "{err}");
}

#[test]
fn bad_options_are_rejected_before_any_runtime_is_touched() {
    assert_rejected(&["xr", "--resolution-scale", "0"], &["resolution scale"]);
    assert_rejected(&["xr", "--resolution-scale", "nan"], &["resolution scale"]);
    assert_rejected(&["xr", "--resolution-scale", "8"], &["resolution scale"]);
    assert_rejected(&["xr", "--max-refresh-rate", "0"], &["refresh rate"]);
    assert_rejected(&["xr", "--deck-height", "inf"], &["deck height"]);
    assert_rejected(&["xr", "--frames", "0"], &["frames"]);
    assert_rejected(&["xr", "--foveation", "extreme"], &["foveation"]);
    assert_rejected(&["xr", "--wind", "-3"], &["wind"]);
}
