//! The painter's egui textures (the font atlas): created, patched and freed as egui's
//! `TexturesDelta` says, uploaded through the painter's staging buffer.

use ash::vk;

use super::PanelPainter;
use crate::render::barrier::{self, Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Image, ImageDesc};

/// One egui texture on the GPU.
pub(super) struct Texture {
    pub id: egui::TextureId,
    pub image: Image,
    pub set: vk::DescriptorSet,
}

impl PanelPainter {
    pub(super) fn upload(
        &mut self,
        ctx: &GpuContext,
        cmd: vk::CommandBuffer,
        id: egui::TextureId,
        delta: &egui::epaint::ImageDelta,
        offset: u64,
    ) -> Result<u64, RenderError> {
        let egui::ImageData::Color(image) = &delta.image;
        let [w, h] = image.size;
        let extent = vk::Extent2D {
            width: w as u32,
            height: h as u32,
        };
        let whole = delta.pos.is_none();
        if whole {
            if let Some(i) = self.textures.iter().position(|t| t.id == id) {
                self.retired.push(self.textures.swap_remove(i));
            }
            let texture = self.new_texture(ctx, id, extent)?;
            self.textures.push(texture);
        }
        let Some(texture) = self.textures.iter().find(|t| t.id == id) else {
            return Err(RenderError::Invalid(format!(
                "egui patched texture {id:?} before creating it"
            )));
        };
        let bytes = bytemuck::cast_slice::<egui::Color32, u8>(&image.pixels);
        let at = offset as usize;
        self.staging.bytes_mut()[at..at + bytes.len()].copy_from_slice(bytes);
        let [x, y] = delta.pos.unwrap_or([0, 0]);
        let from = if whole {
            Access::Nothing
        } else {
            Access::ShaderSampled
        };
        barrier::record(
            &ctx.device,
            cmd,
            [ImageBarrier::colour(
                texture.image.raw,
                1,
                from,
                Access::TransferWrite,
            )],
            None,
        );
        let region = vk::BufferImageCopy {
            buffer_offset: offset,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D {
                x: x as i32,
                y: y as i32,
                z: 0,
            },
            image_extent: vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            },
        };
        // SAFETY: the staging buffer holds the pixels; the image is in TRANSFER_DST_OPTIMAL
        // after the barrier above; the region lies within it (egui's patches do).
        unsafe {
            ctx.device.cmd_copy_buffer_to_image(
                cmd,
                self.staging.raw,
                texture.image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
        }
        barrier::record(
            &ctx.device,
            cmd,
            [ImageBarrier::colour(
                texture.image.raw,
                1,
                Access::TransferWrite,
                Access::ShaderSampled,
            )],
            None,
        );
        Ok(offset + bytes.len() as u64)
    }

    fn new_texture(
        &mut self,
        ctx: &GpuContext,
        id: egui::TextureId,
        extent: vk::Extent2D,
    ) -> Result<Texture, RenderError> {
        let mut image = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R8G8B8A8_UNORM,
                extent,
                layers: 1,
                mips: 1,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        let layouts = [self.set_layout];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pool)
            .set_layouts(&layouts);
        // SAFETY: the pool and the layout are alive.
        let set = match unsafe { ctx.device.allocate_descriptor_sets(&info) } {
            Ok(s) => s[0],
            Err(e) => {
                image.destroy(ctx);
                return Err(RenderError::vk("vkAllocateDescriptorSets")(e));
            }
        };
        let image_info = [vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&image_info)];
        // SAFETY: the set, sampler and view are alive; the set is not in use.
        unsafe { ctx.device.update_descriptor_sets(&write, &[]) };
        Ok(Texture { id, image, set })
    }
}

pub(super) fn free_texture(ctx: &GpuContext, pool: vk::DescriptorPool, t: &mut Texture) {
    // SAFETY: the GPU is done with the texture (the painter's contract); the set came from
    // `pool`, which allows freeing sets.
    unsafe {
        let _ = ctx.device.free_descriptor_sets(pool, &[t.set]);
    }
    t.image.destroy(ctx);
}
