//! The window mode of the desktop backend: a winit window showing both eyes side by side, head
//! pose from the keyboard and mouse ([`FlyControls`]) or a [`CameraPath`] on the real clock,
//! live tweaks of the waves and the quality preset, frame times in the title. The panel's
//! "Into the water" floats the head on the sea as a headset's float mode does
//! ([`crate::xr::locomotion::float`]; Q held ducks under), "Back on the deck" returns to the
//! start.
//!
//! The app owns the loop, so winit is pumped (`pump_app_events`, no waiting) at the start of
//! every frame. The app renders into the backend's own [`DesktopSwapchain`]; [`FrameLoop::end_frame`]
//! blits it into the window's swapchain (see `present`).
//!
//! `input`: keys ([`KEYS_HELP`]): WASD move, Q/E down/up, Shift 5× faster, mouse look while a button is
//! held; 1/2 wind speed −/+1 m/s, 3/4 wind direction −/+15°, 5/6 choppiness −/+0.1, F1-F4
//! quality preset low/medium/high/ultra; Esc or closing the window quits. `panel`: Tab opens
//! the control panel over the view and the mouse drives it. `size`: the window size the
//! user gives.

mod input;
mod panel;
mod size;

pub use input::{move_key, tweak_for_key, KEYS_HELP};
pub use size::WindowSize;

use std::time::{Duration, Instant};

use ash::vk;
use glam::{Quat, Vec3};
use winit::dpi::PhysicalSize;
use winit::event_loop::EventLoop;
use winit::platform::pump_events::{EventLoopExtPumpEvents, PumpStatus};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

use self::input::{Input, PENDING_TWEAKS};
use super::controls::{FlyControls, MoveKey};
use super::present::{Presenter, Screenshot};
use super::{eye_views, CameraPath, DesktopSwapchain};
use crate::render::{ContextOptions, GpuContext, RenderError, TargetImages};
use crate::ui::panel::Panel;
use crate::xr::locomotion::float::{Afloat, FloatSettings};
use crate::xr::locomotion::WATER_ENTRY_DISTANCE;
use crate::xr::{Acquired, FrameLoop, FrameState, XrError};

/// Display period assumed when the monitor does not report its refresh rate (60 Hz).
const DEFAULT_PERIOD: f64 = 1.0 / 60.0;

/// The control panel's image pixels per egui point in the window: 1, so its 440×560-point
/// layout is as many window pixels and its text as sharp as the desktop's own.
const PANEL_PIXELS_PER_POINT: f32 = 1.0;

/// How the window run is set up.
pub struct WindowOptions {
    /// Initial window size.
    pub size: WindowSize,
    /// Poses from this path (on the real clock) instead of the keyboard and mouse.
    pub path: Option<CameraPath>,
    /// Quit after this many frames (unattended runs and tests); `None` runs until Esc.
    pub frames: Option<u64>,
    /// Quit after this much wall-clock time (timed runs: the sound's real-time test); `None`
    /// runs until Esc or `frames`.
    pub duration: Option<Duration>,
    /// Copy the window image of the last frame (needs `frames`) to the CPU.
    pub screenshot: bool,
}

/// Why the window could not be opened.
#[derive(Debug)]
pub enum OpenError {
    /// No display, window or surface could be had (the caller may fall back to headless).
    Unavailable(String),
    /// Something else failed (Vulkan device, resources).
    Failed(XrError),
}

impl std::fmt::Display for OpenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OpenError::Unavailable(why) => write!(f, "cannot open a window: {why}"),
            OpenError::Failed(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for OpenError {}

/// The shared libraries winit opens at run time for the display in use (X11, or Wayland when
/// `wayland`) that cannot be loaded here.
fn window_libraries_missing(wayland: bool) -> Vec<&'static str> {
    let wanted: &[&'static str] = if wayland {
        &["libwayland-client.so.0", "libxkbcommon.so.0"]
    } else {
        &["libX11.so.6", "libxkbcommon-x11.so.0", "libxkbcommon.so.0"]
    };
    wanted
        .iter()
        .copied()
        .filter(|lib| !can_load(lib))
        .collect()
}

/// Whether the dynamic linker can load `lib` (then unloads it).
fn can_load(lib: &str) -> bool {
    #[cfg(unix)]
    {
        use std::ffi::{c_char, c_int, c_void, CString};
        extern "C" {
            fn dlopen(filename: *const c_char, flag: c_int) -> *mut c_void;
            fn dlclose(handle: *mut c_void) -> c_int;
        }
        const RTLD_NOW: c_int = 2;
        let Ok(name) = CString::new(lib) else {
            return false;
        };
        // SAFETY: a NUL-terminated name; the handle is closed again at once. Loading runs the
        // library's initialisers, as winit's own loading would.
        unsafe {
            let h = dlopen(name.as_ptr(), RTLD_NOW);
            if h.is_null() {
                return false;
            }
            dlclose(h);
        }
        true
    }
    #[cfg(not(unix))]
    {
        let _ = lib;
        true
    }
}

/// The window backend.
pub struct WindowXr {
    // Destroyed explicitly in `Drop` while `ctx` lives.
    presenter: Presenter,
    swapchain: DesktopSwapchain,
    ctx: GpuContext,
    events: EventLoop<()>,
    input: Input,
    path: Option<CameraPath>,
    start: Instant,
    last: Instant,
    period: f64,
    frame: u64,
    frames: Option<u64>,
    /// When a timed run ends.
    deadline: Option<Instant>,
    screenshot_wanted: bool,
    screenshot: Option<Screenshot>,
    title: String,
    /// Whether the control panel is open (shown over the view).
    panel_shown: bool,
    /// In the water (the panel's button): the head floats on the sea under it, Q ducks.
    afloat: Option<Afloat>,
    /// Ride the waves in the water (the comfort option; false: a fixed height).
    ride: bool,
    /// The sea's height under the head the app last reported (m).
    water_surface: Option<f32>,
}

impl WindowXr {
    /// Opens the window, creates the device (validation per `opts`, with the window system's
    /// surface extensions and presentation) and both swapchains.
    pub fn new(opts: &ContextOptions, options: WindowOptions) -> Result<Self, OpenError> {
        let unavailable =
            |what: &str, e: &dyn std::fmt::Display| OpenError::Unavailable(format!("{what}: {e}"));
        let has = |var: &str| std::env::var_os(var).is_some_and(|v| !v.is_empty());
        if !has("DISPLAY") && !has("WAYLAND_DISPLAY") && !has("WAYLAND_SOCKET") {
            return Err(OpenError::Unavailable(
                "no display (neither DISPLAY nor WAYLAND_DISPLAY is set)".into(),
            ));
        }
        // winit loads these at run time and panics when they are missing (a fresh minimal
        // system has a display but not them): check first, and say what to install.
        let missing = window_libraries_missing(has("WAYLAND_DISPLAY") || has("WAYLAND_SOCKET"));
        if !missing.is_empty() {
            return Err(OpenError::Unavailable(format!(
                "the window system's libraries are missing ({}): install them (Debian/Ubuntu: \
                 apt install libxkbcommon-x11-0; cargo xtask run does)",
                missing.join(", ")
            )));
        }
        let mut events = EventLoop::new().map_err(|e| unavailable("no window system", &e))?;
        let size = options.size;
        let mut input = Input {
            attributes: Window::default_attributes()
                .with_title("vr-ocean")
                .with_inner_size(PhysicalSize::new(size.extent().width, size.extent().height)),
            window: None,
            error: None,
            controls: FlyControls::new(super::START_POSITION, 0.0, super::START_PITCH),
            pending: [None; PENDING_TWEAKS],
            quit: false,
            resized: false,
            turning: false,
            cursor: None,
            panel: Default::default(),
        };
        // The window is created in `resumed`, which the platforms send at start-up.
        let deadline = Instant::now() + Duration::from_secs(5);
        while input.window.is_none() && input.error.is_none() && Instant::now() < deadline {
            if let PumpStatus::Exit(code) =
                events.pump_app_events(Some(Duration::from_millis(10)), &mut input)
            {
                return Err(OpenError::Unavailable(format!(
                    "the event loop exited ({code}) before the window opened"
                )));
            }
        }
        if let Some(e) = input.error.take() {
            return Err(OpenError::Unavailable(e));
        }
        let window = input
            .window
            .as_ref()
            .ok_or_else(|| OpenError::Unavailable("the window did not open within 5 s".into()))?;
        let display = window
            .display_handle()
            .map_err(|e| unavailable("no display handle", &e))?
            .as_raw();
        let handle = window
            .window_handle()
            .map_err(|e| unavailable("no window handle", &e))?
            .as_raw();
        let extensions = ash_window::enumerate_required_extensions(display)
            .map_err(|e| unavailable("no Vulkan surface extensions for this window system", &e))?;
        let ctx = GpuContext::new(&ContextOptions {
            instance_extensions: extensions.to_vec(),
            present: true,
            ..opts.clone()
        })
        .map_err(|e| match e {
            RenderError::Vk {
                call: "vkCreateInstance",
                result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
            } => OpenError::Unavailable(
                "the Vulkan driver cannot draw to windows (surface extensions missing)".into(),
            ),
            RenderError::Vk {
                call: "vkCreateDevice",
                result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
            } => OpenError::Unavailable(
                "the Vulkan device cannot present to windows (no VK_KHR_swapchain)".into(),
            ),
            e => OpenError::Failed(e.into()),
        })?;
        // SAFETY: the handles belong to `window`, which outlives the surface (destroyed in
        // `Drop` before the window).
        let surface =
            unsafe { ash_window::create_surface(&ctx.entry, &ctx.instance, display, handle, None) }
                .map_err(|e| unavailable("cannot create a Vulkan surface for the window", &e))?;
        let inner = window.inner_size();
        let mut presenter = Presenter::new(
            &ctx,
            surface,
            vk::Extent2D {
                width: inner.width,
                height: inner.height,
            },
        )
        .map_err(|e| match e {
            RenderError::Unsupported(_) => OpenError::Unavailable(e.to_string()),
            e => OpenError::Failed(e.into()),
        })?;
        let swapchain = match DesktopSwapchain::new(&ctx, size.eye()) {
            Ok(s) => s,
            Err(e) => {
                presenter.destroy(&ctx);
                return Err(OpenError::Failed(e.into()));
            }
        };
        let period = window
            .current_monitor()
            .and_then(|m| m.refresh_rate_millihertz())
            .filter(|&mhz| mhz >= 1000)
            .map_or(DEFAULT_PERIOD, |mhz| 1000.0 / mhz as f64);
        let now = Instant::now();
        Ok(Self {
            presenter,
            swapchain,
            ctx,
            events,
            input,
            path: options.path,
            start: now,
            last: now,
            period,
            frame: 0,
            frames: options.frames,
            deadline: options.duration.map(|d| now + d),
            screenshot_wanted: options.screenshot,
            screenshot: None,
            title: String::with_capacity(256),
            panel_shown: false,
            afloat: None,
            ride: true,
            water_surface: None,
        })
    }

    /// The window image of the last frame, when a screenshot was asked for and taken.
    pub fn take_screenshot(&mut self) -> Option<Screenshot> {
        self.screenshot.take()
    }

    /// The window's inner size in pixels (0×0 while minimised).
    fn window_extent(&self) -> vk::Extent2D {
        match &self.input.window {
            Some(w) if w.is_minimized() != Some(true) => {
                let s = w.inner_size();
                vk::Extent2D {
                    width: s.width,
                    height: s.height,
                }
            }
            _ => vk::Extent2D::default(),
        }
    }
}

impl FrameLoop for WindowXr {
    fn gpu(&self) -> &GpuContext {
        &self.ctx
    }

    fn targets(&self) -> TargetImages<'_> {
        self.swapchain.targets()
    }

    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        let timed_out = self.deadline.is_some_and(|d| Instant::now() >= d);
        if timed_out || self.frames.is_some_and(|n| self.frame >= n) {
            return Ok(None);
        }
        let before = self.window_extent();
        let visible = before.width >= 2 && before.height > 0;
        // Minimised: nothing to show, so wait for events instead of spinning.
        let timeout = if visible {
            Duration::ZERO
        } else {
            Duration::from_millis(50)
        };
        if let PumpStatus::Exit(_) = self.events.pump_app_events(Some(timeout), &mut self.input) {
            return Ok(None);
        }
        if let Some(e) = self.input.error.take() {
            return Err(XrError::Backend(e));
        }
        if self.input.quit {
            return Ok(None);
        }
        if std::mem::take(&mut self.input.resized) {
            self.presenter.invalidate();
        }
        let extent = self.window_extent();
        let now = Instant::now();
        let dt = (now - self.last).as_secs_f64();
        self.last = now;
        if self.frame > 0 && visible {
            // The display period the next frame will see: the measured frame interval,
            // smoothed, so a slow device (lavapipe) still animates in real time.
            self.period += 0.1 * (dt.clamp(1.0 / 240.0, 0.5) - self.period);
        }
        self.input.controls.update(dt.min(0.1) as f32);
        if let Some(afloat) = self.afloat.as_mut() {
            // Floating: the sea sets the head's height; Q (down) held ducks under.
            let duck = self.input.controls.held(MoveKey::Down);
            let eyes = afloat.step(self.water_surface, duck, dt.min(0.1) as f32);
            self.input.controls.position.y = eyes;
        }
        let t = (now - self.start).as_secs_f64() + self.period;
        let (position, orientation) = match &self.path {
            Some(p) => p.pose(t),
            None => self.input.controls.pose(),
        };
        // A developer's window keeps the sea moving when it loses the keyboard (not paused).
        let state = FrameState {
            should_render: extent.width >= 2 && extent.height > 0,
            tweaks: self.input.take_tweaks(),
            pointer: self.input.panel.take(),
            in_water: self.afloat.is_some(),
            ..FrameState::seen_from(self.frame, t, self.period, eye_views(position, orientation))
        };
        self.frame += 1;
        Ok(Some(state))
    }

    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        Ok(self.swapchain.acquire())
    }

    fn release_image(&mut self) -> Result<(), XrError> {
        Ok(())
    }

    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError> {
        let Some(image) = self.swapchain.take_acquired() else {
            return Ok(());
        };
        if !frame.should_render {
            return Ok(());
        }
        let last = self.frames.is_some_and(|n| frame.index + 1 == n);
        let window = self.window_extent();
        let shot = self.presenter.present(
            &self.ctx,
            self.swapchain.image(image),
            self.swapchain.extent(),
            window,
            self.panel_shown,
            self.screenshot_wanted && last,
        )?;
        if shot.is_some() {
            self.screenshot = shot;
        }
        let shown = self
            .presenter
            .panel_placement()
            .filter(|_| self.panel_shown);
        self.input.panel.shown(shown);
        Ok(())
    }

    fn panel_pixels_per_point(&self) -> Option<f32> {
        Some(PANEL_PIXELS_PER_POINT)
    }

    fn show_panel(&mut self, panel: &mut Panel) -> Result<(), XrError> {
        self.panel_shown = panel.is_open();
        if self.panel_shown {
            self.presenter.paint_panel(&self.ctx, panel)?;
        }
        Ok(())
    }

    fn report_water(&mut self, surface: f32) {
        self.water_surface = surface.is_finite().then_some(surface);
    }

    fn set_in_water(&mut self, in_water: bool) {
        let c = &mut self.input.controls;
        if in_water && self.afloat.is_none() {
            // Off the deck's edge the way the view faces, floating.
            let forward = Quat::from_rotation_y(c.yaw.to_radians()) * Vec3::NEG_Z;
            let start = super::START_POSITION;
            c.position = Vec3::new(start.x, 0.0, start.z) + forward * WATER_ENTRY_DISTANCE;
            let mut afloat = Afloat::new(FloatSettings::default(), self.ride);
            c.position.y = afloat.step(self.water_surface, false, 0.0);
            self.afloat = Some(afloat);
            log::info!("into the water");
        } else if !in_water && self.afloat.take().is_some() {
            c.position = super::START_POSITION;
            log::info!("back on the deck");
        }
    }

    fn set_comfort(&mut self, comfort: crate::ui::panel::Comfort) {
        self.ride = comfort.ride_waves;
        if let Some(a) = self.afloat.as_mut() {
            a.set_ride(comfort.ride_waves);
        }
    }

    fn show_stats(&mut self, text: &str) {
        if let Some(w) = &self.input.window {
            self.title.clear();
            self.title.push_str("vr-ocean | ");
            self.title.push_str(text);
            w.set_title(&self.title);
        }
    }
}

impl Drop for WindowXr {
    fn drop(&mut self) {
        self.ctx.wait_idle();
        self.presenter.destroy(&self.ctx);
        self.swapchain.destroy(&self.ctx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_window_libraries_are_found_before_winit_panics() {
        assert!(!can_load("libvr-ocean-no-such-library.so.9"));
        if cfg!(target_os = "linux") {
            assert!(can_load("libc.so.6"));
        }
    }
}
