//! Aliasing, measured against a supersampled reference of the same frame (same camera path
//! and frame index, so the same simulation time): the reference is rendered at 3×3 the size
//! with `--msaa 1 --specular-aa off` and box-filtered down in linear light. Luminance RMSE over
//! the far band (the water just under the horizon, 8 % of the image height) and over the nearer
//! water, facing the sun's glitter path and facing away.
//!
//! Gate: with the defaults (MSAA 4 + specular AA) the far band's error facing the sun is at
//! most 0.6× that of `--msaa 1 --specular-aa off`, facing away at most 0.8× (issue 43: the
//! foam's flecks on breaking crests, `filtered_foam` in the water shader). Two defaults are
//! held to it: the desktop's (the highlight supersampled where the finest cascade is
//! minified; trilinear normal maps on lavapipe) on the host, and the headsets' (the lobe
//! filtered alone, the normal maps read with 4 anisotropic taps, no supersampling; issue 43)
//! in both eyes, on Mesa 25's lavapipe in the Monado step's root, where anisotropic taps cost
//! nothing measurable (Mesa 22.3's take ~50x). Also checked: MSAA gives the horizon's edge
//! pixels intermediate colours (from about none without it). The numbers, with stereo
//! consistency of far highlights, are printed and written to `target/aliasing.json`
//! (`target/aliasing-headset.json`).

use crate::common;

use std::time::Duration;

use common::gpu::{self, Frame};
use common::monado;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::render::ocean::Anisotropy;
use vr_ocean::render::tonemap::srgb_decode;
use vr_ocean::render::{Msaa, StereoMode};
use vr_ocean::sim::{OceanConfig, SpectrumKind};

/// Per-eye size of the tested frames; the reference is 3× in each direction.
const SIZE: u32 = 480;
const SCALE: u32 = 3;
/// The captured frame (its simulation time is frame / 72 s).
const FRAME: u64 = 2;
/// Yaw (degrees) that faces the default sun (direction 0.45, 0.3, −0.84), and its opposite.
const SUN_YAW: f32 = -28.0;
const AWAY_YAW: f32 = 152.0;
/// Camera height (m) and pitch (degrees): standing on a deck, the horizon in the upper part.
const HEIGHT: f32 = 4.5;
const PITCH: f32 = -6.0;
/// The far band: from the horizon down this share of the image height.
const FAR_BAND: f32 = 0.08;

/// How the specular AA of a tested frame works.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shading {
    /// None (the reference and the no-AA frames).
    Plain,
    /// The desktop's: the filtered lobe, the highlight supersampled where the finest cascade is
    /// minified, trilinear normal maps (a CPU device's default).
    Desktop,
    /// The headsets' (`android::options`): the filtered lobe alone over normal maps read with 4
    /// anisotropic taps.
    Headset,
}

fn options(msaa: Msaa, shading: Shading) -> vr_ocean::app::RunOptions {
    let mut o = gpu::small_options(StereoMode::Multiview, vec![FRAME]);
    o.ocean = OceanConfig::default_cascades(256).unwrap();
    // The short-crested Phillips sea issue 13's gates were set on: its far band aliases most.
    // (The default JONSWAP sea, smoother far away, measured 8.23 -> 4.92 facing the sun,
    // 0.597x, and 8.80 -> 5.00 facing away, 0.568x.)
    o.ocean.waves.spectrum = SpectrumKind::Phillips { amplitude: 1.0 };
    o.lod = LodSettings::new(QualityPreset::High, OceanSize::new(2048.0).unwrap());
    o.renderer.msaa = msaa;
    o.renderer.specular_aa = shading != Shading::Plain;
    o.renderer.supersampling = shading == Shading::Desktop;
    o.renderer.anisotropy = if shading == Shading::Headset {
        Anisotropy::X4
    } else {
        Anisotropy::Off
    };
    // The reference draws the tested frames' surface: the far mesh collapsed for their size.
    o.renderer.mesh_eye_width = Some(SIZE);
    o
}

fn render(msaa: Msaa, shading: Shading, yaw: f32, size: u32) -> Frame {
    let (_, mut frames) = gpu::render(
        &options(msaa, shading),
        gpu::standing(HEIGHT, yaw, PITCH),
        FRAME + 1,
        size,
        size,
    );
    frames.remove(0)
}

/// Linear to sRGB 8-bit scale (0..255, unrounded).
fn srgb(l: f32) -> f32 {
    let c = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c.clamp(0.0, 1.0) * 255.0
}

/// Per-pixel luminance of `eye` in sRGB code values (0..255), the linear colour box-filtered by
/// `scale`×`scale` first.
fn luminance(f: &Frame, eye: usize, scale: u32) -> Vec<f32> {
    let (w, h) = (f.width / scale, f.height / scale);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut rgb = [0.0f32; 3];
            for dy in 0..scale {
                for dx in 0..scale {
                    let p = f.pixel(eye, x * scale + dx, y * scale + dy);
                    for c in 0..3 {
                        rgb[c] += srgb_decode(p[c]);
                    }
                }
            }
            let n = (scale * scale) as f32;
            let l = (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) / n;
            out.push(srgb(l));
        }
    }
    out
}

/// Rows [start, end) of the far band and of the nearer water in a `size`-high image.
fn bands(horizon: f32, size: u32) -> ((u32, u32), (u32, u32)) {
    // Two pixels below the horizon: its own edge is MSAA's job, measured separately.
    let far0 = (horizon + 2.0).ceil() as u32;
    let far1 = (horizon + FAR_BAND * size as f32).ceil() as u32;
    ((far0, far1), (far1, size))
}

/// Luminance RMSE of `a` against `reference` over rows `rows`.
fn rmse(a: &[f32], reference: &[f32], width: u32, rows: (u32, u32)) -> f64 {
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for y in rows.0..rows.1 {
        for x in 0..width {
            let i = (y * width + x) as usize;
            sum += ((a[i] - reference[i]) as f64).powi(2);
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

/// Errors of one view: far band and near water, both eyes pooled, and the far band's per eye.
#[derive(Clone, Copy, Debug, serde::Serialize)]
struct Errors {
    far: f64,
    near: f64,
    far_eyes: [f64; 2],
}

fn errors(f: &Frame, reference: &[Vec<f32>; 2]) -> Errors {
    let mut far_eyes = [0.0; 2];
    let mut near = 0.0;
    for (eye, reference) in reference.iter().enumerate() {
        let lum = luminance(f, eye, 1);
        let (far_rows, near_rows) = bands(f.horizon_row(eye), f.height);
        far_eyes[eye] = rmse(&lum, reference, f.width, far_rows);
        near += rmse(&lum, reference, f.width, near_rows).powi(2);
    }
    Errors {
        far: ((far_eyes[0].powi(2) + far_eyes[1].powi(2)) / 2.0).sqrt(),
        near: (near / 2.0).sqrt(),
        far_eyes,
    }
}

/// The share of far-band highlight pixels of the left eye that the right eye does not show
/// within a pixel after the eyes' measured offset (best integer shift over the band).
fn one_eyed_highlights(f: &Frame) -> f64 {
    let lum = [luminance(f, 0, 1), luminance(f, 1, 1)];
    let (rows, _) = bands(f.horizon_row(0), f.height);
    let w = f.width as i32;
    let at = |eye: usize, x: i32, y: u32| lum[eye][(y as i32 * w + x) as usize];
    // The horizontal offset between the eyes in the far band: the FOVs' asymmetry (parallax is
    // negligible that far away).
    let shift = (-40..=40)
        .min_by_key(|&s| {
            let mut sad = 0.0f32;
            for y in rows.0..rows.1 {
                for x in 40..w - 40 {
                    sad += (at(0, x, y) - at(1, x + s, y)).abs();
                }
            }
            (sad * 10.0) as i64
        })
        .unwrap();
    let threshold = 200.0;
    let (mut highlights, mut alone) = (0usize, 0usize);
    for y in rows.0..rows.1 {
        for x in 41..w - 41 {
            if at(0, x, y) < threshold {
                continue;
            }
            highlights += 1;
            let seen = (-1..=1).any(|d| at(1, x + shift + d, y) >= 0.8 * threshold);
            if !seen {
                alone += 1;
            }
        }
    }
    if highlights == 0 {
        0.0
    } else {
        alone as f64 / highlights as f64
    }
}

/// Of the water pixels of `eye` next to (magenta) sky, the share with a colour strictly
/// between the two: partial coverage, which only MSAA produces.
fn blended_edge(f: &Frame, eye: usize) -> (usize, f64) {
    // Pure sky is 1; water has none (its blue exceeds its green by far less).
    let magenta = |x: u32, y: u32| {
        let p = f.pixel(eye, x, y);
        (p[0].min(p[2]) as f32 - p[1] as f32) / 255.0
    };
    let (mut edge, mut blended) = (0usize, 0usize);
    for y in 1..f.height - 1 {
        for x in 1..f.width - 1 {
            let m = magenta(x, y);
            if m > 0.97 {
                continue;
            }
            let next_to_sky = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .any(|&(a, b)| magenta(a, b) > 0.97);
            if next_to_sky {
                edge += 1;
                if (0.15..0.97).contains(&m) {
                    blended += 1;
                }
            }
        }
    }
    (edge, blended as f64 / edge.max(1) as f64)
}

/// The far band's errors of every `shadings` against the reference, facing the sun and away:
/// the JSON report, and per view and shading the ratio to no-AA's (pooled, and per eye).
struct Comparison {
    report: serde_json::Map<String, serde_json::Value>,
    /// (view, shading, pooled ratio, per-eye ratios).
    ratios: Vec<(&'static str, Shading, f64, [f64; 2])>,
}

fn compare(shadings: &[Shading]) -> Comparison {
    let mut report = serde_json::Map::new();
    let mut ratios = Vec::new();
    for (name, yaw) in [("sun", SUN_YAW), ("away", AWAY_YAW)] {
        let reference_frame = render(Msaa::X1, Shading::Plain, yaw, SIZE * SCALE);
        let reference = [
            luminance(&reference_frame, 0, SCALE),
            luminance(&reference_frame, 1, SCALE),
        ];
        let plain = render(Msaa::X1, Shading::Plain, yaw, SIZE);
        let msaa_only = render(Msaa::X4, Shading::Plain, yaw, SIZE);
        let e_plain = errors(&plain, &reference);
        let e_msaa = errors(&msaa_only, &reference);
        let stereo_plain = one_eyed_highlights(&plain);
        let mut view = serde_json::json!({
            "plain": e_plain, "msaa4": e_msaa, "one_eyed_highlights_plain": stereo_plain,
        });
        let mut saved = vec![
            (reference_frame, "reference".to_string()),
            (plain, "plain".to_string()),
            (msaa_only, "msaa4".to_string()),
        ];
        for &shading in shadings {
            let frame = render(Msaa::X4, shading, yaw, SIZE);
            let e = errors(&frame, &reference);
            let stereo = one_eyed_highlights(&frame);
            let ratio = e.far / e_plain.far;
            let eyes = [0, 1].map(|i| e.far_eyes[i] / e_plain.far_eyes[i]);
            println!(
                "facing {name}, {shading:?} shading: luminance RMSE vs 3x3 supersampled (of \
                 255): far band {:.2} (msaa 1, no specular AA) -> {:.2} (msaa 4) -> {:.2} (msaa 4 \
                 + specular AA), ratio {ratio:.3} (left {:.3}, right {:.3}); nearer water {:.2} \
                 -> {:.2} -> {:.2}; far highlights seen by one eye only: {:.1} % -> {:.1} %",
                e_plain.far,
                e_msaa.far,
                e.far,
                eyes[0],
                eyes[1],
                e_plain.near,
                e_msaa.near,
                e.near,
                100.0 * stereo_plain,
                100.0 * stereo
            );
            let key = format!("{shading:?}").to_lowercase();
            view[key.as_str()] = serde_json::json!({
                "errors": e, "far_ratio": ratio, "far_ratio_eyes": eyes,
                "one_eyed_highlights": stereo,
            });
            ratios.push((name, shading, ratio, eyes));
            saved.push((frame, key));
        }
        if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
            for (f, what) in &saved {
                eprintln!(
                    "saved {}",
                    f.save(&format!("aliasing-{name}-{what}")).display()
                );
            }
        }
        report.insert(name.into(), view);
    }
    Comparison { report, ratios }
}

impl Comparison {
    fn ratio(&self, view: &str, shading: Shading) -> (f64, [f64; 2]) {
        self.ratios
            .iter()
            .find(|r| r.0 == view && r.1 == shading)
            .map(|r| (r.2, r.3))
            .expect("compared")
    }

    fn json(&self) -> String {
        serde_json::to_string_pretty(&serde_json::Value::Object(self.report.clone())).unwrap()
    }
}

/// `target/<file>`.
fn in_target(file: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .join(file)
}

#[test]
fn msaa_and_specular_aa_bring_the_far_sea_to_the_supersampled_reference() {
    let c = compare(&[Shading::Desktop]);
    let target = in_target("aliasing.json");
    std::fs::write(&target, c.json()).unwrap();
    println!("wrote {}", target.display());
    let (sun_ratio, _) = c.ratio("sun", Shading::Desktop);
    let (away_ratio, _) = c.ratio("away", Shading::Desktop);
    assert!(
        sun_ratio <= 0.6,
        "facing the sun, the far band's error with MSAA 4 + specular AA is {sun_ratio:.3}x that \
         of MSAA 1 without it (gate 0.6)"
    );
    assert!(
        away_ratio <= AWAY_GATE,
        "facing away, the far band's error with MSAA 4 + specular AA is {away_ratio:.3}x that \
         of MSAA 1 without it (gate {AWAY_GATE})"
    );
}

/// The far band's error facing away from the sun, as a share of no-AA's (issue 43: no worse
/// than the 0.80 measured when it was filed; 0.86 before the foam's pattern was filtered).
const AWAY_GATE: f64 = 0.8;

/// Set in the run of this binary inside the Monado step's root.
const IN_ROOT: &str = "VR_OCEAN_ALIASING_IN_ROOT";
/// Marks the report's line in that run's output.
const REPORT_LINE: &str = "aliasing report: ";

/// The headsets' shading (issue 43): the filtered lobe over 4 anisotropic taps, with no
/// supersampling, holds the gates in each eye, facing the sun and facing away.
/// Mesa 22.3's lavapipe on the host filters anisotropic taps ~50x slower, so this runs in the
/// trixie root (Mesa 25): the test runs its own binary there.
#[test]
#[ignore = "needs root and the trixie root (the `openxr (Monado)` step of cargo xtask test)"]
fn the_headsets_filtered_lobe_holds_the_gate_without_supersampling() {
    if std::env::var_os(IN_ROOT).is_none() {
        let root = monado::root_from_env();
        let exe = std::env::current_exe().expect("the test binary's path");
        let run = monado::client_without_service(
            &root,
            "aliasing",
            &exe,
            &[
                "the_headsets_filtered_lobe_holds_the_gate_without_supersampling",
                "--ignored",
                "--nocapture",
            ],
            &[(IN_ROOT, "1")],
            Duration::from_secs(600),
        );
        println!("{}", run.stdout);
        assert!(run.success(), "the run in the root failed: {run}");
        let report = run
            .stdout
            .lines()
            .find_map(|l| l.strip_prefix(REPORT_LINE))
            .expect("the run printed its report");
        let target = in_target("aliasing-headset.json");
        std::fs::write(&target, report).unwrap();
        println!("wrote {}", target.display());
        return;
    }
    let c = compare(&[Shading::Desktop, Shading::Headset]);
    println!(
        "{REPORT_LINE}{}",
        serde_json::Value::Object(c.report.clone())
    );
    let (_, sun_eyes) = c.ratio("sun", Shading::Headset);
    let (_, away_eyes) = c.ratio("away", Shading::Headset);
    assert!(
        sun_eyes.iter().all(|&r| r <= 0.6),
        "facing the sun, the headsets' far-band error is {sun_eyes:.3?}x no-AA's (left, right; \
         gate 0.6 in each eye)"
    );
    assert!(
        away_eyes.iter().all(|&r| r <= AWAY_GATE),
        "facing away, the headsets' far-band error is {away_eyes:.3?}x no-AA's (left, right; \
         gate {AWAY_GATE} in each eye)"
    );
}

#[test]
fn msaa_blends_the_horizon_edge() {
    let shares: Vec<f64> = [Msaa::X1, Msaa::X4]
        .into_iter()
        .map(|msaa| {
            let mut o = options(msaa, Shading::Desktop);
            o.renderer.sky_marker = true;
            o.ocean.waves.wind_speed = 14.0;
            // Low over a fresh, short-crested Phillips sea: wave crests stand against the sky
            // and make the horizon jagged. (A long JONSWAP swell draws a nearly straight
            // horizon whose blended share depends on where it falls within a pixel row.)
            o.ocean.waves.spectrum = SpectrumKind::Phillips { amplitude: 1.0 };
            let (_, frames) = gpu::render(&o, gpu::standing(1.2, 40.0, 0.0), 3, 320, 240);
            let f = &frames[0];
            if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
                eprintln!("saved {}", f.save(&format!("edge-{msaa:?}")).display());
            }
            let (e0, s0) = blended_edge(f, 0);
            let (e1, s1) = blended_edge(f, 1);
            assert!(e0 > 200 && e1 > 200, "edges of {e0} and {e1} pixels");
            (s0 + s1) / 2.0
        })
        .collect();
    println!(
        "water pixels at the sky's edge with an intermediate colour: msaa 1 {:.1} %, msaa 4 \
         {:.1} %",
        100.0 * shares[0],
        100.0 * shares[1]
    );
    assert!(shares[0] < 0.05, "single-sampled edges blend: {shares:?}");
    assert!(shares[1] > 0.5, "MSAA edges do not blend: {shares:?}");
}

/// Luminance change (of 255) between frames that reads as a flicker.
const FLICKER_JUMP: f32 = 32.0;

/// Share of far-band pixels whose highlight state (luminance of at least `threshold`) toggles
/// between consecutive frames with a jump of at least [`FLICKER_JUMP`] (a sparkle coming or
/// going, not a smooth glint drifting across the threshold), averaged over the frames.
fn highlight_toggles(frames: &[Frame], threshold: f32) -> f64 {
    let mut rates = Vec::new();
    for pair in frames.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        for eye in 0..2 {
            let (la, lb) = (luminance(a, eye, 1), luminance(b, eye, 1));
            let (rows, _) = bands(a.horizon_row(eye), a.height);
            let (mut n, mut toggled) = (0usize, 0usize);
            for y in rows.0..rows.1 {
                for x in 0..a.width {
                    let i = (y * a.width + x) as usize;
                    n += 1;
                    let crossed = (la[i] >= threshold) != (lb[i] >= threshold);
                    if crossed && (la[i] - lb[i]).abs() >= FLICKER_JUMP {
                        toggled += 1;
                    }
                }
            }
            rates.push(toggled as f64 / n.max(1) as f64);
        }
    }
    rates.iter().sum::<f64>() / rates.len().max(1) as f64
}

#[test]
fn far_highlights_flicker_less_with_anti_aliasing() {
    // A head turning slowly toward the sun's glitter path: 0.02 degrees a frame, a fifth of a
    // pixel at 480 pixels across a 94-degree field. What still toggles between frames is the
    // waves' motion and aliasing; anti-aliasing removes the latter.
    let turn = CameraPathText::turning(SUN_YAW - 0.5, SUN_YAW + 0.5, 50.0 / 72.0);
    let frames: Vec<u64> = (1..9).collect();
    let mut rates = Vec::new();
    for (msaa, aa) in [(Msaa::X1, Shading::Plain), (Msaa::X4, Shading::Desktop)] {
        let mut o = options(msaa, aa);
        o.capture = frames.clone();
        let (_, captured) = gpu::render(&o, turn.path(), 9, SIZE, SIZE);
        rates.push(highlight_toggles(&captured, 200.0));
    }
    println!(
        "far-band highlight pixels toggling between frames (slow turn): msaa 1 without specular \
         AA {:.2} %, msaa 4 with it {:.2} %",
        100.0 * rates[0],
        100.0 * rates[1]
    );
    assert!(
        rates[1] < rates[0],
        "anti-aliasing does not calm the far highlights: {rates:?}"
    );
}

/// A still head turning at a constant rate.
struct CameraPathText {
    text: String,
}

impl CameraPathText {
    fn turning(from_yaw: f32, to_yaw: f32, seconds: f32) -> Self {
        Self {
            text: format!(
                "0 0 {HEIGHT} 0 {from_yaw} {PITCH}\n{seconds} 0 {HEIGHT} 0 {to_yaw} {PITCH}\n"
            ),
        }
    }

    fn path(&self) -> vr_ocean::xr::desktop::CameraPath {
        vr_ocean::xr::desktop::CameraPath::parse(&self.text).unwrap()
    }
}
