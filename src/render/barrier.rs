//! Pipeline barriers written by name: an image goes `from` one [`Access`] `to` another, and
//! each access state knows its pipeline stages, its access mask and its image layout (in the
//! manner of kajiya's `ImageBarrier` and vk-sync). Nothing positional can be swapped: the old
//! and new layouts, the source and destination masks and the stage masks all follow from the
//! two names.

use ash::vk;

/// How a resource is used on one side of a barrier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Not used yet, contents undefined (the first use of an image).
    Nothing,
    /// A swapchain image just acquired, its acquire semaphore waited at the transfer stage:
    /// contents undefined, but the layout change must wait for that stage.
    AcquiredForTransfer,
    /// Written by a copy, clear or blit.
    TransferWrite,
    /// Read by a copy or blit.
    TransferRead,
    /// Sampled by the vertex and fragment shaders.
    ShaderSampled,
    /// Written as a colour attachment by a render pass.
    ColourAttachment,
    /// Handed to the window system to present.
    Present,
    /// Read by the host (mapped memory) after the queue's work (global barriers only).
    HostRead,
}

impl Access {
    /// The pipeline stages that perform the access.
    pub fn stages(self) -> vk::PipelineStageFlags {
        use vk::PipelineStageFlags as S;
        match self {
            Access::Nothing => S::TOP_OF_PIPE,
            Access::AcquiredForTransfer | Access::TransferWrite | Access::TransferRead => {
                S::TRANSFER
            }
            Access::ShaderSampled => S::VERTEX_SHADER | S::FRAGMENT_SHADER,
            Access::ColourAttachment => S::COLOR_ATTACHMENT_OUTPUT,
            Access::Present => S::BOTTOM_OF_PIPE,
            Access::HostRead => S::HOST,
        }
    }

    /// The memory accesses.
    pub fn access(self) -> vk::AccessFlags {
        use vk::AccessFlags as A;
        match self {
            Access::Nothing | Access::AcquiredForTransfer | Access::Present => A::empty(),
            Access::TransferWrite => A::TRANSFER_WRITE,
            Access::TransferRead => A::TRANSFER_READ,
            Access::ShaderSampled => A::SHADER_READ,
            Access::ColourAttachment => A::COLOR_ATTACHMENT_WRITE,
            Access::HostRead => A::HOST_READ,
        }
    }

    /// Whether the access writes (only writes need to be made available by a barrier).
    pub fn writes(self) -> bool {
        matches!(self, Access::TransferWrite | Access::ColourAttachment)
    }

    /// The image layout the access needs.
    pub fn layout(self) -> vk::ImageLayout {
        use vk::ImageLayout as L;
        match self {
            Access::Nothing | Access::AcquiredForTransfer | Access::HostRead => L::UNDEFINED,
            Access::TransferWrite => L::TRANSFER_DST_OPTIMAL,
            Access::TransferRead => L::TRANSFER_SRC_OPTIMAL,
            Access::ShaderSampled => L::SHADER_READ_ONLY_OPTIMAL,
            Access::ColourAttachment => L::COLOR_ATTACHMENT_OPTIMAL,
            Access::Present => L::PRESENT_SRC_KHR,
        }
    }
}

/// Whether a barrier keeps an image's contents through the layout change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contents {
    /// Keep them.
    Keep,
    /// Discard them: the old layout becomes UNDEFINED (cheaper; for images about to be
    /// overwritten whole).
    Discard,
}

/// One image's transition from one access to another, over all its layers and mips.
#[derive(Clone, Copy, Debug)]
pub struct ImageBarrier {
    /// The image.
    pub image: vk::Image,
    /// Its aspect (colour or depth).
    pub aspect: vk::ImageAspectFlags,
    /// The first array layer.
    pub base_layer: u32,
    /// Array layers, from `base_layer`.
    pub layers: u32,
    /// Mip levels, from 0.
    pub mips: u32,
    /// The access before the barrier.
    pub from: Access,
    /// The access after it.
    pub to: Access,
    /// Whether the contents survive.
    pub contents: Contents,
}

impl ImageBarrier {
    /// A colour image's first `layers` layers (one mip), contents kept.
    pub fn colour(image: vk::Image, layers: u32, from: Access, to: Access) -> Self {
        Self {
            image,
            aspect: vk::ImageAspectFlags::COLOR,
            base_layer: 0,
            layers,
            mips: 1,
            from,
            to,
            contents: Contents::Keep,
        }
    }

    /// The same barrier over layer `layer` alone.
    pub fn layer(self, layer: u32) -> Self {
        Self {
            base_layer: layer,
            layers: 1,
            ..self
        }
    }

    /// The same barrier over `mips` mip levels.
    pub fn mips(self, mips: u32) -> Self {
        Self { mips, ..self }
    }

    /// The same barrier with the contents discarded.
    pub fn discard(self) -> Self {
        Self {
            contents: Contents::Discard,
            ..self
        }
    }

    /// The Vulkan struct.
    pub fn raw(&self) -> vk::ImageMemoryBarrier<'static> {
        let old = match self.contents {
            Contents::Keep => self.from.layout(),
            Contents::Discard => vk::ImageLayout::UNDEFINED,
        };
        vk::ImageMemoryBarrier::default()
            .image(self.image)
            .old_layout(old)
            .new_layout(self.to.layout())
            .src_access_mask(src_access(self.from))
            .dst_access_mask(self.to.access())
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: self.aspect,
                base_mip_level: 0,
                level_count: self.mips,
                base_array_layer: self.base_layer,
                layer_count: self.layers,
            })
    }
}

/// A barrier on all memory (no image): e.g. a copy's writes made visible to the host.
#[derive(Clone, Copy, Debug)]
pub struct GlobalBarrier {
    /// The access before the barrier.
    pub from: Access,
    /// The access after it.
    pub to: Access,
}

/// Only writes need making available; read accesses in a source mask mean nothing.
fn src_access(a: Access) -> vk::AccessFlags {
    if a.writes() {
        a.access()
    } else {
        vk::AccessFlags::empty()
    }
}

/// The stage masks of a set of barriers: the union of every `from` and of every `to`.
pub fn stage_masks(
    images: &[ImageBarrier],
    global: Option<GlobalBarrier>,
) -> (vk::PipelineStageFlags, vk::PipelineStageFlags) {
    let mut src = vk::PipelineStageFlags::empty();
    let mut dst = vk::PipelineStageFlags::empty();
    for (from, to) in images
        .iter()
        .map(|b| (b.from, b.to))
        .chain(global.map(|g| (g.from, g.to)))
    {
        src |= from.stages();
        dst |= to.stages();
    }
    (src, dst)
}

/// Records one `vkCmdPipelineBarrier` for `images` and an optional global barrier, with the
/// stage masks they imply. No allocation: the Vulkan structs live on the stack.
pub fn record<const N: usize>(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: [ImageBarrier; N],
    global: Option<GlobalBarrier>,
) {
    let (src, dst) = stage_masks(&images, global);
    let raw = images.map(|b| b.raw());
    let memory = global.map(|g| {
        vk::MemoryBarrier::default()
            .src_access_mask(src_access(g.from))
            .dst_access_mask(g.to.access())
    });
    let memory = memory.as_slice();
    // SAFETY: `cmd` is a command buffer in the recording state (the caller's contract, as for
    // every `cmd_*` call); the barrier structs live until the call returns.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            src,
            dst,
            vk::DependencyFlags::empty(),
            memory,
            &[],
            &raw,
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transition_takes_its_layouts_masks_and_stages_from_the_names() {
        let b = ImageBarrier::colour(
            vk::Image::null(),
            2,
            Access::ColourAttachment,
            Access::TransferRead,
        )
        .raw();
        assert_eq!(b.old_layout, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        assert_eq!(b.new_layout, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
        assert_eq!(b.src_access_mask, vk::AccessFlags::COLOR_ATTACHMENT_WRITE);
        assert_eq!(b.dst_access_mask, vk::AccessFlags::TRANSFER_READ);
        assert_eq!(b.subresource_range.layer_count, 2);
        // A read before the barrier needs only the execution dependency.
        let upload = ImageBarrier::colour(
            vk::Image::null(),
            1,
            Access::ShaderSampled,
            Access::TransferWrite,
        )
        .mips(9)
        .discard();
        let raw = upload.raw();
        assert_eq!(raw.old_layout, vk::ImageLayout::UNDEFINED);
        assert_eq!(raw.src_access_mask, vk::AccessFlags::empty());
        assert_eq!(raw.subresource_range.level_count, 9);
        let (src, dst) = stage_masks(&[upload], None);
        assert_eq!(
            src,
            vk::PipelineStageFlags::VERTEX_SHADER | vk::PipelineStageFlags::FRAGMENT_SHADER
        );
        assert_eq!(dst, vk::PipelineStageFlags::TRANSFER);
    }

    #[test]
    fn stage_masks_are_the_union_of_every_side() {
        let a = ImageBarrier::colour(
            vk::Image::null(),
            2,
            Access::ColourAttachment,
            Access::TransferRead,
        );
        let b = ImageBarrier::colour(
            vk::Image::null(),
            1,
            Access::AcquiredForTransfer,
            Access::TransferWrite,
        );
        let host = GlobalBarrier {
            from: Access::TransferWrite,
            to: Access::HostRead,
        };
        let (src, dst) = stage_masks(&[a, b], Some(host));
        assert_eq!(
            src,
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER
        );
        assert_eq!(
            dst,
            vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::HOST
        );
    }
}
