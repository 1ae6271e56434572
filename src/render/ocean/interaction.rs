//! The interaction layer's texture (issue 30): RGBA16F (h, ∂h/∂x, ∂h/∂z, foam) of
//! [`crate::sim::interaction`], N × N, clamped (the layer fades to zero at its edges, so beyond
//! them it adds nothing). Re-uploaded on every frame whose layer stepped, through its own part
//! of each slot's staging buffer. Without a layer it is one zero texel and the shaders skip it.

use ash::vk;

use super::textures::region;
use crate::render::barrier::{Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Image, ImageDesc};
use crate::render::sampler::sampler_with;
use crate::render::transfer::record_staged_copies;
use crate::sim::interaction::InteractionLayer;
use crate::sim::GridSize;

/// The layer's image and sampler.
pub(super) struct InteractionTexture {
    image: Image,
    sampler: vk::Sampler,
    /// Cells a side (1 without a layer).
    side: u32,
}

impl InteractionTexture {
    /// The image for a layer of `cells` (a zero texel for `None`). Nothing is left behind when
    /// a step fails.
    pub fn new(ctx: &GpuContext, cells: Option<GridSize>) -> Result<Self, RenderError> {
        let side = cells.map_or(1, |c| c.n() as u32);
        let mut this = Self {
            image: Image::null(),
            sampler: vk::Sampler::null(),
            side,
        };
        if let Err(e) = this.create(ctx) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext) -> Result<(), RenderError> {
        self.image = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R16G16B16A16_SFLOAT,
                extent: vk::Extent2D {
                    width: self.side,
                    height: self.side,
                },
                layers: 1,
                mips: 1,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let clamp = vk::SamplerAddressMode::CLAMP_TO_EDGE;
        self.sampler = sampler_with(ctx, 0.0, [clamp, clamp])?;
        Ok(())
    }

    /// Where this texture's part of a slot's staging buffer starts after `before` bytes:
    /// aligned to the texel (a copy's buffer offset must be a multiple of it).
    pub fn staging_offset(before: u64) -> u64 {
        before.next_multiple_of(8)
    }

    /// Bytes of one upload.
    pub fn staging_size(cells: Option<GridSize>) -> u64 {
        let side = cells.map_or(1, |c| c.n() as u64);
        side * side * 8
    }

    /// The descriptor (binding 7).
    pub fn descriptor(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }
    }

    /// Copies the drawn layer's texels ([`super::RendererSettings::drawn_layer`]: of this
    /// texture's size) into `staging` (this texture's part of a slot's buffer); `None` stages
    /// zeros. No allocation.
    pub fn stage(&self, staging: &mut [u8], layer: Option<&InteractionLayer>) {
        let part = &mut staging[..(self.side * self.side * 8) as usize];
        match layer {
            Some(l) => part.copy_from_slice(bytemuck::cast_slice(l.texels())),
            None => part.fill(0),
        }
    }

    /// Records the copy of the staged texels at `offset` of `staging`: shader reads of the
    /// previous frame → transfer write (contents discarded) → shader reads.
    pub fn record_upload(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        staging: vk::Buffer,
        offset: u64,
    ) {
        let to_copy = [ImageBarrier::colour(
            self.image.raw,
            1,
            Access::ShaderSampled,
            Access::TransferWrite,
        )
        .discard()];
        let region = region(offset as usize, 0, 0, self.side);
        // The region lies inside the staging buffer (`staging_size` at `offset`).
        record_staged_copies(d, cmd, staging, to_copy, [&[region]]);
    }

    /// Frees what was made. The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the sampler; a null handle is a no-op.
        unsafe { ctx.device.destroy_sampler(self.sampler, None) };
        self.sampler = vk::Sampler::null();
        self.image.destroy(ctx);
    }
}
