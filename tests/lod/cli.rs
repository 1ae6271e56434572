//! `vr-ocean lod-svg`: writes a well-formed SVG with one rectangle per patch; bad input is a
//! named error with a non-zero exit, never a panic.

use crate::common;

use std::path::PathBuf;

use common::{assert_rejected, vr_ocean};

fn scratch(name: &str) -> PathBuf {
    common::scratch_path(&format!("lod-{name}"))
}

#[test]
fn lod_svg_writes_a_picture() {
    let path = scratch("ok.svg");
    let p = path.to_str().unwrap();
    let out = vr_ocean(&[
        "lod-svg",
        "--camera",
        "12,1.7,-40",
        "--yaw",
        "30",
        "--pitch",
        "-5",
        "--preset",
        "high",
        "--size",
        "4096",
        "--out",
        p,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let patches = svg.matches("<title>level").count();
    assert!(patches >= 16, "{patches} patches drawn");
    assert!(svg.contains("(culled)") && svg.contains("stroke=\"#d00\""));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&format!("{patches} patches")), "{stdout}");
}

#[test]
fn lod_svg_bad_input_is_named() {
    let path = scratch("bad.svg");
    let p = path.to_str().unwrap();
    let base = |extra: &[&'static str]| -> Vec<String> {
        let mut v: Vec<String> = ["lod-svg", "--yaw", "0", "--out", p]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let run = |extra: &[&'static str], names: &[&str]| {
        let v = base(extra);
        let args: Vec<&str> = v.iter().map(|s| s.as_str()).collect();
        assert_rejected(&args, names);
    };
    run(
        &["--camera", "0,1.7,0", "--size", "100"],
        &["size", "[256, 8192]"],
    );
    run(
        &["--camera", "0,1.7,0", "--size", "9000"],
        &["size", "8192"],
    );
    run(&["--camera", "NaN,1.7,0"], &["position", "NaN"]);
    run(&["--camera", "0,inf,0"], &["position", "finite"]);
    run(&["--camera", "0,1.7"], &["camera", "x,y,z"]);
    run(
        &["--camera", "0,1.7,0", "--pitch", "95"],
        &["pitch", "[-89, 89]"],
    );
    run(
        &["--camera", "0,1.7,0", "--max-displacement=-1,1,1"],
        &["max displacement", "[0, 1000]"],
    );
    run(&["--camera", "0,1.7,0", "--preset", "insane"], &["preset"]);
    assert_rejected(
        &[
            "lod-svg",
            "--camera",
            "0,1.7,0",
            "--yaw",
            "0",
            "--out",
            "/nonexistent-dir/x/lod.svg",
        ],
        &["cannot write", "nonexistent-dir"],
    );
    assert!(!path.exists());
}
