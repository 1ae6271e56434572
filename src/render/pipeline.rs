//! The stereo render pass (multiview view mask 0b11, or one layer per pass for the fallback)
//! and the pipelines built against it: the ocean and the sky, and the solids (floating
//! bodies, the deck).

use std::ffi::CStr;

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;
use super::shaders;
use crate::lod::PatchInstance;
use crate::render::ocean::{SolidInstance, SolidVertex};

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

/// Push constants of every pipeline (vertex stage), mirrored by `Push` in the shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Push {
    /// The eye of this pass (two-pass only).
    pub eye: u32,
    /// 0: quadtree patches; 1: the skirt; 2: the sky.
    pub mode: u32,
    /// Skirt vertices on its inner edge (they morph).
    pub inner_count: u32,
    /// V, cells per patch side.
    pub grid_v: u32,
}

/// Render pass, layouts and pipelines of one stereo mode.
pub struct Pipelines {
    /// The mode these were built for.
    pub mode: StereoMode,
    /// What the render pass was built for.
    pub layout_of_pass: PassLayout,
    /// Colour + depth, cleared; colour ends in `COLOR_ATTACHMENT_OPTIMAL` (what an OpenXR
    /// swapchain image must be in when released).
    pub render_pass: vk::RenderPass,
    /// Set 0: globals (binding 0), displacement (1), normal/foam (2).
    pub set_layout: vk::DescriptorSetLayout,
    /// The layout all pipelines share.
    pub layout: vk::PipelineLayout,
    /// The ocean's pipeline: patches, skirt and sky (push constant `mode`).
    pub ocean: vk::Pipeline,
    /// The solids' pipeline: instanced unit meshes (bodies, deck), back faces culled.
    pub solids: vk::Pipeline,
}

impl Pipelines {
    /// Builds everything for `pass`.
    pub fn new(ctx: &GpuContext, pass: PassLayout) -> Result<Self, RenderError> {
        let mode = pass.mode;
        if mode == StereoMode::Multiview && !ctx.multiview {
            return Err(RenderError::Unsupported("the multiview feature".into()));
        }
        if !ctx.sample_counts.contains(pass.msaa.flag()) {
            return Err(RenderError::Unsupported(format!(
                "{}x MSAA for colour and depth (it offers {:?}); choose another --msaa",
                pass.msaa.samples(),
                ctx.sample_counts
            )));
        }
        if pass.density_map && !ctx.fragment_density_map {
            return Err(RenderError::Unsupported(
                "VK_EXT_fragment_density_map with non-subsampled images (fixed foveation)".into(),
            ));
        }
        if pass.store_depth && pass.msaa.resolves() {
            return Err(RenderError::Invalid(
                "depth kept for the compositor needs --msaa 1 (the multisampled depth is not \
                 resolved)"
                    .into(),
            ));
        }
        let mut this = Self {
            mode,
            layout_of_pass: pass,
            render_pass: vk::RenderPass::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            ocean: vk::Pipeline::null(),
            solids: vk::Pipeline::null(),
        };
        if let Err(e) = this.create(ctx) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    /// Creates the objects in order; [`Pipelines::destroy`] frees whatever was made when a
    /// step fails.
    fn create(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let d = &ctx.device;
        self.render_pass = render_pass(ctx, &self.layout_of_pass)?;
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT),
            vk::DescriptorSetLayoutBinding::default()
                .binding(1)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::VERTEX),
            vk::DescriptorSetLayoutBinding::default()
                .binding(2)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
            // Whitecap coverage of the whole surface (`sim::whitecaps`).
            vk::DescriptorSetLayoutBinding::default()
                .binding(3)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: a valid create info on a live device.
        self.set_layout = ctx.create("vkCreateDescriptorSetLayout", || unsafe {
            d.create_descriptor_set_layout(&info, None)
        })?;
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: std::mem::size_of::<Push>() as u32,
        }];
        let layouts = [self.set_layout];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(&push);
        // SAFETY: the set layout is alive.
        self.layout = ctx.create("vkCreatePipelineLayout", || unsafe {
            d.create_pipeline_layout(&info, None)
        })?;
        let multiview = self.mode == StereoMode::Multiview;
        let target = Target {
            layout: self.layout,
            render_pass: self.render_pass,
            msaa: self.layout_of_pass.msaa,
        };
        self.ocean = build(
            ctx,
            &ocean_program(multiview, &mut Vec::new(), &mut Vec::new()),
            target,
        )?;
        self.solids = build(
            ctx,
            &solid_program(multiview, &mut Vec::new(), &mut Vec::new()),
            target,
        )?;
        Ok(())
    }

    /// Frees everything (null handles are skipped). The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        // SAFETY: the GPU no longer uses them (the caller's contract); null handles are no-ops.
        unsafe {
            d.destroy_pipeline(self.ocean, None);
            d.destroy_pipeline(self.solids, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            d.destroy_render_pass(self.render_pass, None);
        }
    }
}

fn render_pass(ctx: &GpuContext, pass: &PassLayout) -> Result<vk::RenderPass, RenderError> {
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

/// What a pipeline is built against: the shared layout and the pass.
#[derive(Clone, Copy)]
struct Target {
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
    msaa: Msaa,
}

/// The shaders and vertex input of one pipeline.
struct Program<'a> {
    vert: &'a [u32],
    frag: &'a [u32],
    bindings: &'a [vk::VertexInputBindingDescription],
    attributes: &'a [vk::VertexInputAttributeDescription],
    cull: vk::CullModeFlags,
}

fn attr(
    location: u32,
    binding: u32,
    format: vk::Format,
    offset: u32,
) -> vk::VertexInputAttributeDescription {
    vk::VertexInputAttributeDescription {
        location,
        binding,
        format,
        offset,
    }
}

/// The ocean: lattice positions (binding 0) and `PatchInstance`s (binding 1). Not back-face
/// culled: folded crests show triangles from behind, and culling them would open holes.
fn ocean_program<'a>(
    multiview: bool,
    bindings: &'a mut Vec<vk::VertexInputBindingDescription>,
    attributes: &'a mut Vec<vk::VertexInputAttributeDescription>,
) -> Program<'a> {
    bindings.extend([
        vk::VertexInputBindingDescription {
            binding: 0,
            stride: 12,
            input_rate: vk::VertexInputRate::VERTEX,
        },
        vk::VertexInputBindingDescription {
            binding: 1,
            stride: std::mem::size_of::<PatchInstance>() as u32,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
    ]);
    let f = vk::Format::R32_SFLOAT;
    let f2 = vk::Format::R32G32_SFLOAT;
    let u = vk::Format::R32_UINT;
    attributes.extend([
        attr(0, 0, vk::Format::R32G32B32_SFLOAT, 0),
        attr(1, 1, f2, 0),
        attr(2, 1, f, 8),
        attr(3, 1, u, 12),
        attr(4, 1, f2, 16),
        attr(5, 1, f2, 24),
        attr(6, 1, u, 32),
        attr(7, 1, f, 36),
    ]);
    Program {
        vert: if multiview {
            shaders::OCEAN_VERT_MULTIVIEW
        } else {
            shaders::OCEAN_VERT
        },
        frag: shaders::OCEAN_FRAG,
        bindings,
        attributes,
        cull: vk::CullModeFlags::NONE,
    }
}

/// The solids: `SolidVertex`es (binding 0) and `SolidInstance`s (binding 1); closed meshes,
/// back faces culled.
fn solid_program<'a>(
    multiview: bool,
    bindings: &'a mut Vec<vk::VertexInputBindingDescription>,
    attributes: &'a mut Vec<vk::VertexInputAttributeDescription>,
) -> Program<'a> {
    bindings.extend([
        vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<SolidVertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        },
        vk::VertexInputBindingDescription {
            binding: 1,
            stride: std::mem::size_of::<SolidInstance>() as u32,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
    ]);
    let f3 = vk::Format::R32G32B32_SFLOAT;
    let f4 = vk::Format::R32G32B32A32_SFLOAT;
    attributes.extend([
        attr(0, 0, f3, 0),
        attr(1, 0, f3, 12),
        attr(2, 1, f4, 0),
        attr(3, 1, f4, 16),
        attr(4, 1, f4, 32),
        attr(5, 1, f4, 48),
        attr(6, 1, f4, 64),
    ]);
    Program {
        vert: if multiview {
            shaders::SOLID_VERT_MULTIVIEW
        } else {
            shaders::SOLID_VERT
        },
        frag: shaders::SOLID_FRAG,
        bindings,
        attributes,
        cull: vk::CullModeFlags::BACK,
    }
}

fn build(
    ctx: &GpuContext,
    program: &Program<'_>,
    target: Target,
) -> Result<vk::Pipeline, RenderError> {
    let Target {
        layout,
        render_pass,
        msaa,
    } = target;
    let (vert, frag) = (program.vert, program.frag);
    let d = &ctx.device;
    let module = |code: &[u32]| {
        let info = vk::ShaderModuleCreateInfo::default().code(code);
        // SAFETY: `code` is SPIR-V from `build.rs`, validated there.
        ctx.create("vkCreateShaderModule", || unsafe {
            d.create_shader_module(&info, None)
        })
    };
    let vert = module(vert)?;
    let frag = module(frag).inspect_err(|_| {
        // SAFETY: the vertex module is unused when the fragment module fails.
        unsafe { d.destroy_shader_module(vert, None) }
    })?;
    const MAIN: &CStr = c"main";
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vert)
            .name(MAIN),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(frag)
            .name(MAIN),
    ];
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(program.bindings)
        .vertex_attribute_descriptions(program.attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(program.cull)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(msaa.flag());
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::GREATER);
    let blend_attachment = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachment);
    let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .render_pass(render_pass)
        .subpass(0);
    // SAFETY: every struct `info` points at lives until the call returns; the layout and the
    // render pass are alive.
    let result = ctx.create("vkCreateGraphicsPipelines", || unsafe {
        d.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
            .map_err(|(_, e)| e)
    });
    // SAFETY: a pipeline no longer needs its modules once created (or creation failed).
    unsafe {
        d.destroy_shader_module(vert, None);
        d.destroy_shader_module(frag, None);
    }
    result.map(|p| p[0])
}
