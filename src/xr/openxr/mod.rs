//! The OpenXR backend of [`FrameLoop`]: the path a Quest runs, and on the desktop whatever
//! runtime is active (Monado, SteamVR, WiVRn). In the order things happen:
//!
//! - `start`: [`OpenXr::new`], everything below set up in order;
//! - `instance`: the loader, the runtime and our extensions;
//! - [`vulkan`]: `XR_KHR_vulkan_enable2`, the runtime making our Vulkan instance and device;
//! - `session`: the session, its space (STAGE, else LOCAL), the 2-layer sRGB colour swapchain
//!   and the optional depth swapchain ([`swapchain`]), the actions ([`input`]);
//! - `quest_setup`: the Quest extensions' start-up (foveation, refresh rate, performance
//!   levels; their policies in [`quest`]);
//! - `frame`: events into the [`lifecycle`] state machine, `xrWaitFrame`/`xrBeginFrame`,
//!   views located without allocating at the predicted display time (also the simulation
//!   time), the controllers;
//! - `layers`: `xrEndFrame` with the projection layer (none when the frame is not shown) and,
//!   while the control panel is open, its quad layer (`panel`, aimed at as `panel_aim` says);
//! - `stats`: frame statistics and the session [`Summary`];
//! - `exit_signal`: Ctrl-C and SIGTERM end the session cleanly.
//!
//! Every failed call is a [`CallError`] (call and result code); losing the runtime is worded in
//! one place ([`error`]).

pub mod error;
mod exit_signal;
pub mod foveation;
mod frame;
pub mod input;
mod instance;
mod layers;
pub mod lifecycle;
mod panel;
mod panel_aim;
pub mod quest;
mod quest_setup;
pub mod refresh;
mod session;
mod start;
mod stats;
pub mod swapchain;
mod threads;
pub mod vulkan;

use std::time::{Duration, Instant};

use ash::vk;
use openxr as xr;

pub use self::error::CallError;
use self::error::{backend, Call};
pub use self::exit_signal::{install_exit_signal_handler, EXIT_SIGNAL};
use self::lifecycle::{Action, Lifecycle};
use self::quest::{Foveation, Headset, PerfLevel};
use self::refresh::{FrameCost, RefreshGovernor};
use self::session::Session;
use self::stats::FrameStats;
pub use self::stats::Summary;
use super::gpu_governor::{GovernorCaps, GovernorState};
use super::locomotion::Locomotion;
use super::render_scale::RenderScales;
use super::{Acquired, FrameLoop, FrameState, XrError};
use crate::lod::QualityPreset;
use crate::render::{GpuContext, TargetImages, Validation};

/// What the OpenXR backend is started with.
#[derive(Clone, Debug)]
pub struct OpenXrOptions {
    /// Ask the runtime to end the session after this many submitted frames (tests, CI).
    pub frames: Option<u64>,
    /// Factor on the runtime's recommended per-eye size (`None`: the headset's default).
    pub resolution_scale: Option<f32>,
    /// Vulkan validation layer policy.
    pub validation: Validation,
    /// Fixed foveation level (with `XR_FB_foveation`; `None`: the headset's default).
    pub foveation: Option<Foveation>,
    /// Highest display refresh rate to ask for (Hz, with `XR_FB_display_refresh_rate`;
    /// `None`: the headset's default).
    pub max_refresh_rate: Option<f32>,
    /// CPU and GPU levels (with `XR_EXT_performance_settings`).
    pub perf_levels: (PerfLevel, PerfLevel),
    /// Height of the tracking floor above the mean sea level (m): the user stands on a deck.
    pub deck_height: f32,
    /// The quality preset the app starts with (the controller button cycles from it; `None`:
    /// the headset's default, see [`OpenXr::preset`]).
    pub preset: Option<QualityPreset>,
    /// Submit depth to the compositor (`XR_KHR_composition_layer_depth`): for runtimes whose
    /// reprojection uses it (PC runtimes' positional timewarp). Off by default: no feature on
    /// Quest uses it, and storing it costs bandwidth every frame.
    pub submit_depth: bool,
    /// Start in the water, floating off the deck's edge, instead of on the deck.
    pub in_water: bool,
}

impl Default for OpenXrOptions {
    fn default() -> Self {
        Self {
            frames: None,
            resolution_scale: None,
            validation: Validation::IfAvailable,
            foveation: None,
            max_refresh_rate: None,
            perf_levels: (PerfLevel::SustainedHigh, PerfLevel::SustainedHigh),
            deck_height: 2.9,
            preset: None,
            submit_depth: false,
            in_water: false,
        }
    }
}

/// How long the desktop's [`FrameLoop::begin_frame`] sleeps between polls while the session
/// is not running.
pub const IDLE_POLL: Duration = Duration::from_millis(10);

/// What [`OpenXr::poll_frame`] found.
// Returned by value once a frame and unpacked at once: boxing the frame would allocate a frame.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub enum FramePoll {
    /// The next frame, begun: render it (when it should) and end it.
    Frame(FrameState),
    /// The session is not running (waiting for READY, or stopped): nothing to render yet.
    Idle,
    /// The session is over (the runtime went through EXITING).
    Done,
}

/// The frame in progress between [`FrameLoop::begin_frame`] and [`FrameLoop::end_frame`].
#[derive(Clone, Copy)]
struct Pending {
    time: xr::Time,
    views: [xr::View; 2],
    acquired: bool,
    released: bool,
    /// When `xrWaitFrame` returned: the frame's CPU cost runs from here.
    started: Instant,
    /// Time blocked since then on the GPU (the slot's fence) and the compositor
    /// (`xrWaitSwapchainImage`): not the app's work.
    waited: Duration,
}

/// An OpenXR session driving the renderer.
pub struct OpenXr {
    /// Session objects; `None` only while dropping (they go before the device).
    session: Option<Session>,
    /// The Vulkan device the runtime made; `None` only while dropping.
    ctx: Option<GpuContext>,
    instance: xr::Instance,
    lifecycle: Lifecycle,
    headset: Headset,
    options: OpenXrOptions,
    /// Per-eye image size.
    extent: vk::Extent2D,
    /// The eye images' share of the runtime's recommended size (each side) and the share drawn
    /// as configured.
    scales: RenderScales,
    /// The part of each eye image drawn and shown (the GPU-time governor's render scale).
    render_rect: vk::Rect2D,
    /// The fixed foveation started with, and whether the governor raised it a level.
    foveation: (Foveation, bool),
    /// The GPU-time governor has cheaper levels left: GPU time is its to fix, not the
    /// refresh governor's (false while it is off).
    gpu_levels_left: bool,
    /// Where the tracking space sits over the water.
    locomotion: Locomotion,
    /// The sea's height under the head the app last reported (m), for floating.
    water_surface: Option<f32>,
    /// Into the water (true) or out, asked by the panel or the start options; carried out on
    /// the next frame with a located head.
    want_water: Option<bool>,
    /// The quality preset selected now.
    preset: QualityPreset,
    /// The refresh-rate governor, when the rate can be chosen.
    refresh: Option<RefreshGovernor>,
    /// The frame between begin and end.
    pending: Option<Pending>,
    /// Frames begun.
    index: u64,
    /// The GPU time of a recent pass (the app reports it).
    last_gpu: Option<Duration>,
    /// Whether `xrRequestExitSession` was sent.
    exit_sent: bool,
    /// The head's tracking state between frames (last valid eye positions).
    tracking: frame::Tracking,
    /// Which threads the runtime was told about (Android).
    threads: threads::ThreadSettings,
    stats: FrameStats,
    event_buffer: xr::EventDataBuffer,
    /// The control panel's quad layer.
    panel: panel::QuadPanel,
}

impl OpenXr {
    /// The headset the runtime reports.
    pub fn headset(&self) -> Headset {
        self.headset
    }

    /// The quality preset to start with: the option or the headset's default (the controller's
    /// preset button then asks the app for the next one, `Tweak::NextPreset`).
    pub fn preset(&self) -> QualityPreset {
        self.preset
    }

    /// Whether the session runs (between `xrBeginSession` and `xrEndSession`): frames come.
    pub fn session_running(&self) -> bool {
        self.lifecycle.running()
    }

    /// The session summary so far.
    pub fn summary(&self) -> Summary {
        Summary {
            frames_with_panel: self.panel.frames_with_quad,
            panel_images: self.panel.acquired,
            ..self.stats.summary(&self.lifecycle)
        }
    }

    /// Asks the runtime to end the session (Ctrl-C, back button); the frame loop ends once the
    /// runtime has gone through STOPPING to EXITING.
    pub fn request_exit(&mut self) {
        if let Action::Exit(reason) = self.lifecycle.request_exit() {
            self.stats.summary.exit = Some(reason);
        }
    }

    fn session(&self) -> &Session {
        self.session
            .as_ref()
            .expect("the session exists until drop")
    }

    fn session_mut(&mut self) -> &mut Session {
        self.session
            .as_mut()
            .expect("the session exists until drop")
    }

    /// Feeds the frame's cost to the refresh-rate governor and follows its steps.
    fn govern_refresh_rate(&mut self, pending: &Pending) {
        let Some(g) = self.refresh.as_mut() else {
            return;
        };
        let before = g.rate();
        // The app's own work since xrWaitFrame returned (its waits on the GPU and the
        // compositor removed) and the GPU pass (Quest apps are usually GPU-bound).
        let cost = FrameCost {
            cpu: pending
                .started
                .elapsed()
                .saturating_sub(pending.waited)
                .as_secs_f64(),
            gpu: self.last_gpu.map(|d| d.as_secs_f64()),
            gpu_levels_left: self.gpu_levels_left,
        };
        if let Some(rate) = g.observe(cost) {
            if rate < before {
                log::warn!("frames do not fit the budget: asking for {rate} Hz");
            } else {
                log::info!("frames have room for a faster display: asking for {rate} Hz");
            }
            self.stats.summary.refresh_rate = Some(rate);
            if let Err(e) = self.session().session.request_display_refresh_rate(rate) {
                log::warn!("xrRequestDisplayRefreshRateFB: {e:?} ({e})");
            }
        }
    }
}

impl FrameLoop for OpenXr {
    fn gpu(&self) -> &GpuContext {
        self.ctx.as_ref().expect("context exists until drop")
    }

    fn targets(&self) -> TargetImages<'_> {
        let s = self.session();
        TargetImages {
            images: &s.colour.images,
            format: s.colour.format,
            extent: self.extent,
            depth: s.depth.as_ref().map_or(&[], |d| &d.images),
            density_maps: &s.colour.density_maps,
        }
    }

    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        loop {
            match self.poll_frame()? {
                FramePoll::Frame(frame) => return Ok(Some(frame)),
                FramePoll::Done => return Ok(None),
                // IDLE/READY transitions come through events; do not spin.
                FramePoll::Idle => std::thread::sleep(IDLE_POLL),
            }
        }
    }

    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        let s = self.session_mut();
        let asked = Instant::now();
        let colour = s
            .colour
            .acquire()
            .call("acquiring the colour swapchain image")?;
        let depth = match s.depth.as_mut() {
            Some(d) => d.acquire().call("acquiring the depth swapchain image")?,
            None => 0,
        };
        if let Some(p) = self.pending.as_mut() {
            p.acquired = true;
            p.waited += asked.elapsed();
        }
        Ok(Acquired { colour, depth })
    }

    fn release_image(&mut self) -> Result<(), XrError> {
        let s = self.session_mut();
        s.colour
            .handle
            .release_image()
            .call("xrReleaseSwapchainImage (colour)")?;
        if let Some(d) = s.depth.as_mut() {
            d.handle
                .release_image()
                .call("xrReleaseSwapchainImage (depth)")?;
        }
        if let Some(p) = self.pending.as_mut() {
            p.released = true;
        }
        Ok(())
    }

    fn end_frame(&mut self, _frame: &FrameState) -> Result<(), XrError> {
        let Some(pending) = self.pending.take() else {
            return Err(backend("end_frame without begin_frame"));
        };
        self.govern_refresh_rate(&pending);
        let rendered = pending.acquired && pending.released;
        let area = self.render_rect;
        let session = self
            .session
            .as_mut()
            .expect("the session exists until drop");
        let quad = self.panel.layer().filter(|_| rendered);
        let with_quad = quad.is_some();
        let filter = layers::panel_filter(self.instance.exts());
        match layers::end_frame(
            session,
            pending.time,
            &pending.views,
            area,
            rendered,
            quad,
            filter,
        ) {
            Ok(()) => {}
            Err(xr::sys::Result::ERROR_SESSION_NOT_RUNNING) => return Ok(()),
            Err(e) => return Err(CallError::new("xrEndFrame", e).into()),
        }
        self.panel.frames_with_quad += u64::from(with_quad);
        if rendered {
            let submitted = &mut self.stats.summary.frames_submitted;
            *submitted += 1;
            if self.options.frames == Some(*submitted) {
                log::info!(
                    "{} frames submitted: asking the runtime to end the session",
                    submitted
                );
                self.request_exit();
            }
        }
        Ok(())
    }

    fn show_stats(&mut self, text: &str) {
        log::debug!("{text}");
    }

    fn report_gpu_time(&mut self, gpu: Duration) {
        self.last_gpu = Some(gpu);
    }

    fn hand_workers(&mut self, workers: &crate::sim::workers::WorkerThreads) {
        self.threads.hand_workers(workers);
    }

    fn report_cpu_wait(&mut self, waited: Duration) {
        if let Some(p) = self.pending.as_mut() {
            p.waited += waited;
        }
    }

    fn governor_caps(&self) -> GovernorCaps {
        let (base, _) = self.foveation;
        GovernorCaps {
            foveation: self.session().foveation.is_some() && base.higher().is_some(),
            render_rect: Some(self.scales),
            // The app's to say.
            supersampling: false,
            lod: false,
        }
    }

    fn set_foveation_boost(&mut self, boost: bool) -> bool {
        let (base, boosted) = self.foveation;
        let Some(higher) = base.higher() else {
            return false;
        };
        if boost == boosted {
            return self.session().foveation.is_some();
        }
        let level = if boost { higher } else { base };
        let session = self
            .session
            .as_mut()
            .expect("the session exists until drop");
        let applied = quest_setup::set_foveation(&self.instance, session, level);
        if applied {
            self.foveation.1 = boost;
        }
        applied
    }

    fn render_rect(&self) -> vk::Rect2D {
        self.render_rect
    }

    fn set_render_rect(&mut self, rect: vk::Rect2D) -> bool {
        self.render_rect = rect;
        true
    }

    fn report_governor(&mut self, state: GovernorState) {
        self.gpu_levels_left = !state.exhausted;
        self.stats.summary.governor = Some(state.level);
        self.stats.summary.governor_changes = state.changes;
    }

    fn haptic_tick(&mut self, hand: usize) {
        if let Some(s) = self.session.as_ref() {
            s.input.tick_hand(&s.session, hand);
        }
    }

    fn panel_pixels_per_point(&self) -> Option<f32> {
        Some(panel::PANEL_PIXELS_PER_POINT)
    }

    fn panel_draws_cursor(&self) -> bool {
        true
    }

    fn show_panel(&mut self, panel: &mut crate::ui::panel::Panel) -> Result<(), XrError> {
        self.show_quad_panel(panel)
    }

    fn panel_haptic(&mut self) {
        self.panel_tick();
    }

    fn request_quit(&mut self) -> bool {
        self.request_exit();
        true
    }

    fn set_comfort(&mut self, c: crate::ui::panel::Comfort) {
        let deck_raise = c.deck_height_m - self.options.deck_height;
        self.locomotion
            .set_comfort(c.snap_turn_deg, c.smooth_turn, c.seated, deck_raise);
        self.locomotion.set_water_comfort(c.ride_waves, c.vignette);
    }

    fn report_water(&mut self, surface: f32) {
        self.water_surface = surface.is_finite().then_some(surface);
    }

    fn set_in_water(&mut self, in_water: bool) {
        self.want_water = Some(in_water);
    }
}

impl Drop for OpenXr {
    fn drop(&mut self) {
        if let Some(ctx) = self.ctx.as_ref() {
            ctx.wait_idle();
            self.panel.destroy(ctx);
        }
        // The session and its swapchains go before the Vulkan device, the device before the
        // OpenXR instance (a field, dropped after this).
        self.session = None;
        self.ctx = None;
    }
}
