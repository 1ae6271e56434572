//! Helpers for the Vulkan tests: a headless run on lavapipe with the Khronos validation layer
//! required, whose images come back to the test.
#![allow(dead_code)]

use glam::Vec3;
use vr_ocean::app::{self, Capture, RunHooks, RunOptions, RunReport};
use vr_ocean::export;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::render::{ContextOptions, RendererSettings, StereoMode, Validation};
use vr_ocean::sim::OceanConfig;
use vr_ocean::xr::desktop::{CameraPath, EyeSize, HeadlessXr};
use vr_ocean::xr::FrameState;

/// Both eyes of one captured frame.
#[derive(Clone)]
pub struct Frame {
    /// Frame number.
    pub index: u64,
    /// The state it was rendered for.
    pub state: FrameState,
    /// Per-eye size.
    pub width: u32,
    /// Per-eye size.
    pub height: u32,
    /// Left and right RGBA8 (sRGB).
    pub eyes: [Vec<u8>; 2],
}

impl Frame {
    /// RGBA of pixel (x, y) of `eye`.
    pub fn pixel(&self, eye: usize, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.eyes[eye][i..i + 4].try_into().unwrap()
    }
}

/// Hooks that keep every captured frame.
pub struct Collect(pub Vec<Frame>);

impl RunHooks for Collect {
    fn capture(&mut self, c: &Capture<'_>) -> Result<(), app::AppError> {
        self.0.push(Frame {
            index: c.frame,
            state: *c.state,
            width: c.width,
            height: c.height,
            eyes: [c.eyes[0].to_vec(), c.eyes[1].to_vec()],
        });
        Ok(())
    }
}

/// A small, fast scene: 64² grid, three cascades, Low preset, S = 1024 m.
pub fn small_options(stereo: StereoMode, capture: Vec<u64>) -> RunOptions {
    RunOptions {
        ocean: OceanConfig::default_cascades(64).unwrap(),
        threads: 1,
        lod: LodSettings::new(QualityPreset::Low, OceanSize::new(1024.0).unwrap()),
        renderer: RendererSettings {
            stereo,
            ..RendererSettings::default()
        },
        capture,
        warmup: 0,
        floating: None,
        governor: Default::default(),
        audio: Default::default(),
        panel_open: false,
        comfort: Default::default(),
    }
}

/// The validated context the tests run on.
pub fn validated() -> ContextOptions {
    ContextOptions {
        validation: Validation::Required,
        ..ContextOptions::default()
    }
}

/// Renders `frames` frames along `path` at `w`×`h` per eye with validation required; returns
/// the run's report and the captured frames. Panics on any error or validation message.
pub fn render(
    opts: &RunOptions,
    path: CameraPath,
    frames: u64,
    w: u32,
    h: u32,
) -> (RunReport, Vec<Frame>) {
    let mut hooks = Collect(Vec::new());
    let report = render_with(opts, path, frames, w, h, &mut hooks);
    (report, hooks.0)
}

/// [`render`] with the caller's hooks (captures are the hooks' business).
pub fn render_with(
    opts: &RunOptions,
    path: CameraPath,
    frames: u64,
    w: u32,
    h: u32,
    hooks: &mut dyn RunHooks,
) -> RunReport {
    render_set_up(opts, path, frames, w, h, hooks, |_| {})
}

/// [`render_with`] on a backend `set_up` prepared first (a comfort vignette, say).
pub fn render_set_up(
    opts: &RunOptions,
    path: CameraPath,
    frames: u64,
    w: u32,
    h: u32,
    hooks: &mut dyn RunHooks,
    set_up: impl FnOnce(&mut HeadlessXr),
) -> RunReport {
    let mut xr = HeadlessXr::new(&validated(), EyeSize::new(w, h).unwrap(), path, frames)
        .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    set_up(&mut xr);
    let report = app::run(&mut xr, opts, hooks).unwrap_or_else(|e| panic!("run: {e}"));
    let log = xr_validation(&xr);
    drop(xr);
    assert_eq!(
        report.validation_errors,
        0,
        "validation errors: {:?}",
        log.messages()
    );
    assert_eq!(
        log.errors(),
        0,
        "validation errors at teardown (leaked objects are errors): {:?}",
        log.messages()
    );
    report
}

fn xr_validation(xr: &HeadlessXr) -> std::sync::Arc<vr_ocean::render::ValidationLog> {
    use vr_ocean::xr::FrameLoop;
    xr.gpu()
        .validation
        .clone()
        .expect("validation layer loaded")
}

/// A head standing `height` m above the sea at the origin, looking along `yaw`/`pitch`.
pub fn standing(height: f32, yaw: f32, pitch: f32) -> CameraPath {
    CameraPath::still(Vec3::new(0.0, height, 0.0), yaw, pitch)
}

impl Frame {
    /// The image row of the horizon for `eye` (no roll, so one row across the image).
    pub fn horizon_row(&self, eye: usize) -> f32 {
        let v = &self.state.views[eye];
        let forward = v.orientation * Vec3::NEG_Z;
        let flat = Vec3::new(forward.x, 0.0, forward.z).normalize();
        vr_ocean::render::camera::project_to_pixel(
            v,
            v.position + flat * 1.0e6,
            self.width,
            self.height,
        )
        .expect("the horizon ahead is in front of the eye")
        .1
    }

    /// Writes both eyes side by side as a PNG next to the test binaries, for looking at a
    /// failure; returns its path.
    pub fn save(&self, name: &str) -> std::path::PathBuf {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut both = vec![0u8; 2 * w * h * 4];
        for y in 0..h {
            for eye in 0..2 {
                let src = &self.eyes[eye][4 * y * w..4 * (y + 1) * w];
                let at = 4 * (y * 2 * w + eye * w);
                both[at..at + 4 * w].copy_from_slice(src);
            }
        }
        let path = super::scratch_path(&format!("{name}-frame{}.png", self.index));
        export::save_png(&path, 2 * self.width, self.height, &both).unwrap();
        path
    }
}

/// [`render`] after `skip` settling frames ([`HeadlessXr::settle`], 0.1 s apart, simulated but
/// not drawn); `frames` drawn frames follow, numbered from `skip` (what `opts.capture` names).
pub fn render_after(
    opts: &RunOptions,
    path: CameraPath,
    skip: u64,
    frames: u64,
    w: u32,
    h: u32,
) -> (RunReport, Vec<Frame>) {
    let mut xr = HeadlessXr::new(&validated(), EyeSize::new(w, h).unwrap(), path, frames)
        .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"))
        .settle(skip);
    let mut hooks = Collect(Vec::new());
    let report = app::run(&mut xr, opts, &mut hooks).unwrap_or_else(|e| panic!("run: {e}"));
    let log = xr_validation(&xr);
    drop(xr);
    assert_eq!(
        report.validation_errors,
        0,
        "validation: {:?}",
        log.messages()
    );
    assert_eq!(
        log.errors(),
        0,
        "validation at teardown: {:?}",
        log.messages()
    );
    (report, hooks.0)
}

/// Headless frames, each edited by `edit` before the app sees it (a backend that injects
/// tweaks, an absence, a lost runtime); everything else is the headless backend's.
#[allow(dead_code)]
pub struct Edited<F> {
    /// The headless backend.
    pub inner: vr_ocean::xr::desktop::HeadlessXr,
    /// Changes a begun frame, or fails it.
    pub edit: F,
}

impl<F> vr_ocean::xr::FrameLoop for Edited<F>
where
    F: FnMut(&mut vr_ocean::xr::FrameState) -> Result<(), vr_ocean::xr::XrError>,
{
    fn gpu(&self) -> &vr_ocean::render::GpuContext {
        self.inner.gpu()
    }
    fn targets(&self) -> vr_ocean::render::TargetImages<'_> {
        self.inner.targets()
    }
    fn begin_frame(&mut self) -> Result<Option<vr_ocean::xr::FrameState>, vr_ocean::xr::XrError> {
        let mut state = self.inner.begin_frame()?;
        if let Some(s) = state.as_mut() {
            (self.edit)(s)?;
        }
        Ok(state)
    }
    fn acquire_image(&mut self) -> Result<vr_ocean::xr::Acquired, vr_ocean::xr::XrError> {
        self.inner.acquire_image()
    }
    fn release_image(&mut self) -> Result<(), vr_ocean::xr::XrError> {
        self.inner.release_image()
    }
    fn end_frame(&mut self, frame: &vr_ocean::xr::FrameState) -> Result<(), vr_ocean::xr::XrError> {
        self.inner.end_frame(frame)
    }
}
