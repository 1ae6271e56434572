//! The panel's pipeline description: egui's vertices, no culling, no depth, premultiplied alpha.

use ash::vk;

use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::program::{build as build_program, Blend, Depth, Program, Target};
use crate::render::render_pass::Msaa;
use crate::render::shaders;

/// The panel's pipeline: egui's vertices (position, uv: two floats each; colour: four bytes),
/// no culling, no depth, premultiplied-alpha blending, one sample.
pub(super) fn build(
    ctx: &GpuContext,
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
) -> Result<vk::Pipeline, RenderError> {
    let attr = |location, format, offset| vk::VertexInputAttributeDescription {
        location,
        binding: 0,
        format,
        offset,
    };
    let program = Program {
        label: "panel",
        vert: shaders::PANEL_VERT,
        frag: shaders::PANEL_FRAG,
        bindings: vec![vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<egui::epaint::Vertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }],
        attributes: vec![
            attr(0, vk::Format::R32G32_SFLOAT, 0),
            attr(1, vk::Format::R32G32_SFLOAT, 8),
            attr(2, vk::Format::R8G8B8A8_UNORM, 16),
        ],
        cull: vk::CullModeFlags::NONE,
        blend: Blend::Premultiplied,
        depth: Depth::Ignored,
    };
    let target = Target {
        layout,
        render_pass,
        msaa: Msaa::X1,
    };
    build_program(ctx, &program, target)
}
