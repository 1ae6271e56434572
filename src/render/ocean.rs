//! The ocean renderer: uploads the simulation's textures and the LOD's instances through a
//! per-frame ring, records one multiview pass (or two passes) of at most 16 patch draws, the
//! skirt and the sky, and times the pass with GPU timestamps.
//!
//! Invariants:
//! - `frames_in_flight` (≥ 2) slots, each with its own command buffer, fence, staging buffer,
//!   instance buffer, uniform buffer, descriptor set and timestamp queries. A slot is reused
//!   only after its fence signals, so the CPU never writes memory the GPU still reads, and the
//!   frame loop never waits for the whole device.
//! - The cascade textures exist once on the GPU; each frame's copy into them is ordered after
//!   the previous frame's reads by a pipeline barrier in the same queue.
//! - Nothing here allocates per frame: every buffer, region list and set is sized at creation.

use std::time::{Duration, Instant};

use ash::vk;
use glam::Vec3;

use super::camera::Globals;
use super::commands;
use super::context::GpuContext;
use super::error::RenderError;
use super::memory::{create_view, image_barrier, Buffer, Image, ImageDesc};
use super::pipeline::{Pipelines, Push, StereoMode, DEPTH_FORMAT};
use crate::base::EyeView;
use crate::lod::{LodSettings, OceanLod, PatchInstance, StitchFlags};
use crate::sim::{pack, OceanConfig, Surfaces};

/// The most cascades the shaders read (a `vec4` of patch sizes).
pub const MAX_CASCADES: usize = 4;

/// Renderer settings fixed at creation.
#[derive(Clone, Copy, Debug)]
pub struct RendererSettings {
    /// Multiview or the two-pass fallback.
    pub stereo: StereoMode,
    /// Frames the CPU may record ahead of the GPU (≥ 2); also the staging ring's slot count.
    pub frames_in_flight: usize,
    /// Unit direction towards the sun.
    pub sun_direction: Vec3,
    /// Sun intensity (relative; 1 is an overcast disc, 8 a bright one).
    pub sun_intensity: f32,
    /// Distance (m) over which fog reaches 63% (exp(−d/fog)).
    pub fog_distance: f32,
    /// Paint the sky magenta so any sky pixel under the horizon shows (crack tests).
    pub sky_marker: bool,
}

impl Default for RendererSettings {
    fn default() -> Self {
        Self {
            stereo: StereoMode::Multiview,
            frames_in_flight: 2,
            sun_direction: Vec3::new(0.45, 0.3, -0.84).normalize(),
            sun_intensity: 8.0,
            fog_distance: 4000.0,
            sky_marker: false,
        }
    }
}

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
}

/// What one [`OceanRenderer::render`] call measured.
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

/// Timestamp queries per frame: the pass's start and end, and one spare. Mesa 25's lavapipe
/// writes a timestamp recorded after a multiview pass once per view (into queries 1 and 2),
/// and crashed writing past the end of a 2-query pool.
const TIMESTAMP_QUERIES: u32 = 3;

struct Targets {
    own_depth: Option<Image>,
    colours: usize,
    depths: usize,
    passes: usize,
    views: Vec<vk::ImageView>,
    framebuffers: Vec<vk::Framebuffer>,
}

struct Slot {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    staging: Buffer,
    instances: Buffer,
    globals: Buffer,
    set: vk::DescriptorSet,
    queries: vk::QueryPool,
    submitted: bool,
}

/// Where each mesh lives in the shared vertex and index buffers.
struct MeshLayout {
    patch_first_index: [u32; 16],
    patch_index_count: [u32; 16],
    skirt_vertex_offset: Vec<u64>,
    skirt_first_index: Vec<u32>,
    skirt_index_count: Vec<u32>,
    skirt_inner: Vec<u32>,
    boundary_level: u32,
    sky_first_index: u32,
}

/// Draws the ocean and the sky for both eyes.
pub struct OceanRenderer {
    settings: RendererSettings,
    pipelines: Pipelines,
    targets: Targets,
    extent: vk::Extent2D,
    displacement: Image,
    normals: Image,
    disp_sampler: vk::Sampler,
    normal_sampler: vk::Sampler,
    vertices: Buffer,
    indices: Buffer,
    mesh: MeshLayout,
    descriptor_pool: vk::DescriptorPool,
    slots: Vec<Slot>,
    frame: u64,
    grid: u32,
    cascades: usize,
    patch_sizes: [f32; 4],
    fade: [[f32; 4]; 2],
    vertices_per_side: u32,
    max_instances: usize,
    regions: Vec<vk::BufferImageCopy>,
    uploaded: Vec<Option<f64>>,
}

impl OceanRenderer {
    /// Creates everything for drawing `config`'s cascades on `lod`'s meshes into `targets`.
    pub fn new(
        ctx: &GpuContext,
        config: &OceanConfig,
        lod: &OceanLod,
        targets: TargetImages<'_>,
        settings: RendererSettings,
    ) -> Result<Self, RenderError> {
        if settings.frames_in_flight < 2 || settings.frames_in_flight > 4 {
            return Err(RenderError::Invalid(format!(
                "frames in flight: {} is outside [2, 4]",
                settings.frames_in_flight
            )));
        }
        if config.patch_sizes.len() > MAX_CASCADES {
            return Err(RenderError::Invalid(format!(
                "{} cascades: the renderer draws at most {MAX_CASCADES}",
                config.patch_sizes.len()
            )));
        }
        if targets.extent.width == 0 || targets.extent.height == 0 {
            return Err(RenderError::Invalid(format!(
                "target size {}x{}: both sides must be at least 1 pixel",
                targets.extent.width, targets.extent.height
            )));
        }
        let pipelines = Pipelines::new(
            ctx,
            settings.stereo,
            targets.format,
            !targets.depth.is_empty(),
        )?;
        let n = config.grid.n() as u32;
        let cascades = config.patch_sizes.len();
        let mips = config.grid.mip_levels();
        let sampled = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let displacement = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R16G16B16A16_SFLOAT,
                extent: vk::Extent2D {
                    width: n,
                    height: n,
                },
                layers: cascades as u32,
                mips: 1,
                usage: sampled,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let normals = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R8G8B8A8_UNORM,
                extent: vk::Extent2D {
                    width: n,
                    height: n,
                },
                layers: cascades as u32,
                mips,
                usage: sampled,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let disp_sampler = sampler(ctx, 0.0)?;
        let normal_sampler = sampler(ctx, mips as f32)?;

        let out_targets = Targets::new(ctx, &pipelines, targets)?;

        let (vertices, indices, mesh) = upload_meshes(ctx, lod)?;

        let frames = settings.frames_in_flight;
        let pool_sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: frames as u32,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 2 * frames as u32,
            },
        ];
        let descriptor_pool = unsafe {
            ctx.device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(frames as u32)
                    .pool_sizes(&pool_sizes),
                None,
            )
        }
        .map_err(RenderError::vk("vkCreateDescriptorPool"))?;

        let texel_bytes = (n * n) as u64 * 8 + pack::mip_chain_len(config.grid) as u64 * 4;
        let staging_size = texel_bytes * cascades as u64;
        let st = lod.settings();
        let max_instances = (st.map_width() * st.map_width()) as usize + 1;
        let mut slots = Vec::with_capacity(frames);
        for _ in 0..frames {
            slots.push(Slot::new(
                ctx,
                &pipelines,
                descriptor_pool,
                staging_size,
                max_instances,
                &displacement,
                &normals,
                disp_sampler,
                normal_sampler,
            )?);
        }
        let mut patch_sizes = [1.0; 4];
        patch_sizes[..cascades].copy_from_slice(&config.patch_sizes);
        Ok(Self {
            settings,
            pipelines,
            targets: out_targets,
            extent: targets.extent,
            displacement,
            normals,
            disp_sampler,
            normal_sampler,
            vertices,
            indices,
            mesh,
            descriptor_pool,
            slots,
            frame: 0,
            grid: n,
            cascades,
            patch_sizes,
            fade: cascade_fades(st, &patch_sizes[..cascades]),
            vertices_per_side: st.vertices(),
            max_instances,
            regions: Vec::with_capacity(cascades * (1 + mips as usize)),
            uploaded: vec![None; frames],
        })
    }

    /// The settings.
    pub fn settings(&self) -> &RendererSettings {
        &self.settings
    }

    /// Records and submits one frame into target `input.image`. Waits only for the frame that
    /// last used this slot (`frames_in_flight` frames ago).
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput<'_>,
    ) -> Result<FrameReport, RenderError> {
        let d = &ctx.device;
        let slot_index = (self.frame % self.slots.len() as u64) as usize;
        self.frame += 1;
        if input.image as usize >= self.targets.colours
            || input.depth as usize >= self.targets.depths
        {
            return Err(RenderError::Invalid(format!(
                "target image {} of {} (depth {} of {})",
                input.image, self.targets.colours, input.depth, self.targets.depths
            )));
        }
        let t0 = Instant::now();
        let slot = &mut self.slots[slot_index];
        unsafe { d.wait_for_fences(&[slot.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))?;
        let wait = t0.elapsed();
        let t1 = Instant::now();
        // The slot's fence has signalled, so its timestamps are ready (on a CPU device they
        // are read before the submit below instead).
        let mut gpu_pass = if slot.submitted && !ctx.cpu_device {
            read_timestamps(ctx, slot.queries)
        } else {
            None
        };
        // Uniforms.
        let mut g: Globals = bytemuck::Zeroable::zeroed();
        g.set_eyes(input.eyes);
        let viewer = (input.eyes[0].position + input.eyes[1].position) * 0.5;
        g.lod_viewer = viewer.extend(input.surfaces.time() as f32).to_array();
        g.sun = self
            .settings
            .sun_direction
            .extend(self.settings.sun_intensity)
            .to_array();
        g.patch_size = self.patch_sizes;
        g.fade_start = self.fade[0];
        g.fade_end = self.fade[1];
        g.params = [
            self.cascades as f32,
            self.grid as f32,
            self.settings.fog_distance,
            if self.settings.sky_marker { 1.0 } else { 0.0 },
        ];
        slot.globals.bytes_mut()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(&g));

        // Instances: the LOD's, then the skirt's.
        let lod = input.lod;
        let instances = lod.instances();
        if instances.len() + 1 > self.max_instances {
            return Err(RenderError::Invalid(format!(
                "{} instances exceed the buffer's {}",
                instances.len() + 1,
                self.max_instances
            )));
        }
        let skirt_instance = instances.len() as u32;
        {
            let bytes = slot.instances.bytes_mut();
            let src: &[u8] = bytemuck::cast_slice(instances);
            let skirt = lod.skirt_instance();
            let skirt = bytemuck::bytes_of(&skirt);
            bytes[..src.len()].copy_from_slice(src);
            bytes[src.len()..src.len() + skirt.len()].copy_from_slice(skirt);
        }

        // Textures, when the simulation moved on since this slot last uploaded.
        let time = input.surfaces.time();
        let upload = self.uploaded[slot_index] != Some(time) || self.frame <= 1;
        self.regions.clear();
        if upload {
            let grid = input.surfaces.cascades[0].grid;
            let n = grid.n() as u32;
            let bytes = slot.staging.bytes_mut();
            let mut offset = 0usize;
            for (c, s) in input.surfaces.cascades.iter().enumerate() {
                let disp: &[u8] = bytemuck::cast_slice(&s.displacement_f16);
                bytes[offset..offset + disp.len()].copy_from_slice(disp);
                self.regions.push(region(offset, c as u32, 0, n));
                offset += disp.len();
            }
            for (c, s) in input.surfaces.cascades.iter().enumerate() {
                let chain: &[u8] = bytemuck::cast_slice(&s.normal_foam);
                bytes[offset..offset + chain.len()].copy_from_slice(chain);
                for level in 0..grid.mip_levels() {
                    let at = offset + 4 * pack::mip_offset(grid, level);
                    self.regions.push(region(at, c as u32, level, n >> level));
                }
                offset += chain.len();
            }
            self.uploaded[slot_index] = Some(time);
        }
        record_begin(ctx, &self.slots[slot_index])?;
        if upload {
            let disp_regions = input.surfaces.cascades.len();
            self.record_upload(ctx, slot_index, disp_regions);
        }
        let slot = &self.slots[slot_index];
        let cmd = slot.cmd;
        let timed = ctx.timestamp_period.is_some();
        unsafe {
            if timed {
                d.cmd_reset_query_pool(cmd, slot.queries, 0, TIMESTAMP_QUERIES);
                d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, slot.queries, 0);
            }
        }
        let passes: &[u32] = match self.settings.stereo {
            StereoMode::Multiview => &[0],
            StereoMode::TwoPass => &[0, 1],
        };
        let mut draws = 0;
        for &eye in passes {
            draws += self.record_pass(ctx, slot_index, input, eye, skirt_instance);
        }
        unsafe {
            if timed {
                d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, slot.queries, 1);
            }
            d.end_command_buffer(cmd)
                .map_err(RenderError::vk("vkEndCommandBuffer"))?;
        }
        let record = t1.elapsed();
        let mut wait = wait;
        if ctx.cpu_device {
            // lavapipe idles the device in vkGetQueryPoolResults. Reading the previous frame's
            // timestamps here, after recording this one, waits only for work that this submit
            // would queue behind anyway; at the top of the frame it would also stall recording.
            let n = self.slots.len();
            let prev = &self.slots[(slot_index + n - 1) % n];
            if prev.submitted {
                let w = Instant::now();
                gpu_pass = read_timestamps(ctx, prev.queries);
                wait += w.elapsed();
            }
        }
        let t2 = Instant::now();
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // Reset only now: an error above leaves the fence signalled, so no later wait hangs.
        unsafe { d.reset_fences(&[slot.fence]) }.map_err(RenderError::vk("vkResetFences"))?;
        unsafe { d.queue_submit(ctx.queue, &submit, slot.fence) }
            .map_err(RenderError::vk("vkQueueSubmit"))?;
        self.slots[slot_index].submitted = true;
        Ok(FrameReport {
            wait,
            record,
            submit: t2.elapsed(),
            gpu_pass,
            draws,
        })
    }

    fn record_upload(&self, ctx: &GpuContext, slot_index: usize, disp_regions: usize) {
        let d = &ctx.device;
        let slot = &self.slots[slot_index];
        let color = vk::ImageAspectFlags::COLOR;
        let to_dst = [
            image_barrier(
                self.displacement.raw,
                color,
                self.displacement.layers,
                1,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::SHADER_READ,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            image_barrier(
                self.normals.raw,
                color,
                self.normals.layers,
                self.normals.mips,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::SHADER_READ,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
        ];
        let to_read = to_dst.map(|b| {
            b.old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ)
        });
        let shaders =
            vk::PipelineStageFlags::VERTEX_SHADER | vk::PipelineStageFlags::FRAGMENT_SHADER;
        unsafe {
            d.cmd_pipeline_barrier(
                slot.cmd,
                shaders,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_dst,
            );
            d.cmd_copy_buffer_to_image(
                slot.cmd,
                slot.staging.raw,
                self.displacement.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &self.regions[..disp_regions],
            );
            d.cmd_copy_buffer_to_image(
                slot.cmd,
                slot.staging.raw,
                self.normals.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &self.regions[disp_regions..],
            );
            d.cmd_pipeline_barrier(
                slot.cmd,
                vk::PipelineStageFlags::TRANSFER,
                shaders,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_read,
            );
        }
    }

    /// Records one render pass (both eyes with multiview, else eye `eye`); returns its draws.
    fn record_pass(
        &self,
        ctx: &GpuContext,
        slot_index: usize,
        input: &FrameInput<'_>,
        eye: u32,
        skirt_instance: u32,
    ) -> u32 {
        let (image, depth, lod) = (input.image, input.depth, input.lod);
        let d = &ctx.device;
        let slot = &self.slots[slot_index];
        let cmd = slot.cmd;
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
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: self.extent,
        };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(self.pipelines.render_pass)
            .framebuffer(self.targets.framebuffer(image, depth, eye))
            .render_area(area)
            .clear_values(&clear);
        let p = &self.pipelines;
        let mut push = Push {
            eye,
            mode: 0,
            inner_count: 0,
            grid_v: self.vertices_per_side,
        };
        let mut draws = 0;
        unsafe {
            d.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            d.cmd_set_viewport(
                cmd,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: self.extent.width as f32,
                    height: self.extent.height as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            d.cmd_set_scissor(cmd, 0, &[area]);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.ocean);
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                p.layout,
                0,
                &[slot.set],
                &[],
            );
            d.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw, slot.instances.raw], &[0, 0]);
            d.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT16);
            d.cmd_push_constants(
                cmd,
                p.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
            for draw in lod.draws() {
                let k = draw.stitch.bits() as usize;
                d.cmd_draw_indexed(
                    cmd,
                    self.mesh.patch_index_count[k],
                    draw.instance_count,
                    self.mesh.patch_first_index[k],
                    0,
                    draw.first_instance,
                );
                draws += 1;
            }
            let ring = (lod.tree().ring_level() - self.mesh.boundary_level) as usize;
            push.mode = 1;
            push.inner_count = self.mesh.skirt_inner[ring];
            d.cmd_push_constants(
                cmd,
                p.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_bind_vertex_buffers(
                cmd,
                0,
                &[self.vertices.raw],
                &[self.mesh.skirt_vertex_offset[ring]],
            );
            d.cmd_draw_indexed(
                cmd,
                self.mesh.skirt_index_count[ring],
                1,
                self.mesh.skirt_first_index[ring],
                0,
                skirt_instance,
            );
            draws += 1;
            // The sky: mode 2 of the same pipeline, vertices from gl_VertexIndex (indexed with
            // 0, 1, 2: lavapipe's multiview drew a non-indexed draw into the first view only).
            push.mode = 2;
            d.cmd_push_constants(
                cmd,
                p.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_draw_indexed(cmd, 6, 1, self.mesh.sky_first_index, 0, 0);
            draws += 1;
            d.cmd_end_render_pass(cmd);
        }
        draws
    }

    /// Waits for every frame in flight (shutdown and read-back only).
    pub fn wait_all(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        let fences: [vk::Fence; 4] =
            std::array::from_fn(|i| self.slots.get(i).map_or(vk::Fence::null(), |s| s.fence));
        unsafe {
            ctx.device
                .wait_for_fences(&fences[..self.slots.len()], true, u64::MAX)
        }
        .map_err(RenderError::vk("vkWaitForFences"))
    }

    /// Frees everything. The caller makes sure the GPU is idle (e.g. [`GpuContext::wait_idle`]).
    pub fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        for mut s in self.slots.drain(..) {
            s.staging.destroy(ctx);
            s.instances.destroy(ctx);
            s.globals.destroy(ctx);
            unsafe {
                d.destroy_fence(s.fence, None);
                d.destroy_command_pool(s.pool, None);
                d.destroy_query_pool(s.queries, None);
            }
        }
        self.targets.destroy(ctx);
        unsafe {
            d.destroy_descriptor_pool(self.descriptor_pool, None);
            d.destroy_sampler(self.disp_sampler, None);
            d.destroy_sampler(self.normal_sampler, None);
        }
        self.displacement.destroy(ctx);
        self.normals.destroy(ctx);
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
        self.pipelines.destroy(ctx);
    }
}

fn record_begin(ctx: &GpuContext, slot: &Slot) -> Result<(), RenderError> {
    unsafe {
        ctx.device
            .reset_command_pool(slot.pool, vk::CommandPoolResetFlags::empty())
            .map_err(RenderError::vk("vkResetCommandPool"))?;
        ctx.device
            .begin_command_buffer(
                slot.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(RenderError::vk("vkBeginCommandBuffer"))
    }
}

fn read_timestamps(ctx: &GpuContext, pool: vk::QueryPool) -> Option<Duration> {
    let period = ctx.timestamp_period?;
    let mut t = [0u64; 2];
    unsafe {
        ctx.device
            .get_query_pool_results(pool, 0, &mut t, vk::QueryResultFlags::TYPE_64)
            .ok()?;
    }
    let ticks = t[1].checked_sub(t[0])?;
    Some(Duration::from_nanos((ticks as f64 * period as f64) as u64))
}

fn region(offset: usize, layer: u32, level: u32, side: u32) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset: offset as u64,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: level,
            base_array_layer: layer,
            layer_count: 1,
        },
        image_offset: vk::Offset3D::default(),
        image_extent: vk::Extent3D {
            width: side,
            height: side,
            depth: 1,
        },
    }
}

fn sampler(ctx: &GpuContext, max_lod: f32) -> Result<vk::Sampler, RenderError> {
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(vk::Filter::LINEAR)
        .min_filter(vk::Filter::LINEAR)
        .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
        .address_mode_u(vk::SamplerAddressMode::REPEAT)
        .address_mode_v(vk::SamplerAddressMode::REPEAT)
        .address_mode_w(vk::SamplerAddressMode::REPEAT)
        .min_lod(0.0)
        .max_lod(max_lod);
    unsafe { ctx.device.create_sampler(&info, None) }.map_err(RenderError::vk("vkCreateSampler"))
}

/// Per cascade, the distances (m) where its displacement starts and ends fading from the mesh.
///
/// A level-l patch (vertex spacing s_l/V) is split once the viewer is nearer than K·s_l to its
/// square ([`LodSettings::split_distance`]), so at distance d the mesh spacing is at most about
/// d/(K·V); with a factor 2 for vertices up to a patch diagonal beyond the square, 2d/(K·V). A
/// cascade of patch L keeps its displacement while that spacing is under L/8 and is gone where
/// it reaches L/4, beyond which its shorter waves would alias into noise on the coarser mesh
/// (the normals, sampled per pixel with mips, still show them).
fn cascade_fades(st: &LodSettings, patch_sizes: &[f32]) -> [[f32; 4]; 2] {
    let mut out = [[f32::MAX; 4], [f32::MAX; 4]];
    let kv = st.preset().split_scale() * st.vertices() as f32;
    for (c, &l) in patch_sizes.iter().enumerate() {
        let end = l * kv / 8.0;
        out[0][c] = 0.5 * end;
        out[1][c] = end;
    }
    out
}

impl Targets {
    /// Views and framebuffers for every pair of a colour image and a depth image (the given
    /// depth images, or one transient image of our own shared by all frames: the render pass's
    /// external dependency orders its reuse).
    fn new(ctx: &GpuContext, p: &Pipelines, t: TargetImages<'_>) -> Result<Self, RenderError> {
        let own_depth = if t.depth.is_empty() {
            Some(Image::new(
                ctx,
                ImageDesc {
                    format: DEPTH_FORMAT,
                    extent: t.extent,
                    layers: 2,
                    mips: 1,
                    usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                    aspect: vk::ImageAspectFlags::DEPTH,
                    transient: true,
                },
            )?)
        } else {
            None
        };
        let layouts: &[(u32, u32)] = match p.mode {
            StereoMode::Multiview => &[(0, 2)],
            StereoMode::TwoPass => &[(0, 1), (1, 1)],
        };
        let depth_images: Vec<vk::Image> = match &own_depth {
            Some(d) => vec![d.raw],
            None => t.depth.to_vec(),
        };
        let mut out = Self {
            own_depth,
            colours: t.images.len(),
            depths: depth_images.len(),
            passes: layouts.len(),
            views: Vec::new(),
            framebuffers: Vec::new(),
        };
        if let Err(e) = out.create_views(ctx, p, t, layouts, &depth_images) {
            out.destroy(ctx);
            return Err(e);
        }
        Ok(out)
    }

    fn create_views(
        &mut self,
        ctx: &GpuContext,
        p: &Pipelines,
        t: TargetImages<'_>,
        layouts: &[(u32, u32)],
        depth_images: &[vk::Image],
    ) -> Result<(), RenderError> {
        let out = self;
        let colour = vk::ImageAspectFlags::COLOR;
        let depth_aspect = vk::ImageAspectFlags::DEPTH;
        // Views first: [colour image][pass] then [depth image][pass].
        for &image in t.images {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, t.format, colour, base, count, 1);
                out.views.push(v?);
            }
        }
        for &image in depth_images {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, DEPTH_FORMAT, depth_aspect, base, count, 1);
                out.views.push(v?);
            }
        }
        let depth_view0 = out.colours * out.passes;
        for c in 0..out.colours {
            for d in 0..out.depths {
                for pass in 0..out.passes {
                    let attachments = [
                        out.views[c * out.passes + pass],
                        out.views[depth_view0 + d * out.passes + pass],
                    ];
                    // SAFETY: the views and the render pass are alive and compatible.
                    let fb = unsafe {
                        ctx.device.create_framebuffer(
                            &vk::FramebufferCreateInfo::default()
                                .render_pass(p.render_pass)
                                .attachments(&attachments)
                                .width(t.extent.width)
                                .height(t.extent.height)
                                .layers(1),
                            None,
                        )
                    }
                    .map_err(RenderError::vk("vkCreateFramebuffer"));
                    out.framebuffers.push(fb?);
                }
            }
        }
        Ok(())
    }

    /// The framebuffer of colour image `colour`, depth image `depth` and pass `pass`.
    fn framebuffer(&self, colour: u32, depth: u32, pass: u32) -> vk::Framebuffer {
        let i = (colour as usize * self.depths + depth as usize) * self.passes + pass as usize;
        self.framebuffers[i]
    }

    fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses them (the owner waited for idle or never submitted).
        unsafe {
            for f in self.framebuffers.drain(..) {
                ctx.device.destroy_framebuffer(f, None);
            }
            for v in self.views.drain(..) {
                ctx.device.destroy_image_view(v, None);
            }
        }
        if let Some(mut d) = self.own_depth.take() {
            d.destroy(ctx);
        }
    }
}

impl Slot {
    #[allow(clippy::too_many_arguments)]
    fn new(
        ctx: &GpuContext,
        p: &Pipelines,
        descriptor_pool: vk::DescriptorPool,
        staging_size: u64,
        max_instances: usize,
        displacement: &Image,
        normals: &Image,
        disp_sampler: vk::Sampler,
        normal_sampler: vk::Sampler,
    ) -> Result<Self, RenderError> {
        let d = &ctx.device;
        let pool = commands::command_pool(ctx, vk::CommandPoolCreateFlags::TRANSIENT)?;
        let cmd = commands::primary_buffers(ctx, pool, 1)?[0];
        let fence = commands::fence(ctx, true)?;
        let staging = Buffer::new(ctx, staging_size, vk::BufferUsageFlags::TRANSFER_SRC, true)?;
        let instances = Buffer::new(
            ctx,
            (max_instances * std::mem::size_of::<PatchInstance>()) as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            true,
        )?;
        let globals = Buffer::new(
            ctx,
            std::mem::size_of::<Globals>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            true,
        )?;
        let layouts = [p.set_layout];
        let set = unsafe {
            d.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(descriptor_pool)
                    .set_layouts(&layouts),
            )
        }
        .map_err(RenderError::vk("vkAllocateDescriptorSets"))?[0];
        let ubo = [vk::DescriptorBufferInfo {
            buffer: globals.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let disp = [vk::DescriptorImageInfo {
            sampler: disp_sampler,
            image_view: displacement.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let norm = [vk::DescriptorImageInfo {
            sampler: normal_sampler,
            image_view: normals.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let writes = [
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&ubo),
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(1)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(&disp),
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(2)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(&norm),
        ];
        unsafe { d.update_descriptor_sets(&writes, &[]) };
        let queries = unsafe {
            d.create_query_pool(
                &vk::QueryPoolCreateInfo::default()
                    .query_type(vk::QueryType::TIMESTAMP)
                    .query_count(TIMESTAMP_QUERIES),
                None,
            )
        }
        .map_err(RenderError::vk("vkCreateQueryPool"))?;
        Ok(Self {
            pool,
            cmd,
            fence,
            staging,
            instances,
            globals,
            set,
            queries,
            submitted: false,
        })
    }
}

/// Uploads the patch grid, its 16 index sets and every skirt once, through a staging buffer.
fn upload_meshes(
    ctx: &GpuContext,
    lod: &OceanLod,
) -> Result<(Buffer, Buffer, MeshLayout), RenderError> {
    let mesh = lod.mesh();
    let st = lod.settings();
    let mut verts: Vec<[f32; 3]> = mesh.positions().to_vec();
    let mut idx: Vec<u16> = Vec::new();
    let mut layout = MeshLayout {
        patch_first_index: [0; 16],
        patch_index_count: [0; 16],
        skirt_vertex_offset: Vec::new(),
        skirt_first_index: Vec::new(),
        skirt_index_count: Vec::new(),
        skirt_inner: Vec::new(),
        boundary_level: st.boundary_level(),
        sky_first_index: 0,
    };
    for k in 0..16u8 {
        let set = mesh.indices(StitchFlags::from_bits(k));
        layout.patch_first_index[k as usize] = idx.len() as u32;
        layout.patch_index_count[k as usize] = set.len() as u32;
        idx.extend_from_slice(set);
    }
    for ring in st.boundary_level()..=st.max_level() {
        let skirt = lod.skirt_for_ring(ring);
        layout.skirt_vertex_offset.push((verts.len() * 12) as u64);
        layout.skirt_first_index.push(idx.len() as u32);
        layout.skirt_index_count.push(skirt.indices().len() as u32);
        layout.skirt_inner.push(skirt.inner_vertex_count());
        verts.extend_from_slice(skirt.positions());
        idx.extend_from_slice(skirt.indices());
    }
    layout.sky_first_index = idx.len() as u32;
    idx.extend_from_slice(&[0, 1, 2, 2, 1, 3]);
    if idx.len() % 2 == 1 {
        idx.push(0);
    }
    let vbytes: &[u8] = bytemuck::cast_slice(&verts);
    let ibytes: &[u8] = bytemuck::cast_slice(&idx);
    let vertices = Buffer::new(
        ctx,
        vbytes.len() as u64,
        vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        false,
    )?;
    let indices = Buffer::new(
        ctx,
        ibytes.len() as u64,
        vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        false,
    )?;
    let mut staging = Buffer::new(
        ctx,
        (vbytes.len() + ibytes.len()) as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        true,
    )?;
    staging.bytes_mut()[..vbytes.len()].copy_from_slice(vbytes);
    staging.bytes_mut()[vbytes.len()..].copy_from_slice(ibytes);
    super::one_shot(ctx, |cmd| unsafe {
        ctx.device.cmd_copy_buffer(
            cmd,
            staging.raw,
            vertices.raw,
            &[vk::BufferCopy {
                src_offset: 0,
                dst_offset: 0,
                size: vbytes.len() as u64,
            }],
        );
        ctx.device.cmd_copy_buffer(
            cmd,
            staging.raw,
            indices.raw,
            &[vk::BufferCopy {
                src_offset: vbytes.len() as u64,
                dst_offset: 0,
                size: ibytes.len() as u64,
            }],
        );
    })?;
    staging.destroy(ctx);
    Ok((vertices, indices, layout))
}
