//! The control panel in the running app (issue 31): a headless frame loop that shows a panel
//! and aims at its widgets as the window's mouse would (pointer events in panel pixels,
//! several frames apart). Checks that a Beaufort preset reaches the simulation, a dragged sun
//! slider the sky, the spawn button the bodies (the panel's own count), that closing and
//! reopening works, that an untouched open panel is not redrawn, that Quit ends the run, and
//! that nothing raises a validation message.

use crate::common;

use common::gpu;
use vr_ocean::app::{self, DeckPlacement, FloatOptions};
use vr_ocean::physics::BodyCount;
use vr_ocean::render::{GpuContext, StereoMode, TargetImages};
use vr_ocean::ui::panel::{Panel, PointerEvent, Widgets};
use vr_ocean::ui::Beaufort;
use vr_ocean::xr::desktop::{EyeSize, HeadlessXr};
use vr_ocean::xr::{Acquired, FrameLoop, FrameState, XrError};

/// What the script does on a frame.
#[derive(Clone, Copy)]
enum Act {
    /// Aim at a point of a widget: fraction across and down its rectangle.
    Aim(fn(&Widgets) -> [f32; 4], f32, f32),
    Press,
    Release,
    Menu,
}

/// Headless frames with a panel at 1 pixel per point and a scripted pointer.
struct Pointing {
    inner: HeadlessXr,
    script: Vec<(u64, Act)>,
    widgets: Widgets,
    /// Per shown frame: (frame, panel open, generation, bodies the panel shows).
    shown: Vec<(u64, bool, u64, u32)>,
    frame: u64,
    haptics: usize,
    /// An aim ray to hand the app every frame (world space), as the headset's would.
    ray: Option<[glam::Vec3; 2]>,
}

impl FrameLoop for Pointing {
    fn gpu(&self) -> &GpuContext {
        self.inner.gpu()
    }
    fn targets(&self) -> TargetImages<'_> {
        self.inner.targets()
    }
    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        let mut state = self.inner.begin_frame()?;
        if let Some(s) = state.as_mut() {
            self.frame = s.index;
            s.rays[1] = self.ray;
            let acts = self.script.iter().filter(|(f, _)| *f == s.index);
            for ((_, act), slot) in acts.zip(s.pointer.iter_mut()) {
                *slot = Some(match *act {
                    Act::Aim(w, fx, fy) => {
                        let r = w(&self.widgets);
                        PointerEvent::Aim(Some([
                            r[0] + fx * (r[2] - r[0]),
                            r[1] + fy * (r[3] - r[1]),
                        ]))
                    }
                    Act::Press => PointerEvent::Trigger(true),
                    Act::Release => PointerEvent::Trigger(false),
                    Act::Menu => PointerEvent::Menu,
                });
            }
        }
        Ok(state)
    }
    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        self.inner.acquire_image()
    }
    fn release_image(&mut self) -> Result<(), XrError> {
        self.inner.release_image()
    }
    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError> {
        self.inner.end_frame(frame)
    }
    fn panel_pixels_per_point(&self) -> Option<f32> {
        Some(1.0)
    }
    fn show_panel(&mut self, panel: &mut Panel) -> Result<(), XrError> {
        if panel.is_open() {
            self.widgets = *panel.widgets();
        }
        let bodies = panel.shown().map_or(0, |m| m.bodies);
        self.shown
            .push((self.frame, panel.is_open(), panel.generation(), bodies));
        Ok(())
    }
    fn panel_haptic(&mut self) {
        self.haptics += 1;
    }
}

/// A click on `w`'s centre: aim, press, release on three frames from `at`.
fn click(at: u64, w: fn(&Widgets) -> [f32; 4]) -> [(u64, Act); 3] {
    [
        (at, Act::Aim(w, 0.5, 0.5)),
        (at + 1, Act::Press),
        (at + 2, Act::Release),
    ]
}

#[test]
fn the_panel_drives_the_running_app() {
    let inner = HeadlessXr::new(
        &gpu::validated(),
        EyeSize::new(64, 64).unwrap(),
        gpu::standing(4.5, 0.0, -8.0),
        200,
    )
    .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    let log = inner.gpu().validation.clone().expect("validation layer");
    let mut script = Vec::new();
    script.extend(click(3, |w| w.beaufort[8]));
    // Drag the sun height from near its left end to near its right end.
    script.extend([
        (8, Act::Aim(|w| w.sun, 0.1, 0.5)),
        (9, Act::Press),
        (10, Act::Aim(|w| w.sun, 0.5, 0.5)),
        (11, Act::Aim(|w| w.sun, 0.9, 0.5)),
        (12, Act::Release),
    ]);
    script.extend(click(14, |w| w.spawn));
    // Closed, then open again.
    script.extend([(20, Act::Menu), (24, Act::Menu)]);
    script.extend(click(70, |w| w.quit));
    let mut xr = Pointing {
        inner,
        script,
        widgets: Widgets::default(),
        shown: Vec::new(),
        frame: 0,
        haptics: 0,
        ray: None,
    };
    let mut opts = gpu::small_options(StereoMode::Multiview, Vec::new());
    opts.panel_open = true;
    opts.floating = Some(FloatOptions {
        bodies: BodyCount::new(3).unwrap(),
        deck: DeckPlacement::UnderViewer,
        interaction: None,
    });
    let sun_before = opts.renderer.sun.elevation_deg;
    let report = app::run(&mut xr, &opts, &mut app::NoHooks).expect("run with the panel");
    let shown = std::mem::take(&mut xr.shown);
    let haptics = xr.haptics;
    drop(xr);
    assert_eq!(log.errors(), 0, "validation errors: {:?}", log.messages());

    // Quit (released on frame 72) ends the session after that frame, not at 200.
    assert_eq!(report.frames, 73, "frames run");
    // Beaufort 8 reached the simulation; the sun went up with the drag.
    let b8 = Beaufort::new(8).unwrap().wind_speed();
    assert_eq!(report.chosen.waves.wind_speed, b8);
    let sun = report.chosen.sun.elevation_deg;
    println!("sun height {sun_before:.0}° -> {sun:.0}°");
    assert!(sun > sun_before + 30.0, "{sun_before} -> {sun}");
    // Every press that landed ticked: Beaufort, sun, spawn, quit.
    assert_eq!(haptics, 4);

    // The spawn button (released on frame 16) dropped a crate: the panel counts it.
    let bodies = |f: u64| shown.iter().find(|s| s.0 == f).map(|s| s.3).unwrap();
    assert_eq!((bodies(14), bodies(19)), (3, 4));
    // Closed from frame 20 to 23, open again from 24.
    let open = |f: u64| shown.iter().find(|s| s.0 == f).map(|s| s.1);
    assert_eq!(open(19), Some(true));
    assert_eq!((open(20), open(23)), (Some(false), Some(false)));
    assert_eq!(open(24), Some(true));
    // Redrawn only when something changed: none in a quiet stretch (frames 40-69: no input,
    // and the performance line is taken once a second of the 72 Hz clock, at frame 72).
    let generation = |f: u64| shown.iter().find(|s| s.0 == f).map(|s| s.2).unwrap();
    let redraws: Vec<u64> = shown
        .windows(2)
        .filter(|w| w[1].2 != w[0].2)
        .map(|w| w[1].0)
        .collect();
    println!("redrawn on frames {redraws:?}");
    assert_eq!(generation(40), generation(69), "redrawn on {redraws:?}");
    assert!(redraws.len() < 40, "redrawn on {redraws:?}");
}

/// The headset's aim ray, drawn by the app as a thin glowing solid where the backend says it
/// meets the panel: the frame with it differs from the one without along the ray, brighter.
/// Writes `target/aim-ray.png`.
#[test]
fn aim_rays_are_drawn_as_thin_bright_lines() {
    const W: u32 = 256;
    let run = |ray: Option<[glam::Vec3; 2]>| {
        let inner = HeadlessXr::new(
            &gpu::validated(),
            EyeSize::new(W, W).unwrap(),
            gpu::standing(4.5, 0.0, -8.0),
            4,
        )
        .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
        let log = inner.gpu().validation.clone().expect("validation layer");
        let mut xr = Pointing {
            inner,
            script: Vec::new(),
            widgets: Widgets::default(),
            shown: Vec::new(),
            frame: 0,
            haptics: 0,
            ray,
        };
        let mut opts = gpu::small_options(StereoMode::Multiview, vec![3]);
        opts.floating = Some(FloatOptions {
            // Bodies, so one box is wholly on screen: lavapipe 22.3's multiview draws a draw
            // whose every instance is clipped into the first view only (Mesa's draw module,
            // fixed in 23.0.4; docs/notes/lavapipe-multiview-solids.md).
            bodies: BodyCount::new(3).unwrap(),
            deck: DeckPlacement::UnderViewer,
            interaction: None,
        });
        let mut frames = gpu::Collect(Vec::new());
        app::run(&mut xr, &opts, &mut frames).expect("run");
        drop(xr);
        assert_eq!(log.errors(), 0, "validation errors: {:?}", log.messages());
        frames.0.pop().expect("one capture")
    };
    // From a hand low and to the right, 10 cm ahead, to a panel 60 cm ahead.
    let ray = [
        glam::Vec3::new(0.08, 4.3, -0.1),
        glam::Vec3::new(0.0, 4.38, -0.6),
    ];
    let (plain, with) = (run(None), run(Some(ray)));
    let luma = |p: [u8; 4]| 0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32;
    let counts = [0, 1].map(|eye| {
        let (mut brighter, mut darker) = (0, 0);
        for y in 0..W {
            for x in 0..W {
                let d = luma(with.pixel(eye, x, y)) - luma(plain.pixel(eye, x, y));
                if d > 30.0 {
                    brighter += 1;
                } else if d < -30.0 {
                    darker += 1;
                }
            }
        }
        (brighter, darker)
    });
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .join("aim-ray.png");
    image::save_buffer(&out, &with.eyes[0], W, W, image::ColorType::Rgba8).unwrap();
    println!(
        "ray: (brighter, darker) pixels per eye {counts:?} ({})",
        out.display()
    );
    for (eye, (brighter, darker)) in counts.into_iter().enumerate() {
        assert!(brighter > 80, "eye {eye}: {brighter} pixels brighter");
        assert!(darker < brighter / 4, "eye {eye}: {darker} pixels darker");
    }
}
