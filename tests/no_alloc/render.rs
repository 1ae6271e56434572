//! The headless frame loop (simulation hand-over, LOD, uniforms, instances, staging copies,
//! recording, submission) makes no heap allocation per frame once warm; with floating bodies,
//! none beyond rapier's own (see `tests/no_alloc/physics.rs`).

use crate::common;

use common::gpu;
use vr_ocean::app::{interaction_for, DeckPlacement, FloatOptions, RunHooks};
use vr_ocean::lod::QualityPreset;
use vr_ocean::physics::{BodyCount, PHYSICS_HZ};
use vr_ocean::render::StereoMode;
use vr_ocean::xr::FrameState;

struct CountFrames {
    from: u64,
    to: u64,
    counted: Option<usize>,
}

impl RunHooks for CountFrames {
    fn frame_done(&mut self, frame: &FrameState) {
        if frame.index == self.from {
            common::set_counting(true);
        } else if frame.index == self.to {
            common::set_counting(false);
            self.counted = Some(common::allocations());
        }
    }
}

/// Steady-state frames counted.
const COUNTED: u64 = 240;

/// Most allocations rapier 0.36 makes in one step (`tests/no_alloc/physics.rs` gates it).
const RAPIER_PER_STEP: usize = 20;

fn steady_state_allocations(stereo: StereoMode, bodies: Option<usize>) -> usize {
    // A walk with turns, so the LOD tree and the instance count change every frame.
    let path = vr_ocean::xr::desktop::CameraPath::parse(
        "0 0 1.7 0 0 -5
         2 30 3 -40 120 -20
         4 -10 1.7 10 250 0",
    )
    .unwrap();
    let mut opts = gpu::small_options(stereo, Vec::new());
    // The GPU-time governor runs every frame too (a budget no lavapipe frame misses: its
    // per-frame path is counted, not a level change).
    opts.governor = vr_ocean::app::GovernorOptions {
        enabled: true,
        budget: Some(std::time::Duration::from_secs(100)),
        fault: None,
    };
    opts.floating = bodies.map(|n| FloatOptions {
        bodies: BodyCount::new(n).unwrap(),
        deck: DeckPlacement::At(2.9),
        interaction: Some(interaction_for(QualityPreset::High)),
    });
    let mut hooks = CountFrames {
        from: 40,
        to: 40 + COUNTED,
        counted: None,
    };
    gpu::render_with(&opts, path, 290, 64, 48, &mut hooks);
    hooks.counted.expect("counted")
}

fn frame_loop_allocates_nothing_per_frame() {
    // One test function: counting is process-wide.
    for stereo in [StereoMode::Multiview, StereoMode::TwoPass] {
        let n = steady_state_allocations(stereo, None);
        assert_eq!(
            n, 0,
            "{stereo:?}: {n} allocations in {COUNTED} steady-state frames"
        );
    }
    // The deck alone: the physics world steps with no body in it, the solids path draws.
    let n = steady_state_allocations(StereoMode::Multiview, Some(0));
    println!("deck, no bodies: {n} allocations in {COUNTED} frames");
    assert_eq!(
        n, 0,
        "deck only: {n} allocations in {COUNTED} steady-state frames"
    );
    // 16 bodies: what rapier allocates each step, nothing of ours (instances, solids, hands,
    // the water queries) on top.
    let n = steady_state_allocations(StereoMode::Multiview, Some(16));
    let steps = (COUNTED as f32 * PHYSICS_HZ / 72.0).ceil() as usize;
    println!(
        "16 bodies: {n} allocations in {COUNTED} frames ({steps} physics steps, {:.1} a step)",
        n as f64 / steps as f64
    );
    assert!(
        n <= RAPIER_PER_STEP * steps,
        "16 bodies: {n} allocations in {steps} steps, more than rapier's {RAPIER_PER_STEP} a step"
    );
}

/// No libtest harness (`harness = false` in Cargo.toml): the counter is process-wide, and
/// libtest's main thread allocates while it waits for a test thread (its channel registers
/// a waiter), which made the count depend on timing. Here the tests run on the main thread,
/// one after another, and nothing else runs.
/// Runs this suite (`main.rs` calls it).
pub fn main() {
    crate::run(
        "frame_loop_allocates_nothing_per_frame",
        frame_loop_allocates_nothing_per_frame,
    );
}
