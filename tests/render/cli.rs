//! Bad input to the headless renderer: a clear error and a non-zero exit, never a panic, and
//! nothing rendered when the output cannot be written; settling frames numbered apart from the
//! drawn ones.

use crate::common;

use std::process::Command;

use common::{assert_rejected, scratch_path, vr_ocean};

#[test]
fn missing_vulkan_driver_names_the_package_to_install() {
    let out_dir = scratch_path("nodriver");
    // Point the loader at a driver manifest that does not exist: no device at all.
    let out = Command::new(env!("CARGO_BIN_EXE_vr-ocean"))
        .args(["headless", "--frames", "1", "--size", "8x8", "--out"])
        .arg(&out_dir)
        .env("VK_ICD_FILENAMES", "/nonexistent/vr-ocean-no-driver.json")
        .env("VK_DRIVER_FILES", "/nonexistent/vr-ocean-no-driver.json")
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_ne!(out.status.code(), Some(101), "panicked: {err}");
    assert!(err.contains("no Vulkan device"), "{err}");
    assert!(err.contains("mesa-vulkan-drivers"), "{err}");
}

#[test]
fn bad_sizes_frames_and_captures_are_rejected() {
    let out = scratch_path("bad-args");
    let out = out.to_str().unwrap();
    for size in ["0x10", "10x0", "x", "640", "-5x5", "99999x10"] {
        assert_rejected(&["headless", "--size", size, "--out", out], &["size"]);
    }
    assert_rejected(&["headless", "--frames", "0", "--out", out], &["frames"]);
    assert_rejected(
        &["headless", "--anisotropy", "3", "--out", out],
        &["anisotropy", "1 (off), 2, 4, 8 or 16"],
    );
    assert_rejected(
        &["gpu-budget", "--anisotropy", "32", "--views", "down"],
        &["anisotropy", "1 (off), 2, 4, 8 or 16"],
    );
    assert_rejected(
        &["headless", "--settle=-1", "--out", out],
        &["settle", "[0, 600]"],
    );
    assert_rejected(&["headless", "--settle", "nan", "--out", out], &["settle"]);
    assert_rejected(&["headless", "--settle", "601", "--out", out], &["settle"]);
    assert_rejected(
        &["headless", "--frames", "5", "--capture", "5", "--out", out],
        &["capture"],
    );
    assert_rejected(
        &["headless", "--ocean-size", "100", "--out", out],
        &["size", "256"],
    );
    assert_rejected(&["headless", "--threads", "0", "--out", out], &["threads"]);
    // The sky's cloud cover is a share of the sky.
    assert_rejected(
        &["headless", "--clouds", "1.5", "--out", out],
        &["clouds", "[0, 1]"],
    );
    assert_rejected(
        &["headless", "--clouds", "-0.1", "--out", out],
        &["clouds", "[0, 1]"],
    );
    assert_rejected(&["headless", "--grid", "100", "--out", out], &["grid"]);
}

#[test]
fn unwritable_output_is_refused_before_rendering() {
    assert_rejected(
        &["headless", "--frames", "1", "--out", "/proc/vr-ocean/out"],
        &["/proc/vr-ocean/out"],
    );
}

#[test]
fn malformed_camera_paths_name_the_file_and_line() {
    let path = scratch_path("bad.path");
    std::fs::write(&path, "0 0 1.7 0 0 0\n1 0 1.7 0 zero 0\n").unwrap();
    let out = scratch_path("bad-path-out");
    assert_rejected(
        &[
            "headless",
            "--path",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["bad.path", "line 2", "zero"],
    );
    assert_rejected(
        &[
            "headless",
            "--path",
            "/nonexistent/vr-ocean.path",
            "--out",
            out.to_str().unwrap(),
        ],
        &["/nonexistent/vr-ocean.path"],
    );
    let _ = std::fs::remove_file(path);
}

#[test]
fn settling_frames_are_simulated_but_not_counted_or_saved() {
    let dir = scratch_path("settle");
    let out = dir.to_str().unwrap();
    let run = vr_ocean(&[
        "headless", "--settle", "2", "--frames", "2", "--size", "32x32", "--bodies", "0", "--out",
        out,
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // 20 settling frames, then the two drawn ones, numbered 0 and 1; the last is saved.
    assert!(dir.join("frame_00001_left.png").exists());
    assert!(!dir.join("frame_00021_left.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
