//! One-time uploads of textures made on the CPU at set-up (the sky's environment map, the foam
//! pattern): every level through a temporary staging buffer, then ready for sampling. Waits for
//! the copy, so never in the steady state.

use ash::vk;

use crate::render::barrier::{Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Buffer, Image};
use crate::render::transfer::{colour_region, record_staged_copies};

/// One mip level's texels, tightly packed in the image's format.
pub(crate) struct Level<'a> {
    /// The texels, row after row.
    pub bytes: &'a [u8],
    /// Its size in texels.
    pub width: u32,
    /// Its height in texels.
    pub height: u32,
}

/// Copies `levels` (mip 0 first, layer 0) into `image` and leaves it in
/// SHADER_READ_ONLY_OPTIMAL. The staging buffer is freed whatever happens.
pub(crate) fn upload_levels(
    ctx: &GpuContext,
    image: &Image,
    levels: &[Level<'_>],
) -> Result<(), RenderError> {
    upload_layers(ctx, image, &[levels])
}

/// Copies each of `layers` (its levels, mip 0 first; every layer as many) into its array layer
/// of `image` and leaves them all in SHADER_READ_ONLY_OPTIMAL. The staging buffer is freed
/// whatever happens.
pub(crate) fn upload_layers(
    ctx: &GpuContext,
    image: &Image,
    layers: &[&[Level<'_>]],
) -> Result<(), RenderError> {
    let levels = layers.first().map_or(&[][..], |l| *l);
    debug_assert!(layers.iter().all(|l| l.len() == levels.len()));
    let total: usize = layers
        .iter()
        .flat_map(|l| l.iter())
        .map(|l| l.bytes.len())
        .sum();
    let mut staging = Buffer::new(ctx, total as u64, vk::BufferUsageFlags::TRANSFER_SRC, true)?;
    let mut regions = Vec::with_capacity(layers.len() * levels.len());
    let bytes = staging.bytes_mut();
    let mut offset = 0usize;
    for (layer, levels) in layers.iter().enumerate() {
        for (m, level) in levels.iter().enumerate() {
            bytes[offset..offset + level.bytes.len()].copy_from_slice(level.bytes);
            regions.push(colour_region(
                offset as u64,
                layer as u32,
                m as u32,
                [0, 0],
                [level.width, level.height],
            ));
            offset += level.bytes.len();
        }
    }
    let mips = levels.len() as u32;
    let layer_count = layers.len() as u32;
    let result = crate::render::one_shot(ctx, |cmd| {
        let d = &ctx.device;
        let to_copy = ImageBarrier::colour(
            image.raw,
            layer_count,
            Access::Nothing,
            Access::TransferWrite,
        )
        .mips(mips)
        .discard();
        // Every region lies inside the staging buffer and its level.
        record_staged_copies(d, cmd, staging.raw, [to_copy], [&regions]);
    });
    staging.destroy(ctx);
    result
}
