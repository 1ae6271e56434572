//! The window mode of the desktop backend: a winit window showing both eyes side by side, head
//! pose from the keyboard and mouse ([`FlyControls`]) or a [`CameraPath`] on the real clock,
//! live tweaks of the waves and the quality preset, frame times in the title.
//!
//! The app owns the loop, so winit is pumped (`pump_app_events`, no waiting) at the start of
//! every frame. The app renders into the backend's own [`DesktopSwapchain`]; [`FrameLoop::end_frame`]
//! blits it into the window's swapchain (see `present`).
//!
//! Keys ([`KEYS_HELP`]): WASD move, Q/E down/up, Shift 5× faster, mouse look while a button is
//! held; 1/2 wind speed −/+1 m/s, 3/4 wind direction −/+15°, 5/6 choppiness −/+0.1, F1-F4
//! quality preset low/medium/high/ultra; Esc or closing the window quits.

use std::time::{Duration, Instant};

use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::platform::pump_events::{EventLoopExtPumpEvents, PumpStatus};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use super::controls::{FlyControls, MoveKey};
use super::present::{Presenter, Screenshot};
use super::{eye_views, CameraPath, DesktopSwapchain, EyeSize};
use crate::lod::QualityPreset;
use crate::render::{ContextOptions, GpuContext, RenderError, TargetImages};
use crate::xr::{Acquired, FrameLoop, FrameState, Tweak, XrError, MAX_TWEAKS};

/// The controls, as printed at start-up and in the README.
pub const KEYS_HELP: &str = concat!(
    "  W/A/S/D  move                  Q/E    down/up           Shift  5x faster\n",
    "  mouse    look around while a mouse button is held\n",
    "  1/2      wind speed -/+ 1 m/s  3/4    wind direction -/+ 15 deg\n",
    "  5/6      choppiness -/+ 0.1    F1-F4  quality low/medium/high/ultra\n",
    "  Esc      quit (or close the window)",
);

/// Display period assumed when the monitor does not report its refresh rate (60 Hz).
const DEFAULT_PERIOD: f64 = 1.0 / 60.0;

/// Tweaks waiting for a frame (key presses faster than frames queue here).
const PENDING_TWEAKS: usize = 16;

/// A validated window size: at least 2×1 pixels (one per eye), at most 8192 a side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowSize {
    width: u32,
    height: u32,
}

impl WindowSize {
    /// The largest side accepted.
    pub const MAX: u32 = 8192;

    /// Checks the width is in [2, 8192] and the height in [1, 8192].
    pub fn new(width: u32, height: u32) -> Result<Self, String> {
        if (2..=Self::MAX).contains(&width) && (1..=Self::MAX).contains(&height) {
            Ok(Self { width, height })
        } else {
            Err(format!(
                "window size {width}x{height}: the width must be in [2, {max}] pixels (one half \
                 per eye) and the height in [1, {max}]",
                max = Self::MAX
            ))
        }
    }

    /// Parses `WxH`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let (w, h) = s
            .split_once(['x', 'X'])
            .ok_or_else(|| format!("window size `{s}`: expected WIDTHxHEIGHT, e.g. 1600x800"))?;
        let p = |v: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|_| format!("window size `{s}`: `{v}` is not a whole number of pixels"))
        };
        Self::new(p(w)?, p(h)?)
    }

    /// The per-eye image size: half the width, the full height (capped at [`EyeSize::MAX`]).
    pub fn eye(self) -> EyeSize {
        // Both sides are in [1, EyeSize::MAX] because `new` keeps the width at least 2.
        EyeSize {
            width: (self.width / 2).min(EyeSize::MAX),
            height: self.height.min(EyeSize::MAX),
        }
    }

    /// As a Vulkan extent.
    pub fn extent(self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.width,
            height: self.height,
        }
    }
}

/// How the window run is set up.
pub struct WindowOptions {
    /// Initial window size.
    pub size: WindowSize,
    /// Poses from this path (on the real clock) instead of the keyboard and mouse.
    pub path: Option<CameraPath>,
    /// Quit after this many frames (unattended runs and tests); `None` runs until Esc.
    pub frames: Option<u64>,
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

/// The movement key a physical key drives, if any.
pub fn move_key(code: KeyCode) -> Option<MoveKey> {
    Some(match code {
        KeyCode::KeyW => MoveKey::Forward,
        KeyCode::KeyS => MoveKey::Back,
        KeyCode::KeyA => MoveKey::Left,
        KeyCode::KeyD => MoveKey::Right,
        KeyCode::KeyE => MoveKey::Up,
        KeyCode::KeyQ => MoveKey::Down,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => MoveKey::Fast,
        _ => return None,
    })
}

/// The live tweak a physical key asks for, if any (see [`KEYS_HELP`]).
pub fn tweak_for_key(code: KeyCode) -> Option<Tweak> {
    Some(match code {
        KeyCode::Digit1 => Tweak::WindSpeed(-1.0),
        KeyCode::Digit2 => Tweak::WindSpeed(1.0),
        KeyCode::Digit3 => Tweak::WindDirection(-15.0),
        KeyCode::Digit4 => Tweak::WindDirection(15.0),
        KeyCode::Digit5 => Tweak::Choppiness(-0.1),
        KeyCode::Digit6 => Tweak::Choppiness(0.1),
        KeyCode::F1 => Tweak::Preset(QualityPreset::Low),
        KeyCode::F2 => Tweak::Preset(QualityPreset::Medium),
        KeyCode::F3 => Tweak::Preset(QualityPreset::High),
        KeyCode::F4 => Tweak::Preset(QualityPreset::Ultra),
        _ => return None,
    })
}

/// winit's side: the window and what its events asked for since the last frame.
struct Input {
    attributes: winit::window::WindowAttributes,
    window: Option<Window>,
    error: Option<String>,
    controls: FlyControls,
    pending: [Option<Tweak>; PENDING_TWEAKS],
    quit: bool,
    resized: bool,
    turning: bool,
    cursor: Option<(f64, f64)>,
}

impl Input {
    fn push_tweak(&mut self, t: Tweak) {
        match self.pending.iter_mut().find(|p| p.is_none()) {
            Some(slot) => *slot = Some(t),
            None => log::warn!("too many key presses at once; {t:?} ignored"),
        }
    }

    /// Moves up to [`MAX_TWEAKS`] queued tweaks out, oldest first.
    fn take_tweaks(&mut self) -> [Option<Tweak>; MAX_TWEAKS] {
        let mut out = [None; MAX_TWEAKS];
        let n = self.pending.iter().take_while(|p| p.is_some()).count();
        let k = n.min(MAX_TWEAKS);
        out[..k].copy_from_slice(&self.pending[..k]);
        self.pending.copy_within(k.., 0);
        for p in &mut self.pending[PENDING_TWEAKS - k..] {
            *p = None;
        }
        out
    }
}

impl ApplicationHandler for Input {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() && self.error.is_none() {
            match event_loop.create_window(self.attributes.clone()) {
                Ok(w) => self.window = Some(w),
                Err(e) => self.error = Some(format!("cannot create the window: {e}")),
            }
        }
    }

    fn window_event(&mut self, _: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => self.quit = true,
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => self.resized = true,
            WindowEvent::Focused(false) => {
                self.controls.release_all();
                self.turning = false;
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let down = event.state == ElementState::Pressed;
                if let Some(k) = move_key(code) {
                    self.controls.key(k, down);
                }
                if !down {
                    return;
                }
                if code == KeyCode::Escape {
                    self.quit = true;
                } else if let Some(t) = tweak_for_key(code) {
                    // Holding a wave key repeats it; a preset switch happens once.
                    if !(event.repeat && matches!(t, Tweak::Preset(_))) {
                        self.push_tweak(t);
                    }
                }
            }
            WindowEvent::MouseInput { state, .. } => {
                self.turning = state == ElementState::Pressed;
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(prev)) = (self.turning, self.cursor) {
                    self.controls.look(now.0 - prev.0, now.1 - prev.1);
                }
                self.cursor = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            _ => {}
        }
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
    screenshot_wanted: bool,
    screenshot: Option<Screenshot>,
    acquired: Option<u32>,
    title: String,
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
        let mut events = EventLoop::new().map_err(|e| unavailable("no window system", &e))?;
        let size = options.size;
        let mut input = Input {
            attributes: Window::default_attributes()
                .with_title("vr-ocean")
                .with_inner_size(PhysicalSize::new(size.width, size.height)),
            window: None,
            error: None,
            controls: FlyControls::new(super::START_POSITION, 0.0, super::START_PITCH),
            pending: [None; PENDING_TWEAKS],
            quit: false,
            resized: false,
            turning: false,
            cursor: None,
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
            screenshot_wanted: options.screenshot,
            screenshot: None,
            acquired: None,
            title: String::with_capacity(256),
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
        if self.frames.is_some_and(|n| self.frame >= n) {
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
        let t = (now - self.start).as_secs_f64() + self.period;
        let (position, orientation) = match &self.path {
            Some(p) => p.pose(t),
            None => self.input.controls.pose(),
        };
        let state = FrameState {
            index: self.frame,
            predicted_display_time: t,
            period: self.period,
            views: eye_views(position, orientation),
            should_render: extent.width >= 2 && extent.height > 0,
            tweaks: self.input.take_tweaks(),
        };
        self.frame += 1;
        Ok(Some(state))
    }

    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        let i = self.swapchain.acquire();
        self.acquired = Some(i);
        Ok(Acquired {
            colour: i,
            depth: 0,
        })
    }

    fn release_image(&mut self) -> Result<(), XrError> {
        Ok(())
    }

    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError> {
        let Some(image) = self.acquired.take() else {
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
            self.screenshot_wanted && last,
        )?;
        if shot.is_some() {
            self.screenshot = shot;
        }
        Ok(())
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
    fn window_sizes_are_checked() {
        assert!(WindowSize::parse("0x800")
            .unwrap_err()
            .contains("[2, 8192]"));
        assert!(WindowSize::parse("1600x0").is_err());
        assert!(WindowSize::parse("1x10").is_err());
        assert!(WindowSize::parse("1600").is_err());
        assert!(WindowSize::parse("axb").is_err());
        let s = WindowSize::parse("1600x800").unwrap();
        assert_eq!(
            s.eye().extent(),
            vk::Extent2D {
                width: 800,
                height: 800
            }
        );
        assert_eq!(
            WindowSize::parse("8192x8192")
                .unwrap()
                .eye()
                .extent()
                .height,
            EyeSize::MAX
        );
    }

    #[test]
    fn keys_map_to_moves_and_tweaks() {
        assert_eq!(move_key(KeyCode::KeyW), Some(MoveKey::Forward));
        assert_eq!(move_key(KeyCode::ShiftRight), Some(MoveKey::Fast));
        assert_eq!(move_key(KeyCode::Digit1), None);
        assert_eq!(tweak_for_key(KeyCode::Digit2), Some(Tweak::WindSpeed(1.0)));
        assert_eq!(
            tweak_for_key(KeyCode::F4),
            Some(Tweak::Preset(QualityPreset::Ultra))
        );
        assert_eq!(tweak_for_key(KeyCode::KeyW), None);
    }

    #[test]
    fn queued_tweaks_leave_in_order_a_few_per_frame() {
        let mut input = Input {
            attributes: Window::default_attributes(),
            window: None,
            error: None,
            controls: FlyControls::new(glam::Vec3::Y, 0.0, 0.0),
            pending: [None; PENDING_TWEAKS],
            quit: false,
            resized: false,
            turning: false,
            cursor: None,
        };
        for i in 0..(PENDING_TWEAKS + 2) {
            input.push_tweak(Tweak::WindSpeed(i as f32));
        }
        let mut seen = Vec::new();
        loop {
            let t = input.take_tweaks();
            if t[0].is_none() {
                break;
            }
            seen.extend(t.into_iter().flatten());
        }
        let want: Vec<Tweak> = (0..PENDING_TWEAKS)
            .map(|i| Tweak::WindSpeed(i as f32))
            .collect();
        assert_eq!(seen, want);
    }
}
