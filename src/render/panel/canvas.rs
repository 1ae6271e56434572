//! A [`PanelPainter`] with its own command buffer and fence: paints a [`Panel`]'s latest image
//! into a target view and submits it on the context's queue, for a front end that shows the
//! panel apart from the frame's pass (the window's overlay image, the headset's quad-layer
//! swapchain image). Each paint first waits for the previous one (the painter's buffers are
//! reused); a front end paints only when the panel drew a new image, so that wait is over
//! long before.

use ash::vk;

use super::{PanelFrame, PanelPainter, PanelTarget};
use crate::render::{commands, GpuContext, RenderError};
use crate::ui::panel::Panel;

/// The painter and what submits its work.
pub struct PanelCanvas {
    painter: PanelPainter,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    /// Signalled when the last paint finished (made signalled).
    fence: vk::Fence,
}

impl PanelCanvas {
    /// A canvas painting into images of `target`'s format. Nothing is left behind on error.
    pub fn new(ctx: &GpuContext, target: PanelTarget) -> Result<Self, RenderError> {
        let mut this = Self {
            painter: PanelPainter::new(ctx, target)?,
            pool: vk::CommandPool::null(),
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
        };
        let made = (|| {
            this.pool =
                commands::command_pool(ctx, vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
            this.cmd = commands::primary_buffers(ctx, this.pool, 1)?[0];
            this.fence = commands::fence(ctx, true)?;
            Ok(())
        })();
        match made {
            Ok(()) => Ok(this),
            Err(e) => {
                this.destroy(ctx);
                Err(e)
            }
        }
    }

    /// Paints `panel`'s latest image (with its texture changes) into `view` of `extent` and
    /// submits it. The image ends in the target's `then` access; earlier uses of it on the
    /// queue in that access are waited for by the pass.
    pub fn paint(
        &mut self,
        ctx: &GpuContext,
        panel: &mut Panel,
        view: vk::ImageView,
        extent: vk::Extent2D,
    ) -> Result<(), RenderError> {
        let d = &ctx.device;
        // SAFETY: the fence is alive; the last paint's commands (and the painter's buffers
        // they read) are done once it signals.
        unsafe { d.wait_for_fences(&[self.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))?;
        let textures = panel.take_textures();
        // SAFETY: the fence signalled, so the command buffer is not pending.
        unsafe {
            d.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(RenderError::vk("vkResetCommandBuffer"))?;
            d.begin_command_buffer(
                self.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(RenderError::vk("vkBeginCommandBuffer"))?;
        }
        self.painter.record(
            ctx,
            self.cmd,
            PanelFrame {
                view,
                extent,
                primitives: panel.primitives(),
                textures: &textures,
                pixels_per_point: panel.pixels_per_point(),
            },
        )?;
        let cmds = [self.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the command buffer is recorded and ended before the submit; the fence is
        // reset only after it signalled.
        unsafe {
            d.end_command_buffer(self.cmd)
                .map_err(RenderError::vk("vkEndCommandBuffer"))?;
            d.reset_fences(&[self.fence])
                .map_err(RenderError::vk("vkResetFences"))?;
            d.queue_submit(ctx.queue, &submit, self.fence)
                .map_err(RenderError::vk("vkQueueSubmit"))?;
        }
        Ok(())
    }

    /// Frees everything. Waits for the device first.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        ctx.wait_idle();
        self.painter.destroy(ctx);
        // SAFETY: the device is idle; null handles are no-ops.
        unsafe {
            ctx.device.destroy_fence(self.fence, None);
            ctx.device.destroy_command_pool(self.pool, None);
        }
        self.fence = vk::Fence::null();
        self.pool = vk::CommandPool::null();
    }
}
