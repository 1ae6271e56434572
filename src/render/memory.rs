//! Buffers and images with their own memory. The renderer owns a few dozen long-lived
//! resources, all created up front, so one allocation each is simple and costs nothing per frame.

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;

/// A buffer bound to its own memory, persistently mapped when host-visible.
pub struct Buffer {
    /// The buffer.
    pub raw: vk::Buffer,
    memory: vk::DeviceMemory,
    /// Size in bytes.
    pub size: u64,
    mapped: *mut u8,
}

// SAFETY: the mapping is plain memory owned by this buffer; access follows Rust borrows.
unsafe impl Send for Buffer {}

impl Buffer {
    /// A buffer not made yet: destroying it does nothing (a placeholder for parts created in
    /// steps).
    pub fn null() -> Self {
        Self {
            raw: vk::Buffer::null(),
            memory: vk::DeviceMemory::null(),
            size: 0,
            mapped: std::ptr::null_mut(),
        }
    }

    /// A device-local buffer (`host_visible` false) or a host-visible, coherent, mapped one.
    /// Nothing is left behind when a step fails.
    pub fn new(
        ctx: &GpuContext,
        size: u64,
        usage: vk::BufferUsageFlags,
        host_visible: bool,
    ) -> Result<Self, RenderError> {
        let d = &ctx.device;
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: a valid create info on a live device.
        let raw = ctx.create("vkCreateBuffer", || unsafe { d.create_buffer(&info, None) })?;
        let mut this = Self {
            raw,
            memory: vk::DeviceMemory::null(),
            size,
            mapped: std::ptr::null_mut(),
        };
        if let Err(e) = this.bind(ctx, host_visible) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    /// Allocates, binds and (host-visible) maps the buffer's memory.
    fn bind(&mut self, ctx: &GpuContext, host_visible: bool) -> Result<(), RenderError> {
        let d = &ctx.device;
        // SAFETY: the buffer is alive.
        let req = unsafe { d.get_buffer_memory_requirements(self.raw) };
        let flags = if host_visible {
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT
        } else {
            vk::MemoryPropertyFlags::DEVICE_LOCAL
        };
        self.memory = allocate(ctx, req, flags)?;
        // SAFETY: fresh memory of the buffer's requirements, bound once at offset 0.
        unsafe { d.bind_buffer_memory(self.raw, self.memory, 0) }
            .map_err(RenderError::vk("vkBindBufferMemory"))?;
        if host_visible {
            // SAFETY: host-visible memory, mapped once for the buffer's lifetime.
            let p = unsafe {
                d.map_memory(self.memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
            }
            .map_err(RenderError::vk("vkMapMemory"))?;
            self.mapped = p as *mut u8;
        }
        Ok(())
    }

    /// The mapped bytes (host-visible buffers only).
    ///
    /// # Panics
    /// On a device-local buffer.
    pub fn bytes_mut(&mut self) -> &mut [u8] {
        assert!(!self.mapped.is_null(), "buffer is not host-visible");
        // SAFETY: the mapping covers `size` bytes and lives as long as `self`.
        unsafe { std::slice::from_raw_parts_mut(self.mapped, self.size as usize) }
    }

    /// The mapped bytes, read-only.
    ///
    /// # Panics
    /// On a device-local buffer.
    pub fn bytes(&self) -> &[u8] {
        assert!(!self.mapped.is_null(), "buffer is not host-visible");
        // SAFETY: as in `bytes_mut`.
        unsafe { std::slice::from_raw_parts(self.mapped, self.size as usize) }
    }

    /// Frees the buffer (null handles are skipped). The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the buffer (the caller's contract); freeing the memory
        // unmaps it; destroying null handles is a no-op.
        unsafe {
            ctx.device.destroy_buffer(self.raw, None);
            ctx.device.free_memory(self.memory, None);
        }
        self.raw = vk::Buffer::null();
        self.memory = vk::DeviceMemory::null();
        self.mapped = std::ptr::null_mut();
    }
}

/// A 2D (array) image with its own memory and one view over all layers and mips.
pub struct Image {
    /// The image.
    pub raw: vk::Image,
    memory: vk::DeviceMemory,
    /// View of every layer and mip (2D array).
    pub view: vk::ImageView,
    /// Format.
    pub format: vk::Format,
    /// Size of mip 0.
    pub extent: vk::Extent2D,
    /// Array layers.
    pub layers: u32,
    /// Mip levels.
    pub mips: u32,
    /// Bytes of device memory bound to it.
    pub bytes: u64,
}

/// What an [`Image`] is made of.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc {
    /// Format.
    pub format: vk::Format,
    /// Mip-0 size.
    pub extent: vk::Extent2D,
    /// Array layers.
    pub layers: u32,
    /// Mip levels.
    pub mips: u32,
    /// Samples per pixel (`TYPE_1` but for multisampled attachments).
    pub samples: vk::SampleCountFlags,
    /// Usage.
    pub usage: vk::ImageUsageFlags,
    /// Aspect of the view.
    pub aspect: vk::ImageAspectFlags,
    /// Prefer lazily allocated memory (transient attachments on tile-based GPUs).
    pub transient: bool,
}

impl Image {
    /// Creates the image, its memory and its array view. Nothing is left behind when a step
    /// fails.
    pub fn new(ctx: &GpuContext, desc: ImageDesc) -> Result<Self, RenderError> {
        let d = &ctx.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.extent.width,
                height: desc.extent.height,
                depth: 1,
            })
            .mip_levels(desc.mips)
            .array_layers(desc.layers)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a valid create info on a live device.
        let raw = ctx.create("vkCreateImage", || unsafe { d.create_image(&info, None) })?;
        let mut this = Self {
            raw,
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
            format: desc.format,
            extent: desc.extent,
            layers: desc.layers,
            mips: desc.mips,
            bytes: 0,
        };
        if let Err(e) = this.bind_and_view(ctx, desc) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    /// An image not made yet: destroying it does nothing (a placeholder for parts created in
    /// steps).
    pub fn null() -> Self {
        Self {
            raw: vk::Image::null(),
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
            layers: 0,
            mips: 0,
            bytes: 0,
        }
    }

    /// Allocates and binds the memory (lazily allocated for transient attachments where the
    /// device offers it), then makes the view.
    fn bind_and_view(&mut self, ctx: &GpuContext, desc: ImageDesc) -> Result<(), RenderError> {
        let d = &ctx.device;
        // SAFETY: the image is alive.
        let req = unsafe { d.get_image_memory_requirements(self.raw) };
        let lazy =
            vk::MemoryPropertyFlags::DEVICE_LOCAL | vk::MemoryPropertyFlags::LAZILY_ALLOCATED;
        let flags = if desc.transient && ctx.memory_type(req.memory_type_bits, lazy).is_some() {
            lazy
        } else {
            vk::MemoryPropertyFlags::DEVICE_LOCAL
        };
        self.memory = allocate(ctx, req, flags)?;
        self.bytes = req.size;
        // SAFETY: fresh memory of the image's requirements, bound once at offset 0.
        unsafe { d.bind_image_memory(self.raw, self.memory, 0) }
            .map_err(RenderError::vk("vkBindImageMemory"))?;
        self.view = create_view(
            ctx,
            self.raw,
            desc.format,
            desc.aspect,
            0,
            desc.layers,
            desc.mips,
        )?;
        Ok(())
    }

    /// Frees the image (null handles are skipped). The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the image (the caller's contract); destroying null
        // handles is a no-op.
        unsafe {
            ctx.device.destroy_image_view(self.view, None);
            ctx.device.destroy_image(self.raw, None);
            ctx.device.free_memory(self.memory, None);
        }
        self.raw = vk::Image::null();
        self.view = vk::ImageView::null();
        self.memory = vk::DeviceMemory::null();
    }
}

/// A 2D-array view of `count` layers from `base` (all `mips`).
pub fn create_view(
    ctx: &GpuContext,
    image: vk::Image,
    format: vk::Format,
    aspect: vk::ImageAspectFlags,
    base: u32,
    count: u32,
    mips: u32,
) -> Result<vk::ImageView, RenderError> {
    let info = vk::ImageViewCreateInfo::default()
        .image(image)
        .view_type(vk::ImageViewType::TYPE_2D_ARRAY)
        .format(format)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: aspect,
            base_mip_level: 0,
            level_count: mips,
            base_array_layer: base,
            layer_count: count,
        });
    // SAFETY: `image` is alive and the range lies within it (the caller's contract).
    ctx.create("vkCreateImageView", || unsafe {
        ctx.device.create_image_view(&info, None)
    })
}

fn allocate(
    ctx: &GpuContext,
    req: vk::MemoryRequirements,
    flags: vk::MemoryPropertyFlags,
) -> Result<vk::DeviceMemory, RenderError> {
    let index = ctx
        .memory_type(req.memory_type_bits, flags)
        .ok_or_else(|| RenderError::Unsupported(format!("a memory type with {flags:?}")))?;
    let info = vk::MemoryAllocateInfo::default()
        .allocation_size(req.size)
        .memory_type_index(index);
    // SAFETY: a valid allocate info of one of the device's memory types.
    ctx.create("vkAllocateMemory", || unsafe {
        ctx.device.allocate_memory(&info, None)
    })
}
