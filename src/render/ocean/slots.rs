//! Frame slots: `frames_in_flight` (≥ 2) sets of what one frame writes from the CPU (command
//! buffer, fence, staging buffer, instance buffer, uniform buffer, descriptor set, timestamp
//! queries). A slot is reused only after its fence signals, so the CPU never writes memory the
//! GPU still reads, and the frame loop never waits for the whole device.
//!
//! On a CPU device (lavapipe), whose `vkGetQueryPoolResults` idles the device, the previous
//! frame's timestamps are read just before submitting, where the queue would serialize anyway.

use std::time::Duration;

use ash::vk;

use super::pipelines::Pipelines;
use super::solids::{Shape, Solid, SolidInstance, MAX_SOLIDS};
use crate::lod::{OceanLod, PatchInstance};
use crate::render::camera::Globals;
use crate::render::commands;
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::Buffer;

/// Timestamp queries per frame: the pass's start and end, and one spare. Mesa 25's lavapipe
/// writes a timestamp recorded after a multiview pass once per view (into queries 1 and 2),
/// and crashed writing past the end of a 2-query pool.
pub(super) const TIMESTAMP_QUERIES: u32 = 3;

/// Sizes of a slot's buffers.
#[derive(Clone, Copy, Debug)]
pub(super) struct SlotSizes {
    /// Staging bytes for one upload of the cascade textures.
    pub staging: u64,
    /// Instances the instance buffer holds (the LOD's worst case plus the skirt).
    pub instances: usize,
}

/// One frame's CPU-written resources.
pub(super) struct Slot {
    pool: vk::CommandPool,
    /// The frame's command buffer.
    pub cmd: vk::CommandBuffer,
    /// Signalled when the frame's commands finished.
    pub fence: vk::Fence,
    /// Mapped staging memory for the texture upload.
    pub staging: Buffer,
    /// Mapped per-instance vertex data.
    pub instances: Buffer,
    /// Mapped per-instance data of the solids, grouped by shape.
    pub solids: Buffer,
    globals: Buffer,
    /// Set 0 of the pipeline: the globals and both texture arrays.
    pub set: vk::DescriptorSet,
    /// Timestamps of the pass.
    pub queries: vk::QueryPool,
    /// Whether the slot was ever submitted (its queries hold results).
    pub submitted: bool,
    /// The simulation time this slot last uploaded.
    pub uploaded: Option<f64>,
}

/// The ring of slots and the descriptor pool their sets come from.
pub(super) struct Slots {
    descriptor_pool: vk::DescriptorPool,
    /// The slots, used round-robin.
    pub ring: Vec<Slot>,
}

impl Slots {
    /// `frames` slots with buffers of `sizes`, their sets pointing at `textures`. Nothing is
    /// left behind when a step fails.
    pub fn new(
        ctx: &GpuContext,
        pipelines: &Pipelines,
        images: &[vk::DescriptorImageInfo; 7],
        tally: Option<vk::DescriptorBufferInfo>,
        sizes: SlotSizes,
        frames: usize,
    ) -> Result<Self, RenderError> {
        let mut this = Self {
            descriptor_pool: vk::DescriptorPool::null(),
            ring: Vec::with_capacity(frames),
        };
        if let Err(e) = this.create(ctx, pipelines, images, tally, sizes, frames) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(
        &mut self,
        ctx: &GpuContext,
        pipelines: &Pipelines,
        images: &[vk::DescriptorImageInfo; 7],
        tally: Option<vk::DescriptorBufferInfo>,
        sizes: SlotSizes,
        frames: usize,
    ) -> Result<(), RenderError> {
        let pool_sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: frames as u32,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: frames as u32,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 7 * frames as u32,
            },
        ];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(frames as u32)
            .pool_sizes(&pool_sizes);
        // SAFETY: a valid create info on a live device.
        self.descriptor_pool = ctx.create("vkCreateDescriptorPool", || unsafe {
            ctx.device.create_descriptor_pool(&info, None)
        })?;
        for _ in 0..frames {
            let slot = Slot::new(ctx, pipelines, self.descriptor_pool, images, tally, sizes)?;
            self.ring.push(slot);
        }
        Ok(())
    }

    /// Frees every slot and the pool. The GPU must be done with them.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        for mut s in self.ring.drain(..) {
            s.destroy(ctx);
        }
        // SAFETY: the GPU no longer uses the sets; a null pool is a no-op.
        unsafe {
            ctx.device
                .destroy_descriptor_pool(self.descriptor_pool, None)
        };
        self.descriptor_pool = vk::DescriptorPool::null();
    }
}

impl Slot {
    /// One slot. Nothing is left behind when a step fails (its set goes with the pool).
    fn new(
        ctx: &GpuContext,
        p: &Pipelines,
        descriptor_pool: vk::DescriptorPool,
        images: &[vk::DescriptorImageInfo; 7],
        tally: Option<vk::DescriptorBufferInfo>,
        sizes: SlotSizes,
    ) -> Result<Self, RenderError> {
        let mut slot = Self {
            pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            staging: Buffer::null(),
            instances: Buffer::null(),
            solids: Buffer::null(),
            globals: Buffer::null(),
            set: vk::DescriptorSet::null(),
            queries: vk::QueryPool::null(),
            submitted: false,
            uploaded: None,
        };
        if let Err(e) = slot.create(ctx, p, descriptor_pool, images, tally, sizes) {
            slot.destroy(ctx);
            return Err(e);
        }
        Ok(slot)
    }

    fn create(
        &mut self,
        ctx: &GpuContext,
        p: &Pipelines,
        descriptor_pool: vk::DescriptorPool,
        images: &[vk::DescriptorImageInfo; 7],
        tally: Option<vk::DescriptorBufferInfo>,
        sizes: SlotSizes,
    ) -> Result<(), RenderError> {
        let d = &ctx.device;
        self.pool = commands::command_pool(ctx, vk::CommandPoolCreateFlags::TRANSIENT)?;
        self.cmd = commands::primary_buffers(ctx, self.pool, 1)?[0];
        self.fence = commands::fence(ctx, true)?;
        let host = true;
        self.staging = Buffer::new(ctx, sizes.staging, vk::BufferUsageFlags::TRANSFER_SRC, host)?;
        let instance_bytes = sizes.instances * std::mem::size_of::<PatchInstance>();
        self.instances = Buffer::new(
            ctx,
            instance_bytes as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            host,
        )?;
        self.solids = Buffer::new(
            ctx,
            (MAX_SOLIDS * std::mem::size_of::<SolidInstance>()) as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            host,
        )?;
        self.globals = Buffer::new(
            ctx,
            std::mem::size_of::<Globals>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            host,
        )?;
        let layouts = [p.set_layout];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(descriptor_pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for one set per slot (`Slots::create`).
        self.set = ctx.create("vkAllocateDescriptorSets", || unsafe {
            d.allocate_descriptor_sets(&info)
        })?[0];
        let ubo = [vk::DescriptorBufferInfo {
            buffer: self.globals.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let [disp, norm, caps, sky, foam, layer, aniso] = images.map(|i| [i]);
        let write = |binding, ty| {
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(binding)
                .descriptor_type(ty)
        };
        let image = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let writes = [
            write(0, vk::DescriptorType::UNIFORM_BUFFER).buffer_info(&ubo),
            write(1, image).image_info(&disp),
            write(2, image).image_info(&norm),
            write(3, image).image_info(&caps),
            write(4, image).image_info(&sky),
            write(5, image).image_info(&foam),
            write(7, image).image_info(&layer),
            write(8, image).image_info(&aniso),
        ];
        // SAFETY: the set is not in use; the buffer, views and samplers are alive.
        unsafe { d.update_descriptor_sets(&writes, &[]) };
        if let Some(tally) = tally {
            let info = [tally];
            let write = [write(6, vk::DescriptorType::STORAGE_BUFFER).buffer_info(&info)];
            // SAFETY: as above; the tally buffer is alive.
            unsafe { d.update_descriptor_sets(&write, &[]) };
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(TIMESTAMP_QUERIES);
        // SAFETY: a valid create info on a live device.
        self.queries = ctx.create("vkCreateQueryPool", || unsafe {
            d.create_query_pool(&info, None)
        })?;
        Ok(())
    }

    /// Waits until the GPU finished this slot's previous frame.
    pub fn wait(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        // SAFETY: the fence is alive.
        unsafe { ctx.device.wait_for_fences(&[self.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))
    }

    /// Points the set's sky binding (4) at `sky`. Only while the GPU uses no frame's set.
    pub fn write_sky(&self, ctx: &GpuContext, sky: vk::DescriptorImageInfo) {
        let info = [sky];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(4)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&info)];
        // SAFETY: the caller waited for every frame, so the set is not in use; the view and
        // sampler are alive.
        unsafe { ctx.device.update_descriptor_sets(&write, &[]) };
    }

    /// Writes this frame's uniforms.
    pub fn write_globals(&mut self, g: &Globals) {
        self.globals.bytes_mut()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(g));
    }

    /// Writes the LOD's instances, then the skirt's; returns the skirt's instance index.
    pub fn write_instances(&mut self, lod: &OceanLod) -> Result<u32, RenderError> {
        let instances = lod.instances();
        let size = std::mem::size_of::<PatchInstance>();
        let capacity = self.instances.size as usize / size;
        if instances.len() + 1 > capacity {
            return Err(RenderError::Invalid(format!(
                "{} instances exceed the buffer's {capacity}",
                instances.len() + 1
            )));
        }
        let bytes = self.instances.bytes_mut();
        let src: &[u8] = bytemuck::cast_slice(instances);
        let skirt = lod.skirt_instance();
        bytes[..src.len()].copy_from_slice(src);
        bytes[src.len()..src.len() + size].copy_from_slice(bytemuck::bytes_of(&skirt));
        Ok(instances.len() as u32)
    }

    /// Writes the solids' instances grouped by shape (in [`Shape::ALL`] order); returns each
    /// shape's first instance and count. Allocates nothing.
    pub fn write_solids(&mut self, solids: &[Solid]) -> Result<[(u32, u32); 3], RenderError> {
        if solids.len() > MAX_SOLIDS {
            return Err(RenderError::Invalid(format!(
                "{} solids: at most {MAX_SOLIDS} (every body, the deck, two rays)",
                solids.len()
            )));
        }
        let size = std::mem::size_of::<SolidInstance>();
        let bytes = self.solids.bytes_mut();
        let mut draws = [(0, 0); 3];
        let mut n = 0;
        for (draw, shape) in draws.iter_mut().zip(Shape::ALL) {
            draw.0 = n as u32;
            for s in solids.iter().filter(|s| s.kind.shape() == shape) {
                let instance = SolidInstance::of(s);
                bytes[n * size..(n + 1) * size].copy_from_slice(bytemuck::bytes_of(&instance));
                n += 1;
            }
            draw.1 = n as u32 - draw.0;
        }
        Ok(draws)
    }

    /// Resets the command pool and begins the command buffer (the fence has signalled).
    pub fn begin(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        let d = &ctx.device;
        let info = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the slot's fence signalled, so nothing from the pool is pending.
        unsafe {
            d.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty())
                .map_err(RenderError::vk("vkResetCommandPool"))?;
            d.begin_command_buffer(self.cmd, &info)
                .map_err(RenderError::vk("vkBeginCommandBuffer"))
        }
    }

    /// The GPU time between the pass's two timestamps, when the device has timestamps and
    /// the results are there.
    pub fn read_timestamps(&self, ctx: &GpuContext) -> Option<Duration> {
        let period = ctx.timestamp_period?;
        let mut t = [0u64; 2];
        // SAFETY: the pool is alive and has at least 2 queries.
        unsafe {
            ctx.device
                .get_query_pool_results(self.queries, 0, &mut t, vk::QueryResultFlags::TYPE_64)
                .ok()?;
        }
        let ticks = t[1].checked_sub(t[0])?;
        Some(Duration::from_nanos((ticks as f64 * period as f64) as u64))
    }

    /// Frees what was made. The GPU must be done with it.
    fn destroy(&mut self, ctx: &GpuContext) {
        let d = &ctx.device;
        self.staging.destroy(ctx);
        self.instances.destroy(ctx);
        self.solids.destroy(ctx);
        self.globals.destroy(ctx);
        // SAFETY: the slot's fence has signalled or it never was submitted; null handles are
        // no-ops; destroying the pool frees the command buffer.
        unsafe {
            d.destroy_fence(self.fence, None);
            d.destroy_command_pool(self.pool, None);
            d.destroy_query_pool(self.queries, None);
        }
    }
}
