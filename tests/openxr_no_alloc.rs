//! The OpenXR frame loop (events, xrWaitFrame/xrBeginFrame, view location, input, swapchain
//! acquire/release, xrEndFrame with the projection and depth layers) plus the simulation
//! hand-over, LOD and rendering makes no Rust heap allocation per frame once warm, against a
//! real runtime (Monado).
//!
//! One binary, two roles: run by the test harness it starts Monado in the trixie root and runs
//! itself inside the root as the client (`VR_OCEAN_NO_ALLOC_CLIENT`), which counts allocations
//! with the counting allocator between frames 40 and 120. Like the `#[ignore]`d tests of
//! `openxr_monado`, it runs only when asked with `--ignored` (the `openxr (Monado)` step of
//! `cargo xtask test`): it needs root and `VR_OCEAN_MONADO_ROOT`.

mod common;

use std::time::Duration;

use common::gpu;
use common::monado::{self, Monado};
use vr_ocean::app::{self, RunHooks};
use vr_ocean::render::{StereoMode, Validation};
use vr_ocean::xr::openxr::{OpenXr, OpenXrOptions};
use vr_ocean::xr::FrameState;

#[global_allocator]
static GLOBAL: common::Counting = common::Counting;

const NAME: &str = "openxr_frame_loop_allocates_nothing_per_frame";
const CLIENT_ENV: &str = "VR_OCEAN_NO_ALLOC_CLIENT";
/// Set for the client run with the control panel open.
const PANEL_ENV: &str = "VR_OCEAN_NO_ALLOC_PANEL";
/// Set for the client run floating in the water (issue 45), bodies and their waves on.
const FLOAT_ENV: &str = "VR_OCEAN_NO_ALLOC_FLOAT";
const FROM: u64 = 40;
const TO: u64 = 120;

struct CountFrames {
    counted: Option<usize>,
    /// Allocations so far at the last frame's end, and on frames the panel was redrawn.
    last: usize,
    on_redraws: usize,
    redraws: u64,
    /// The panel drew a new image during the frame now running.
    drawn: bool,
}

impl RunHooks for CountFrames {
    fn frame_done(&mut self, frame: &FrameState) {
        if (FROM + 1..=TO).contains(&frame.index) {
            let now = common::allocations();
            if std::mem::take(&mut self.drawn) {
                self.on_redraws += now - self.last;
                self.redraws += 1;
            }
            self.last = now;
        }
        self.drawn = false;
        if frame.index == FROM {
            common::set_counting(true);
        } else if frame.index == TO {
            common::set_counting(false);
            self.counted = Some(common::allocations());
        }
    }

    fn panel_drawn(&mut self, _frame: &FrameState) {
        self.drawn = true;
    }
}

/// Inside the root: a session of `TO + 10` frames, counting allocations in between.
fn client() {
    let float = std::env::var_os(FLOAT_ENV).is_some();
    let mut xr = OpenXr::new(OpenXrOptions {
        frames: Some(TO + 10),
        validation: Validation::Off,
        // The depth swapchain's acquire/release and layer chain are counted too.
        submit_depth: true,
        in_water: float,
        ..OpenXrOptions::default()
    })
    .unwrap_or_else(|e| panic!("OpenXR set-up: {e}"));
    let mut opts = gpu::small_options(StereoMode::Multiview, Vec::new());
    // Submitted depth is single-sample.
    opts.renderer.msaa = vr_ocean::render::Msaa::X1;
    // The GPU-time governor is on in the OpenXR path; a budget nothing misses counts its
    // per-frame path without a level change.
    opts.governor = vr_ocean::app::GovernorOptions {
        enabled: true,
        budget: Some(std::time::Duration::from_secs(100)),
        fault: None,
    };
    // With the panel open, egui runs (and allocates) only on frames where the panel changed.
    let panel = std::env::var_os(PANEL_ENV).is_some();
    opts.panel_open = panel;
    if float {
        // The deck and the interaction layer the user's body makes waves in. No bodies:
        // rapier 0.36 allocates in every step with bodies in it (`physics_no_alloc.rs` pins
        // that separately); without them any allocation here is the float mode's or ours.
        opts.floating = Some(vr_ocean::app::floating::FloatOptions {
            bodies: vr_ocean::physics::BodyCount::new(0).expect("zero bodies"),
            deck: vr_ocean::app::floating::DeckPlacement::At(2.9),
            interaction: Some(vr_ocean::app::floating::interaction_for(
                vr_ocean::lod::QualityPreset::Low,
            )),
        });
    }
    let mut hooks = CountFrames {
        counted: None,
        last: 0,
        on_redraws: 0,
        redraws: 0,
        drawn: false,
    };
    let report = app::run(&mut xr, &opts, &mut hooks).unwrap_or_else(|e| panic!("run: {e}"));
    let summary = xr.summary();
    drop(xr);
    let n = hooks
        .counted
        .unwrap_or_else(|| panic!("only {} frames ran", report.frames));
    let quiet = n - hooks.on_redraws;
    if panel {
        println!(
            "panel open: allocations in {} steady-state OpenXR frames: {quiet} outside the \
             {} frames the panel was redrawn (those: {}; panel images {}, frames with the \
             quad {})",
            TO - FROM,
            hooks.redraws,
            hooks.on_redraws,
            summary.panel_images,
            summary.frames_with_panel
        );
        let few = hooks.redraws * 10 <= TO - FROM;
        std::process::exit(if quiet == 0 && few && summary.frames_with_panel > TO {
            0
        } else {
            1
        });
    }
    if float {
        println!(
            "in the water: allocations in {} steady-state OpenXR frames: {n} ({} frames \
             afloat)",
            TO - FROM,
            summary.afloat.frames
        );
        std::process::exit(if n == 0 && summary.afloat.frames > TO {
            0
        } else {
            1
        });
    }
    println!(
        "allocations in {} steady-state OpenXR frames: {n} (states {})",
        TO - FROM,
        summary.states
    );
    std::process::exit(if n == 0 { 0 } else { 1 });
}

fn openxr_frame_loop_allocates_nothing_per_frame() {
    let root = monado::root_from_env();
    let service = Monado::start(&root, "noalloc");
    let exe = std::env::current_exe().expect("own path");
    let run = service.client(
        &exe,
        &[],
        &[(CLIENT_ENV, "1"), ("RUST_LOG", "warn")],
        Duration::from_secs(300),
    );
    let _ = service.finish();
    assert!(
        run.stdout.contains(&format!(
            "allocations in {} steady-state OpenXR frames: 0 ",
            TO - FROM
        )),
        "{run}"
    );
    assert!(run.success(), "{run}");
    // The same with the control panel open: its quad layer every frame, egui only when it
    // changed.
    let service = Monado::start(&root, "noalloc-panel");
    let run = service.client(
        &exe,
        &[],
        &[(CLIENT_ENV, "1"), (PANEL_ENV, "1"), ("RUST_LOG", "warn")],
        Duration::from_secs(300),
    );
    let _ = service.finish();
    println!("{}", run.stdout.trim_end());
    assert!(
        run.stdout.contains(&format!(
            "panel open: allocations in {} steady-state OpenXR frames: 0 outside",
            TO - FROM
        )),
        "{run}"
    );
    assert!(run.success(), "{run}");
    // Floating in the water: the ride, the swim and the body's waves every frame.
    let service = Monado::start(&root, "noalloc-float");
    let run = service.client(
        &exe,
        &[],
        &[(CLIENT_ENV, "1"), (FLOAT_ENV, "1"), ("RUST_LOG", "warn")],
        Duration::from_secs(300),
    );
    let _ = service.finish();
    println!("{}", run.stdout.trim_end());
    assert!(
        run.stdout.contains(&format!(
            "in the water: allocations in {} steady-state OpenXR frames: 0 ",
            TO - FROM
        )),
        "{run}"
    );
    assert!(run.success(), "{run}");
}

/// No libtest harness (`harness = false`): the counter is process-wide (see
/// `render_no_alloc.rs`).
fn main() {
    if std::env::var_os(CLIENT_ENV).is_some() {
        client();
        return;
    }
    let asked = std::env::args().any(|a| a == "--ignored" || a == "--include-ignored");
    print!("test {NAME} ... ");
    if !asked {
        println!("ignored, needs root and the Monado root (the `openxr (Monado)` step)");
        return;
    }
    openxr_frame_loop_allocates_nothing_per_frame();
    println!("ok");
}
