//! Stereo culling: never drops a patch that a brute-force test says either eye can see, culls
//! most of the ocean behind a standing user looking at the horizon, and keeps the draw count at
//! ≤ 16 + the skirt. Also the per-preset triangle counts (printed; recorded in BENCHMARKS.md).

use crate::common;

use common::lod::{culled_frame, quest_eyes, Lcg};

use glam::Vec3;

use vr_ocean::base::EyeView;
use vr_ocean::lod::{FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset};

/// Independent visibility oracle: a point is seen by an eye when, in that eye's view space
/// (inverse pose), it is in front of the near plane and its tangents x/−z, y/−z lie within the
/// FOV angles. A box is visible when any of a dense 9×5×9 grid of its points is.
fn brute_force_sees(eye: &EyeView, c: Vec3, e: Vec3) -> bool {
    let inv = eye.orientation.normalize().inverse();
    for i in 0..9 {
        for j in 0..5 {
            for k in 0..9 {
                let t = Vec3::new(i as f32 / 8.0, j as f32 / 4.0, k as f32 / 8.0) * 2.0 - 1.0;
                let v = inv * (c + t * e - eye.position);
                let depth = -v.z;
                if depth <= 0.06 {
                    continue;
                }
                let (tx, ty) = (v.x / depth, v.y / depth);
                if tx >= eye.fov.angle_left.tan()
                    && tx <= eye.fov.angle_right.tan()
                    && ty >= eye.fov.angle_down.tan()
                    && ty <= eye.fov.angle_up.tan()
                {
                    return true;
                }
            }
        }
    }
    false
}

#[test]
fn culling_never_drops_a_visible_patch() {
    let pad = MaxDisplacement::new([1.2, 2.5, 0.8]).unwrap();
    let mut rng = Lcg(7);
    let mut rnd = move || rng.next();
    let mut kept_total = 0;
    for preset in QualityPreset::ALL {
        for size in [256.0, 2048.0, 8192.0] {
            let st = LodSettings::new(preset, OceanSize::new(size).unwrap());
            let mut lod = OceanLod::new(st);
            for n in 0..40 {
                let h = [0.5, 1.7, 1.7, 10.0, 200.0][n % 5];
                let pos = Vec3::new((rnd() - 0.5) * 500.0, h, (rnd() - 0.5) * 500.0);
                let pitch = (rnd() - 0.6) * 2.5;
                let eyes = quest_eyes(pos, rnd() * std::f32::consts::TAU, pitch);
                culled_frame(&mut lod, &eyes, pad);
                assert!(lod.draws().len() <= 16);
                for (leaf, &kept) in lod.leaves().iter().zip(lod.visible()) {
                    let inst = lod.instance_of(leaf);
                    let beta = preset.cull_scale();
                    let [dx, hmax, dz] = pad.get();
                    // The patch footprint padded by β × the real maximum displacement.
                    let half = inst.size / 2.0;
                    let c = Vec3::new(inst.centre[0], 0.0, inst.centre[1]);
                    let e = Vec3::new(half + beta * dx, beta * hmax, half + beta * dz);
                    let seen = eyes.eyes().iter().any(|eye| brute_force_sees(eye, c, e));
                    assert!(
                        kept || !seen,
                        "{preset:?} S={size}: visible patch {leaf:?} culled (eye at {pos})"
                    );
                    kept_total += kept as usize;
                }
            }
        }
    }
    assert!(kept_total > 0);
}

#[test]
fn a_standing_user_looking_at_the_horizon_culls_at_least_40_percent() {
    let pad = MaxDisplacement::new([1.0, 1.5, 1.0]).unwrap();
    for preset in QualityPreset::ALL {
        for size in [256.0, 512.0, 1024.0, 2048.0, 4096.0, 8192.0] {
            let st = LodSettings::new(preset, OceanSize::new(size).unwrap());
            let mut lod = OceanLod::new(st);
            let mut worst = 1.0f32;
            for k in 0..16 {
                let yaw = k as f32 * std::f32::consts::TAU / 16.0;
                let eyes = quest_eyes(Vec3::new(3.0, 1.7, -2.0), yaw, 0.0);
                let s = culled_frame(&mut lod, &eyes, pad);
                let culled = 1.0 - s.visible as f32 / s.patches as f32;
                worst = worst.min(culled);
            }
            println!(
                "horizon view {:>6} S={size:>6}: culled >= {:.0}% of patches",
                preset.name(),
                worst * 100.0
            );
            // At S = 256 (L_max = 2, eq. 56) the whole ocean is 16 patches of 64 m and the
            // user stands at the corner the 4 central ones share: with 6 more in view, the
            // brute-force test above finds 10 of 16 padded boxes visible at some headings, so
            // no conservative culling reaches 40 % there. The claim is for S >= 512.
            if size >= 512.0 {
                assert!(worst >= 0.4, "{preset:?} S={size}: only {worst} culled");
            }
        }
    }
}

#[test]
fn triangle_and_draw_counts_per_preset() {
    // A standing user (1.7 m) looking at the horizon, S = 8192, modest sea state.
    let pad = MaxDisplacement::new([1.0, 1.5, 1.0]).unwrap();
    let eyes = quest_eyes(Vec3::new(0.0, 1.7, 0.0), 0.3, -0.1);
    println!("preset   V  patches visible draws triangles(culled)  triangles(all)");
    for preset in QualityPreset::ALL {
        let st = LodSettings::new(preset, OceanSize::new(8192.0).unwrap());
        let mut lod = OceanLod::new(st);
        let all = lod
            .update(&FrameInput {
                viewer: eyes.centre(),
                culling: None,
                max_displacement: pad,
            })
            .unwrap();
        let s = culled_frame(&mut lod, &eyes, pad);
        println!(
            "{:<7} {:>3} {:>8} {:>7} {:>5} {:>18} {:>15}",
            preset.name(),
            st.vertices(),
            s.patches,
            s.visible,
            s.draws + 1,
            s.triangles,
            all.triangles
        );
        assert!(s.draws <= 16 && all.draws <= 16);
        assert!(s.triangles < all.triangles);
    }
}
