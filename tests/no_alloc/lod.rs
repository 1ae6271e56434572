//! The LOD's steady state allocates nothing: a counting global allocator watches frames with
//! the viewer moving, turning and changing height (so the tree, ring level, visible set and
//! batches all change) after one warm-up frame.

use crate::common;

use glam::Vec3;

use vr_ocean::base::{EyeView, Fov};
use vr_ocean::lod::{
    FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset, StereoFrustum,
};

fn frames_do_not_allocate() {
    // One test in this binary, so nothing else allocates while counting.
    let fov = Fov::symmetric(1.7, 1.6);
    for preset in QualityPreset::ALL {
        for size in [256.0, 8192.0] {
            let mut lod = OceanLod::new(LodSettings::new(preset, OceanSize::new(size).unwrap()));
            let pad = MaxDisplacement::new([1.0, 2.0, 1.0]).unwrap();
            let frame = |lod: &mut OceanLod, n: u32| {
                let t = n as f32 * 0.05;
                let pos = Vec3::new(
                    t * 40.0,
                    [0.0, 1.7, 30.0, 900.0][(n / 7) as usize % 4],
                    -t * 7.0,
                );
                let eyes = StereoFrustum::new(
                    EyeView::looking(pos - Vec3::X * 0.03, t, -0.2, fov),
                    EyeView::looking(pos + Vec3::X * 0.03, t, -0.2, fov),
                )
                .unwrap();
                let culling = (!n.is_multiple_of(5)).then_some(&eyes);
                let s = lod
                    .update(&FrameInput {
                        viewer: eyes.centre(),
                        culling,
                        max_displacement: pad,
                    })
                    .unwrap();
                s.triangles as usize + lod.instances().len()
            };
            let mut sum = frame(&mut lod, 0);
            let ((), count) = common::count_allocations(|| {
                for n in 1..300 {
                    sum += frame(&mut lod, n);
                }
            });
            assert!(sum > 0);
            assert_eq!(
                count, 0,
                "{count} allocations in 299 frames ({preset:?}, S={size})"
            );
        }
    }
    // The counter is live (guards against a vacuous pass).
    let (v, count) = common::count_allocations(|| std::hint::black_box(vec![1u8; 10]));
    assert_eq!(v.len(), 10);
    assert!(count >= 1);
}

/// No libtest harness (`harness = false` in Cargo.toml): the counter is process-wide, and
/// libtest's main thread allocates while it waits for a test thread (its channel registers
/// a waiter), which made the count depend on timing. Here the tests run on the main thread,
/// one after another, and nothing else runs.
/// Runs this suite (`main.rs` calls it).
pub fn main() {
    crate::run("frames_do_not_allocate", frames_do_not_allocate);
}
