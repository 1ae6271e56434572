//! The desktop XR backend: a [`FrameLoop`] without a headset. It creates the Vulkan device itself,
//! owns a 3-image 2-layer "swapchain", and makes both eye views from a head pose (63 mm IPD,
//! Quest-3-like asymmetric FOVs) taken from a scripted [`CameraPath`] or, in a window, from the
//! keyboard and mouse ([`controls`]). Headless it runs on a fixed 72 Hz clock, so the same path
//! gives the same frames on any machine.

pub mod controls;
pub mod path;
#[cfg(not(target_os = "android"))]
mod present;
#[cfg(not(target_os = "android"))]
pub mod window;

use ash::vk;
use glam::{Quat, Vec3};

use super::gpu_governor::GovernorCaps;
use super::render_scale::{scaled_rect, RenderScales};
use super::{Acquired, FrameLoop, FrameState, Tweak, XrError, MAX_TWEAKS};
use crate::base::{EyeView, Fov};
use crate::render::memory::{Image, ImageDesc};
use crate::render::{ContextOptions, GpuContext, RenderError, TargetImages};
pub use path::{CameraPath, PathError};

/// Where a session without a path starts: a standing head (1.7 m) on a deck 2.8 m above the
/// mean sea level, so crests of a 10-15 m/s sea (up to about 2-3 m) stay below the eyes.
pub const START_POSITION: glam::Vec3 = glam::Vec3::new(0.0, 4.5, 0.0);

/// The starting pitch (degrees): slightly down, the horizon in the upper third of the view.
pub const START_PITCH: f32 = -8.0;

/// Inter-pupillary distance (m).
pub const IPD: f32 = 0.063;

/// Images in the desktop swapchain.
pub const SWAPCHAIN_IMAGES: usize = 3;

/// The colour format of the desktop swapchain (what a Quest runtime offers first).
pub const COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Display period of the fixed clock (s): 72 Hz, the Quest default.
pub const PERIOD: f64 = 1.0 / 72.0;

/// Both eyes for a head at `position` with `orientation`: each eye IPD/2 to its side, the
/// Quest-3-like FOVs of [`Fov::QUEST_EYES`].
pub fn eye_views(position: Vec3, orientation: Quat) -> [EyeView; 2] {
    let side = orientation * Vec3::X * (IPD / 2.0);
    [
        EyeView {
            position: position - side,
            orientation,
            fov: Fov::QUEST_EYES[0],
        },
        EyeView {
            position: position + side,
            orientation,
            fov: Fov::QUEST_EYES[1],
        },
    ]
}

/// Validated per-eye image size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EyeSize {
    width: u32,
    height: u32,
}

impl EyeSize {
    /// The largest side accepted (the Vulkan 1.1 minimum of maxImageDimension2D).
    pub const MAX: u32 = 4096;

    /// Checks both sides are in [1, 4096].
    pub fn new(width: u32, height: u32) -> Result<Self, String> {
        if (1..=Self::MAX).contains(&width) && (1..=Self::MAX).contains(&height) {
            Ok(Self { width, height })
        } else {
            Err(format!(
                "eye size {width}x{height}: each side must be in [1, {}] pixels",
                Self::MAX
            ))
        }
    }

    /// Parses `WxH`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let (w, h) = s
            .split_once(['x', 'X'])
            .ok_or_else(|| format!("size `{s}`: expected WIDTHxHEIGHT, e.g. 640x480"))?;
        let p = |v: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|_| format!("size `{s}`: `{v}` is not a whole number of pixels"))
        };
        Self::new(p(w)?, p(h)?)
    }

    /// As a Vulkan extent.
    pub fn extent(self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.width,
            height: self.height,
        }
    }
}

/// Where head poses come from.
pub enum PoseSource {
    /// A scripted path on the fixed clock.
    Path(CameraPath),
    /// Keyboard and mouse (window mode).
    Controls(controls::FlyControls),
}

/// The 3-image, 2-layer colour "swapchain" the desktop backends render into.
pub struct DesktopSwapchain {
    images: Vec<Image>,
    raw: Vec<vk::Image>,
    extent: vk::Extent2D,
    next: u32,
    /// The image acquired for the frame being drawn, until it is shown or read.
    acquired: Option<u32>,
}

impl DesktopSwapchain {
    /// Creates the images (colour attachment, transfer source for read-back and blits).
    /// Nothing is left behind when one fails.
    pub fn new(ctx: &GpuContext, size: EyeSize) -> Result<Self, RenderError> {
        let extent = size.extent();
        let mut this = Self {
            images: Vec::with_capacity(SWAPCHAIN_IMAGES),
            raw: Vec::with_capacity(SWAPCHAIN_IMAGES),
            extent,
            next: 0,
            acquired: None,
        };
        let desc = ImageDesc {
            format: COLOUR_FORMAT,
            extent,
            layers: 2,
            mips: 1,
            samples: vk::SampleCountFlags::TYPE_1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
            transient: false,
        };
        for _ in 0..SWAPCHAIN_IMAGES {
            match Image::new(ctx, desc) {
                Ok(image) => {
                    this.raw.push(image.raw);
                    this.images.push(image);
                }
                Err(e) => {
                    this.destroy(ctx);
                    return Err(e);
                }
            }
        }
        Ok(this)
    }

    /// The images, as the renderer takes them.
    pub fn targets(&self) -> TargetImages<'_> {
        TargetImages {
            images: &self.raw,
            format: COLOUR_FORMAT,
            extent: self.extent,
            depth: &[],
            density_maps: &[],
        }
    }

    /// The next image, round robin, as the frame's target (no depth images).
    pub fn acquire(&mut self) -> Acquired {
        let i = self.next;
        self.next = (self.next + 1) % SWAPCHAIN_IMAGES as u32;
        self.acquired = Some(i);
        Acquired {
            colour: i,
            depth: 0,
        }
    }

    /// The image acquired for this frame, if any.
    pub fn acquired(&self) -> Option<u32> {
        self.acquired
    }

    /// The image acquired for this frame, if any, handed over (it is shown or read once).
    pub fn take_acquired(&mut self) -> Option<u32> {
        self.acquired.take()
    }

    /// Image `i`.
    pub fn image(&self, i: u32) -> vk::Image {
        self.raw[i as usize]
    }

    /// Per-eye size.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    fn destroy(&mut self, ctx: &GpuContext) {
        for mut i in self.images.drain(..) {
            i.destroy(ctx);
        }
    }
}

/// Spacing (s) of the frames a headless run settles the sea with ([`HeadlessXr::settle`]).
pub const SETTLE_DT: f64 = 0.1;

/// The headless backend: renders `frames` frames along a path on the fixed 72 Hz clock, after
/// optional settling frames that step the sea without drawing.
pub struct HeadlessXr {
    // Declared before `ctx`, destroyed explicitly in `Drop` while the device lives.
    swapchain: DesktopSwapchain,
    ctx: GpuContext,
    path: CameraPath,
    frames: u64,
    settle: u64,
    frame: u64,
    /// The comfort vignette shown in every frame (0: none).
    vignette: f32,
    /// The images' and the configured drawn share of their size ([`HeadlessXr::draw_scaled`]).
    scales: RenderScales,
    /// The part of the images drawn now.
    shown: vk::Rect2D,
}

impl HeadlessXr {
    /// Creates the device (validation per `opts`) and the swapchain for `frames` frames.
    pub fn new(
        opts: &ContextOptions,
        size: EyeSize,
        path: CameraPath,
        frames: u64,
    ) -> Result<Self, XrError> {
        let ctx = GpuContext::new(opts)?;
        let swapchain = DesktopSwapchain::new(&ctx, size)?;
        Ok(Self {
            swapchain,
            ctx,
            path,
            frames,
            settle: 0,
            frame: 0,
            vignette: 0.0,
            scales: RenderScales::whole(1.0),
            shown: vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: size.extent(),
            },
        })
    }

    /// Draws `start` of the images (each side, centred) as configured, as a headset whose
    /// default render scale is under its recommended size does (`RenderScales`: the images
    /// at the recommended size): the GPU-time governor may then step up to the whole image
    /// ([`crate::xr::gpu_governor::QualityStep::FullSize`]) as well as down. For testing
    /// that path; read-backs copy the whole image, its border stale. `start` must be in
    /// (0, 1].
    pub fn draw_scaled(&mut self, start: f32) -> Result<(), XrError> {
        if !(start > 0.0 && start <= 1.0) {
            return Err(XrError::Backend(format!(
                "drawn share {start} of the eye images: must be in (0, 1]"
            )));
        }
        self.scales = RenderScales { images: 1.0, start };
        self.shown = scaled_rect(self.swapchain.extent(), start);
        Ok(())
    }

    /// Shows the comfort vignette at `strength` (0 to 1) in every frame, as a headset's
    /// locomotion would while the view is moved: for looking at it and testing it.
    pub fn show_vignette(&mut self, strength: f32) {
        self.vignette = strength;
    }

    /// Lets the sea run for `frames` × [`SETTLE_DT`] seconds before the first drawn frame:
    /// those frames (numbered 0..`frames`, the drawn ones after them) step the simulation and
    /// the floating bodies but draw nothing, so foam and bodies start in their steady state
    /// at the cost of a few CPU steps, not minutes of rendering. The camera path's clock
    /// starts at the first drawn frame.
    pub fn settle(mut self, frames: u64) -> Self {
        self.settle = frames;
        self
    }

    /// The swapchain (read-back of the last image).
    pub fn swapchain(&self) -> &DesktopSwapchain {
        &self.swapchain
    }

    /// The image acquired this frame, if any.
    pub fn acquired(&self) -> Option<u32> {
        self.swapchain.acquired()
    }
}

impl FrameLoop for HeadlessXr {
    fn gpu(&self) -> &GpuContext {
        &self.ctx
    }

    fn targets(&self) -> TargetImages<'_> {
        self.swapchain.targets()
    }

    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        if self.frame >= self.settle + self.frames {
            return Ok(None);
        }
        let settling = self.frame < self.settle;
        let settled = self.settle as f64 * SETTLE_DT;
        let (path_time, time, period) = if settling {
            (0.0, self.frame as f64 * SETTLE_DT, SETTLE_DT)
        } else {
            let t = (self.frame - self.settle) as f64 * PERIOD;
            (t, settled + t, PERIOD)
        };
        let (position, orientation) = self.path.pose(path_time);
        let mut tweaks = [None; MAX_TWEAKS];
        if !settling {
            // The path's throws in this frame's span (at most MAX_TWEAKS a frame).
            let throws = self.path.throws_in(path_time, path_time + PERIOD);
            let boats = self.path.boats_in(path_time, path_time + PERIOD);
            let scripted =
                std::iter::repeat_n(Tweak::Throw, throws).chain(boats.map(Tweak::LaunchBoat));
            for (slot, t) in tweaks.iter_mut().zip(scripted) {
                *slot = Some(t);
            }
        }
        let state = FrameState {
            should_render: !settling,
            tweaks,
            vignette: self.vignette,
            ..FrameState::seen_from(self.frame, time, period, eye_views(position, orientation))
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

    fn end_frame(&mut self, _frame: &FrameState) -> Result<(), XrError> {
        Ok(())
    }

    /// Nothing is shown, so a smaller drawn rectangle needs nothing more: the render scale
    /// steps apply (read-backs still copy the whole image, its border then stale).
    fn governor_caps(&self) -> GovernorCaps {
        GovernorCaps {
            render_rect: Some(self.scales),
            ..GovernorCaps::default()
        }
    }

    fn set_render_rect(&mut self, rect: vk::Rect2D) -> bool {
        self.shown = rect;
        true
    }

    fn render_rect(&self) -> vk::Rect2D {
        self.shown
    }
}

impl Drop for HeadlessXr {
    fn drop(&mut self) {
        self.ctx.wait_idle();
        self.swapchain.destroy(&self.ctx);
    }
}
