//! The OpenXR backend of [`FrameLoop`]: the path a Quest runs, and on the desktop whatever
//! runtime is active (Monado, SteamVR, WiVRn).
//!
//! Set-up: instance (with `XR_KHR_vulkan_enable2` and the optional extensions the runtime
//! lists) → HMD system → Vulkan through the runtime ([`vulkan`]) → session → STAGE space
//! (LOCAL when STAGE is not offered) → a 2-layer sRGB colour swapchain and, with
//! `XR_KHR_composition_layer_depth`, a 2-layer depth swapchain ([`swapchain`]) → actions
//! ([`input`]).
//!
//! A frame: events are polled and fed to the [`lifecycle`] state machine; while the session
//! runs, `xrWaitFrame`, `xrBeginFrame` and `xrLocateViews` at the predicted display time, which
//! is also the simulation time; the app renders both eyes with one multiview pass into the
//! acquired images; `xrEndFrame` with a projection layer (none when `shouldRender` is false).

pub mod input;
pub mod lifecycle;
pub mod quest;
pub mod swapchain;
pub mod vulkan;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use ash::vk;
use glam::{Quat, Vec3};
use openxr as xr;

use self::input::Input;
use self::lifecycle::{Action, Event, ExitReason, Lifecycle};
use self::quest::{Foveation, Headset, PerfLevel, RefreshGovernor};
use self::swapchain::ArraySwapchain;
use super::locomotion::{Locomotion, LocomotionSettings};
use super::{Acquired, FrameLoop, FrameState, Tweak, XrError, MAX_TWEAKS};
use crate::base::{EyeView, Fov};
use crate::lod::QualityPreset;
use crate::render::{ContextOptions, GpuContext, TargetImages, Validation};

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
        }
    }
}

/// Set (e.g. from a signal handler) to ask for a clean end of the session: the backend calls
/// `xrRequestExitSession` and leaves after STOPPING and EXITING.
pub static EXIT_SIGNAL: AtomicBool = AtomicBool::new(false);

/// How long the desktop's [`FrameLoop::begin_frame`] sleeps between polls while the session
/// is not running.
pub const IDLE_POLL: Duration = Duration::from_millis(10);

/// What [`OpenXr::poll_frame`] found.
#[derive(Clone, Copy, Debug)]
pub enum FramePoll {
    /// The next frame, begun: render it (when it should) and end it.
    Frame(FrameState),
    /// The session is not running (waiting for READY, or stopped): nothing to render yet.
    Idle,
    /// The session is over (the runtime went through EXITING).
    Done,
}

/// Standing eye height assumed when the runtime offers only LOCAL space (m above its floor).
const LOCAL_EYE_HEIGHT: f32 = 1.6;

/// What a session did, for logs and tests.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// `xrWaitFrame` calls that returned.
    pub frames_waited: u64,
    /// Frames ended with a projection layer.
    pub frames_submitted: u64,
    /// Frames the runtime did not want rendered (`shouldRender` false or poses invalid).
    pub frames_not_rendered: u64,
    /// The session states in order, `IDLE>READY>...`.
    pub states: String,
    /// Mean spacing of predicted display times (ms).
    pub mean_period_ms: f64,
    /// Median wall time between `xrWaitFrame` returns (ms).
    pub wait_p50_ms: f64,
    /// 99th percentile of the same (ms).
    pub wait_p99_ms: f64,
    /// Why the session ended (`None`: still running or set-up failed).
    pub exit: Option<ExitReason>,
    /// The runtime's name and version.
    pub runtime: String,
    /// Per-eye image size.
    pub eye_size: (u32, u32),
    /// Colour format.
    pub colour_format: String,
    /// Whether depth is submitted.
    pub depth: bool,
    /// The reference space (STAGE or LOCAL).
    pub space: String,
    /// Display refresh rate asked for, if the runtime supports choosing.
    pub refresh_rate: Option<f32>,
}

impl Summary {
    /// One line for the log: `key=value` pairs.
    pub fn line(&self) -> String {
        format!(
            "frames_waited={} frames_submitted={} frames_not_rendered={} states={} \
             mean_period_ms={:.3} wait_p50_ms={:.3} wait_p99_ms={:.3} exit={:?} eye={}x{} \
             format={} depth={} space={} refresh_hz={} runtime=\"{}\"",
            self.frames_waited,
            self.frames_submitted,
            self.frames_not_rendered,
            self.states,
            self.mean_period_ms,
            self.wait_p50_ms,
            self.wait_p99_ms,
            self.exit,
            self.eye_size.0,
            self.eye_size.1,
            self.colour_format,
            self.depth,
            self.space,
            self.refresh_rate
                .map_or("n/a".to_string(), |r| format!("{r}")),
            self.runtime
        )
    }
}

/// The frame in progress between [`FrameLoop::begin_frame`] and [`FrameLoop::end_frame`].
#[derive(Clone, Copy)]
struct Pending {
    time: xr::Time,
    views: [xr::View; 2],
    acquired: bool,
    released: bool,
}

/// Session objects, destroyed before the Vulkan device.
struct Parts {
    session: xr::Session<xr::Vulkan>,
    waiter: xr::FrameWaiter,
    stream: xr::FrameStream<xr::Vulkan>,
    space: xr::Space,
    colour: ArraySwapchain,
    depth: Option<ArraySwapchain>,
    input: Input,
    _foveation: Option<xr::FoveationProfileFB>,
}

/// Sample capacity for the frame spacing statistics.
const WAIT_SAMPLES: usize = 1 << 16;

/// An OpenXR session driving the renderer.
pub struct OpenXr {
    parts: Option<Parts>,
    ctx: Option<GpuContext>,
    instance: xr::Instance,
    lifecycle: Lifecycle,
    headset: Headset,
    exit_sent: bool,
    pending: Option<Pending>,
    extent: vk::Extent2D,
    locomotion: Locomotion,
    preset: QualityPreset,
    refresh: Option<RefreshGovernor>,
    options: OpenXrOptions,
    index: u64,
    first_time: Option<xr::Time>,
    last_time: Option<xr::Time>,
    last_wait: Option<Instant>,
    frame_started: Option<Instant>,
    last_gpu: Option<Duration>,
    waits_ms: Vec<f64>,
    period_sum: f64,
    period_count: u64,
    summary: Summary,
    event_buffer: xr::EventDataBuffer,
}

/// Why the backend could not start or stopped: a message that says what to install or check.
fn backend(msg: impl Into<String>) -> XrError {
    XrError::Backend(msg.into())
}

/// A failed call of the frame loop. Losing the runtime (crash, update, service killed) can
/// surface in any call; it gets one message.
fn call_failed(call: &str, e: xr::sys::Result) -> XrError {
    match e {
        xr::sys::Result::ERROR_INSTANCE_LOST => backend(format!(
            "the OpenXR runtime went away ({call}: XR_ERROR_INSTANCE_LOST)"
        )),
        xr::sys::Result::ERROR_SESSION_LOST => backend(format!(
            "the OpenXR session was lost ({call}: XR_ERROR_SESSION_LOST)"
        )),
        e => backend(format!("{call}: {e:?} ({e})")),
    }
}

impl OpenXr {
    /// Loads the OpenXR loader, connects to the active runtime and sets everything up for the
    /// frame loop. Every failure is an error whose message names what is missing.
    pub fn new(options: OpenXrOptions) -> Result<Self, XrError> {
        if let Some(s) = options.resolution_scale {
            if !(s.is_finite() && (0.1..=4.0).contains(&s)) {
                return Err(backend(format!(
                    "resolution scale {s}: must be in [0.1, 4]"
                )));
            }
        }
        if let Some(r) = options.max_refresh_rate {
            if !(r.is_finite() && r >= 1.0) {
                return Err(backend(format!(
                    "maximum refresh rate {r}: must be at least 1 Hz"
                )));
            }
        }
        if !(options.deck_height.is_finite() && options.deck_height.abs() <= 1000.0) {
            return Err(backend(format!(
                "deck height {}: must be within ±1000 m",
                options.deck_height
            )));
        }
        let entry = load_entry(&())?;
        let instance = create_instance(&entry, &(), false)?;
        Self::with_instance(instance, options)
    }

    /// On Android: like [`OpenXr::new`], with the loader initialised through
    /// `XR_KHR_loader_init_android` and the instance created with
    /// `XR_KHR_android_create_instance`, both from the app's Java VM and Activity.
    ///
    /// # Safety
    ///
    /// `java_vm` must be the process's `JavaVM*` and `activity` a valid JNI reference to the
    /// `android.app.Activity` that drives the session, both alive while the backend is.
    #[cfg(target_os = "android")]
    pub unsafe fn new_android(
        options: OpenXrOptions,
        java_vm: *mut std::ffi::c_void,
        activity: *mut std::ffi::c_void,
    ) -> Result<Self, XrError> {
        // SAFETY: the caller's contract.
        let platform = unsafe { xr::AndroidPlatformInfo::new(java_vm, activity) };
        let entry = load_entry(&platform)?;
        let instance = create_instance(&entry, &platform, true)?;
        Self::with_instance(instance, options)
    }

    fn with_instance(instance: xr::Instance, options: OpenXrOptions) -> Result<Self, XrError> {
        let props = instance
            .properties()
            .map_err(|e| backend(format!("xrGetInstanceProperties: {e:?} ({e})")))?;
        let runtime = format!("{} {}", props.runtime_name, props.runtime_version);
        log::info!("OpenXR runtime: {runtime}");
        let system = instance
            .system(xr::FormFactor::HEAD_MOUNTED_DISPLAY)
            .map_err(|e| match e {
                xr::sys::Result::ERROR_FORM_FACTOR_UNAVAILABLE => backend(format!(
                    "the OpenXR runtime ({runtime}) has no headset right now \
                     (XR_ERROR_FORM_FACTOR_UNAVAILABLE): connect and switch on the headset"
                )),
                e => backend(format!("xrGetSystem: {e:?} ({e})")),
            })?;
        let sys_props = instance
            .system_properties(system)
            .map_err(|e| backend(format!("xrGetSystemProperties: {e:?} ({e})")))?;
        let headset = Headset::from_system_name(&sys_props.system_name);
        let defaults = headset.defaults();
        log::info!("OpenXR system: {} ({headset:?})", sys_props.system_name);
        let scale = options
            .resolution_scale
            .unwrap_or(defaults.resolution_scale);
        let views = instance
            .enumerate_view_configuration_views(system, xr::ViewConfigurationType::PRIMARY_STEREO)
            .map_err(|e| {
                backend(format!(
                    "the runtime has no PRIMARY_STEREO view configuration: {e:?} ({e})"
                ))
            })?;
        if views.len() != 2 {
            return Err(backend(format!(
                "PRIMARY_STEREO has {} views, expected 2",
                views.len()
            )));
        }
        let extent = swapchain::eye_extent(&views[0], scale).map_err(backend)?;

        let requirements = instance
            .graphics_requirements::<xr::Vulkan>(system)
            .map_err(|e| backend(format!("xrGetVulkanGraphicsRequirements2KHR: {e:?} ({e})")))?;
        let api_version = vulkan::api_version(&requirements).map_err(backend)?;
        let factory = vulkan::RuntimeVulkan::new(&instance, system);
        let ctx = GpuContext::with_factory(
            &ContextOptions {
                validation: options.validation,
                api_version,
                ..ContextOptions::default()
            },
            &factory,
        )?;
        if !ctx.multiview {
            log::warn!("the device has no multiview; rendering both eyes in two passes");
        }
        let mut this = Self {
            parts: None,
            ctx: Some(ctx),
            instance,
            lifecycle: Lifecycle::new(),
            exit_sent: false,
            pending: None,
            extent,
            locomotion: Locomotion::new(Vec3::ZERO, LocomotionSettings::default()),
            headset,
            preset: options.preset.unwrap_or(defaults.preset),
            refresh: None,
            options,
            index: 0,
            first_time: None,
            last_time: None,
            last_wait: None,
            frame_started: None,
            last_gpu: None,
            waits_ms: Vec::with_capacity(WAIT_SAMPLES),
            period_sum: 0.0,
            period_count: 0,
            summary: Summary {
                runtime,
                eye_size: (extent.width, extent.height),
                ..Summary::default()
            },
            event_buffer: xr::EventDataBuffer::new(),
        };
        this.create_session(system)?;
        Ok(this)
    }

    fn create_session(&mut self, system: xr::SystemId) -> Result<(), XrError> {
        let ctx = self.ctx.as_ref().expect("context exists until drop");
        let exts = self.instance.exts();
        // SAFETY: the handles come from the context the runtime created for this system; the
        // queue is only used from this thread.
        let (session, waiter, stream) = unsafe {
            self.instance.create_session::<xr::Vulkan>(
                system,
                &xr::vulkan::SessionCreateInfo {
                    instance: ash::vk::Handle::as_raw(ctx.instance.handle()) as _,
                    physical_device: ash::vk::Handle::as_raw(ctx.physical) as _,
                    device: ash::vk::Handle::as_raw(ctx.device.handle()) as _,
                    queue_family_index: ctx.queue_family,
                    queue_index: 0,
                },
            )
        }
        .map_err(|e| backend(format!("xrCreateSession: {e:?} ({e})")))?;

        let spaces = session
            .enumerate_reference_spaces()
            .map_err(|e| backend(format!("xrEnumerateReferenceSpaces: {e:?} ({e})")))?;
        let (space_type, origin_height, space_name) =
            if spaces.contains(&xr::ReferenceSpaceType::STAGE) {
                (
                    xr::ReferenceSpaceType::STAGE,
                    self.options.deck_height,
                    "STAGE",
                )
            } else {
                (
                    xr::ReferenceSpaceType::LOCAL,
                    self.options.deck_height + LOCAL_EYE_HEIGHT,
                    "LOCAL",
                )
            };
        let space = session
            .create_reference_space(space_type, xr::Posef::IDENTITY)
            .map_err(|e| backend(format!("xrCreateReferenceSpace({space_name}): {e:?} ({e})")))?;
        self.locomotion = Locomotion::new(
            Vec3::new(0.0, origin_height, 0.0),
            LocomotionSettings::default(),
        );
        self.summary.space = space_name.into();

        let formats = session
            .enumerate_swapchain_formats()
            .map_err(|e| backend(format!("xrEnumerateSwapchainFormats: {e:?} ({e})")))?;
        let formats: Vec<i64> = formats.iter().map(|&f| f as i64).collect();
        let colour_format = swapchain::choose_colour_format(&formats).map_err(backend)?;
        let colour = ArraySwapchain::new(
            &session,
            colour_format,
            self.extent,
            xr::SwapchainUsageFlags::COLOR_ATTACHMENT,
        )
        .map_err(backend)?;
        let depth = if exts.khr_composition_layer_depth.is_some()
            && swapchain::offers_depth(&formats)
        {
            Some(
                ArraySwapchain::new(
                    &session,
                    crate::render::DEPTH_FORMAT,
                    self.extent,
                    xr::SwapchainUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                )
                .map_err(backend)?,
            )
        } else {
            log::info!("depth is not submitted (no XR_KHR_composition_layer_depth or D32 format)");
            None
        };
        self.summary.colour_format = format!("{colour_format:?}");
        self.summary.depth = depth.is_some();
        log::info!(
            "swapchains: {}x{} per eye, 2 layers, {colour_format:?} ({} images){}",
            self.extent.width,
            self.extent.height,
            colour.images.len(),
            if depth.is_some() {
                ", depth D32_SFLOAT submitted"
            } else {
                ""
            }
        );

        let foveation = self.set_up_foveation(&session, &colour);
        let input = Input::new(&self.instance).map_err(backend)?;
        input.attach(&session).map_err(backend)?;

        if exts.fb_display_refresh_rate.is_some() {
            match session.enumerate_display_refresh_rates() {
                Ok(rates) => {
                    self.refresh = RefreshGovernor::new(&rates, self.max_refresh_rate());
                    match &self.refresh {
                        Some(g) => {
                            log::info!("display refresh rates {rates:?}: asking for {}", g.rate());
                            if let Err(e) = session.request_display_refresh_rate(g.rate()) {
                                log::warn!("xrRequestDisplayRefreshRateFB: {e:?} ({e})");
                            }
                            self.summary.refresh_rate = Some(g.rate());
                        }
                        None => log::warn!(
                            "no display refresh rate at or under {} Hz in {rates:?}",
                            self.max_refresh_rate()
                        ),
                    }
                }
                Err(e) => log::warn!("xrEnumerateDisplayRefreshRatesFB: {e:?} ({e})"),
            }
        }
        if let Some(perf) = exts.ext_performance_settings.as_ref() {
            for (domain, level, name) in [
                (
                    xr::sys::PerfSettingsDomainEXT::CPU,
                    self.options.perf_levels.0,
                    "CPU",
                ),
                (
                    xr::sys::PerfSettingsDomainEXT::GPU,
                    self.options.perf_levels.1,
                    "GPU",
                ),
            ] {
                // SAFETY: a valid session and enum values of the extension.
                let r = unsafe {
                    (perf.perf_settings_set_performance_level)(
                        session.as_raw(),
                        domain,
                        level.raw(),
                    )
                };
                if r.into_raw() < 0 {
                    log::warn!("xrPerfSettingsSetPerformanceLevelEXT({name}): {r:?} ({r})");
                } else {
                    log::info!("{name} performance level: {level:?}");
                }
            }
        }
        self.parts = Some(Parts {
            session,
            waiter,
            stream,
            space,
            colour,
            depth,
            input,
            _foveation: foveation,
        });
        Ok(())
    }

    /// Fixed foveation on the colour swapchain, when the runtime has both extensions.
    fn set_up_foveation(
        &self,
        session: &xr::Session<xr::Vulkan>,
        colour: &ArraySwapchain,
    ) -> Option<xr::FoveationProfileFB> {
        let exts = self.instance.exts();
        let update = exts.fb_swapchain_update_state.as_ref()?;
        exts.fb_foveation.as_ref()?;
        let profile = session
            .create_foveation_profile(Some(xr::FoveationLevelProfile {
                level: self.foveation().level(),
                vertical_offset: 0.0,
                dynamic: xr::FoveationDynamicFB::DISABLED,
            }))
            .map_err(|e| log::warn!("xrCreateFoveationProfileFB: {e:?} ({e})"))
            .ok()?;
        let state = xr::sys::SwapchainStateFoveationFB {
            ty: xr::sys::SwapchainStateFoveationFB::TYPE,
            next: std::ptr::null_mut(),
            flags: xr::sys::SwapchainStateFoveationFlagsFB::EMPTY,
            profile: profile.as_raw(),
        };
        // SAFETY: a valid swapchain and a state struct of the extension that outlives the call.
        let r = unsafe {
            (update.update_swapchain)(
                colour.handle.as_raw(),
                &state as *const _ as *const xr::sys::SwapchainStateBaseHeaderFB,
            )
        };
        if r.into_raw() < 0 {
            log::warn!("xrUpdateSwapchainFB (foveation): {r:?} ({r})");
            return None;
        }
        log::info!("fixed foveation: {:?}", self.foveation());
        Some(profile)
    }

    /// The headset the runtime reports.
    pub fn headset(&self) -> Headset {
        self.headset
    }

    /// The quality preset selected now: the option or the headset's default, then whatever
    /// the controller's preset button chose. The app starts its LOD with it.
    pub fn preset(&self) -> QualityPreset {
        self.preset
    }

    /// The refresh rate cap in use: the option, or the headset's default.
    fn max_refresh_rate(&self) -> f32 {
        self.options
            .max_refresh_rate
            .unwrap_or(self.headset.defaults().max_refresh_rate)
    }

    /// The foveation level in use: the option, or the headset's default.
    fn foveation(&self) -> Foveation {
        self.options
            .foveation
            .unwrap_or(self.headset.defaults().foveation)
    }

    /// Whether the session runs (between `xrBeginSession` and `xrEndSession`): frames come.
    pub fn session_running(&self) -> bool {
        self.lifecycle.running()
    }

    /// The session summary so far.
    pub fn summary(&self) -> Summary {
        let mut s = self.summary.clone();
        let mut states = String::new();
        self.lifecycle.history_text(&mut states);
        s.states = states;
        s.mean_period_ms = if self.period_count > 0 {
            self.period_sum / self.period_count as f64 * 1e3
        } else {
            0.0
        };
        let mut w = self.waits_ms.clone();
        w.sort_by(f64::total_cmp);
        let pick = |q: f64| {
            if w.is_empty() {
                0.0
            } else {
                w[((w.len() - 1) as f64 * q).round() as usize]
            }
        };
        s.wait_p50_ms = pick(0.5);
        s.wait_p99_ms = pick(0.99);
        s
    }

    /// Asks the runtime to end the session (Ctrl-C, back button); the frame loop ends once the
    /// runtime has gone through STOPPING to EXITING.
    pub fn request_exit(&mut self) {
        if let Action::Exit(reason) = self.lifecycle.request_exit() {
            self.summary.exit = Some(reason);
        }
    }

    fn parts(&self) -> &Parts {
        self.parts.as_ref().expect("session parts exist until drop")
    }

    fn parts_mut(&mut self) -> &mut Parts {
        self.parts.as_mut().expect("session parts exist until drop")
    }

    /// Polls every queued event into the lifecycle and carries out what it says.
    fn poll_events(&mut self) -> Result<(), XrError> {
        loop {
            let event = match self.instance.poll_event(&mut self.event_buffer) {
                Ok(Some(e)) => e,
                Ok(None) => return Ok(()),
                Err(e) => return Err(call_failed("xrPollEvent", e)),
            };
            let ev = match event {
                xr::Event::SessionStateChanged(s) => {
                    log::info!("session state: {}", lifecycle::state_name(s.state()));
                    Event::State(s.state())
                }
                xr::Event::InstanceLossPending(_) => {
                    log::warn!("the OpenXR instance is about to be lost");
                    Event::InstanceLossPending
                }
                xr::Event::EventsLost(l) => {
                    log::warn!("{} OpenXR events were lost", l.lost_event_count());
                    continue;
                }
                xr::Event::InteractionProfileChanged(_) => {
                    log::info!("interaction profile changed");
                    continue;
                }
                xr::Event::ReferenceSpaceChangePending(_) => {
                    log::info!("reference space change pending (recentre)");
                    continue;
                }
                xr::Event::DisplayRefreshRateChangedFB(r) => {
                    log::info!(
                        "display refresh rate {} -> {} Hz",
                        r.from_display_refresh_rate(),
                        r.to_display_refresh_rate()
                    );
                    continue;
                }
                _ => continue,
            };
            let action = self.lifecycle.on_event(ev);
            self.apply(action)?;
        }
    }

    fn apply(&mut self, action: Action) -> Result<(), XrError> {
        match action {
            Action::None => {}
            Action::Begin => {
                self.parts()
                    .session
                    .begin(xr::ViewConfigurationType::PRIMARY_STEREO)
                    .map_err(|e| call_failed("xrBeginSession", e))?;
                log::info!("session begun");
            }
            Action::End => {
                self.parts()
                    .session
                    .end()
                    .map_err(|e| call_failed("xrEndSession", e))?;
                log::info!("session ended");
            }
            Action::Exit(reason) => {
                self.summary.exit = Some(reason);
            }
        }
        Ok(())
    }

    /// Locates both eyes in the tracking space at `time` without allocating.
    fn locate_views(&self, time: xr::Time) -> Result<Option<[xr::View; 2]>, XrError> {
        let p = self.parts();
        let info = xr::sys::ViewLocateInfo {
            ty: xr::sys::ViewLocateInfo::TYPE,
            next: std::ptr::null(),
            view_configuration_type: xr::ViewConfigurationType::PRIMARY_STEREO,
            display_time: time,
            space: p.space.as_raw(),
        };
        let mut state = xr::sys::ViewState {
            ty: xr::sys::ViewState::TYPE,
            next: std::ptr::null_mut(),
            view_state_flags: xr::ViewStateFlags::EMPTY,
        };
        let blank = xr::sys::View {
            ty: xr::sys::View::TYPE,
            next: std::ptr::null_mut(),
            pose: xr::Posef::IDENTITY,
            fov: xr::Fovf::default(),
        };
        let mut raw = [blank; 2];
        let mut count = 0;
        // SAFETY: valid session and space, and an output array of the stated capacity.
        let r = unsafe {
            (self.instance.fp().locate_views)(
                p.session.as_raw(),
                &info,
                &mut state,
                2,
                &mut count,
                raw.as_mut_ptr(),
            )
        };
        if r.into_raw() < 0 {
            return Err(call_failed("xrLocateViews", r));
        }
        let valid = xr::ViewStateFlags::ORIENTATION_VALID | xr::ViewStateFlags::POSITION_VALID;
        if count != 2 || !state.view_state_flags.contains(valid) {
            return Ok(None);
        }
        Ok(Some(raw.map(|v| xr::View {
            pose: v.pose,
            fov: v.fov,
        })))
    }

    /// Reads the controllers, moves the user and collects the tweaks of this frame.
    fn handle_input(
        &mut self,
        views: Option<&[xr::View; 2]>,
        dt: f32,
        tweaks: &mut [Option<Tweak>; MAX_TWEAKS],
    ) -> Result<(), XrError> {
        if !self.lifecycle.focused() {
            return Ok(());
        }
        let parts = self.parts.as_mut().expect("session parts exist until drop");
        let frame = match parts.input.read(&parts.session, dt) {
            Ok(f) => f,
            Err(xr::sys::Result::SESSION_NOT_FOCUSED) => return Ok(()),
            Err(e) => return Err(call_failed("xrSyncActions", e)),
        };
        if let Some(v) = views {
            let (p, q) = head_pose(v);
            if self.locomotion.update(p, q, frame.glide, frame.turn_x, dt) {
                log::debug!("snap turn: yaw {:.0}°", self.locomotion.yaw().to_degrees());
            }
        }
        let mut n = 0;
        if frame.next_preset {
            self.preset = next_preset(self.preset);
            tweaks[n] = Some(Tweak::Preset(self.preset));
            n += 1;
            let parts = self.parts.as_ref().expect("session parts exist until drop");
            parts.input.tick(&parts.session);
        }
        if frame.wind_steps != 0 {
            tweaks[n] = Some(Tweak::WindSpeed(frame.wind_steps as f32));
        }
        Ok(())
    }

    /// One step of [`FrameLoop::begin_frame`] that never waits for the session to run: polls
    /// the runtime's events, and while the session runs waits for, begins and returns the next
    /// frame. [`FramePoll::Idle`] when the session is not running (call again later: the
    /// desktop sleeps [`IDLE_POLL`], Android waits for its activity events instead);
    /// [`FramePoll::Done`] once the session is over.
    pub fn poll_frame(&mut self) -> Result<FramePoll, XrError> {
        loop {
            self.poll_events()?;
            if EXIT_SIGNAL.swap(false, Ordering::Relaxed) {
                log::info!("exit requested by signal");
                self.request_exit();
            }
            if let Some(reason) = self.summary.exit {
                log::info!("leaving: {reason:?}");
                return if reason.is_clean() {
                    Ok(FramePoll::Done)
                } else {
                    Err(backend(match reason {
                        ExitReason::SessionLost => {
                            "the OpenXR session was lost (LOSS_PENDING): the headset was \
                             disconnected or the runtime stopped it"
                        }
                        _ => "the OpenXR runtime went away (instance loss pending)",
                    }))
                };
            }
            if self.lifecycle.needs_exit_request() && !self.exit_sent {
                self.exit_sent = true;
                log::info!("requesting exit");
                if let Err(e) = self.parts().session.request_exit() {
                    log::warn!("xrRequestExitSession: {e:?} ({e})");
                }
            }
            if !self.lifecycle.running() {
                return Ok(FramePoll::Idle);
            }
            let state = match self.parts_mut().waiter.wait() {
                Ok(s) => s,
                // STOPPING raced the wait: handle the events first.
                Err(xr::sys::Result::ERROR_SESSION_NOT_RUNNING) => continue,
                Err(e) => return Err(call_failed("xrWaitFrame", e)),
            };
            let now = Instant::now();
            if let Some(last) = self.last_wait {
                if self.waits_ms.len() < WAIT_SAMPLES {
                    self.waits_ms
                        .push(now.duration_since(last).as_secs_f64() * 1e3);
                }
            }
            self.last_wait = Some(now);
            self.summary.frames_waited += 1;
            self.parts_mut()
                .stream
                .begin()
                .map_err(|e| call_failed("xrBeginFrame", e))?;
            let time = state.predicted_display_time;
            let first = *self.first_time.get_or_insert(time);
            if let Some(last) = self.last_time {
                let d = (time.as_nanos() - last.as_nanos()) as f64 * 1e-9;
                if d > 0.0 {
                    self.period_sum += d;
                    self.period_count += 1;
                }
            }
            self.last_time = Some(time);
            let period = (state.predicted_display_period.as_nanos() as f64 * 1e-9).max(1e-4);
            let located = if state.should_render {
                self.locate_views(time)?
            } else {
                None
            };
            let mut tweaks = [None; MAX_TWEAKS];
            self.handle_input(located.as_ref(), period as f32, &mut tweaks)?;
            let blank_view = xr::View {
                pose: xr::Posef::IDENTITY,
                fov: xr::Fovf {
                    angle_left: -0.7,
                    angle_right: 0.7,
                    angle_up: 0.7,
                    angle_down: -0.7,
                },
            };
            let raw_views = located.unwrap_or([blank_view; 2]);
            let views = raw_views.map(|v| {
                let (position, orientation) = self
                    .locomotion
                    .to_world(vec3(v.pose.position), quat(v.pose.orientation));
                EyeView {
                    position,
                    orientation,
                    fov: fov(v.fov),
                }
            });
            let should_render = located.is_some();
            if !should_render {
                self.summary.frames_not_rendered += 1;
            }
            self.pending = Some(Pending {
                time,
                views: raw_views,
                acquired: false,
                released: false,
            });
            self.frame_started = Some(Instant::now());
            let frame = FrameState {
                index: self.index,
                predicted_display_time: (time.as_nanos() - first.as_nanos()) as f64 * 1e-9,
                period,
                views,
                should_render,
                tweaks,
            };
            self.index += 1;
            return Ok(FramePoll::Frame(frame));
        }
    }
}

/// The quality preset after `p`, wrapping around.
pub fn next_preset(p: QualityPreset) -> QualityPreset {
    match p {
        QualityPreset::Low => QualityPreset::Medium,
        QualityPreset::Medium => QualityPreset::High,
        QualityPreset::High => QualityPreset::Ultra,
        QualityPreset::Ultra => QualityPreset::Low,
    }
}

/// The head pose: midway between the eyes, with the left eye's orientation.
fn head_pose(v: &[xr::View; 2]) -> (Vec3, Quat) {
    let p = (vec3(v[0].pose.position) + vec3(v[1].pose.position)) * 0.5;
    (p, quat(v[0].pose.orientation))
}

fn vec3(v: xr::Vector3f) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

fn quat(q: xr::Quaternionf) -> Quat {
    Quat::from_xyzw(q.x, q.y, q.z, q.w).normalize()
}

fn fov(f: xr::Fovf) -> Fov {
    Fov {
        angle_left: f.angle_left,
        angle_right: f.angle_right,
        angle_up: f.angle_up,
        angle_down: f.angle_down,
    }
}

fn load_entry(platform: &dyn xr::PlatformInfo) -> Result<xr::Entry, XrError> {
    // SAFETY: loads the system's OpenXR loader, which follows the specification.
    unsafe { xr::Entry::load(platform) }.map_err(|e| {
        backend(format!(
            "no OpenXR loader could be loaded ({e}). Install the Khronos OpenXR loader \
             (Debian/Ubuntu: apt install libopenxr-loader1) and an OpenXR runtime: Monado \
             (apt install monado-service, then start monado-service), SteamVR or WiVRn"
        ))
    })
}

fn create_instance(
    entry: &xr::Entry,
    platform: &dyn xr::PlatformInfo,
    android: bool,
) -> Result<xr::Instance, XrError> {
    let available = entry.enumerate_extensions().map_err(|e| {
        backend(format!(
            "no active OpenXR runtime ({e:?} ({e})). Install one and make it active: Monado (apt \
             install monado-service, then run monado-service), SteamVR (set it as the OpenXR \
             runtime in its settings) or WiVRn; or point XR_RUNTIME_JSON at a runtime's manifest"
        ))
    })?;
    if !available.khr_vulkan_enable2 {
        return Err(backend(
            "the active OpenXR runtime does not support XR_KHR_vulkan_enable2, which vr-ocean \
             needs to render with Vulkan (the older XR_KHR_vulkan_enable is not used)",
        ));
    }
    let mut enabled = xr::ExtensionSet::default();
    enabled.khr_vulkan_enable2 = true;
    enabled.khr_composition_layer_depth = available.khr_composition_layer_depth;
    enabled.fb_display_refresh_rate = available.fb_display_refresh_rate;
    enabled.fb_foveation = available.fb_foveation && available.fb_swapchain_update_state;
    enabled.fb_swapchain_update_state = enabled.fb_foveation;
    enabled.ext_performance_settings = available.ext_performance_settings;
    #[cfg(target_os = "android")]
    if android {
        if !available.khr_android_create_instance {
            return Err(backend(
                "the OpenXR loader lacks XR_KHR_android_create_instance (an outdated loader: \
                 ship the Khronos loader 1.0.34 or later)",
            ));
        }
        enabled.khr_android_create_instance = true;
    }
    #[cfg(not(target_os = "android"))]
    let _ = android;
    let listed: Vec<&str> = [
        (
            "XR_KHR_composition_layer_depth",
            enabled.khr_composition_layer_depth,
        ),
        (
            "XR_FB_display_refresh_rate",
            enabled.fb_display_refresh_rate,
        ),
        ("XR_FB_foveation", enabled.fb_foveation),
        (
            "XR_EXT_performance_settings",
            enabled.ext_performance_settings,
        ),
    ]
    .iter()
    .filter(|(_, on)| *on)
    .map(|(n, _)| *n)
    .collect();
    log::info!(
        "OpenXR extensions: XR_KHR_vulkan_enable2 {}",
        listed.join(" ")
    );
    let app = xr::ApplicationInfo {
        application_name: "vr-ocean",
        application_version: 1,
        engine_name: "vr-ocean",
        engine_version: 1,
        api_version: xr::Version::new(1, 0, 0),
    };
    entry
        .create_instance(&app, &enabled, &[], platform)
        .map_err(|e| match e {
            xr::sys::Result::ERROR_EXTENSION_NOT_PRESENT => backend(
                "the active OpenXR runtime refused XR_KHR_vulkan_enable2 \
                 (XR_ERROR_EXTENSION_NOT_PRESENT), which vr-ocean needs to render with Vulkan",
            ),
            xr::sys::Result::ERROR_RUNTIME_FAILURE | xr::sys::Result::ERROR_RUNTIME_UNAVAILABLE => {
                backend(format!(
                    "the OpenXR runtime failed to start ({e:?} ({e})); for Monado, is monado-service \
                     running?"
                ))
            }
            e => backend(format!("xrCreateInstance: {e:?} ({e})")),
        })
}

impl FrameLoop for OpenXr {
    fn gpu(&self) -> &GpuContext {
        self.ctx.as_ref().expect("context exists until drop")
    }

    fn targets(&self) -> TargetImages<'_> {
        let p = self.parts();
        TargetImages {
            images: &p.colour.images,
            format: p.colour.format,
            extent: self.extent,
            depth: p.depth.as_ref().map_or(&[], |d| &d.images),
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
        let parts = self.parts_mut();
        let colour = parts
            .colour
            .acquire()
            .map_err(|e| call_failed("acquiring the colour swapchain image", e))?;
        let depth = match parts.depth.as_mut() {
            Some(d) => d
                .acquire()
                .map_err(|e| call_failed("acquiring the depth swapchain image", e))?,
            None => 0,
        };
        if let Some(p) = self.pending.as_mut() {
            p.acquired = true;
        }
        Ok(Acquired { colour, depth })
    }

    fn release_image(&mut self) -> Result<(), XrError> {
        let parts = self.parts_mut();
        parts
            .colour
            .handle
            .release_image()
            .map_err(|e| call_failed("xrReleaseSwapchainImage (colour)", e))?;
        if let Some(d) = parts.depth.as_mut() {
            d.handle
                .release_image()
                .map_err(|e| call_failed("xrReleaseSwapchainImage (depth)", e))?;
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
        if let (Some(started), Some(g)) = (self.frame_started.take(), self.refresh.as_mut()) {
            // The frame costs what the slower side costs: the app's CPU work since
            // xrWaitFrame returned, or the GPU pass (Quest apps are usually GPU-bound).
            let cpu = started.elapsed().as_secs_f64();
            let gpu = self.last_gpu.map_or(0.0, |d| d.as_secs_f64());
            if let Some(rate) = g.observe(cpu.max(gpu)) {
                log::warn!("frames do not fit the budget: asking for {rate} Hz");
                self.summary.refresh_rate = Some(rate);
                if let Err(e) = self.parts().session.request_display_refresh_rate(rate) {
                    log::warn!("xrRequestDisplayRefreshRateFB: {e:?} ({e})");
                }
            }
        }
        let rendered = pending.acquired && pending.released;
        let extent = self.extent;
        let parts = self.parts.as_mut().expect("session parts exist until drop");
        let rect = xr::Rect2Di {
            offset: xr::Offset2Di { x: 0, y: 0 },
            extent: xr::Extent2Di {
                width: extent.width as i32,
                height: extent.height as i32,
            },
        };
        let result = if rendered {
            // Reversed-Z with an infinite far plane: depth 0 is infinitely far, 1 is the near
            // plane.
            let depth_info = parts.depth.as_ref().map(|d| {
                [0u32, 1].map(|layer| xr::sys::CompositionLayerDepthInfoKHR {
                    ty: xr::sys::CompositionLayerDepthInfoKHR::TYPE,
                    next: std::ptr::null(),
                    sub_image: xr::sys::SwapchainSubImage {
                        swapchain: d.handle.as_raw(),
                        image_rect: rect,
                        image_array_index: layer,
                    },
                    min_depth: 0.0,
                    max_depth: 1.0,
                    near_z: f32::INFINITY,
                    far_z: crate::render::camera::NEAR,
                })
            });
            let views = [0usize, 1].map(|i| {
                let v = xr::CompositionLayerProjectionView::new()
                    .pose(pending.views[i].pose)
                    .fov(pending.views[i].fov)
                    .sub_image(
                        xr::SwapchainSubImage::new()
                            .swapchain(&parts.colour.handle)
                            .image_array_index(i as u32)
                            .image_rect(rect),
                    );
                let mut raw = v.into_raw();
                if let Some(d) = depth_info.as_ref() {
                    raw.next = &d[i] as *const _ as *const std::ffi::c_void;
                }
                // SAFETY: `raw` came from a valid view; `next` points at a depth info that
                // lives until `end` below returns.
                unsafe { xr::CompositionLayerProjectionView::from_raw(raw) }
            });
            let layer = xr::CompositionLayerProjection::new()
                .space(&parts.space)
                .views(&views);
            parts
                .stream
                .end(pending.time, xr::EnvironmentBlendMode::OPAQUE, &[&layer])
        } else {
            parts
                .stream
                .end(pending.time, xr::EnvironmentBlendMode::OPAQUE, &[])
        };
        match result {
            Ok(()) => {}
            Err(xr::sys::Result::ERROR_SESSION_NOT_RUNNING) => return Ok(()),
            Err(e) => return Err(call_failed("xrEndFrame", e)),
        }
        if rendered {
            self.summary.frames_submitted += 1;
            if self.options.frames == Some(self.summary.frames_submitted) {
                log::info!(
                    "{} frames submitted: asking the runtime to end the session",
                    self.summary.frames_submitted
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
}

impl Drop for OpenXr {
    fn drop(&mut self) {
        if let Some(ctx) = self.ctx.as_ref() {
            ctx.wait_idle();
        }
        // The session and its swapchains go before the Vulkan device, the device before the
        // OpenXR instance (a field, dropped after this).
        self.parts = None;
        self.ctx = None;
    }
}
