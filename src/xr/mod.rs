//! The XR frame loop: one interface ([`FrameLoop`]) and its backends. The desktop backends
//! ([`desktop`]: the window and headless) own their 2-layer "swapchain" and make head poses
//! from the keyboard and mouse or a scripted camera path; the OpenXR backend ([`openxr`]) drives the same frame loop from a
//! real runtime, with [`locomotion`] placing the tracked user over the water.
//!
//! A frame: [`FrameLoop::begin_frame`] (predicted display time and both eye views),
//! [`FrameLoop::acquire_image`], the renderer records and submits into that image,
//! [`FrameLoop::release_image`], [`FrameLoop::end_frame`].
//!
//! [`gpu_governor`] is the pure GPU-time governor the app feeds with the pass's GPU time;
//! the backends say which of its levels they can apply ([`FrameLoop::governor_caps`]).

pub mod desktop;
pub mod gpu_governor;
pub mod locomotion;
pub mod openxr;
pub mod render_scale;

use crate::base::EyeView;
use crate::lod::QualityPreset;
use crate::physics::HandInput;
use crate::render::{GpuContext, RenderError, TargetImages};
use crate::ui::panel::{Comfort, Panel, PointerEvent};

/// A live change asked for by the user (window keys); the app applies it at the frame start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tweak {
    /// Change the wind speed by this many m/s.
    WindSpeed(f32),
    /// Turn the wind by this many degrees.
    WindDirection(f32),
    /// Change the choppiness λ by this much.
    Choppiness(f32),
    /// Step the sea state by this many Beaufort forces (the wind set to the new force's
    /// middle; 0 calm to 10 storm).
    SeaState(i8),
    /// Switch to this quality preset (rebuilds the LOD and the renderer).
    Preset(QualityPreset),
    /// Switch to the preset after the user's current one, whatever set it (the kept settings,
    /// the panel, a key; not a step the GPU governor took): the controller's preset button.
    NextPreset,
    /// Throw a crate from the head along the view (the window's throw key).
    Throw,
    /// Launch a boat ahead of the head along the view, its motor holding this speed (m/s).
    LaunchBoat(f32),
    /// Move the sun: elevation and azimuth by these many degrees (time-of-day keys).
    Sun {
        /// Degrees up (negative: down).
        elevation: f32,
        /// Degrees from +x toward +z.
        azimuth: f32,
    },
}

/// Most tweaks one frame carries; later ones wait for the next frame.
pub const MAX_TWEAKS: usize = 4;

/// Most panel pointer events one frame carries (moves in a row are merged into the last).
pub const MAX_POINTER_EVENTS: usize = 8;

/// What a frame is rendered for.
#[derive(Clone, Copy, Debug)]
pub struct FrameState {
    /// Frame number from 0.
    pub index: u64,
    /// When the frame will be shown (s since the session started): the simulation time.
    pub predicted_display_time: f64,
    /// Time until the next frame's display (s).
    pub period: f64,
    /// Left and right eye.
    pub views: [EyeView; 2],
    /// False when the runtime wants the frame skipped (hidden, not focused).
    pub should_render: bool,
    /// The user is away (the session visible but not focused: the system menu, the headset
    /// taken off, another app in front; Meta's VRC.Quest.Functional.2): the world holds still
    /// (its clock, the physics, the sound), input is ignored, and the last world keeps being
    /// drawn while the runtime asks for frames.
    pub paused: bool,
    /// Live changes to apply before this frame, first to last (`None` slots are empty).
    pub tweaks: [Option<Tweak>; MAX_TWEAKS],
    /// Left and right hands (controller grip pose, squeeze, velocities) where tracked: they
    /// grab and throw the floating bodies. `None` without controllers (desktop backends).
    pub hands: [Option<HandInput>; 2],
    /// What the pointer did to the control panel since the last frame, first to last (the
    /// window's mouse and Tab key, a controller's aim ray, trigger and menu button), in panel
    /// pixels. `None` slots are empty.
    pub pointer: [Option<PointerEvent>; MAX_POINTER_EVENTS],
    /// Per hand, its aim ray where it meets the open panel: start and end in the world (the
    /// app draws them). `None` without controllers or off the panel.
    pub rays: [Option<[glam::Vec3; 2]>; 2],
    /// The user floats in the water ([`locomotion::float`]): the body makes waves.
    pub in_water: bool,
    /// The comfort vignette's strength for this frame, 0 (none) to 1 ([`locomotion`]).
    pub vignette: f32,
}

impl FrameState {
    /// A frame seen from `views`, shown at `predicted_display_time` (s) with `period` (s) to
    /// the next, numbered `index`, in which nothing else happens: drawn, not paused, no
    /// tweaks, hands, pointer events or rays, on the deck, no vignette. The desktop backends
    /// start from it and set what they have.
    pub fn seen_from(
        index: u64,
        predicted_display_time: f64,
        period: f64,
        views: [EyeView; 2],
    ) -> Self {
        Self {
            index,
            predicted_display_time,
            period,
            views,
            should_render: true,
            paused: false,
            tweaks: [None; MAX_TWEAKS],
            hands: [None; 2],
            pointer: [None; MAX_POINTER_EVENTS],
            rays: [None; 2],
            in_water: false,
            vignette: 0.0,
        }
    }
}

/// The images a frame renders into: indices into [`TargetImages::images`] and
/// [`TargetImages::depth`] (0 when the backend has no depth images).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Acquired {
    /// The colour image.
    pub colour: u32,
    /// The depth image.
    pub depth: u32,
}

/// Why the frame loop stopped with an error.
#[derive(Debug)]
pub enum XrError {
    /// The Vulkan side failed.
    Render(RenderError),
    /// A pose source or window failed, or an OpenXR runtime is missing or unusable (the
    /// message says what to install or check).
    Backend(String),
    /// An OpenXR call failed (its name and result code; losing the runtime is worded there).
    OpenXr(openxr::CallError),
    /// The runtime said the session or the instance is going away (`LOSS_PENDING`, instance
    /// loss pending): this one is over; a new instance may work once the runtime is back.
    Lost(&'static str),
}

impl XrError {
    /// Whether the session or the runtime went away (rather than something being wrong): a
    /// caller that outlives sessions may create a new instance later.
    pub fn is_lost(&self) -> bool {
        match self {
            XrError::Lost(_) => true,
            XrError::OpenXr(e) => e.runtime_lost() || e.session_lost(),
            _ => false,
        }
    }
}

impl std::fmt::Display for XrError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            XrError::Render(e) => e.fmt(f),
            XrError::Backend(e) => f.write_str(e),
            XrError::OpenXr(e) => e.fmt(f),
            XrError::Lost(e) => f.write_str(e),
        }
    }
}

impl std::error::Error for XrError {}

impl From<openxr::CallError> for XrError {
    fn from(e: openxr::CallError) -> Self {
        XrError::OpenXr(e)
    }
}

impl From<RenderError> for XrError {
    fn from(e: RenderError) -> Self {
        XrError::Render(e)
    }
}

/// The frame loop every XR backend offers.
pub trait FrameLoop {
    /// The Vulkan device the backend created (an OpenXR runtime chooses it).
    fn gpu(&self) -> &GpuContext;
    /// The 2-layer colour images frames are rendered into.
    fn targets(&self) -> TargetImages<'_>;
    /// Waits for the next frame; `None` when the session is over (window closed, path done).
    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError>;
    /// The target images to render this frame into (called only when the frame should render).
    fn acquire_image(&mut self) -> Result<Acquired, XrError>;
    /// Hands the image back; its rendering commands have been submitted.
    fn release_image(&mut self) -> Result<(), XrError>;
    /// Shows the frame (presents the window, or nothing headless).
    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError>;
    /// Shows a one-line statistics summary (the window's title); called about twice a second.
    /// Backends without a place for it ignore it.
    fn show_stats(&mut self, _text: &str) {}

    /// The GPU time of a recent frame's pass (from timestamps, a frame or two late). Backends
    /// that adapt to the frame cost (the OpenXR refresh-rate governor) use it; others ignore it.
    fn report_gpu_time(&mut self, _gpu: std::time::Duration) {}

    /// Time this frame's CPU work spent blocked on the GPU (the renderer's wait for its frame
    /// slot), reported before [`FrameLoop::end_frame`]. The refresh-rate governor removes it
    /// from the frame's CPU cost: a wait is not work.
    fn report_cpu_wait(&mut self, _waited: std::time::Duration) {}

    /// This run's simulation workers, for a backend that tells the runtime which threads are
    /// which (OpenXR's `XR_KHR_android_thread_settings`); others ignore them.
    fn hand_workers(&mut self, _workers: &crate::sim::workers::WorkerThreads) {}

    /// What the GPU-time governor ([`gpu_governor`]) may change through this backend (the
    /// levels it cannot are skipped). Default: nothing.
    fn governor_caps(&self) -> gpu_governor::GovernorCaps {
        gpu_governor::GovernorCaps::default()
    }

    /// Raises fixed foveation one level above the configured one (`boost`) or restores it.
    /// Returns whether it was applied (false: the backend cannot).
    fn set_foveation_boost(&mut self, _boost: bool) -> bool {
        false
    }

    /// Shows the eye images from `rect` (the part the renderer drew into, same field of view)
    /// from the next frame on. Returns whether the backend can (false: it keeps showing the
    /// whole image, so the renderer must draw all of it).
    fn set_render_rect(&mut self, _rect: ash::vk::Rect2D) -> bool {
        false
    }

    /// The part of each eye image shown now: what [`FrameLoop::set_render_rect`] last set, at
    /// the start the configured render scale's centred rectangle of images that leave room
    /// above it (`GovernorCaps::render_rect`). The renderer draws it. Default: the whole image.
    fn render_rect(&self) -> ash::vk::Rect2D {
        ash::vk::Rect2D {
            offset: ash::vk::Offset2D::default(),
            extent: self.targets().extent,
        }
    }

    /// The GPU-time governor's state after a change (the OpenXR summary; with levels left,
    /// the refresh governor leaves GPU time to it). Backends without a place ignore it.
    fn report_governor(&mut self, _state: gpu_governor::GovernorState) {}

    /// Plays a short haptic tick on hand `hand` (0 left, 1 right): a body was grabbed, a
    /// press landed on the panel. Backends without controllers ignore it.
    fn haptic_tick(&mut self, _hand: usize) {}

    /// Image pixels per egui point of the control panel this backend shows ([`Panel::new`]);
    /// `None` when it shows none (headless).
    fn panel_pixels_per_point(&self) -> Option<f32> {
        None
    }

    /// Whether the panel draws its own cursor (the headset's aim rays have none; the window
    /// has the mouse's).
    fn panel_draws_cursor(&self) -> bool {
        false
    }

    /// Shows `panel` with this frame (called every frame after the app updated it, before
    /// [`FrameLoop::end_frame`]): a closed panel hides it; an open one is repainted only when
    /// its [`Panel::generation`] moved since the last paint.
    fn show_panel(&mut self, _panel: &mut Panel) -> Result<(), XrError> {
        Ok(())
    }

    /// A press landed on the panel: a haptic tick on the hand that aims at it. Backends
    /// without controllers ignore it.
    fn panel_haptic(&mut self) {}

    /// The user asked to quit (the panel's button). Returns true when the backend ends the
    /// session itself (OpenXR: `xrRequestExitSession`, then [`FrameLoop::begin_frame`]
    /// returns `None` once the runtime has stopped it); false: the app stops after this frame.
    fn request_quit(&mut self) -> bool {
        false
    }

    /// The user's comfort options changed (the panel): snap-turn angle, smooth turning, deck
    /// height, seated, riding the waves, the vignette. Backends without locomotion ignore
    /// them.
    fn set_comfort(&mut self, _comfort: Comfort) {}

    /// The sea's height under the head (m over the mean level; the mean over a floating
    /// body's footprint), which the app reports each frame: a backend whose user floats rides
    /// it from the next frame on. Others ignore it.
    fn report_water(&mut self, _surface: f32) {}

    /// The user asked to go into the water (true) or back onto the deck (the panel's button).
    /// Backends without locomotion ignore it.
    fn set_in_water(&mut self, _in_water: bool) {}
}
