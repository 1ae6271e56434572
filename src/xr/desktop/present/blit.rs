//! The per-frame blit: both layers of the eye image side by side into the acquired window
//! image (black bars keep the eyes' aspect), optionally copied on to a host buffer for a
//! screenshot.

use ash::vk;

use super::overlay::OverlayBlit;
use crate::render::barrier::{self, Access, GlobalBarrier, ImageBarrier};

/// What one frame's blit reads and writes.
pub(super) struct Blit<'a> {
    pub device: &'a ash::Device,
    /// A command buffer in the recording state.
    pub cmd: vk::CommandBuffer,
    /// The 2-layer eye image, in `COLOR_ATTACHMENT_OPTIMAL` (and left so).
    pub eyes: vk::Image,
    /// One eye's size.
    pub eye: vk::Extent2D,
    /// The acquired window image (its acquire semaphore waited at the transfer stage).
    pub target: vk::Image,
    /// The window image's size.
    pub window: vk::Extent2D,
    /// Blit filter (linear when the format allows).
    pub filter: vk::Filter,
    /// The control panel's image to blit over the eyes, when shown.
    pub overlay: Option<OverlayBlit>,
}

impl Blit<'_> {
    /// Records clear, blit and hand-over to presentation; with `readback`, also the copy of the
    /// window image into that buffer, made visible to the host.
    pub fn record(&self, readback: Option<vk::Buffer>) {
        let (d, cmd, target) = (self.device, self.cmd, self.target);
        barrier::record(
            d,
            cmd,
            [
                ImageBarrier::colour(self.eyes, 2, Access::ColourAttachment, Access::TransferRead),
                ImageBarrier::colour(
                    target,
                    1,
                    Access::AcquiredForTransfer,
                    Access::TransferWrite,
                )
                .discard(),
            ],
            None,
        );
        self.clear_and_blit();
        if let Some(o) = &self.overlay {
            let eyes_done =
                ImageBarrier::colour(target, 1, Access::TransferWrite, Access::TransferWrite);
            barrier::record(d, cmd, [eyes_done], None);
            // SAFETY: `cmd` is recording; the panel image is in TRANSFER_SRC_OPTIMAL (its
            // painter's pass, submitted earlier on this queue, left it so) and the window image
            // in TRANSFER_DST_OPTIMAL; the placement lies inside the window.
            unsafe {
                d.cmd_blit_image(
                    cmd,
                    o.image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    target,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[o.region()],
                    self.filter,
                )
            };
        }
        let window_access = if readback.is_some() {
            Access::TransferRead
        } else {
            Access::Present
        };
        barrier::record(
            d,
            cmd,
            [
                ImageBarrier::colour(self.eyes, 2, Access::TransferRead, Access::ColourAttachment),
                ImageBarrier::colour(target, 1, Access::TransferWrite, window_access),
            ],
            None,
        );
        if let Some(buffer) = readback {
            self.copy_to(buffer);
        }
    }

    /// Clears the window image to black, then blits each eye into its half.
    fn clear_and_blit(&self) {
        let (d, cmd, target) = (self.device, self.cmd, self.target);
        let range = [vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        }];
        let black = vk::ClearColorValue {
            float32: [0.0, 0.0, 0.0, 1.0],
        };
        let rects = eye_rects(self.window, self.eye);
        let regions: [vk::ImageBlit; 2] = std::array::from_fn(|layer| vk::ImageBlit {
            src_subresource: layers(layer as u32),
            src_offsets: [
                vk::Offset3D::default(),
                vk::Offset3D {
                    x: self.eye.width as i32,
                    y: self.eye.height as i32,
                    z: 1,
                },
            ],
            dst_subresource: layers(0),
            dst_offsets: rects[layer],
        });
        // SAFETY: `cmd` is recording and the window image is in TRANSFER_DST_OPTIMAL.
        unsafe {
            d.cmd_clear_color_image(
                cmd,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &black,
                &range,
            )
        };
        let clear_done =
            ImageBarrier::colour(target, 1, Access::TransferWrite, Access::TransferWrite);
        barrier::record(d, cmd, [clear_done], None);
        // SAFETY: `cmd` is recording; the eye image is in TRANSFER_SRC_OPTIMAL and the window
        // image in TRANSFER_DST_OPTIMAL; the regions lie inside both (`eye_rects`).
        unsafe {
            d.cmd_blit_image(
                cmd,
                self.eyes,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
                self.filter,
            )
        };
    }

    /// Copies the window image (in TRANSFER_SRC_OPTIMAL) into `buffer`, then hands the image
    /// to presentation and the buffer to the host.
    fn copy_to(&self, buffer: vk::Buffer) {
        let (d, cmd, target) = (self.device, self.cmd, self.target);
        let copy = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: layers(0),
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.window.width,
                height: self.window.height,
                depth: 1,
            },
        };
        // SAFETY: `cmd` is recording; the image is in TRANSFER_SRC_OPTIMAL and the buffer holds
        // the whole window image (the presenter sizes it).
        unsafe {
            d.cmd_copy_image_to_buffer(
                cmd,
                target,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                &[copy],
            )
        };
        barrier::record(
            d,
            cmd,
            [ImageBarrier::colour(
                target,
                1,
                Access::TransferRead,
                Access::Present,
            )],
            Some(GlobalBarrier {
                from: Access::TransferWrite,
                to: Access::HostRead,
            }),
        );
    }
}

fn layers(layer: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: layer,
        layer_count: 1,
    }
}

/// Destination corners of the left and right eye in a window of `window` pixels: each eye
/// scaled to fit its half (aspect kept), centred, at least one pixel.
pub fn eye_rects(window: vk::Extent2D, eye: vk::Extent2D) -> [[vk::Offset3D; 2]; 2] {
    let half = window.width / 2;
    let (ew, eh) = (eye.width.max(1) as f64, eye.height.max(1) as f64);
    let scale = (half as f64 / ew).min(window.height as f64 / eh);
    let w = ((ew * scale).round() as u32).clamp(1, half.max(1));
    let h = ((eh * scale).round() as u32).clamp(1, window.height.max(1));
    let y0 = ((window.height - h.min(window.height)) / 2) as i32;
    std::array::from_fn(|side| {
        let x0 = (side as u32 * half + (half - w.min(half)) / 2) as i32;
        [
            vk::Offset3D { x: x0, y: y0, z: 0 },
            vk::Offset3D {
                x: x0 + w as i32,
                y: y0 + h as i32,
                z: 1,
            },
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ext(width: u32, height: u32) -> vk::Extent2D {
        vk::Extent2D { width, height }
    }

    #[test]
    fn eyes_fill_their_halves_and_keep_their_aspect() {
        // Exact fit.
        let r = eye_rects(ext(1600, 800), ext(800, 800));
        assert_eq!(
            (r[0][0].x, r[0][0].y, r[0][1].x, r[0][1].y),
            (0, 0, 800, 800)
        );
        assert_eq!((r[1][0].x, r[1][1].x), (800, 1600));
        // A wide window: bars left and right of each eye.
        let r = eye_rects(ext(2000, 800), ext(800, 800));
        assert_eq!((r[0][0].x, r[0][1].x, r[0][1].y), (100, 900, 800));
        assert_eq!((r[1][0].x, r[1][1].x), (1100, 1900));
        // A tall window: bars above and below.
        let r = eye_rects(ext(800, 1000), ext(800, 800));
        assert_eq!((r[0][0].y, r[0][1].y, r[0][1].x), (300, 700, 400));
        // Degenerate sizes stay inside the window with at least one pixel.
        let r = eye_rects(ext(2, 1), ext(800, 600));
        assert_eq!((r[0][0].x, r[0][1].x, r[1][0].x, r[1][1].x), (0, 1, 1, 2));
        assert_eq!((r[0][0].y, r[0][1].y), (0, 1));
    }
}
