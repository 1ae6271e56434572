//! What every graphics pipeline is made with: its description ([`Program`]: shaders, vertex
//! input, culling, blending, depth) built once by [`build`], a vertex and a fragment module
//! alive only until the pipeline exists ([`ShaderPair`]), and a layout of one descriptor set
//! and one push-constant range ([`pipeline_layout`]). The ocean's pipelines
//! (`ocean/pipelines.rs`), the panel's and the calibration kernels' are `Program`s.

use std::ffi::CStr;

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;
use super::render_pass::Msaa;

/// The entry point of every module.
const MAIN: &CStr = c"main";

/// A vertex and a fragment shader module, freed by [`ShaderPair::create`]: make the pair just
/// before it, with nothing fallible between.
pub(crate) struct ShaderPair {
    vert: vk::ShaderModule,
    frag: vk::ShaderModule,
}

impl ShaderPair {
    /// The modules of SPIR-V `vert` and `frag` (from `build.rs`, validated there). Nothing is
    /// left behind when the second fails.
    pub fn new(ctx: &GpuContext, vert: &[u32], frag: &[u32]) -> Result<Self, RenderError> {
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
        Ok(Self { vert, frag })
    }

    /// The two stages, entry point `main`.
    pub fn stages(&self) -> [vk::PipelineShaderStageCreateInfo<'static>; 2] {
        [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(self.vert)
                .name(MAIN),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(self.frag)
                .name(MAIN),
        ]
    }

    /// Creates the pipeline `info` describes (its stages from [`ShaderPair::stages`]), then
    /// frees the modules, whether it was made or not. Where the context captures compiler
    /// statistics ([`GpuContext::pipeline_statistics`]), the driver is asked for them and they
    /// are filed under `label`.
    pub fn create(
        self,
        ctx: &GpuContext,
        label: &'static str,
        info: &vk::GraphicsPipelineCreateInfo,
    ) -> Result<vk::Pipeline, RenderError> {
        let d = &ctx.device;
        let capture = ctx.pipeline_statistics.as_ref();
        let mut info = *info;
        if capture.is_some() {
            info.flags |= vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR;
        }
        // SAFETY: every struct `info` points at lives until the call returns (the caller's
        // borrow); its layout and render pass are alive.
        let result = ctx.create("vkCreateGraphicsPipelines", || unsafe {
            d.create_graphics_pipelines(
                vk::PipelineCache::null(),
                std::slice::from_ref(&info),
                None,
            )
            .map_err(|(_, e)| e)
        });
        self.free(ctx);
        let pipeline = result.map(|p| p[0])?;
        if let Some(log) = capture {
            if let Err(e) = log.record(&ctx.instance, &ctx.device, label, pipeline) {
                // SAFETY: the pipeline was just made and nothing uses it yet.
                unsafe { d.destroy_pipeline(pipeline, None) };
                return Err(e);
            }
        }
        Ok(pipeline)
    }

    /// Frees the modules (a pipeline no longer needs them once made, or when making it failed).
    fn free(self, ctx: &GpuContext) {
        // SAFETY: no pipeline creation is using the modules any more.
        unsafe {
            ctx.device.destroy_shader_module(self.vert, None);
            ctx.device.destroy_shader_module(self.frag, None);
        }
    }
}

/// A pipeline layout of `set_layout` and one push-constant range of `push_size` bytes seen by
/// `push_stages`.
pub(crate) fn pipeline_layout(
    ctx: &GpuContext,
    set_layout: vk::DescriptorSetLayout,
    push_stages: vk::ShaderStageFlags,
    push_size: usize,
) -> Result<vk::PipelineLayout, RenderError> {
    let push = [vk::PushConstantRange {
        stage_flags: push_stages,
        offset: 0,
        size: push_size as u32,
    }];
    let layouts = [set_layout];
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&layouts)
        .push_constant_ranges(&push);
    // SAFETY: the set layout is alive.
    ctx.create("vkCreatePipelineLayout", || unsafe {
        ctx.device.create_pipeline_layout(&info, None)
    })
}

/// What a pipeline is built against: its layout, render pass and samples per pixel.
#[derive(Clone, Copy)]
pub(crate) struct Target {
    /// The pipeline layout.
    pub layout: vk::PipelineLayout,
    /// The render pass.
    pub render_pass: vk::RenderPass,
    /// Its samples per pixel.
    pub msaa: Msaa,
}

/// One graphics pipeline's description: its shaders, vertex input, culling, blending and
/// depth, and the name its compiler statistics are filed under. Every pipeline the renderer
/// makes (the ocean's, the solids', the vignette's, the panel's, the calibration kernels') is
/// one of these built by [`build`].
pub(crate) struct Program {
    /// What the pipeline draws (`GpuContext::pipeline_statistics`' label).
    pub label: &'static str,
    /// The vertex shader.
    pub vert: &'static [u32],
    /// The fragment shader.
    pub frag: &'static [u32],
    /// The vertex buffers' bindings (none: vertices from `gl_VertexIndex`).
    pub bindings: Vec<vk::VertexInputBindingDescription>,
    /// Their attributes.
    pub attributes: Vec<vk::VertexInputAttributeDescription>,
    /// Faces culled.
    pub cull: vk::CullModeFlags,
    /// How its colour meets the target's.
    pub blend: Blend,
    /// Whether it tests and writes depth.
    pub depth: Depth,
}

/// How a pipeline's colour meets what the target holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Blend {
    /// Written as is (the ocean, the solids).
    Opaque,
    /// Blended by its alpha, the target's alpha kept (the comfort vignette over the frame).
    Over,
    /// Premultiplied alpha (egui's panel).
    Premultiplied,
}

/// Whether a pipeline tests and writes depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Depth {
    /// Tested `GREATER` (reversed Z) and written.
    ReversedZ,
    /// Neither tested nor written (an overlay, or a pass without depth).
    Ignored,
}

/// Creates `program`'s pipeline against `target`: triangle lists, filled, counter-clockwise
/// front faces, its culling, blending and depth, viewport and scissor dynamic.
pub(crate) fn build(
    ctx: &GpuContext,
    program: &Program,
    target: Target,
) -> Result<vk::Pipeline, RenderError> {
    let Target {
        layout,
        render_pass,
        msaa,
    } = target;
    let shaders = ShaderPair::new(ctx, program.vert, program.frag)?;
    let stages = shaders.stages();
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&program.bindings)
        .vertex_attribute_descriptions(&program.attributes);
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
        .depth_test_enable(program.depth == Depth::ReversedZ)
        .depth_write_enable(program.depth == Depth::ReversedZ)
        .depth_compare_op(vk::CompareOp::GREATER);
    let blended = |src_colour, src_alpha, dst_alpha| {
        vk::PipelineColorBlendAttachmentState::default()
            .blend_enable(true)
            .src_color_blend_factor(src_colour)
            .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
            .color_blend_op(vk::BlendOp::ADD)
            .src_alpha_blend_factor(src_alpha)
            .dst_alpha_blend_factor(dst_alpha)
            .alpha_blend_op(vk::BlendOp::ADD)
            .color_write_mask(vk::ColorComponentFlags::RGBA)
    };
    let blend_attachment = [match program.blend {
        Blend::Opaque => vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA),
        Blend::Over => blended(
            vk::BlendFactor::SRC_ALPHA,
            vk::BlendFactor::ZERO,
            vk::BlendFactor::ONE,
        ),
        Blend::Premultiplied => blended(
            vk::BlendFactor::ONE,
            vk::BlendFactor::ONE,
            vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
        ),
    }];
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
    shaders.create(ctx, program.label, &info)
}
