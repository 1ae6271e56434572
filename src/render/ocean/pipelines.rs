//! The ocean's pipelines, built against the stereo render pass (`render_pass`): the ocean and
//! the sky (from the air and from under the water), the solids (floating bodies, the deck) and
//! the comfort vignette, with their shared layout and push constants.

use ash::vk;

use super::solids::{SolidInstance, SolidVertex};
use crate::lod::PatchInstance;
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::program::{build, pipeline_layout, Blend, Depth, Program, Target};
use crate::render::render_pass::{render_pass, PassLayout, StereoMode};
use crate::render::shaders;

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
    /// Set 0: globals (binding 0), displacement (1), normal/foam (2), whitecaps (3), sky (4),
    /// foam pattern (5), the path tally (6: a storage buffer only the counting variant of
    /// the fragment shader uses; unwritten otherwise) and the interaction layer (7).
    pub set_layout: vk::DescriptorSetLayout,
    /// The layout all pipelines share.
    pub layout: vk::PipelineLayout,
    /// The ocean's pipeline: patches, skirt and sky (push constant `mode`), drawn from the air.
    pub ocean: vk::Pipeline,
    /// The same with the view from under the water and the waterline (issue 45), bound for
    /// frames some of which are under it: a device that runs both sides of a branch (lavapipe
    /// masks them) would otherwise pay for the water's underside in every frame (12-18 % of
    /// lavapipe's pass above the water, measured).
    pub ocean_under: vk::Pipeline,
    /// The solids' pipeline: instanced unit meshes (bodies, deck), back faces culled.
    pub solids: vk::Pipeline,
    /// The comfort vignette's: blended over the frame, no depth (`ocean::vignette`).
    pub vignette: vk::Pipeline,
    /// The ocean's fragment shader is the counting variant (`vr-ocean gpu-budget`).
    pub counting: bool,
}

impl Pipelines {
    /// Builds everything for `pass`; with `counting`, the ocean's fragment shader tallies its
    /// paths into binding 6 (needs [`GpuContext::probes`]).
    pub fn new(ctx: &GpuContext, pass: PassLayout, counting: bool) -> Result<Self, RenderError> {
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
        if counting && !ctx.probes {
            return Err(RenderError::Unsupported(
                "fragmentStoresAndAtomics and pipelineStatisticsQuery (the GPU budget's counting \
                 pass)"
                    .into(),
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
            ocean_under: vk::Pipeline::null(),
            solids: vk::Pipeline::null(),
            vignette: vk::Pipeline::null(),
            counting,
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
                // The fragments read it too: the waterline's test per pixel (issue 45).
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT),
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
            // The sky's prefiltered environment map (`ocean::sky_map`): the fog's colour per
            // vertex, the reflections per fragment.
            vk::DescriptorSetLayoutBinding::default()
                .binding(4)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT),
            // The tiling foam pattern (`ocean::foam_pattern`).
            vk::DescriptorSetLayoutBinding::default()
                .binding(5)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
            // The interaction layer (`ocean::interaction`): heights in the vertex shader,
            // slopes and foam in the fragment shader.
            vk::DescriptorSetLayoutBinding::default()
                .binding(7)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT),
            // The normal maps through the anisotropic sampler (`ocean::anisotropy`).
            vk::DescriptorSetLayoutBinding::default()
                .binding(8)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
            // The path tally of the counting variant (`ocean::probe`).
            vk::DescriptorSetLayoutBinding::default()
                .binding(6)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: a valid create info on a live device.
        self.set_layout = ctx.create("vkCreateDescriptorSetLayout", || unsafe {
            d.create_descriptor_set_layout(&info, None)
        })?;
        self.layout = pipeline_layout(
            ctx,
            self.set_layout,
            vk::ShaderStageFlags::VERTEX,
            std::mem::size_of::<Push>(),
        )?;
        let multiview = self.mode == StereoMode::Multiview;
        let target = Target {
            layout: self.layout,
            render_pass: self.render_pass,
            msaa: self.layout_of_pass.msaa,
        };
        // (label, above the water, from under it); the counting variant counts both.
        let (label, frag, under) = if self.counting {
            (
                "ocean (counting)",
                shaders::OCEAN_FRAG_COUNT,
                shaders::OCEAN_FRAG_COUNT,
            )
        } else if self.layout_of_pass.density_map {
            (
                "ocean (foveated)",
                shaders::OCEAN_FRAG_FDM,
                shaders::OCEAN_FRAG_FDM_UNDER,
            )
        } else {
            ("ocean", shaders::OCEAN_FRAG, shaders::OCEAN_FRAG_UNDER)
        };
        self.ocean = build(ctx, &ocean_program(label, multiview, frag), target)?;
        let under_label = if self.counting {
            "ocean (counting, under the water)"
        } else if self.layout_of_pass.density_map {
            "ocean (foveated, under the water)"
        } else {
            "ocean (under the water)"
        };
        self.ocean_under = build(ctx, &ocean_program(under_label, multiview, under), target)?;
        self.solids = build(ctx, &solid_program(multiview), target)?;
        self.vignette = build(ctx, &vignette_program(multiview), target)?;
        Ok(())
    }

    /// Frees everything (null handles are skipped). The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        // SAFETY: the GPU no longer uses them (the caller's contract); null handles are no-ops.
        unsafe {
            d.destroy_pipeline(self.ocean, None);
            d.destroy_pipeline(self.ocean_under, None);
            d.destroy_pipeline(self.solids, None);
            d.destroy_pipeline(self.vignette, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            d.destroy_render_pass(self.render_pass, None);
        }
    }
}

/// Binding 0 per vertex of `vertex` bytes, binding 1 per instance of `instance` bytes.
fn vertex_and_instance(vertex: usize, instance: usize) -> Vec<vk::VertexInputBindingDescription> {
    vec![
        vk::VertexInputBindingDescription {
            binding: 0,
            stride: vertex as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        },
        vk::VertexInputBindingDescription {
            binding: 1,
            stride: instance as u32,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
    ]
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
/// `frag`: the fragment shader variant (plain, foveated, counting), filed as `label`.
pub(crate) fn ocean_program(label: &'static str, multiview: bool, frag: &'static [u32]) -> Program {
    let f = vk::Format::R32_SFLOAT;
    let f2 = vk::Format::R32G32_SFLOAT;
    let u = vk::Format::R32_UINT;
    let attributes = vec![
        attr(0, 0, vk::Format::R32G32B32_SFLOAT, 0),
        attr(1, 1, f2, 0),
        attr(2, 1, f, 8),
        attr(3, 1, u, 12),
        attr(4, 1, f2, 16),
        attr(5, 1, f2, 24),
        attr(6, 1, u, 32),
        attr(7, 1, f, 36),
    ];
    Program {
        label,
        vert: if multiview {
            shaders::OCEAN_VERT_MULTIVIEW
        } else {
            shaders::OCEAN_VERT
        },
        frag,
        bindings: vertex_and_instance(12, std::mem::size_of::<PatchInstance>()),
        attributes,
        cull: vk::CullModeFlags::NONE,
        blend: Blend::Opaque,
        depth: Depth::ReversedZ,
    }
}

/// The solids: `SolidVertex`es (binding 0) and `SolidInstance`s (binding 1); closed meshes,
/// back faces culled.
fn solid_program(multiview: bool) -> Program {
    let f3 = vk::Format::R32G32B32_SFLOAT;
    let f4 = vk::Format::R32G32B32A32_SFLOAT;
    let attributes = vec![
        attr(0, 0, f3, 0),
        attr(1, 0, f3, 12),
        attr(2, 1, f4, 0),
        attr(3, 1, f4, 16),
        attr(4, 1, f4, 32),
        attr(5, 1, f4, 48),
        attr(6, 1, f4, 64),
    ];
    Program {
        label: "solids",
        vert: if multiview {
            shaders::SOLID_VERT_MULTIVIEW
        } else {
            shaders::SOLID_VERT
        },
        frag: shaders::SOLID_FRAG,
        bindings: vertex_and_instance(
            std::mem::size_of::<SolidVertex>(),
            std::mem::size_of::<SolidInstance>(),
        ),
        attributes,
        cull: vk::CullModeFlags::BACK,
        blend: Blend::Opaque,
        depth: Depth::ReversedZ,
    }
}

/// The comfort vignette: no vertex buffers (its rings' directions from `gl_VertexIndex`),
/// blended over the frame.
fn vignette_program(multiview: bool) -> Program {
    Program {
        label: "vignette",
        vert: if multiview {
            shaders::VIGNETTE_VERT_MULTIVIEW
        } else {
            shaders::VIGNETTE_VERT
        },
        frag: shaders::VIGNETTE_FRAG,
        bindings: Vec::new(),
        attributes: Vec::new(),
        cull: vk::CullModeFlags::NONE,
        blend: Blend::Over,
        depth: Depth::Ignored,
    }
}
