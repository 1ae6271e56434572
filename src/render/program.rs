//! What every graphics pipeline is made with: a vertex and a fragment module, alive only until
//! the pipeline exists ([`ShaderPair`]), and a layout of one descriptor set and one push-constant
//! range ([`pipeline_layout`]). The ocean's and solids' pipelines (`pipeline`) and the panel's
//! (`panel`) describe their fixed-function state themselves.

use std::ffi::CStr;

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;

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
