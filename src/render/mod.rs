//! The ash Vulkan 1.1 renderer: one multiview pass (view mask 0b11) draws both eyes into
//! 2-layer array images, with a two-pass fallback; the simulation's textures arrive through a
//! per-frame staging ring. It draws what `sim` and `lod` produce and knows nothing of XR: the
//! backend in `xr` owns the target images and hands them in.
//!
//! - [`context`]: instance, device, queue.
//! - [`validation`]: the validation layer's messages, counted (tests fail on any error).
//! - [`budget`]: the GPU cost model of `vr-ocean gpu-budget` (counted paths × counted
//!   instructions × published Quest GPU throughput).
//! - [`calibration`]: the calibration passes of `gpu-budget --calibrate` (known work per
//!   fragment, small triangles), timed in the ocean's own pass settings.
//! - [`commands`]: command pools, buffers and fences.
//! - [`memory`]: buffers and images with their own memory.
//! - [`barrier`]: pipeline barriers written as named access states (`from` → `to`).
//! - [`render_pass`]: the stereo render pass (multiview or two passes, MSAA, density map).
//! - `program`: every pipeline's description and its one builder, the shader pair and layout.
//! - [`panel`]: the control panel's painter (egui's triangles into the panel's image).
//! - [`camera`]: reversed-Z projections and the uniform block.
//! - [`ocean`]: the per-frame renderer.
//! - [`sky`]: the sky (a scattering atmosphere and a cloud layer) and its prefiltered
//!   environment map, baked on the CPU when the sun, haze or clouds change.
//! - [`tonemap`]: the shaders' tone curve (Khronos PBR Neutral) and the sRGB encoding, for
//!   tests to check the GPU against.
//! - [`readback`]: copies a rendered array image to the CPU (screenshots, tests).
//! - `targets`: views and framebuffers of a stereo pass's target images (the ocean's, the
//!   calibration's).
//! - [`statistics`]: the driver's compiler statistics of every pipeline (`shader-stats`).
//! - `sampler`: the samplers every texture is read through (trilinear, anisotropic).
//! - `upload`: one-time copies of textures made on the CPU.
//! - `transfer`: every staged copy into a sampled image, between its barriers.
//! - [`shaders`]: SPIR-V compiled from `shaders/` by `build.rs`.

pub mod barrier;
pub mod budget;
pub mod calibration;
pub mod camera;
pub mod commands;
pub mod context;
pub mod error;
pub mod memory;
pub mod ocean;
pub mod panel;
pub(crate) mod program;
pub mod readback;
pub mod render_pass;
pub(crate) mod sampler;
pub mod shaders;
pub mod sky;
pub mod statistics;
pub(crate) mod targets;
pub mod tonemap;
pub(crate) mod transfer;
pub(crate) mod upload;
pub mod validation;

pub use context::{
    ContextOptions, DirectVulkan, GpuContext, Validation, ValidationLog, VulkanFactory,
};
pub use error::RenderError;
pub use ocean::{FrameInput, FrameReport, OceanRenderer, RendererSettings, TargetImages};
pub use render_pass::{Msaa, StereoMode, DEPTH_FORMAT};

use ash::vk;

/// Records `f` into a fresh command buffer, submits it and waits for it. For set-up and
/// read-back only, never in the frame loop.
pub fn one_shot(ctx: &GpuContext, f: impl FnOnce(vk::CommandBuffer)) -> Result<(), RenderError> {
    let d = &ctx.device;
    let pool = commands::command_pool(ctx, vk::CommandPoolCreateFlags::TRANSIENT)?;
    let result = (|| {
        let cmd = commands::primary_buffers(ctx, pool, 1)?[0];
        // SAFETY: a fresh command buffer of a pool only this function uses.
        unsafe {
            d.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
        }
        .map_err(RenderError::vk("vkBeginCommandBuffer"))?;
        f(cmd);
        // SAFETY: `cmd` is recording.
        unsafe { d.end_command_buffer(cmd) }.map_err(RenderError::vk("vkEndCommandBuffer"))?;
        let fence = commands::fence(ctx, false)?;
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: `cmd` is executable and the fence unsignalled; the queue is only used from
        // this thread.
        let r = unsafe { d.queue_submit(ctx.queue, &submit, fence) }
            .map_err(RenderError::vk("vkQueueSubmit"))
            .and_then(|_| {
                // SAFETY: the fence is alive.
                unsafe { d.wait_for_fences(&[fence], true, u64::MAX) }
                    .map_err(RenderError::vk("vkWaitForFences"))
            });
        // SAFETY: the submission finished (or never started).
        unsafe { d.destroy_fence(fence, None) };
        r
    })();
    // SAFETY: nothing from the pool is pending any more.
    unsafe { d.destroy_command_pool(pool, None) };
    result
}
