//! Images from the headless renderer on lavapipe, validation layer required: sky above and
//! ocean below the horizon with no crack at grazing angles, no black pixels, stereo parallax
//! as the eye poses predict, and multiview equal to the two-pass fallback.

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::render::camera::project_to_pixel;
use vr_ocean::render::StereoMode;
use vr_ocean::xr::desktop::CameraPath;

const MAGENTA: [u8; 4] = [255, 0, 255, 255];

#[test]
fn sky_above_ocean_below_and_no_cracks_at_grazing_angles() {
    // Standing and crouching heights, looking at the horizon and just below it, turning.
    let path = CameraPath::parse(
        "0    0    1.7  0    0    -2
         0.5  3    1.2  -5   60    0
         1.0  -4   2.0  3    170  -6
         1.5  10   1.5  -8   260   4
         2.0  -20  1.8  30   330  -1",
    )
    .unwrap();
    let mut opts = gpu::small_options(StereoMode::Multiview, vec![0, 36, 54, 72, 90, 108, 144]);
    opts.ocean.waves.wind_speed = 6.0;
    opts.renderer.sky_marker = true;
    let (report, frames) = gpu::render(&opts, path, 145, 160, 120);
    assert_eq!(frames.len(), 7);
    assert!(report.max_draws <= 20, "{} draws", report.max_draws);
    for f in &frames {
        for eye in 0..2 {
            let row = f.horizon_row(eye);
            let (mut sky_below, mut ocean_above, mut black) = (0, 0, 0);
            for y in 0..f.height {
                for x in 0..f.width {
                    let p = f.pixel(eye, x, y);
                    if p[..3] == [0, 0, 0] {
                        black += 1;
                    }
                    let yc = y as f32 + 0.5;
                    if yc > row + 1.5 && p == MAGENTA {
                        sky_below += 1;
                    }
                    if yc < row - 1.5 && p != MAGENTA {
                        ocean_above += 1;
                    }
                }
            }
            if black + sky_below + ocean_above > 0 {
                eprintln!("saved {}", f.save("horizon").display());
            }
            assert_eq!(black, 0, "frame {} eye {eye}: black pixels", f.index);
            assert_eq!(
                sky_below, 0,
                "frame {} eye {eye}: sky shows through the ocean below the horizon (row {row:.1})",
                f.index
            );
            assert_eq!(
                ocean_above, 0,
                "frame {} eye {eye}: non-sky pixels above the horizon (row {row:.1})",
                f.index
            );
            // Both parts are really there.
            assert!(
                row > 2.0 && row < f.height as f32 - 2.0,
                "horizon off-screen"
            );
        }
    }
}

/// The horizontal shift s minimising the mean absolute difference between left row `y` at x
/// and right row `y` at x + s, over `range`.
fn best_shift(f: &Frame, y: u32, range: std::ops::RangeInclusive<i32>) -> i32 {
    let lum = |eye: usize, x: u32| {
        let p = f.pixel(eye, x, y);
        p[0] as f32 * 0.3 + p[1] as f32 * 0.6 + p[2] as f32 * 0.1
    };
    let w = f.width as i32;
    range
        .min_by_key(|&s| {
            let xs = (0.max(-s))..(w.min(w - s));
            let n = xs.len().max(1) as f32;
            let sad: f32 = xs
                .map(|x| (lum(0, x as u32) - lum(1, (x + s) as u32)).abs())
                .sum();
            (sad / n * 1000.0) as i64
        })
        .unwrap()
}

#[test]
fn eyes_differ_by_the_parallax_their_poses_predict() {
    // Looking down at the water close by, where 63 mm of IPD shows as several pixels. Two-pass:
    // with Mesa 22.3's lavapipe, multiview rasterizes primitives that need clipping (here the
    // triangles passing under the viewer) of the second view into the first view's layer.
    let path = gpu::standing(1.7, 0.0, -55.0);
    let mut opts = gpu::small_options(StereoMode::TwoPass, vec![8]);
    opts.ocean.waves.wind_speed = 5.0;
    opts.ocean.waves.choppiness = 0.0;
    // The thesis's Phillips sea: at 5 m/s its waves are lower than a fetch-limited JONSWAP
    // sea's (Hs 0.54 m), whose long swell moves the surface by a third of the 1.7 m depth.
    opts.ocean.waves.spectrum = vr_ocean::sim::SpectrumKind::Phillips { amplitude: 1.0 };
    // The sun ahead, as high as the view looks down: its glitter fills the view with texture
    // both eyes see (deep water seen from above is otherwise an even, dark blue).
    opts.renderer.sun = vr_ocean::render::sky::SunSky {
        elevation_deg: 55.0,
        azimuth_deg: -90.0,
        turbidity: 2.5,
        clouds: 0.0,
    };
    let (_, frames) = gpu::render(&opts, path, 9, 480, 480);
    let f = &frames[0];
    eprintln!("saved {}", f.save("parallax").display());
    let [left, right] = f.state.views;
    // Predicted shift of row y: where the sea-level point seen at (centre, y) by the left eye
    // lands in the right eye.
    let predicted = |y: u32| -> Option<f32> {
        let h = f.height as f32;
        let ndc = Vec3::new(0.0, (y as f32 + 0.5) / h * 2.0 - 1.0, 1.0);
        let clip_to_world = (vr_ocean::render::camera::projection(&left.fov, 0.05)
            * vr_ocean::render::camera::view(&left))
        .inverse();
        let p = clip_to_world.project_point3(ndc);
        let dir = (p - left.position).normalize();
        if dir.y >= -0.05 {
            return None;
        }
        let hit = left.position + dir * (-left.position.y / dir.y);
        let (xl, _) = project_to_pixel(&left, hit, f.width, f.height)?;
        let (xr, _) = project_to_pixel(&right, hit, f.width, f.height)?;
        Some(xr - xl)
    };
    // Shift of points at infinity: only the two FOVs' asymmetry, no parallax.
    let forward = left.orientation * Vec3::NEG_Z;
    let inf = |v: &vr_ocean::base::EyeView| {
        project_to_pixel(v, v.position + forward * 1.0e7, f.width, f.height)
            .unwrap()
            .0
    };
    let p_inf = inf(&right) - inf(&left);
    let mut rows = Vec::new();
    for y in (f.height / 2..f.height).step_by(12) {
        let Some(p) = predicted(y) else { continue };
        let s = best_shift(f, y, (p.round() as i32 - 15)..=(p.round() as i32 + 15)) as f32;
        // Waves move the surface off sea level, changing the depth of what a row sees by up
        // to a few tens of percent: allow that share of the parallax part of the shift.
        let tolerance = 1.5f32.max(0.35 * (p - p_inf).abs());
        assert!(
            (s - p).abs() <= tolerance,
            "row {y}: measured shift {s} px, predicted {p:.2} px (infinity {p_inf:.2})"
        );
        rows.push((p, s));
    }
    assert!(rows.len() >= 10, "only {} rows checked", rows.len());
    // The rows really differ in depth, and the image shows it: parallax, not just the
    // asymmetric FOVs' offset.
    let (far, near) = (rows[0], rows[rows.len() - 1]);
    let predicted_parallax = (near.0 - far.0).abs();
    let measured_parallax = (near.1 - far.1).abs();
    assert!(
        predicted_parallax >= 3.0 && measured_parallax >= 0.5 * predicted_parallax,
        "parallax between far and near rows: measured {measured_parallax} px, predicted {predicted_parallax:.2} px"
    );
}

#[test]
fn multiview_matches_the_two_pass_fallback_with_half_the_draws() {
    let path = gpu::standing(1.7, 20.0, -10.0);
    let capture = vec![3, 12];
    let (mv, a) = gpu::render(
        &gpu::small_options(StereoMode::Multiview, capture.clone()),
        path.clone(),
        13,
        200,
        150,
    );
    let (tp, b) = gpu::render(
        &gpu::small_options(StereoMode::TwoPass, capture),
        path,
        13,
        200,
        150,
    );
    assert_eq!(
        2 * mv.max_draws,
        tp.max_draws,
        "draws: multiview {} two-pass {}",
        mv.max_draws,
        tp.max_draws
    );
    // Identical within 1/255 except for rare silhouette pixels: lavapipe's multiview path
    // computes clip positions with different rounding, so a pixel whose centre sits on the
    // horizon edge can flip between ocean and sky (measured: 1 pixel of 30 000). At most
    // 0.05 % of pixels may differ by more than 1/255.
    for (fa, fb) in a.iter().zip(&b) {
        for eye in 0..2 {
            let (x, y) = (&fa.eyes[eye], &fb.eyes[eye]);
            let pixels = x.len() / 4;
            let bad = (0..pixels)
                .filter(|&i| (0..3).any(|c| x[4 * i + c].abs_diff(y[4 * i + c]) > 1))
                .count();
            if bad > 0 {
                eprintln!(
                    "frame {} eye {eye}: {bad} of {pixels} pixels differ by more than 1/255",
                    fa.index
                );
            }
            if bad * 2000 > pixels {
                eprintln!(
                    "saved {} and {}",
                    fa.save("multiview").display(),
                    fb.save("two-pass").display()
                );
            }
            assert!(
                bad * 2000 <= pixels,
                "frame {} eye {eye}: {bad} of {pixels} pixels differ by more than 1/255",
                fa.index
            );
        }
    }
}
