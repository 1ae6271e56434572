//! Small constructors for the command pools, command buffers and fences every part of the
//! renderer and the XR backends create.

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;

/// A command pool on the context's queue family.
pub fn command_pool(
    ctx: &GpuContext,
    flags: vk::CommandPoolCreateFlags,
) -> Result<vk::CommandPool, RenderError> {
    let info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(ctx.queue_family)
        .flags(flags);
    // SAFETY: a valid create info on a live device.
    ctx.create("vkCreateCommandPool", || unsafe {
        ctx.device.create_command_pool(&info, None)
    })
}

/// `count` primary command buffers from `pool`.
pub fn primary_buffers(
    ctx: &GpuContext,
    pool: vk::CommandPool,
    count: u32,
) -> Result<Vec<vk::CommandBuffer>, RenderError> {
    let info = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(count);
    // SAFETY: `pool` is alive and belongs to this device (the caller's contract).
    ctx.create("vkAllocateCommandBuffers", || unsafe {
        ctx.device.allocate_command_buffers(&info)
    })
}

/// A fence, created signalled when `signalled` (so a first wait returns at once).
pub fn fence(ctx: &GpuContext, signalled: bool) -> Result<vk::Fence, RenderError> {
    let flags = if signalled {
        vk::FenceCreateFlags::SIGNALED
    } else {
        vk::FenceCreateFlags::empty()
    };
    // SAFETY: a valid create info on a live device.
    ctx.create("vkCreateFence", || unsafe {
        ctx.device
            .create_fence(&vk::FenceCreateInfo::default().flags(flags), None)
    })
}
