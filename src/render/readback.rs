//! Copies both layers of a rendered 2-layer RGBA8 image into host memory: headless PNGs and
//! image tests. A read-back waits for the GPU, so the frame loop does it only on frames the user
//! asked to save.

use ash::vk;

use super::barrier::{self, Access, ImageBarrier};
use super::context::GpuContext;
use super::error::RenderError;
use super::memory::Buffer;

/// A host buffer big enough for both eyes of one target image.
pub struct Readback {
    buffer: Buffer,
    extent: vk::Extent2D,
}

impl Readback {
    /// For 2-layer RGBA8 images of `extent`.
    pub fn new(ctx: &GpuContext, extent: vk::Extent2D) -> Result<Self, RenderError> {
        let size = 2 * 4 * extent.width as u64 * extent.height as u64;
        Ok(Self {
            buffer: Buffer::new(ctx, size, vk::BufferUsageFlags::TRANSFER_DST, true)?,
            extent,
        })
    }

    /// Copies `image` (in `COLOR_ATTACHMENT_OPTIMAL`, left as it was) after all submitted work
    /// and returns the left and right eyes as tightly packed RGBA8 rows.
    pub fn read(&mut self, ctx: &GpuContext, image: vk::Image) -> Result<[&[u8]; 2], RenderError> {
        let (w, h) = (self.extent.width, self.extent.height);
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 2,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            },
        };
        let buffer = self.buffer.raw;
        super::one_shot(ctx, |cmd| {
            let d = &ctx.device;
            let to_src =
                ImageBarrier::colour(image, 2, Access::ColourAttachment, Access::TransferRead);
            barrier::record(d, cmd, [to_src], None);
            // SAFETY: `cmd` is recording; the image is in TRANSFER_SRC_OPTIMAL after the barrier
            // and the buffer holds both layers.
            unsafe {
                d.cmd_copy_image_to_buffer(
                    cmd,
                    image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buffer,
                    &[region],
                )
            };
            let back =
                ImageBarrier::colour(image, 2, Access::TransferRead, Access::ColourAttachment);
            barrier::record(d, cmd, [back], None);
        })?;
        let eye = 4 * w as usize * h as usize;
        let bytes = self.buffer.bytes();
        Ok([&bytes[..eye], &bytes[eye..2 * eye]])
    }

    /// Frees the buffer.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        self.buffer.destroy(ctx);
    }
}
