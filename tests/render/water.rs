//! The water near the viewer (issue 29, item 2), on lavapipe with the validation layer
//! required: in the gallery's midday view (10 m/s, the sun 60° high, standing 4.5 m up, looking
//! 7° down across the wind) the water 6-9 m away must not be a flat navy. The issue measured it
//! at linear-luminance p95/p5 1.55 and high-pass std/mean 0.028 under Preetham's sky (its
//! high-pass window unstated). This test's statistics (a 5 × 5 box as the low pass), with the
//! new sky: without light scattered out of the crests 2.05 / 0.38 (left eye) and 4.24 / 0.47
//! (right, more of the sun's glitter); with it (`CREST_SCATTER` in `shaders/ocean.frag`) 2.40 /
//! 0.32 and 4.12 / 0.40: the lifted crests lighter and greener, the spread between them and the
//! troughs wider (the high-pass share falls as the mean rises). Gated: the smaller eye's p95/p5
//! at 2.2 (fails without the crests' light) and the high-pass figure as a floor.
//!
//! The detail near the viewer (`sim::detail`, item 2's last part): standing 1.7 m up, looking
//! 50° down, the water 1.5-3 m away must show ripples finer than the finest cascade's 6 cm
//! texels (high-pass over a 3 × 3 box, with the detail against without it), and the water
//! 10-18 m away, where the detail's mips have averaged it out and the highlight's lobe takes its
//! slopes back, must look the same.

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::render::camera::project_to_pixel;
use vr_ocean::render::sky::SunSky;
use vr_ocean::render::tonemap::srgb_decode;
use vr_ocean::render::{Msaa, StereoMode};
use vr_ocean::sim::OceanConfig;

const SIZE: u32 = 480;

fn luminance(p: [u8; 4]) -> f32 {
    let lin = srgb_decode;
    0.2126 * lin(p[0]) + 0.7152 * lin(p[1]) + 0.0722 * lin(p[2])
}

fn midday() -> Frame {
    let mut opts = gpu::small_options(StereoMode::Multiview, vec![31]);
    let mut ocean = OceanConfig::default_cascades(256).unwrap();
    ocean.waves.wind_speed = 10.0;
    ocean.fit_patches();
    opts.ocean = ocean;
    opts.renderer.msaa = Msaa::X1;
    opts.renderer.sun = SunSky {
        elevation_deg: 60.0,
        azimuth_deg: 30.0,
        turbidity: 2.5,
        clouds: 0.0,
    };
    let (_, mut frames) = gpu::render(&opts, gpu::standing(4.5, -30.0, -7.0), 32, SIZE, SIZE);
    let f = frames.pop().expect("one capture");
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        println!("saved {}", f.save("near-water").display());
    }
    f
}

/// The pixels of `eye` showing the sea 6-9 m from the viewer (rest positions on the mean
/// plane, projected), away from the image's edges.
fn near_water(f: &Frame, eye: usize) -> Vec<(u32, u32)> {
    water_between(f, eye, 6.0, 9.0)
}

/// The pixels of `eye` showing the sea `near`-`far` m from the viewer.
fn water_between(f: &Frame, eye: usize, near: f32, far: f32) -> Vec<(u32, u32)> {
    let v = &f.state.views[eye];
    let mut pixels = std::collections::BTreeSet::new();
    for r in 0..=240 {
        let d = near + (far - near) * r as f32 / 240.0;
        for a in 0..1440 {
            let (s, c) = (a as f32 * 0.5f32).to_radians().sin_cos();
            let p = Vec3::new(v.position.x + d * c, 0.0, v.position.z + d * s);
            if let Some((x, y)) = project_to_pixel(v, p, f.width, f.height) {
                if (4.0..f.width as f32 - 4.0).contains(&x)
                    && (4.0..f.height as f32 - 4.0).contains(&y)
                {
                    pixels.insert((x as u32, y as u32));
                }
            }
        }
    }
    pixels.into_iter().collect()
}

/// (p95 / p5 of the linear luminance, std of the luminance less its 5 × 5 mean / the mean).
fn contrast(f: &Frame, eye: usize) -> (f32, f32) {
    let pixels = near_water(f, eye);
    assert!(pixels.len() > 2000, "{} near-water pixels", pixels.len());
    let lum = |x: u32, y: u32| luminance(f.pixel(eye, x, y));
    let mut values: Vec<f32> = pixels.iter().map(|&(x, y)| lum(x, y)).collect();
    let mean = values.iter().sum::<f32>() / values.len() as f32;
    let high: Vec<f32> = pixels
        .iter()
        .map(|&(x, y)| {
            let mut s = 0.0;
            for dy in -2i32..=2 {
                for dx in -2i32..=2 {
                    s += lum((x as i32 + dx) as u32, (y as i32 + dy) as u32);
                }
            }
            lum(x, y) - s / 25.0
        })
        .collect();
    let std = (high.iter().map(|h| h * h).sum::<f32>() / high.len() as f32).sqrt();
    values.sort_by(f32::total_cmp);
    let p = |q: usize| values[values.len() * q / 100];
    (p(95) / p(5), std / mean)
}

#[test]
fn near_water_has_light_and_detail() {
    let f = midday();
    let mut smallest = f32::MAX;
    for eye in 0..2 {
        let (spread, detail) = contrast(&f, eye);
        println!(
            "eye {eye}: water 6-9 m away: luminance p95/p5 {spread:.2}, high-pass std/mean \
             {detail:.3}"
        );
        smallest = smallest.min(spread);
        assert!(detail >= GATE_DETAIL, "featureless near water: {detail:.3}");
    }
    assert!(
        smallest >= GATE_SPREAD,
        "flat near water: p95/p5 {smallest:.2}"
    );
}

/// The gates: the spread the crests' light gives (2.40; 2.05 without it), and the issue's
/// high-pass figure (0.028) as a floor.
const GATE_SPREAD: f32 = 2.2;
const GATE_DETAIL: f32 = 0.028;

/// Standing on a low deck (1.7 m), looking 50° down across the wind, with and without the
/// detail: 640 px per eye (7 px a degree: the water 2 m away is about 1 cm a pixel).
fn close_look(detail: bool) -> Frame {
    let mut opts = gpu::small_options(StereoMode::Multiview, vec![31]);
    let mut ocean = OceanConfig::default_cascades(256).unwrap();
    ocean.waves.wind_speed = 10.0;
    ocean.fit_patches();
    opts.ocean = ocean;
    // Quest 2's preset (the tests' default, low, draws node seams this close: see the note).
    opts.lod = LodSettings::new(QualityPreset::Medium, OceanSize::new(2048.0).unwrap());
    opts.renderer.msaa = Msaa::X4;
    opts.renderer.detail = detail;
    opts.renderer.sun = SunSky {
        elevation_deg: 40.0,
        azimuth_deg: -20.0,
        turbidity: 2.5,
        clouds: 0.0,
    };
    let (_, mut frames) = gpu::render(&opts, gpu::standing(1.7, -30.0, -50.0), 32, 640, 640);
    let f = frames.pop().expect("one capture");
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        println!(
            "saved {}",
            f.save(&format!("close-water-detail-{detail}")).display()
        );
    }
    f
}

/// (high-pass std over a 3 × 3 box / mean, mean) of the linear luminance over `pixels`.
fn fine_contrast(f: &Frame, eye: usize, pixels: &[(u32, u32)]) -> (f32, f32) {
    let lum = |x: u32, y: u32| luminance(f.pixel(eye, x, y));
    let mut sum = 0.0;
    let mut sq = 0.0;
    for &(x, y) in pixels {
        let mut s = 0.0;
        for dy in -1i32..=1 {
            for dx in -1i32..=1 {
                s += lum((x as i32 + dx) as u32, (y as i32 + dy) as u32);
            }
        }
        let h = lum(x, y) - s / 9.0;
        sq += h * h;
        sum += lum(x, y);
    }
    let n = pixels.len() as f32;
    ((sq / n).sqrt() / (sum / n), sum / n)
}

#[test]
fn detail_ripples_show_near_the_viewer_and_fade_far_away() {
    let with = close_look(true);
    let without = close_look(false);
    for eye in 0..2 {
        let near = water_between(&with, eye, 1.5, 3.0);
        assert!(near.len() > 5000, "{} near pixels", near.len());
        let (fine_with, _) = fine_contrast(&with, eye, &near);
        let (fine_without, _) = fine_contrast(&without, eye, &near);
        let far = water_between(&with, eye, 10.0, 18.0);
        assert!(far.len() > 500, "{} far pixels", far.len());
        let (far_fine_with, far_with) = fine_contrast(&with, eye, &far);
        let (far_fine_without, far_without) = fine_contrast(&without, eye, &far);
        println!(
            "eye {eye}: water 1.5-3 m away: high-pass std/mean {fine_without:.3} without the \
             detail, {fine_with:.3} with it ({:.2}x); 10-18 m away: mean {far_without:.4} / \
             {far_with:.4}, high-pass {far_fine_without:.3} / {far_fine_with:.3}",
            fine_with / fine_without
        );
        assert!(
            fine_with >= GATE_DETAIL_GAIN * fine_without,
            "eye {eye}: no ripples near the viewer: {fine_without:.3} -> {fine_with:.3}"
        );
        assert!(
            (far_with / far_without - 1.0).abs() < 0.03,
            "eye {eye}: the far water changed: mean {far_without} -> {far_with}"
        );
    }
}

/// The detail's gain in fine contrast near the viewer.
const GATE_DETAIL_GAIN: f32 = 1.5;
