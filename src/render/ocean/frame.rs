//! What the ocean renderer draws into and what one frame gives it and gets back: the vocabulary
//! its parts, its pass and the renderer's targets share.

use std::time::Duration;

use ash::vk;

use crate::base::EyeView;
use crate::lod::OceanLod;
use crate::render::ocean::solids::Solid;
use crate::sim::interaction::InteractionLayer;
use crate::sim::Surfaces;

/// The most cascades the shaders read (a `vec4` of patch sizes).
pub const MAX_CASCADES: usize = 4;

/// The target images a renderer draws into: 2-layer colour arrays owned by the XR backend.
#[derive(Clone, Copy, Debug)]
pub struct TargetImages<'a> {
    /// The swapchain's images (each 2 layers: left, right).
    pub images: &'a [vk::Image],
    /// Their format (sRGB).
    pub format: vk::Format,
    /// Their size per eye.
    pub extent: vk::Extent2D,
    /// 2-layer depth images (`DEPTH_FORMAT`) whose contents are kept for the compositor (an
    /// OpenXR depth swapchain); empty: the renderer uses a transient depth image of its own.
    pub depth: &'a [vk::Image],
    /// Fixed foveation: one 2-layer fragment density map (`R8G8_UNORM`, made by the runtime,
    /// `XR_FB_foveation_vulkan`) per colour image, read when its pass begins; empty: none.
    pub density_maps: &'a [vk::Image],
}

/// One frame's inputs.
#[derive(Clone, Copy)]
pub struct FrameInput<'a> {
    /// Which target image to draw into.
    pub image: u32,
    /// Which of [`TargetImages::depth`] to use (0 without them).
    pub depth: u32,
    /// Both eyes.
    pub eyes: &'a [EyeView; 2],
    /// The LOD, already updated for this frame.
    pub lod: &'a OceanLod,
    /// The simulation result to show.
    pub surfaces: &'a Surfaces,
    /// Solid things in the water and the deck (at most [`MAX_SOLIDS`](super::MAX_SOLIDS)); drawn in the same
    /// pass, at most three more draws.
    pub solids: &'a [Solid],
    /// The interaction layer's waves, added to the sea's (`None`: none).
    pub interaction: Option<&'a InteractionLayer>,
    /// The comfort vignette's strength, 0 (not drawn) to 1 ([`vignette`](super::vignette)).
    pub vignette: f32,
}

/// What one [`OceanRenderer::render`](super::OceanRenderer::render) call measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameReport {
    /// Waiting for this slot's previous frame (GPU back-pressure).
    pub wait: Duration,
    /// Writing uniforms, instances and staging data, and recording.
    pub record: Duration,
    /// `vkQueueSubmit`.
    pub submit: Duration,
    /// GPU time of the ocean pass of the frame that last used this slot, if timed.
    pub gpu_pass: Option<Duration>,
    /// Draw calls recorded this frame (all passes).
    pub draws: u32,
}
