//! The runtime going away or never there: killed mid-session, installed but not running, not
//! installed at all. Each is a clear error and exit status 1, never a panic or a hang.

use std::path::Path;
use std::time::Duration;

use crate::common::monado::{self, Monado};
use crate::EXE;

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn runtime_killed_mid_session_is_a_clean_error() {
    let root = monado::root_from_env();
    let service = Monado::start(&root, "killed");
    // The run's choice (`--wind 14`) must be kept though the runtime dies (issue 44).
    let config = root.join("tmp/vr-ocean-killed-config");
    let _ = std::fs::remove_dir_all(&config);
    let run = std::thread::scope(|s| {
        let client = s.spawn(|| {
            service.client(
                Path::new(EXE),
                &["xr", "--grid", "64", "--preset", "low", "--wind", "14"],
                &[
                    ("RUST_LOG", "info"),
                    ("XDG_CONFIG_HOME", "/tmp/vr-ocean-killed-config"),
                ],
                Duration::from_secs(180),
            )
        });
        // Let it reach the frame loop, then take the runtime away.
        let log = service.log_path().to_path_buf();
        let started = std::time::Instant::now();
        while started.elapsed() < Duration::from_secs(120) {
            std::thread::sleep(Duration::from_millis(500));
            if std::fs::read_to_string(&log).is_ok_and(|l| l.contains("Frame late"))
                || started.elapsed() > Duration::from_secs(40)
            {
                break;
            }
        }
        service.kill_service();
        client.join().unwrap()
    });
    assert!(!run.timed_out, "hung after the runtime died\n{run}");
    assert_eq!(run.status, Some(1), "{run}");
    assert!(
        run.stderr.contains("error: the OpenXR runtime went away"),
        "{run}"
    );
    assert!(!run.stderr.contains("panicked"), "{run}");
    let _ = service.finish();
    let kept = std::fs::read_to_string(config.join("vr-ocean/settings.json"))
        .unwrap_or_else(|e| panic!("no settings kept: {e}\n{run}"));
    let kept: serde_json::Value = serde_json::from_str(&kept).expect("JSON settings");
    assert_eq!(kept["wind_speed"].as_f64(), Some(14.0), "{kept}");
    let _ = std::fs::remove_dir_all(&config);
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn runtime_not_running_is_a_clear_error() {
    let root = monado::root_from_env();
    let run = monado::client_without_service(
        &root,
        "absent",
        Path::new(EXE),
        &["xr"],
        &[],
        Duration::from_secs(60),
    );
    assert_eq!(run.status, Some(1), "{run}");
    assert!(
        run.stderr.contains("the OpenXR runtime failed to start")
            && run.stderr.contains("is monado-service running?"),
        "{run}"
    );
    assert!(!run.stderr.contains("panicked"), "{run}");
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn no_runtime_installed_is_a_clear_error() {
    let root = monado::root_from_env();
    let run = monado::client_without_service(
        &root,
        "none",
        Path::new(EXE),
        &["xr"],
        &[("XR_RUNTIME_JSON", "/nonexistent/openxr_runtime.json")],
        Duration::from_secs(60),
    );
    assert_eq!(run.status, Some(1), "{run}");
    assert!(
        run.stderr.contains("no active OpenXR runtime")
            && run.stderr.contains("apt install monado-service"),
        "{run}"
    );
    assert!(!run.stderr.contains("panicked"), "{run}");
}
