//! The control panel's painter (issue 31): egui's tessellated triangles ([`crate::ui::panel`])
//! drawn into a single-sample colour image of the panel's size, the headset's quad-layer
//! swapchain image or the window's overlay image. One render pass, one pipeline
//! (`shaders/panel.*`), a texture per egui texture (the font atlas), host-visible vertex and
//! index buffers that grow only when a panel needs more. Recorded only when the panel changed.

use ash::vk;

mod canvas;
mod pipeline;
mod textures;

pub use canvas::PanelCanvas;

use textures::{PanelTextures, TextureSets};

use super::barrier::Access;
use super::context::GpuContext;
use super::error::RenderError;
use super::memory::Buffer;
use super::program;

/// What the painter draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PanelTarget {
    /// The colour format: a `_UNORM` image stores egui's sRGB-encoded colours as they are; an
    /// `_SRGB` one gets linear light, encoded on write (the blend then runs in linear light).
    pub format: vk::Format,
    /// How the image is used after the pass (the pass ends in that access's layout).
    pub then: Access,
}

impl PanelTarget {
    fn linear_out(&self) -> bool {
        matches!(
            self.format,
            vk::Format::R8G8B8A8_SRGB
                | vk::Format::B8G8R8A8_SRGB
                | vk::Format::A8B8G8R8_SRGB_PACK32
        )
    }
}

/// One image of the panel to paint.
pub struct PanelFrame<'a> {
    /// The target image's view (an image of `extent` in the painter's format).
    pub view: vk::ImageView,
    /// Its size in pixels.
    pub extent: vk::Extent2D,
    /// egui's triangles, in points.
    pub primitives: &'a [egui::ClippedPrimitive],
    /// egui's texture changes since the last recording.
    pub textures: &'a egui::TexturesDelta,
    /// Image pixels per point.
    pub pixels_per_point: f32,
}

/// Push constants of `shaders/panel.*`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    size: [f32; 2],
    linear_out: f32,
    pad: f32,
}

/// Most egui textures the painter holds at once (the font atlas, and a few images).
const MAX_TEXTURES: u32 = 8;
/// Vertices and indices the buffers hold at first (a full panel uses a few thousand).
const FIRST_VERTICES: u64 = 16 * 1024;
const FIRST_INDICES: u64 = 48 * 1024;

/// The painter's Vulkan objects.
pub struct PanelPainter {
    target: PanelTarget,
    render_pass: vk::RenderPass,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    sampler: vk::Sampler,
    pool: vk::DescriptorPool,
    /// The egui textures, and those egui freed (destroyed at the next
    /// [`PanelPainter::record`]).
    textures: PanelTextures,
    vertices: Buffer,
    indices: Buffer,
    staging: Buffer,
    framebuffers: Vec<(vk::ImageView, vk::Extent2D, vk::Framebuffer)>,
}

impl PanelPainter {
    /// The painter for `target`. Nothing is left behind when a step fails.
    pub fn new(ctx: &GpuContext, target: PanelTarget) -> Result<Self, RenderError> {
        let mut this = Self {
            target,
            render_pass: vk::RenderPass::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            sampler: vk::Sampler::null(),
            pool: vk::DescriptorPool::null(),
            textures: PanelTextures::default(),
            vertices: Buffer::null(),
            indices: Buffer::null(),
            staging: Buffer::null(),
            framebuffers: Vec::new(),
        };
        if let Err(e) = this.create(ctx) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let d = &ctx.device;
        let attachment = [vk::AttachmentDescription::default()
            .format(self.target.format)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(self.target.then.layout())];
        let colour = [vk::AttachmentReference::default()
            .attachment(0)
            .layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)];
        let subpass = [vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&colour)];
        // The pass waits for the previous image's use (a blit or the compositor reading it)
        // before clearing it, and makes its writes available to the next use.
        let dependency = [
            vk::SubpassDependency::default()
                .src_subpass(vk::SUBPASS_EXTERNAL)
                .dst_subpass(0)
                .src_stage_mask(self.target.then.stages())
                .dst_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
                .dst_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE),
            vk::SubpassDependency::default()
                .src_subpass(0)
                .dst_subpass(vk::SUBPASS_EXTERNAL)
                .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
                .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                .dst_stage_mask(self.target.then.stages())
                .dst_access_mask(self.target.then.access()),
        ];
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachment)
            .subpasses(&subpass)
            .dependencies(&dependency);
        // SAFETY: a valid create info on a live device.
        self.render_pass = ctx.create("vkCreateRenderPass", || unsafe {
            d.create_render_pass(&info, None)
        })?;
        let bindings = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::FRAGMENT)];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: as above.
        self.set_layout = ctx.create("vkCreateDescriptorSetLayout", || unsafe {
            d.create_descriptor_set_layout(&info, None)
        })?;
        self.layout = program::pipeline_layout(
            ctx,
            self.set_layout,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            std::mem::size_of::<Push>(),
        )?;
        self.pipeline = pipeline::build(ctx, self.layout, self.render_pass)?;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        // SAFETY: as above.
        self.sampler = ctx.create("vkCreateSampler", || unsafe {
            d.create_sampler(&info, None)
        })?;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            descriptor_count: MAX_TEXTURES,
        }];
        let info = vk::DescriptorPoolCreateInfo::default()
            .flags(vk::DescriptorPoolCreateFlags::FREE_DESCRIPTOR_SET)
            .max_sets(MAX_TEXTURES)
            .pool_sizes(&sizes);
        // SAFETY: as above.
        self.pool = ctx.create("vkCreateDescriptorPool", || unsafe {
            d.create_descriptor_pool(&info, None)
        })?;
        self.vertices = Buffer::new(
            ctx,
            FIRST_VERTICES * std::mem::size_of::<egui::epaint::Vertex>() as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            true,
        )?;
        self.indices = Buffer::new(
            ctx,
            FIRST_INDICES * 4,
            vk::BufferUsageFlags::INDEX_BUFFER,
            true,
        )?;
        Ok(())
    }

    /// Records `frame` into `cmd`: its texture changes uploaded, then one pass into its view
    /// clearing it and drawing its triangles. The commands of the previous recording must have
    /// completed.
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        cmd: vk::CommandBuffer,
        frame: PanelFrame,
    ) -> Result<(), RenderError> {
        let PanelFrame {
            view,
            extent,
            primitives,
            textures,
            pixels_per_point,
        } = frame;
        self.textures.free_retired(ctx, self.pool);
        // Every upload of this recording gets its own part of the staging buffer.
        let staged: u64 = textures
            .set
            .iter()
            .map(|(_, d)| 4 * (d.image.size()[0] * d.image.size()[1]) as u64)
            .sum();
        if staged > self.staging.size {
            let mut old = std::mem::replace(
                &mut self.staging,
                Buffer::new(
                    ctx,
                    staged.next_power_of_two(),
                    vk::BufferUsageFlags::TRANSFER_SRC,
                    true,
                )?,
            );
            ctx.wait_idle();
            old.destroy(ctx);
        }
        let mut offset = 0;
        for change in &textures.set {
            let sets = TextureSets {
                pool: self.pool,
                set_layout: self.set_layout,
                sampler: self.sampler,
            };
            offset = self
                .textures
                .upload(ctx, cmd, sets, &mut self.staging, change, offset)?;
        }
        let (vertex_count, index_count) =
            primitives
                .iter()
                .fold((0, 0), |(v, i), p| match &p.primitive {
                    egui::epaint::Primitive::Mesh(m) => (v + m.vertices.len(), i + m.indices.len()),
                    egui::epaint::Primitive::Callback(_) => (v, i),
                });
        self.reserve(ctx, vertex_count as u64, index_count as u64)?;
        let framebuffer = self.framebuffer(ctx, view, extent)?;
        let d = &ctx.device;
        let clear = [vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.0, 0.0, 0.0, 0.0],
            },
        }];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(framebuffer)
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            })
            .clear_values(&clear);
        let push = Push {
            size: [
                extent.width as f32 / pixels_per_point,
                extent.height as f32 / pixels_per_point,
            ],
            linear_out: if self.target.linear_out() { 1.0 } else { 0.0 },
            pad: 0.0,
        };
        // SAFETY: `cmd` is recording outside a render pass; every handle is alive; the buffers
        // hold what the draws read (written below before submission, host-coherent).
        unsafe {
            d.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            d.cmd_set_viewport(
                cmd,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: extent.width as f32,
                    height: extent.height as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            d.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            d.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
        }
        let (mut first_vertex, mut first_index) = (0usize, 0usize);
        for p in primitives {
            let egui::epaint::Primitive::Mesh(mesh) = &p.primitive else {
                continue;
            };
            let Some(set) = self.textures.get(mesh.texture_id) else {
                continue;
            };
            let v_bytes = bytemuck::cast_slice::<egui::epaint::Vertex, u8>(&mesh.vertices);
            let v_at = first_vertex * std::mem::size_of::<egui::epaint::Vertex>();
            self.vertices.bytes_mut()[v_at..v_at + v_bytes.len()].copy_from_slice(v_bytes);
            let i_bytes = bytemuck::cast_slice::<u32, u8>(&mesh.indices);
            let i_at = first_index * 4;
            self.indices.bytes_mut()[i_at..i_at + i_bytes.len()].copy_from_slice(i_bytes);
            let clip = scissor(p.clip_rect, pixels_per_point, extent);
            if clip.extent.width > 0 && clip.extent.height > 0 {
                // SAFETY: inside the pass begun above; the set and buffers are alive.
                unsafe {
                    d.cmd_set_scissor(cmd, 0, &[clip]);
                    d.cmd_bind_descriptor_sets(
                        cmd,
                        vk::PipelineBindPoint::GRAPHICS,
                        self.layout,
                        0,
                        &[set.set],
                        &[],
                    );
                    d.cmd_draw_indexed(
                        cmd,
                        mesh.indices.len() as u32,
                        1,
                        first_index as u32,
                        first_vertex as i32,
                        0,
                    );
                }
            }
            first_vertex += mesh.vertices.len();
            first_index += mesh.indices.len();
        }
        // SAFETY: the pass begun above.
        unsafe { d.cmd_end_render_pass(cmd) };
        for id in &textures.free {
            self.textures.retire(*id);
        }
        Ok(())
    }

    /// Makes the vertex and index buffers hold at least this many (growing only: a larger
    /// panel, never per frame once grown).
    fn reserve(
        &mut self,
        ctx: &GpuContext,
        vertices: u64,
        indices: u64,
    ) -> Result<(), RenderError> {
        let v = vertices * std::mem::size_of::<egui::epaint::Vertex>() as u64;
        if v > self.vertices.size {
            let mut old = std::mem::replace(
                &mut self.vertices,
                Buffer::new(
                    ctx,
                    v.next_power_of_two(),
                    vk::BufferUsageFlags::VERTEX_BUFFER,
                    true,
                )?,
            );
            ctx.wait_idle();
            old.destroy(ctx);
        }
        if indices * 4 > self.indices.size {
            let mut old = std::mem::replace(
                &mut self.indices,
                Buffer::new(
                    ctx,
                    (indices * 4).next_power_of_two(),
                    vk::BufferUsageFlags::INDEX_BUFFER,
                    true,
                )?,
            );
            ctx.wait_idle();
            old.destroy(ctx);
        }
        Ok(())
    }

    /// The framebuffer of `view`, made on first use.
    fn framebuffer(
        &mut self,
        ctx: &GpuContext,
        view: vk::ImageView,
        extent: vk::Extent2D,
    ) -> Result<vk::Framebuffer, RenderError> {
        if let Some(&(_, _, f)) = self
            .framebuffers
            .iter()
            .find(|(v, e, _)| *v == view && *e == extent)
        {
            return Ok(f);
        }
        let attachments = [view];
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&attachments)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: the pass and the view are alive (the view outlives the painter's use of it:
        // the caller's contract).
        let f = ctx.create("vkCreateFramebuffer", || unsafe {
            ctx.device.create_framebuffer(&info, None)
        })?;
        self.framebuffers.push((view, extent, f));
        Ok(f)
    }

    /// Frees everything (null handles are skipped). The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        self.textures.destroy(ctx, self.pool);
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
        self.staging.destroy(ctx);
        // SAFETY: the GPU no longer uses them (the caller's contract); null handles are no-ops.
        unsafe {
            for (_, _, f) in self.framebuffers.drain(..) {
                d.destroy_framebuffer(f, None);
            }
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_sampler(self.sampler, None);
            d.destroy_pipeline(self.pipeline, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            d.destroy_render_pass(self.render_pass, None);
        }
        self.pool = vk::DescriptorPool::null();
        self.sampler = vk::Sampler::null();
        self.pipeline = vk::Pipeline::null();
        self.layout = vk::PipelineLayout::null();
        self.set_layout = vk::DescriptorSetLayout::null();
        self.render_pass = vk::RenderPass::null();
    }
}

/// egui's clip rectangle (points) as a scissor in image pixels, within `extent`.
fn scissor(clip: egui::Rect, ppp: f32, extent: vk::Extent2D) -> vk::Rect2D {
    let x0 = (clip.min.x * ppp).round().clamp(0.0, extent.width as f32) as u32;
    let y0 = (clip.min.y * ppp).round().clamp(0.0, extent.height as f32) as u32;
    let x1 = (clip.max.x * ppp)
        .round()
        .clamp(x0 as f32, extent.width as f32) as u32;
    let y1 = (clip.max.y * ppp)
        .round()
        .clamp(y0 as f32, extent.height as f32) as u32;
    vk::Rect2D {
        offset: vk::Offset2D {
            x: x0 as i32,
            y: y0 as i32,
        },
        extent: vk::Extent2D {
            width: x1 - x0,
            height: y1 - y0,
        },
    }
}
