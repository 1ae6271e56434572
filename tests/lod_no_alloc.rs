//! The LOD's steady state allocates nothing: a counting global allocator watches frames with
//! the viewer moving, turning and changing height (so the tree, ring level, visible set and
//! batches all change) after one warm-up frame.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::Vec3;

use vr_ocean::lod::{
    EyeView, Fov, FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset,
    StereoFrustum,
};

struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as ours.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
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
            ALLOCATIONS.store(0, Ordering::SeqCst);
            COUNTING.store(true, Ordering::SeqCst);
            for n in 1..300 {
                sum += frame(&mut lod, n);
            }
            COUNTING.store(false, Ordering::SeqCst);
            let count = ALLOCATIONS.load(Ordering::SeqCst);
            assert!(sum > 0);
            assert_eq!(
                count, 0,
                "{count} allocations in 299 frames ({preset:?}, S={size})"
            );
        }
    }
    // The counter is live (guards against a vacuous pass).
    COUNTING.store(true, Ordering::SeqCst);
    let v = std::hint::black_box(vec![1u8; 10]);
    COUNTING.store(false, Ordering::SeqCst);
    assert_eq!(v.len(), 10);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) >= 1);
}
