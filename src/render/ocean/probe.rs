//! The counting variant of the ocean pass (`vr-ocean gpu-budget`, [`crate::render::budget`]):
//! a storage buffer the counting fragment shader tallies its paths and quads into (binding 6,
//! summed over every frame rendered), and a pipeline-statistics query around each frame's pass
//! (vertex invocations, primitives through the clipper, fragment invocations, read when the
//! frame's slot comes round again). Made only
//! when the renderer counts; never in a user's run.

use ash::vk;

use crate::render::budget::PathCounts;
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::Buffer;

/// Tallies the shader writes (`t_paths.tally` in `shaders/ocean.frag`, `COUNT_*` order).
const TALLIES: usize = 8 + 2 * PathCounts::AREA_BINS + 3 + 3;

/// The counting pass's buffer and queries.
pub(super) struct PathProbe {
    tally: Buffer,
    stats: vk::QueryPool,
    /// Per slot: a query was recorded and not read yet.
    pending: Vec<bool>,
    /// The statistics read so far: vertex invocations, primitives into and out of the
    /// clipper, fragment invocations (Vulkan's bit order).
    invocations: [u64; 4],
    /// Frames whose pass was counted.
    frames: u64,
}

impl PathProbe {
    /// A zeroed tally and one statistics query per frame slot (`slots`).
    pub fn new(ctx: &GpuContext, slots: usize) -> Result<Self, RenderError> {
        let mut this = Self {
            tally: Buffer::null(),
            stats: vk::QueryPool::null(),
            pending: vec![false; slots],
            invocations: [0; 4],
            frames: 0,
        };
        if let Err(e) = this.create(ctx, slots) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext, slots: usize) -> Result<(), RenderError> {
        let bytes = (TALLIES * 4) as u64;
        self.tally = Buffer::new(ctx, bytes, vk::BufferUsageFlags::STORAGE_BUFFER, true)?;
        self.tally.bytes_mut()[..bytes as usize].fill(0);
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(slots as u32)
            .pipeline_statistics(
                vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS
                    | vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS
                    | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES
                    | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
            );
        // SAFETY: a valid create info on a live device with `pipelineStatisticsQuery` enabled
        // (`Pipelines::new` refused to count without it).
        self.stats = ctx.create("vkCreateQueryPool", || unsafe {
            ctx.device.create_query_pool(&info, None)
        })?;
        Ok(())
    }

    /// The tally for the slots' descriptor sets (binding 6).
    pub fn descriptor(&self) -> vk::DescriptorBufferInfo {
        vk::DescriptorBufferInfo {
            buffer: self.tally.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }
    }

    /// Reads slot `slot`'s statistics from its last frame (its fence has signalled).
    pub fn collect(&mut self, ctx: &GpuContext, slot: usize) -> Result<(), RenderError> {
        if !std::mem::take(&mut self.pending[slot]) {
            return Ok(());
        }
        // One query (ash takes the count from the slice): four 64-bit statistics.
        let mut r = [[0u64; 4]; 1];
        // SAFETY: the query was begun and ended in a submitted command buffer whose fence has
        // signalled; four 64-bit results for the four statistics asked for.
        unsafe {
            ctx.device.get_query_pool_results(
                self.stats,
                slot as u32,
                &mut r,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(RenderError::vk("vkGetQueryPoolResults"))?;
        for (sum, v) in self.invocations.iter_mut().zip(r[0]) {
            *sum += v;
        }
        Ok(())
    }

    /// Records the start of slot `slot`'s statistics (outside a render pass, so a multiview
    /// pass takes one query).
    pub fn begin(&mut self, d: &ash::Device, cmd: vk::CommandBuffer, slot: usize) {
        // SAFETY: `cmd` is recording outside a render pass; the pool has a query per slot.
        unsafe {
            d.cmd_reset_query_pool(cmd, self.stats, slot as u32, 1);
            d.cmd_begin_query(cmd, self.stats, slot as u32, vk::QueryControlFlags::empty());
        }
        self.pending[slot] = true;
        self.frames += 1;
    }

    /// Records the end of slot `slot`'s statistics, and makes the shader's tallies visible to
    /// the host once the frame's fence signals.
    pub fn end(&self, d: &ash::Device, cmd: vk::CommandBuffer, slot: usize) {
        let to_host = [vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::SHADER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ)];
        // SAFETY: `cmd` is recording outside a render pass, after `begin` of the same query.
        unsafe {
            d.cmd_end_query(cmd, self.stats, slot as u32);
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::FRAGMENT_SHADER,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &to_host,
                &[],
                &[],
            );
        }
    }

    /// The counts per frame so far, averaged over the counted frames. The caller has waited
    /// for every frame in flight.
    pub fn counts(&mut self, ctx: &GpuContext) -> Result<PathCounts, RenderError> {
        for slot in 0..self.pending.len() {
            self.collect(ctx, slot)?;
        }
        let mut t = [0u32; TALLIES];
        for (v, b) in t.iter_mut().zip(self.tally.bytes().chunks_exact(4)) {
            *v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        }
        let per_frame = |x: u64| x / self.frames.max(1);
        Ok(PathCounts {
            sky: per_frame(t[0].into()),
            single: per_frame(t[1].into()),
            supersampled: per_frame(t[2].into()),
            foam: per_frame(t[3].into()),
            plain: per_frame(t[4].into()),
            resamples: per_frame(t[5].into()),
            detail: per_frame(t[6].into()),
            aniso_taps: per_frame(t[7].into()),
            by_area: std::array::from_fn(|b| per_frame(t[8 + b].into())),
            quarter_lanes: std::array::from_fn(|b| {
                per_frame(t[8 + PathCounts::AREA_BINS + b].into())
            }),
            by_thickness: std::array::from_fn(|b| {
                per_frame(t[8 + PathCounts::AREA_BINS + 3 + b].into())
            }),
            knee: per_frame(t[8 + 2 * PathCounts::AREA_BINS + 3].into()),
            below: per_frame(t[8 + 2 * PathCounts::AREA_BINS + 4].into()),
            depths: per_frame(t[8 + 2 * PathCounts::AREA_BINS + 5].into()),
            vertex_invocations: per_frame(self.invocations[0]),
            clipped_primitives: per_frame(self.invocations[2]),
            fragment_invocations: per_frame(self.invocations[3]),
        })
    }

    /// Frees the buffer and the pool. The GPU must be done with them.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        self.tally.destroy(ctx);
        // SAFETY: no submitted work uses the pool any more (the caller's contract); null is a
        // no-op.
        unsafe { ctx.device.destroy_query_pool(self.stats, None) };
        self.stats = vk::QueryPool::null();
    }
}
