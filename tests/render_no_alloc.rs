//! The headless frame loop (simulation hand-over, LOD, uniforms, instances, staging copies,
//! recording, submission) makes no heap allocation per frame once warm.

mod common;

use common::gpu;
use vr_ocean::app::RunHooks;
use vr_ocean::render::StereoMode;
use vr_ocean::xr::FrameState;

#[global_allocator]
static GLOBAL: common::Counting = common::Counting;

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

fn steady_state_allocations(stereo: StereoMode) -> usize {
    // A walk with turns, so the LOD tree and the instance count change every frame.
    let path = vr_ocean::xr::desktop::CameraPath::parse(
        "0 0 1.7 0 0 -5
         2 30 3 -40 120 -20
         4 -10 1.7 10 250 0",
    )
    .unwrap();
    let opts = gpu::small_options(stereo, Vec::new());
    let mut hooks = CountFrames {
        from: 40,
        to: 280,
        counted: None,
    };
    gpu::render_with(&opts, path, 290, 64, 48, &mut hooks);
    hooks.counted.expect("counted")
}

fn frame_loop_allocates_nothing_per_frame() {
    // One test function: counting is process-wide.
    for stereo in [StereoMode::Multiview, StereoMode::TwoPass] {
        let n = steady_state_allocations(stereo);
        assert_eq!(
            n, 0,
            "{stereo:?}: {n} allocations in 240 steady-state frames"
        );
    }
}

/// No libtest harness (`harness = false` in Cargo.toml): the counter is process-wide, and
/// libtest's main thread allocates while it waits for a test thread (its channel registers
/// a waiter), which made the count depend on timing. Here the tests run on the main thread,
/// one after another, and nothing else runs.
fn main() {
    run(
        "frame_loop_allocates_nothing_per_frame",
        frame_loop_allocates_nothing_per_frame,
    );
}

fn run(name: &str, test: fn()) {
    print!("test {name} ... ");
    test();
    println!("ok");
}
