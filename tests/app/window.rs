//! The window mode: a real window under Xvfb (lavapipe, validation layer required) shows both
//! eyes side by side; bad sizes and a missing display are clear errors; live tweaks (wave
//! changes, refused values, a preset switch) keep the frame loop running without validation
//! errors; the sound keeps time for a minute beside the rendering.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{assert_rejected, gpu};
use vr_ocean::app;
use vr_ocean::lod::QualityPreset;
use vr_ocean::render::StereoMode;
use vr_ocean::xr::desktop::{EyeSize, HeadlessXr};
use vr_ocean::xr::{FrameLoop, FrameState, Tweak, MAX_TWEAKS};

#[test]
fn bad_window_sizes_are_clear_errors() {
    assert_rejected(&["window", "--size", "0x800"], &["window size 0x800"]);
    assert_rejected(&["window", "--size", "1600x0"], &["window size"]);
    assert_rejected(
        &["window", "--size", "wide"],
        &["window size", "WIDTHxHEIGHT"],
    );
    assert_rejected(&["window", "--frames", "0"], &["frames"]);
}

#[test]
fn window_without_a_display_is_a_clear_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_vr-ocean"))
        .args(["window", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_ne!(out.status.code(), Some(101), "panicked: {err}");
    assert!(err.contains("no display"), "{err}");
}

/// Mean RGB of a `size`-pixel square at (x, y) of an RGBA image `w` pixels wide.
fn mean(rgba: &[u8], w: u32, x: u32, y: u32, size: u32) -> [f32; 3] {
    let mut sum = [0.0; 3];
    for yy in y..y + size {
        for xx in x..x + size {
            let i = 4 * (yy * w + xx) as usize;
            for c in 0..3 {
                sum[c] += rgba[i + c] as f32;
            }
        }
    }
    sum.map(|s| s / (size * size) as f32)
}

/// The tests that open a window take turns: the sound's minute measures the app under its own
/// load (lavapipe on both cores), not under a second window's beside it (which made a buffer
/// finish late once in 6000 on a 2-core host).
static WINDOWS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Issue 32: a minute of the window with its sound on. CI has no sound card, so the sound runs
/// on its silent clock (10 ms buffers, the callback a device would call) while lavapipe
/// renders on both cores: no buffer may finish late, and ALSA's complaints about the missing
/// card are one warning of ours.
#[test]
fn the_window_sounds_for_a_minute_without_underruns() {
    let _turn = WINDOWS.lock().unwrap_or_else(|e| e.into_inner());
    if !common::need_xvfb_run("the_window_sounds_for_a_minute_without_underruns") {
        return;
    }
    let path = common::scratch_path("window-sound-path.txt");
    std::fs::write(&path, "0  0 6 0  0 -8\n").unwrap();
    let minute = || {
        let out = common::xvfb_window(
            &common::scratch_path("window-config"),
            &[
                "--seconds",
                "60",
                "--wind",
                "12",
                "--path",
                path.to_str().unwrap(),
            ],
        );
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
        assert!(!stderr.contains("ALSA lib"), "{stderr}");
        assert!(stderr.matches("audio output").count() <= 1, "{stderr}");
        let sound = common::sound_report(&stdout);
        println!("{}", sound.line);
        assert!(
            sound.seconds >= 59.0,
            "{} s of sound\n{stdout}",
            sound.seconds
        );
        (sound, stdout)
    };
    let (mut sound, mut stdout) = minute();
    if sound.late_only_by_the_host() {
        // A real-time thread whose work fitted was woken late: the host held the vCPU (seen
        // once in 6000 buffers on 2-vCPU KVM hosts). The minute runs again and must be clean.
        println!("late only by the host; the minute again");
        (sound, stdout) = minute();
    }
    assert_eq!(sound.underruns, 0, "{stdout}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn window_under_xvfb_shows_both_eyes_without_validation_errors() {
    let _turn = WINDOWS.lock().unwrap_or_else(|e| e.into_inner());
    if !common::need_xvfb_run("window_under_xvfb_shows_both_eyes_without_validation_errors") {
        return;
    }
    let shot = common::scratch_path("window-shot.png");
    let _ = std::fs::remove_file(&shot);
    // 6 m above a moderate sea, so no crest reaches the eyes whatever the wall-clock time.
    let path = common::scratch_path("window-path.txt");
    std::fs::write(&path, "0  0 6 0  0 -8\n").unwrap();
    let out = common::xvfb_window(
        &common::scratch_path("window-config"),
        &[
            "--validation",
            "--frames",
            "60",
            "--wind",
            "7",
            "--path",
            path.to_str().unwrap(),
            "--screenshot",
            shot.to_str().unwrap(),
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "exit {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
        out.status.code()
    );
    assert!(stdout.contains("60 frames"), "{stdout}");
    assert!(!stderr.contains("Vulkan validation"), "{stderr}");

    let img = image::open(Path::new(&shot))
        .expect("screenshot")
        .to_rgba8();
    let (w, h) = img.dimensions();
    assert_eq!((w, h), (320, 160));
    let px = img.as_raw();
    // Each eye fills its half (square eyes in a 2:1 window): sky on top, sea below, no black.
    let mut halves = Vec::new();
    for x0 in [0, 160] {
        // The sky's sample left of centre: the default sun is ahead and to the right, and its
        // aureole (white, as the CIE clear sky's is within ~25° of the sun) fills the right.
        let sky = mean(px, w, x0 + 24, 4, 16);
        let sea = mean(px, w, x0 + 72, 140, 16);
        assert!(
            sky[2] > 120.0 && sky[2] >= sky[0],
            "eye at x={x0}: sky {sky:?}"
        );
        assert!(
            sea[2] > 20.0 && sea[2] < sky[2],
            "eye at x={x0}: sea {sea:?}"
        );
        for y in 0..h {
            for x in x0..x0 + 160 {
                let i = 4 * (y * w + x) as usize;
                assert!(
                    px[i..i + 3] != [0, 0, 0],
                    "black pixel at ({x}, {y}) of {}",
                    shot.display()
                );
            }
        }
        let half: Vec<u8> = (0..h)
            .flat_map(|y| {
                let i = 4 * (y * w + x0) as usize;
                px[i..i + 4 * 160].to_vec()
            })
            .collect();
        halves.push(half);
    }
    // The eyes are 63 mm apart: their images differ.
    let differing = halves[0]
        .chunks(4)
        .zip(halves[1].chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 160 * 160 / 20, "{differing} pixels differ");
    let _ = std::fs::remove_file(&shot);
    let _ = std::fs::remove_file(&path);
}

/// Issue 31: `--panel open` shows the control panel over the view, centred at one window pixel
/// per point (440×560), its text sharp, without validation errors. The image is
/// `docs/panel/window.png` in the README when made at 1000x600.
#[test]
fn window_shows_the_control_panel_over_the_view() {
    let _turn = WINDOWS.lock().unwrap_or_else(|e| e.into_inner());
    if !common::need_xvfb_run("window_shows_the_control_panel_over_the_view") {
        return;
    }
    let shot = common::scratch_path("window-panel.png");
    let _ = std::fs::remove_file(&shot);
    let out = common::xvfb_window_sized(
        &common::scratch_path("window-panel-config"),
        "1000x600",
        &[
            "--validation",
            "--frames",
            "12",
            "--wind",
            "9",
            "--panel",
            "open",
            "--screenshot",
            shot.to_str().unwrap(),
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(!stderr.contains("Vulkan validation"), "{stderr}");
    let img = image::open(&shot).expect("screenshot").to_rgba8();
    let (w, h) = img.dimensions();
    assert_eq!((w, h), (1000, 600));
    let px = img.as_raw();
    // The panel's fill (egui's dark panel colour) below its last line, at its centred place
    // (280, 20)-(720, 580); outside it, the view.
    let fill = [18.0, 28.0, 38.0];
    let near = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 3.0);
    let inside = mean(px, w, 690, 550, 16);
    assert!(near(inside, fill), "panel fill {inside:?}");
    for (x, y) in [(100, 100), (900, 100), (100, 500), (262, 300), (722, 300)] {
        let outside = mean(px, w, x, y, 8);
        assert!(!near(outside, fill), "view at ({x}, {y}): {outside:?}");
    }
    // Text: the heading row of the panel holds bright glyph pixels.
    let bright = (30..52)
        .flat_map(|y| (288..400).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let i = 4 * (y * w + x) as usize;
            px[i] as u32 + px[i + 1] as u32 + px[i + 2] as u32 > 3 * 170
        })
        .count();
    assert!(bright > 150, "{bright} bright heading pixels");
    let _ = std::fs::remove_file(&shot);
}

#[test]
fn live_tweaks_change_waves_refuse_bad_values_and_switch_presets() {
    let _turn = WINDOWS.lock().unwrap_or_else(|e| e.into_inner());
    let inner = HeadlessXr::new(
        &gpu::validated(),
        EyeSize::new(64, 64).unwrap(),
        gpu::standing(1.7, 0.0, -8.0),
        10,
    )
    .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    let log = inner.gpu().validation.clone().expect("validation layer");
    // Tweaks injected as the window's keys would send them.
    let script: Vec<(u64, Vec<Tweak>)> = vec![
        (
            2,
            vec![
                Tweak::WindSpeed(2.0),
                Tweak::WindSpeed(-1000.0), // refused: wind must stay > 0
                Tweak::Choppiness(5.0),    // refused: choppiness in [0, 2]
                Tweak::WindDirection(-30.0),
            ],
        ),
        (4, vec![Tweak::Preset(QualityPreset::Medium)]),
        (6, vec![Tweak::Preset(QualityPreset::Medium)]), // already: nothing to do
        (7, vec![Tweak::Preset(QualityPreset::Low)]),
        // The controller's preset button: the next after the user's current (issue 44).
        (8, vec![Tweak::NextPreset]),
    ];
    let mut xr = gpu::Edited {
        inner,
        edit: |s: &mut FrameState| {
            for (frame, tweaks) in &script {
                if *frame == s.index {
                    assert!(tweaks.len() <= MAX_TWEAKS);
                    for (slot, t) in s.tweaks.iter_mut().zip(tweaks) {
                        *slot = Some(*t);
                    }
                }
            }
            Ok(())
        },
    };
    let opts = gpu::small_options(StereoMode::Multiview, vec![9]);
    let mut frames = Vec::new();
    struct Keep<'a>(&'a mut Vec<Vec<u8>>);
    impl app::RunHooks for Keep<'_> {
        fn capture(&mut self, c: &app::Capture<'_>) -> Result<(), app::AppError> {
            self.0.push(c.eyes[0].to_vec());
            Ok(())
        }
    }
    let report = app::run(&mut xr, &opts, &mut Keep(&mut frames)).expect("run with tweaks");
    drop(xr);
    assert_eq!(report.frames, 10);
    assert_eq!(
        report.chosen.preset,
        QualityPreset::Medium,
        "Low, then the next"
    );
    assert_eq!(log.errors(), 0, "validation errors: {:?}", log.messages());
    // The frame after the last switch is a normal picture (sky on top, no black pixels).
    let eye = &frames[0];
    assert!(eye.chunks(4).all(|p| p[..3] != [0, 0, 0]));
    assert!(eye[2] > 120, "sky {:?}", &eye[..4]);
}
