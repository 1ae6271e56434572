//! The stereo render pass: how both eyes are drawn (multiview with view mask 0b11, or one
//! layer per pass), its samples, the depth it keeps and the fragment density map it reads,
//! and the `VkRenderPass` made for them. The pipelines are built against it (`program`,
//! `ocean/pipelines`).

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;

/// How both eyes are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StereoMode {
    /// One render pass with view mask 0b11; `gl_ViewIndex` picks the eye.
    Multiview,
    /// One render pass per eye into one layer each; a push constant picks the eye.
    TwoPass,
}

impl StereoMode {
    /// Lower-case name, as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            StereoMode::Multiview => "multiview",
            StereoMode::TwoPass => "two-pass",
        }
    }
}

/// The depth format: float, for reversed Z.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Multisample anti-aliasing: samples per pixel of the pass's colour and depth. With more than
/// one, the pass draws into transient multisampled attachments (lazily allocated where the
/// device offers it, never stored) and resolves colour into the eye image at the end of the
/// subpass: on a tile-based GPU (Quest) the resolve happens on the tile and the samples never
/// reach memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Msaa {
    /// One sample: no anti-aliasing of edges.
    X1,
    /// Two samples.
    X2,
    /// Four samples (Meta's recommendation for Quest).
    X4,
}

impl Msaa {
    /// From a sample count (1, 2 or 4).
    pub fn from_samples(n: u32) -> Option<Self> {
        match n {
            1 => Some(Msaa::X1),
            2 => Some(Msaa::X2),
            4 => Some(Msaa::X4),
            _ => None,
        }
    }

    /// Samples per pixel.
    pub fn samples(self) -> u32 {
        match self {
            Msaa::X1 => 1,
            Msaa::X2 => 2,
            Msaa::X4 => 4,
        }
    }

    /// As Vulkan spells it.
    pub fn flag(self) -> vk::SampleCountFlags {
        match self {
            Msaa::X1 => vk::SampleCountFlags::TYPE_1,
            Msaa::X2 => vk::SampleCountFlags::TYPE_2,
            Msaa::X4 => vk::SampleCountFlags::TYPE_4,
        }
    }

    /// Whether the pass resolves multisampled attachments.
    pub fn resolves(self) -> bool {
        self != Msaa::X1
    }
}

/// What the render pass is built for.
#[derive(Clone, Copy, Debug)]
pub struct PassLayout {
    /// Multiview or two passes.
    pub mode: StereoMode,
    /// The eye images' format.
    pub colour_format: vk::Format,
    /// Samples per pixel.
    pub msaa: Msaa,
    /// Keep the depth after the pass (an OpenXR depth swapchain; single-sample only).
    pub store_depth: bool,
    /// A fragment density map attachment (fixed foveation), last in the framebuffer.
    pub density_map: bool,
}

/// The format of the runtime's fragment density maps (every runtime and engine uses it; the
/// OpenXR specification does not say).
pub const DENSITY_MAP_FORMAT: vk::Format = vk::Format::R8G8_UNORM;

impl PassLayout {
    /// Whether the subpass resolves the multisampled colour into the eye image (a resolve
    /// attachment: on a tiler, on the tile). True with MSAA and multiview. The two-pass
    /// fallback resolves each eye with `vkCmdResolveImage` after its pass instead: lavapipe
    /// (Mesa 22.3) writes a resolve attachment whose view starts at layer 1 into layer 0.
    pub fn resolves_in_pass(&self) -> bool {
        self.msaa.resolves() && self.mode == StereoMode::Multiview
    }

    /// Whether each pass is followed by an explicit resolve (MSAA, two passes).
    pub fn resolves_after_pass(&self) -> bool {
        self.msaa.resolves() && self.mode == StereoMode::TwoPass
    }

    /// The attachments of a framebuffer, in order: colour (multisampled with MSAA; the eye
    /// image without), depth (likewise), then, resolving in the pass, the eye image, then the
    /// density map.
    pub fn attachment_count(&self) -> usize {
        2 + usize::from(self.resolves_in_pass()) + usize::from(self.density_map)
    }
}

/// The render pass for `pass`: colour and depth cleared, colour ending where an OpenXR
/// swapchain image must be when released (or ready for the resolve after the pass).
pub(super) fn render_pass(
    ctx: &GpuContext,
    pass: &PassLayout,
) -> Result<vk::RenderPass, RenderError> {
    let samples = pass.msaa.flag();
    let resolves = pass.resolves_in_pass();
    let resolves_after = pass.resolves_after_pass();
    let depth_store = if pass.store_depth {
        vk::AttachmentStoreOp::STORE
    } else {
        vk::AttachmentStoreOp::DONT_CARE
    };
    // Resolved in the pass, the multisampled colour is never stored: only its resolve is.
    let colour_store = if resolves {
        vk::AttachmentStoreOp::DONT_CARE
    } else {
        vk::AttachmentStoreOp::STORE
    };
    // Resolved after the pass, it ends ready for `vkCmdResolveImage`.
    let colour_final = if resolves_after {
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL
    } else {
        // What an OpenXR swapchain image must be in when released.
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
    };
    let mut attachments = vec![
        vk::AttachmentDescription::default()
            .format(pass.colour_format)
            .samples(samples)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(colour_store)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(colour_final),
        vk::AttachmentDescription::default()
            .format(DEPTH_FORMAT)
            .samples(samples)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(depth_store)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
    ];
    if resolves {
        // The eye image: every pixel is written by the resolve, so nothing is loaded.
        attachments.push(
            vk::AttachmentDescription::default()
                .format(pass.colour_format)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(vk::AttachmentLoadOp::DONT_CARE)
                .store_op(vk::AttachmentStoreOp::STORE)
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::UNDEFINED)
                .final_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        );
    }
    let density_ref = vk::AttachmentReference {
        attachment: attachments.len() as u32,
        layout: vk::ImageLayout::FRAGMENT_DENSITY_MAP_OPTIMAL_EXT,
    };
    if pass.density_map {
        // The runtime's map stays in its layout; it is read (never written) when the pass
        // begins.
        attachments.push(
            vk::AttachmentDescription::default()
                .format(DENSITY_MAP_FORMAT)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(vk::AttachmentLoadOp::LOAD)
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::FRAGMENT_DENSITY_MAP_OPTIMAL_EXT)
                .final_layout(vk::ImageLayout::FRAGMENT_DENSITY_MAP_OPTIMAL_EXT),
        );
    }
    let colour_ref = [vk::AttachmentReference {
        attachment: 0,
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    }];
    let depth_ref = vk::AttachmentReference {
        attachment: 1,
        layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    };
    let resolve_ref = [vk::AttachmentReference {
        attachment: 2,
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    }];
    let mut subpass = vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour_ref)
        .depth_stencil_attachment(&depth_ref);
    if resolves {
        subpass = subpass.resolve_attachments(&resolve_ref);
    }
    let subpass = [subpass];
    // The previous frame's use of the same attachments (colour read by a blit or the
    // compositor, depth written) finishes before this pass clears them.
    let deps = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                    | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS
                    | vk::PipelineStageFlags::TRANSFER,
            )
            .dst_stage_mask(
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                    | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS,
            )
            .src_access_mask(
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE
                    | vk::AccessFlags::TRANSFER_READ,
            )
            .dst_access_mask(
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
            ),
        // The pass's colour writes finish before a resolve after the pass reads them.
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
            .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
            .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
            .dst_access_mask(vk::AccessFlags::TRANSFER_READ),
    ];
    let view_masks = [0b11u32];
    let correlation = [0b11u32];
    let mut multiview = vk::RenderPassMultiviewCreateInfo::default()
        .view_masks(&view_masks)
        .correlation_masks(&correlation);
    let mut density = vk::RenderPassFragmentDensityMapCreateInfoEXT::default()
        .fragment_density_map_attachment(density_ref);
    let mut info = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpass)
        .dependencies(&deps);
    if pass.mode == StereoMode::Multiview {
        info = info.push_next(&mut multiview);
    }
    if pass.density_map {
        info = info.push_next(&mut density);
    }
    // SAFETY: every array `info` points at lives until the call returns.
    ctx.create("vkCreateRenderPass", || unsafe {
        ctx.device.create_render_pass(&info, None)
    })
}
