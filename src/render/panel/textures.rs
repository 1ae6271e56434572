//! The painter's egui textures (the font atlas): created, patched and freed as egui's
//! `TexturesDelta` says, uploaded through the painter's staging buffer.

use ash::vk;

use crate::render::barrier::{Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Buffer, Image, ImageDesc};
use crate::render::transfer::{colour_region, record_staged_copies};

/// One egui texture on the GPU.
pub(super) struct Texture {
    pub id: egui::TextureId,
    pub image: Image,
    pub set: vk::DescriptorSet,
}

/// What a texture's descriptor set is made from: the painter's pool, set layout and sampler.
#[derive(Clone, Copy)]
pub(super) struct TextureSets {
    pub pool: vk::DescriptorPool,
    pub set_layout: vk::DescriptorSetLayout,
    pub sampler: vk::Sampler,
}

/// The painter's egui textures: the live ones, and those egui freed, destroyed at the next
/// recording (the caller waits for each recording's commands before the next).
#[derive(Default)]
pub(super) struct PanelTextures {
    live: Vec<Texture>,
    retired: Vec<Texture>,
}

impl PanelTextures {
    /// The live texture egui calls `id`.
    pub fn get(&self, id: egui::TextureId) -> Option<&Texture> {
        self.live.iter().find(|t| t.id == id)
    }

    /// Retires the texture `id` (egui freed it): destroyed at the next [`Self::free_retired`].
    pub fn retire(&mut self, id: egui::TextureId) {
        if let Some(i) = self.live.iter().position(|t| t.id == id) {
            self.retired.push(self.live.swap_remove(i));
        }
    }

    /// Destroys the retired textures (the GPU is done with them).
    pub fn free_retired(&mut self, ctx: &GpuContext, pool: vk::DescriptorPool) {
        for mut t in self.retired.drain(..) {
            free_texture(ctx, pool, &mut t);
        }
    }

    /// Destroys every texture, live and retired (the GPU is done with them).
    pub fn destroy(&mut self, ctx: &GpuContext, pool: vk::DescriptorPool) {
        for mut t in self.live.drain(..).chain(self.retired.drain(..)) {
            free_texture(ctx, pool, &mut t);
        }
    }

    /// Uploads one egui texture change (`id` and its delta, as `TexturesDelta::set` lists
    /// them) through `staging` from byte `offset`: a new texture (or a whole replacement), or a
    /// patch of an existing one (the font atlas growing). Returns where the next upload's bytes
    /// go.
    pub fn upload(
        &mut self,
        ctx: &GpuContext,
        cmd: vk::CommandBuffer,
        sets: TextureSets,
        staging: &mut Buffer,
        (id, delta): &(egui::TextureId, egui::epaint::ImageDelta),
        offset: u64,
    ) -> Result<u64, RenderError> {
        let id = *id;
        let egui::ImageData::Color(image) = &delta.image;
        let [w, h] = image.size;
        let extent = vk::Extent2D {
            width: w as u32,
            height: h as u32,
        };
        let whole = delta.pos.is_none();
        if whole {
            self.retire(id);
            let texture = new_texture(ctx, sets, id, extent)?;
            self.live.push(texture);
        }
        let Some(texture) = self.get(id) else {
            return Err(RenderError::Invalid(format!(
                "egui patched texture {id:?} before creating it"
            )));
        };
        let bytes = bytemuck::cast_slice::<egui::Color32, u8>(&image.pixels);
        let at = offset as usize;
        staging.bytes_mut()[at..at + bytes.len()].copy_from_slice(bytes);
        let [x, y] = delta.pos.unwrap_or([0, 0]);
        let from = if whole {
            Access::Nothing
        } else {
            Access::ShaderSampled
        };
        let region = colour_region(
            offset,
            0,
            0,
            [x as i32, y as i32],
            [extent.width, extent.height],
        );
        let to_copy = ImageBarrier::colour(texture.image.raw, 1, from, Access::TransferWrite);
        // The staging buffer holds the pixels at `offset`; the region lies within the image
        // (egui's patches do).
        record_staged_copies(&ctx.device, cmd, staging.raw, [to_copy], [&[region]]);
        Ok(offset + bytes.len() as u64)
    }
}

/// A texture of `extent` for egui's `id`, with its descriptor set from `sets`.
fn new_texture(
    ctx: &GpuContext,
    sets: TextureSets,
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
    let layouts = [sets.set_layout];
    let info = vk::DescriptorSetAllocateInfo::default()
        .descriptor_pool(sets.pool)
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
        sampler: sets.sampler,
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

fn free_texture(ctx: &GpuContext, pool: vk::DescriptorPool, t: &mut Texture) {
    // SAFETY: the GPU is done with the texture (the painter's contract); the set came from
    // `pool`, which allows freeing sets.
    unsafe {
        let _ = ctx.device.free_descriptor_sets(pool, &[t.set]);
    }
    t.image.destroy(ctx);
}
