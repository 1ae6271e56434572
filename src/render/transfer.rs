//! Copies from a staging buffer into sampled images, recorded between the barriers that make
//! each image a transfer destination and then readable by shaders again: every upload of the
//! renderer (the sky's and the foam pattern's at set-up, the cascades' and the interaction
//! layer's every frame, the panel's textures) goes through [`record_staged_copies`], so the
//! layout dance is written once.

use ash::vk;

use crate::render::barrier::{self, Access, ImageBarrier};

/// The copy of a `width` × `height` block of texels at byte `offset` of a staging buffer
/// (tightly packed) to `at` in mip `level` of colour layer `layer`.
pub(crate) fn colour_region(
    offset: u64,
    layer: u32,
    level: u32,
    at: [i32; 2],
    [width, height]: [u32; 2],
) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset: offset,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: level,
            base_array_layer: layer,
            layer_count: 1,
        },
        image_offset: vk::Offset3D {
            x: at[0],
            y: at[1],
            z: 0,
        },
        image_extent: vk::Extent3D {
            width,
            height,
            depth: 1,
        },
    }
}

/// Records, for each image `i`, the barrier `to_copy[i]` (its `to` must be
/// [`Access::TransferWrite`]), the copies `regions[i]` from `staging`, then one barrier per
/// image from the transfer to [`Access::ShaderSampled`], contents kept.
///
/// The caller's contract: `cmd` is recording, and every region lies inside `staging` and its
/// image's subresources the barrier covers.
pub(crate) fn record_staged_copies<const N: usize>(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    staging: vk::Buffer,
    to_copy: [ImageBarrier; N],
    regions: [&[vk::BufferImageCopy]; N],
) {
    debug_assert!(to_copy.iter().all(|b| b.to == Access::TransferWrite));
    barrier::record(d, cmd, to_copy, None);
    for (b, regions) in to_copy.iter().zip(regions) {
        if regions.is_empty() {
            continue;
        }
        // SAFETY: `cmd` is recording; the image is in TRANSFER_DST_OPTIMAL after the barrier
        // above, and every region lies inside the staging buffer and the image (the caller's
        // contract).
        unsafe {
            d.cmd_copy_buffer_to_image(
                cmd,
                staging,
                b.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                regions,
            );
        }
    }
    let to_read = to_copy.map(|b| ImageBarrier {
        from: Access::TransferWrite,
        to: Access::ShaderSampled,
        contents: barrier::Contents::Keep,
        ..b
    });
    barrier::record(d, cmd, to_read, None);
}
