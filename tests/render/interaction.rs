//! The interaction layer drawn (issue 30), on lavapipe with the validation layer required: a
//! thrown crate's splash rings change the picture around where it lands, and the layer meets
//! the FFT sea without a seam: beyond its edge the picture is the same bits as without it, and
//! its change fades out toward the edge instead of stopping at a step.

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::app::{interaction_for, DeckPlacement, FloatOptions};
use vr_ocean::base::EyeView;
use vr_ocean::lod::QualityPreset;
use vr_ocean::physics::BodyCount;
use vr_ocean::render::StereoMode;
use vr_ocean::xr::desktop::CameraPath;

const W: u32 = 240;
const H: u32 = 180;
/// 2.5 s at 72 Hz: the crate lands about 1 s in, its rings spread 1.5 s.
const FRAMES: u64 = 180;
/// The layer of the `Low` preset: 128 cells of 0.32 m, its edges 20.5 m from its centre.
const HALF_SIDE: f32 = 64.0 * 0.32;

fn render(interaction: bool) -> Frame {
    let mut opts = gpu::small_options(StereoMode::TwoPass, vec![FRAMES - 1]);
    opts.floating = Some(FloatOptions {
        bodies: BodyCount::new(0).unwrap(),
        // 12 m up: too high for a deck.
        deck: DeckPlacement::UnderViewer,
        interaction: interaction.then(|| interaction_for(QualityPreset::Low)),
    });
    // 12 m above the sea looking 35° down along −z, a crate thrown along the view at 0.1 s.
    let path = CameraPath::parse("0 0 12 0 0 -35\nthrow 0.1\n").unwrap();
    let (_, mut frames) = gpu::render(&opts, path, FRAMES, W, H);
    frames.pop().expect("one capture")
}

/// Where the ray through pixel (x, y) of `eye` meets the mean sea level (world x, z).
fn ground(eye: &EyeView, x: u32, y: u32) -> Option<(f32, f32)> {
    let f = eye.fov;
    let u = (x as f32 + 0.5) / W as f32;
    let v = (y as f32 + 0.5) / H as f32;
    let tx = f.angle_left.tan() + u * (f.angle_right.tan() - f.angle_left.tan());
    let ty = f.angle_up.tan() - v * (f.angle_up.tan() - f.angle_down.tan());
    let d = eye.orientation * Vec3::new(tx, ty, -1.0);
    (d.y < 0.0).then(|| {
        let t = -eye.position.y / d.y;
        (eye.position.x + t * d.x, eye.position.z + t * d.z)
    })
}

#[test]
fn splash_rings_show_and_meet_the_sea_without_a_seam() {
    let (on, off) = (render(true), render(false));
    on.save("interaction-on");
    off.save("interaction-off");
    let eye = &on.state.views[0];
    // Mean absolute difference (codes, summed over RGB) by distance from the layer's edge,
    // in 1 m bands: 0 = the last metre inside, negative = beyond it.
    let mut bands = [(0.0f64, 0usize); 12];
    let (mut beyond_max, mut beyond_n) = (0i32, 0);
    for y in 0..H {
        for x in 0..W {
            let Some((gx, gz)) = ground(eye, x, y) else {
                continue;
            };
            let (p, q) = (on.pixel(0, x, y), off.pixel(0, x, y));
            let diff: i32 = (0..3).map(|c| (p[c] as i32 - q[c] as i32).abs()).sum();
            // The layer follows the viewer (x 0, z 0) by whole cells.
            let inside = HALF_SIDE - gx.abs().max(gz.abs());
            if inside < -1.5 {
                beyond_max = beyond_max.max(diff);
                beyond_n += 1;
            } else if inside >= 0.0 && (inside as usize) < bands.len() {
                let b = &mut bands[inside as usize];
                b.0 += diff as f64;
                b.1 += 1;
            }
        }
    }
    let mean: Vec<f64> = bands
        .iter()
        .map(|&(s, n)| if n > 0 { s / n as f64 } else { 0.0 })
        .collect();
    println!("mean |on − off| by metre inside the edge (0 = outermost): {mean:.2?}");
    println!("beyond the edge: {beyond_n} pixels, largest difference {beyond_max}");
    assert!(
        beyond_n > 1000,
        "the view should reach past the layer: {beyond_n}"
    );
    assert_eq!(beyond_max, 0, "the layer changed the sea beyond its edge");
    // The absorbing band (5 m) fades the layer out: its outermost metres change the picture
    // less than the water well inside it, with no step at the edge.
    assert!(mean[0] < 1.0, "a step at the edge: {mean:?}");
    // The splash: the crate lands ~6 m ahead, its rings reach 10 m and more.
    let near = mean[8..].iter().cloned().fold(0.0, f64::max);
    assert!(
        near > 3.0 * mean[0].max(0.3),
        "no rings inside the layer: {mean:?}"
    );
}
