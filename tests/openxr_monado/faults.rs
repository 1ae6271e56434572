//! The runtime misbehaving on purpose through the fault-injection layer
//! (`tests/fixtures/xr-fault-layer`): refused extensions and formats, a failed swapchain are
//! clear errors; an old Vulkan maximum, a lost head position and Quest-like refresh rates are
//! lived with.

use std::path::Path;
use std::time::Duration;

use crate::common::fault_layer;
use crate::common::monado::{self, ClientRun, Monado};
use crate::{summary_value, EXE};

/// Runs `vr-ocean xr` against Monado with the fault-injection layer (`tests/fixtures/
/// xr-fault-layer`) making the runtime misbehave as `fault` says, the core validation layer
/// on as well; expects a clean error exit.
fn with_fault(fault: &str) -> ClientRun {
    let run = run_with_fault(fault, &["--frames", "5"]);
    assert_eq!(run.status, Some(1), "{run}");
    run
}

/// [`with_fault`] with `args` after `xr --grid 64 --preset low`, whatever the exit.
fn run_with_fault(fault: &str, args: &[&str]) -> ClientRun {
    let root = monado::root_from_env();
    // Service names go into socket paths: letters, digits, '-' and '_' only.
    let name = format!("fault-{}", fault.replace('.', "-"));
    let service = Monado::start(&root, &name);
    let mut env = fault_layer::install(&root, &fault_layer::built_library());
    env.push(fault_layer::fault(fault));
    env.push(("RUST_LOG".into(), "info".into()));
    fault_layer::enable_core_validation(&mut env);
    let mut all = vec!["xr", "--grid", "64", "--preset", "low"];
    all.extend_from_slice(args);
    let run = service.client(
        Path::new(EXE),
        &all,
        &monado::env_refs(&env),
        Duration::from_secs(600),
    );
    // The service exits by itself only after a client connected; finish() ends it otherwise.
    let _ = service.finish();
    assert!(!run.timed_out, "hung\n{run}");
    assert!(!run.stderr.contains("panicked"), "{run}");
    assert!(
        run.stderr.contains(&format!("xr-fault-layer: {fault}")),
        "the fault never fired\n{run}"
    );
    run
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn a_vulkan_maximum_below_ours_is_a_warning_and_depth_is_submitted_when_asked() {
    // Meta's PC runtime has reported a maximum of Vulkan 1.0: the maximum is what a runtime was
    // tested with, only its minimum binds.
    let run = run_with_fault(
        "vulkan-max-1.0",
        &["--frames", "20", "--submit-depth", "--msaa", "1"],
    );
    assert_eq!(run.status, Some(0), "{run}");
    assert!(
        run.stderr
            .contains("was tested with Vulkan 1.0 to 1.0; asking for 1.1"),
        "{run}"
    );
    assert_eq!(summary_value(&run, "depth"), "true", "{run}");
    let submitted: u64 = summary_value(&run, "frames_submitted").parse().unwrap();
    assert!(submitted >= 20, "{run}");
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn a_lost_head_position_keeps_frames_coming() {
    // From the 40th xrLocateViews on, the position is invalid (and NaN): the frames still
    // render, from the last known position, instead of going blank.
    let run = run_with_fault("position-lost", &["--frames", "80"]);
    assert_eq!(run.status, Some(0), "{run}");
    let skipped: u64 = summary_value(&run, "frames_not_rendered").parse().unwrap();
    let submitted: u64 = summary_value(&run, "frames_submitted").parse().unwrap();
    assert!(submitted >= 80 && skipped <= 2, "{run}");
    assert_eq!(
        run.stderr.matches("head position lost").count(),
        1,
        "logged once\n{run}"
    );
    assert!(!run.stderr.contains("Vulkan validation"), "{run}");
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn the_refresh_rate_never_drops_below_72_hz() {
    // Quest-like rates 60, 72, 90: the app starts at 90; lavapipe cannot hold it, so the
    // governor steps down after two seconds' worth of frames, to 72 and never to 60.
    // The GPU-time governor acts on GPU time before the refresh governor does; off here, so
    // this test sees the refresh governor alone.
    let run = run_with_fault(
        "refresh-rates",
        &["--frames", "240", "--gpu-governor", "off"],
    );
    assert_eq!(run.status, Some(0), "{run}");
    let asked: Vec<&str> = run
        .stderr
        .lines()
        .filter_map(|l| l.split("xrRequestDisplayRefreshRateFB(").nth(1))
        .collect();
    assert!(
        asked.first().is_some_and(|a| a.starts_with("90 Hz")),
        "first request {asked:?}\n{run}"
    );
    assert!(
        asked.iter().any(|a| a.starts_with("72 Hz")),
        "never stepped down {asked:?}\n{run}"
    );
    assert!(
        !asked.iter().any(|a| a.starts_with("60")),
        "asked for 60 Hz {asked:?}\n{run}"
    );
    assert_eq!(summary_value(&run, "refresh_hz"), "72", "{run}");
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn runtime_without_vulkan_enable2_is_a_clear_error() {
    let run = with_fault("no-vulkan-enable2");
    assert!(
        run.stderr
            .contains("error: the active OpenXR runtime refused XR_KHR_vulkan_enable2"),
        "{run}"
    );
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn runtime_without_srgb_formats_is_a_clear_error() {
    let run = with_fault("no-srgb");
    assert!(
        run.stderr
            .contains("error: the OpenXR runtime offers no sRGB swapchain format")
            && run.stderr.contains("R8G8B8A8_UNORM"),
        "{run}"
    );
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn swapchain_creation_failure_is_a_clear_error() {
    let run = with_fault("swapchain-fail");
    assert!(
        run.stderr.contains(
            "error: xrCreateSwapchain (R8G8B8A8_SRGB, 320x240 x2 layers) failed: \
             ERROR_RUNTIME_FAILURE"
        ),
        "{run}"
    );
}
