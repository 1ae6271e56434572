//! The calibration passes of `vr-ocean gpu-budget --calibrate`: full-screen fragment shaders of
//! a known amount of one kind of work (FP32, relaxed-precision and special-function arithmetic,
//! trilinear and anisotropic samples), and grids of small triangles, drawn in the ocean's own
//! stereo pass (its render pass, eye size, MSAA, stereo mode, colour format, resolve and
//! sampler settings), each timed by GPU timestamps around the pass as the ocean's pass is
//! timed. `render::budget::calibration` turns the times into the device's costs and predicts
//! the ocean pass from them.
//!
//! - [`kernels`]: what each pass draws and measures;
//! - this file: the [`Calibrator`], which owns the pass's targets, the sampled texture, the
//!   pipelines and the queries, and times one kernel at a time.
//!
//! Set-up and measuring only: it waits for each submission, never runs in a user's frame loop.

pub mod kernels;

use std::time::Duration;

use ash::vk;

use self::kernels::{Geometry, Kernel, Shader};
use super::barrier::Access;
use super::commands;
use super::context::GpuContext;
use super::error::RenderError;
use super::memory::{Image, ImageDesc};
use super::ocean::TargetImages;
use super::program::{build, pipeline_layout, Blend, Depth, Program, Target};
use super::render_pass::{render_pass, PassLayout, StereoMode};
use super::sampler::{sampler, sampler_of};
use super::shaders;
use super::targets::{resolve_eye, Targets};
use super::upload::{upload_levels, Level};

/// Push constants of the calibration pipelines (`Push` in `shaders/calibrate.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct KernelPush {
    /// The kernels' operands: x scales the position into the first value; y, z, w are the
    /// arithmetic's operands.
    pub k: [f32; 4],
    /// The same, read in relaxed precision by the relaxed kernel.
    pub kh: [f32; 4],
    /// x, y: the grid's cells across and down (0: one triangle over the viewport); z: a
    /// cell's side (pixels).
    pub grid: [u32; 4],
    /// x, y: the viewport (pixels).
    pub viewport: [u32; 4],
}

/// The operands every kernel runs with: values the compiler cannot see, chosen so that the
/// arithmetic stays finite and never denormal (the fma-min-add rounds settle near 1).
const OPERANDS: [f32; 4] = [1.0 / 4096.0, 0.5, 0.5, 1.0];

/// Texels a side of the sampled texture: the ocean's normal maps' at its default 256² grid.
pub const TEXTURE_SIDE: u32 = 256;

/// What the calibration draws into and samples with: the ocean pass's settings.
#[derive(Clone, Copy, Debug)]
pub struct CalibrationSettings {
    /// Multiview or two passes, MSAA, the eye images' format (the pass's own layout).
    pub pass: PassLayout,
    /// Pixels of each eye.
    pub eye: vk::Extent2D,
    /// The anisotropic sampler's most taps (as the ocean's normal maps get; 1: trilinear).
    pub anisotropy_taps: u32,
}

/// The calibration pass's objects (see the module docs).
pub struct Calibrator {
    settings: CalibrationSettings,
    render_pass: vk::RenderPass,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    descriptor_pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    texture: Image,
    trilinear: vk::Sampler,
    anisotropic: vk::Sampler,
    colour: Image,
    targets: Option<Targets>,
    pipelines: Vec<(Shader, vk::Pipeline)>,
    queries: vk::QueryPool,
    command_pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// How the eye image was last used (its resolve after the pass starts from there).
    eye_access: Access,
}

impl Calibrator {
    /// Makes everything for `settings`; nothing is left behind when a step fails. Needs GPU
    /// timestamps.
    pub fn new(ctx: &GpuContext, settings: CalibrationSettings) -> Result<Self, RenderError> {
        if ctx.timestamp_period.is_none() {
            return Err(RenderError::Unsupported(
                "GPU timestamps on the graphics queue (the calibration times passes)".into(),
            ));
        }
        if settings.pass.mode == StereoMode::Multiview && !ctx.multiview {
            return Err(RenderError::Unsupported("the multiview feature".into()));
        }
        if settings.pass.density_map || settings.pass.store_depth {
            return Err(RenderError::Invalid(
                "the calibration draws without a density map or a kept depth".into(),
            ));
        }
        let mut this = Self {
            settings,
            render_pass: vk::RenderPass::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            descriptor_pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            texture: Image::null(),
            trilinear: vk::Sampler::null(),
            anisotropic: vk::Sampler::null(),
            colour: Image::null(),
            targets: None,
            pipelines: Vec::new(),
            queries: vk::QueryPool::null(),
            command_pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            eye_access: Access::Nothing,
        };
        if let Err(e) = this.create(ctx) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let d = &ctx.device;
        let s = self.settings;
        self.render_pass = render_pass(ctx, &s.pass)?;
        let bindings = [0, 1].map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT)
        });
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: a valid create info on a live device.
        self.set_layout = ctx.create("vkCreateDescriptorSetLayout", || unsafe {
            d.create_descriptor_set_layout(&info, None)
        })?;
        self.layout = pipeline_layout(
            ctx,
            self.set_layout,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            std::mem::size_of::<KernelPush>(),
        )?;
        self.make_texture(ctx)?;
        self.make_set(ctx)?;
        // The eye images: one, both layers, as the XR backend's.
        self.colour = Image::new(
            ctx,
            ImageDesc {
                format: s.pass.colour_format,
                extent: s.eye,
                layers: 2,
                mips: 1,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let images = [self.colour.raw];
        self.targets = Some(Targets::new(
            ctx,
            &s.pass,
            self.render_pass,
            TargetImages {
                images: &images,
                format: s.pass.colour_format,
                extent: s.eye,
                depth: &[],
                density_maps: &[],
            },
        )?);
        let target = Target {
            layout: self.layout,
            render_pass: self.render_pass,
            msaa: s.pass.msaa,
        };
        for shader in Shader::ALL {
            let program = Program {
                label: shader.label(),
                vert: shaders::CALIBRATE_VERT,
                frag: shader.spirv(),
                bindings: Vec::new(),
                attributes: Vec::new(),
                cull: vk::CullModeFlags::NONE,
                blend: Blend::Opaque,
                depth: Depth::ReversedZ,
            };
            let pipeline = build(ctx, &program, target)?;
            self.pipelines.push((shader, pipeline));
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2);
        // SAFETY: a valid create info on a live device.
        self.queries = ctx.create("vkCreateQueryPool", || unsafe {
            d.create_query_pool(&info, None)
        })?;
        self.command_pool =
            commands::command_pool(ctx, vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
        self.cmd = commands::primary_buffers(ctx, self.command_pool, 1)?[0];
        self.fence = commands::fence(ctx, false)?;
        Ok(())
    }

    /// The sampled texture (RGBA8 with every mip, as the ocean's normal maps; value noise so
    /// that no two texels repeat a pattern a cache could exploit) and its two samplers.
    fn make_texture(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let mips = TEXTURE_SIDE.ilog2() + 1;
        self.texture = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R8G8B8A8_UNORM,
                extent: vk::Extent2D {
                    width: TEXTURE_SIDE,
                    height: TEXTURE_SIDE,
                },
                layers: 1,
                mips,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let texels: Vec<Vec<u8>> = (0..mips)
            .map(|m| {
                let side = (TEXTURE_SIDE >> m).max(1) as usize;
                noise_bytes(side * side * 4, m)
            })
            .collect();
        let levels: Vec<Level<'_>> = texels
            .iter()
            .enumerate()
            .map(|(m, bytes)| {
                let side = (TEXTURE_SIDE >> m).max(1);
                Level {
                    bytes,
                    width: side,
                    height: side,
                }
            })
            .collect();
        upload_levels(ctx, &self.texture, &levels)?;
        self.trilinear = sampler(ctx, mips as f32)?;
        let taps = self.settings.anisotropy_taps.max(1) as f32;
        let repeat = [vk::SamplerAddressMode::REPEAT; 2];
        self.anisotropic = sampler_of(ctx, mips as f32, repeat, taps)?;
        Ok(())
    }

    /// The descriptor set: the texture through the trilinear (binding 0) and the anisotropic
    /// sampler (binding 1).
    fn make_set(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        let d = &ctx.device;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            descriptor_count: 2,
        }];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: a valid create info on a live device.
        self.descriptor_pool = ctx.create("vkCreateDescriptorPool", || unsafe {
            d.create_descriptor_pool(&info, None)
        })?;
        let layouts = [self.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.descriptor_pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for the one set of this layout.
        self.set = ctx.create("vkAllocateDescriptorSets", || unsafe {
            d.allocate_descriptor_sets(&alloc)
        })?[0];
        let images = [self.trilinear, self.anisotropic].map(|sampler| {
            [vk::DescriptorImageInfo {
                sampler,
                image_view: self.texture.view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            }]
        });
        let writes = [0usize, 1].map(|b| {
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(b as u32)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(&images[b])
        });
        // SAFETY: the set, the view and the samplers are alive; the set is not in use.
        unsafe { d.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }

    /// The GPU time of `kernel`'s pass, once per repetition (`repeats` submissions, each waited
    /// for): from a timestamp before the pass to one after it (and its resolve, with two
    /// passes), as the ocean's pass is timed.
    pub fn time(
        &mut self,
        ctx: &GpuContext,
        kernel: Kernel,
        repeats: usize,
    ) -> Result<Vec<Duration>, RenderError> {
        let mut out = Vec::with_capacity(repeats);
        for _ in 0..repeats {
            self.record(ctx, kernel)?;
            out.push(self.submit_and_read(ctx)?);
        }
        Ok(out)
    }

    /// Records one timed pass of `kernel` into the command buffer.
    fn record(&mut self, ctx: &GpuContext, kernel: Kernel) -> Result<(), RenderError> {
        let d = &ctx.device;
        let cmd = self.cmd;
        let s = self.settings;
        let Some(targets) = self.targets.as_ref() else {
            return Err(RenderError::Invalid("the calibrator was destroyed".into()));
        };
        let pipeline = self
            .pipelines
            .iter()
            .find(|(sh, _)| *sh == kernel.shader)
            .map(|(_, p)| *p)
            .ok_or_else(|| RenderError::Invalid(format!("no pipeline for {}", kernel.name())))?;
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: s.eye,
        };
        let [cells_x, cells_y] = kernel.cells(s.eye.width, s.eye.height);
        let cell = match kernel.geometry {
            Geometry::Grid(cell) => cell,
            _ => 0,
        };
        let push = KernelPush {
            k: OPERANDS,
            kh: OPERANDS,
            grid: [cells_x, cells_y, cell, 0],
            viewport: [s.eye.width, s.eye.height, 0, 0],
        };
        let vertices = kernel.vertices(s.eye.width, s.eye.height);
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.0, 0.0, 0.0, 1.0],
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
                    stencil: 0,
                },
            },
        ];
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: s.eye.width as f32,
            height: s.eye.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let passes: &[u32] = match s.pass.mode {
            StereoMode::Multiview => &[0],
            StereoMode::TwoPass => &[0, 1],
        };
        // SAFETY: the command buffer is not pending (its last submission was waited for) and
        // its pool allows resetting it.
        unsafe {
            d.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .map_err(RenderError::vk("vkResetCommandBuffer"))?;
            d.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(RenderError::vk("vkBeginCommandBuffer"))?;
            d.cmd_reset_query_pool(cmd, self.queries, 0, 2);
            d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, self.queries, 0);
        }
        let msaa = targets.msaa_colour();
        for &eye in passes {
            let begin = vk::RenderPassBeginInfo::default()
                .render_pass(self.render_pass)
                .framebuffer(targets.framebuffer(0, 0, eye))
                .render_area(area)
                .clear_values(&clear);
            // SAFETY: `cmd` is recording outside a render pass; the framebuffer, pipeline,
            // layout and set are alive and made for this render pass; the draw reads no
            // vertex buffer.
            unsafe {
                d.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
                if kernel.geometry != Geometry::Empty {
                    d.cmd_set_viewport(cmd, 0, &[viewport]);
                    d.cmd_set_scissor(cmd, 0, &[area]);
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                    d.cmd_bind_descriptor_sets(
                        cmd,
                        vk::PipelineBindPoint::GRAPHICS,
                        self.layout,
                        0,
                        &[self.set],
                        &[],
                    );
                    d.cmd_push_constants(
                        cmd,
                        self.layout,
                        vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                    d.cmd_draw(cmd, vertices, 1, 0, 0);
                }
                d.cmd_end_render_pass(cmd);
            }
            if let (true, Some(msaa)) = (s.pass.resolves_after_pass(), msaa) {
                resolve_eye(d, cmd, msaa, self.colour.raw, eye, area, self.eye_access);
                self.eye_access = Access::ColourAttachment;
            }
        }
        // SAFETY: `cmd` is recording, outside a render pass.
        unsafe {
            d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, self.queries, 1);
            d.end_command_buffer(cmd)
                .map_err(RenderError::vk("vkEndCommandBuffer"))?;
        }
        Ok(())
    }

    /// Submits the recorded pass, waits for it and reads its two timestamps.
    fn submit_and_read(&self, ctx: &GpuContext) -> Result<Duration, RenderError> {
        let d = &ctx.device;
        let cmds = [self.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the command buffer is executable, the fence unsignalled; the queue is used
        // from this thread only while calibrating.
        unsafe {
            d.queue_submit(ctx.queue, &submit, self.fence)
                .map_err(RenderError::vk("vkQueueSubmit"))?;
            d.wait_for_fences(&[self.fence], true, u64::MAX)
                .map_err(RenderError::vk("vkWaitForFences"))?;
            d.reset_fences(&[self.fence])
                .map_err(RenderError::vk("vkResetFences"))?;
        }
        let mut stamps = [0u64; 2];
        // SAFETY: both queries were written by the finished submission.
        unsafe {
            d.get_query_pool_results(
                self.queries,
                0,
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(RenderError::vk("vkGetQueryPoolResults"))?;
        let period = f64::from(ctx.timestamp_period.unwrap_or(1.0));
        let ticks = stamps[1].saturating_sub(stamps[0]) as f64;
        Ok(Duration::from_secs_f64(ticks * period * 1e-9))
    }

    /// Frees everything (null handles are skipped). The GPU must be done with it (every
    /// submission here is waited for).
    pub fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        if let Some(mut t) = self.targets.take() {
            t.destroy(ctx);
        }
        self.colour.destroy(ctx);
        self.texture.destroy(ctx);
        // SAFETY: nothing submitted is pending; null handles are no-ops.
        unsafe {
            for (_, p) in self.pipelines.drain(..) {
                d.destroy_pipeline(p, None);
            }
            d.destroy_fence(self.fence, None);
            d.destroy_command_pool(self.command_pool, None);
            d.destroy_query_pool(self.queries, None);
            d.destroy_sampler(self.trilinear, None);
            d.destroy_sampler(self.anisotropic, None);
            d.destroy_descriptor_pool(self.descriptor_pool, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            d.destroy_render_pass(self.render_pass, None);
        }
        self.fence = vk::Fence::null();
        self.command_pool = vk::CommandPool::null();
        self.queries = vk::QueryPool::null();
        self.trilinear = vk::Sampler::null();
        self.anisotropic = vk::Sampler::null();
        self.descriptor_pool = vk::DescriptorPool::null();
        self.layout = vk::PipelineLayout::null();
        self.set_layout = vk::DescriptorSetLayout::null();
        self.render_pass = vk::RenderPass::null();
    }
}

/// `len` bytes of hashed noise (level `salt`), the same on every run.
fn noise_bytes(len: usize, salt: u32) -> Vec<u8> {
    (0..len as u32)
        .map(|i| {
            let mut h = i.wrapping_mul(0x9E37_79B9) ^ salt.wrapping_mul(0x85EB_CA6B);
            h ^= h >> 15;
            h = h.wrapping_mul(0x2C1B_3C6D);
            h ^= h >> 12;
            (h >> 24) as u8
        })
        .collect()
}
