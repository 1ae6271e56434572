//! Showing the desktop backend's eye images in a window: a `VkSwapchainKHR` on the window's surface (FIFO,
//! sRGB when offered) and, per frame, one command buffer that blits layer 0 of the rendered
//! array image to the left half and layer 1 to the right half of the acquired window image,
//! keeping the eyes' aspect ratio (black bars around).
//!
//! Two frames may be in flight: each has its own command buffer, acquire semaphore and fence,
//! and each window image its own "blit done" semaphore (a present may wait on it after the
//! frame slot is reused). Nothing waits for the whole device except swapchain re-creation.

use ash::vk;

use super::COLOUR_FORMAT;
use crate::render::memory::{image_barrier, Buffer};
use crate::render::{commands, GpuContext, RenderError};

/// Frames the blit may run ahead of the GPU.
const FRAMES_IN_FLIGHT: usize = 2;

/// One frame slot's command buffer and synchronisation.
#[derive(Clone, Copy, Default)]
struct FrameSync {
    cmd: vk::CommandBuffer,
    acquired: vk::Semaphore,
    fence: vk::Fence,
}

/// A window image copied to the CPU (`--screenshot`).
pub struct Screenshot {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Tightly packed sRGB RGBA8 rows.
    pub rgba: Vec<u8>,
}

/// The window's swapchain and the blit that fills it.
pub struct Presenter {
    surface_fn: ash::khr::surface::Instance,
    swapchain_fn: ash::khr::swapchain::Device,
    surface: vk::SurfaceKHR,
    swapchain: vk::SwapchainKHR,
    format: vk::SurfaceFormatKHR,
    extent: vk::Extent2D,
    images: Vec<vk::Image>,
    blitted: Vec<vk::Semaphore>,
    pool: vk::CommandPool,
    frames: [FrameSync; FRAMES_IN_FLIGHT],
    frame: usize,
    stale: bool,
    filter: vk::Filter,
    can_capture: bool,
    capture: Option<Buffer>,
}

impl Presenter {
    /// Takes ownership of `surface` (destroyed on error) and creates a swapchain for a window of
    /// `size` pixels. Fails when the context's queue cannot present to the surface or the
    /// formats cannot be blitted.
    pub fn new(
        ctx: &GpuContext,
        surface: vk::SurfaceKHR,
        size: vk::Extent2D,
    ) -> Result<Self, RenderError> {
        let surface_fn = ash::khr::surface::Instance::new(&ctx.entry, &ctx.instance);
        let swapchain_fn = ash::khr::swapchain::Device::new(&ctx.instance, &ctx.device);
        let mut this = Self {
            surface_fn,
            swapchain_fn,
            surface,
            swapchain: vk::SwapchainKHR::null(),
            format: vk::SurfaceFormatKHR::default(),
            extent: vk::Extent2D::default(),
            images: Vec::new(),
            blitted: Vec::new(),
            pool: vk::CommandPool::null(),
            frames: [FrameSync::default(); FRAMES_IN_FLIGHT],
            frame: 0,
            stale: true,
            filter: vk::Filter::NEAREST,
            can_capture: false,
            capture: None,
        };
        match this.init(ctx, size) {
            Ok(()) => Ok(this),
            Err(e) => {
                this.destroy(ctx);
                Err(e)
            }
        }
    }

    fn init(&mut self, ctx: &GpuContext, size: vk::Extent2D) -> Result<(), RenderError> {
        // SAFETY: the surface belongs to the context's instance; the device and family are its.
        let supported = unsafe {
            self.surface_fn.get_physical_device_surface_support(
                ctx.physical,
                ctx.queue_family,
                self.surface,
            )
        }
        .map_err(RenderError::vk("vkGetPhysicalDeviceSurfaceSupportKHR"))?;
        if !supported {
            return Err(RenderError::Unsupported(format!(
                "presentation to this window from its graphics queue family {} \
                 (try another driver, or `vr-ocean headless`)",
                ctx.queue_family
            )));
        }
        let src = unsafe {
            ctx.instance
                .get_physical_device_format_properties(ctx.physical, COLOUR_FORMAT)
        }
        .optimal_tiling_features;
        if !src.contains(vk::FormatFeatureFlags::BLIT_SRC) {
            return Err(RenderError::Unsupported(format!(
                "blits from {COLOUR_FORMAT:?} images"
            )));
        }
        if src.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR) {
            self.filter = vk::Filter::LINEAR;
        }
        let d = &ctx.device;
        self.pool = commands::command_pool(ctx, vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
        let cmds = commands::primary_buffers(ctx, self.pool, FRAMES_IN_FLIGHT as u32)?;
        for (f, cmd) in self.frames.iter_mut().zip(cmds) {
            f.cmd = cmd;
            f.acquired = unsafe { d.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .map_err(RenderError::vk("vkCreateSemaphore"))?;
            f.fence = commands::fence(ctx, true)?;
        }
        self.recreate(ctx, size)?;
        Ok(())
    }

    /// Marks the swapchain for re-creation before the next frame (the window was resized).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Re-creates the swapchain for a window of `size`; false when it has no area (minimised).
    fn recreate(&mut self, ctx: &GpuContext, size: vk::Extent2D) -> Result<bool, RenderError> {
        let caps = unsafe {
            self.surface_fn
                .get_physical_device_surface_capabilities(ctx.physical, self.surface)
        }
        .map_err(RenderError::vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR"))?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size.width.clamp(
                    caps.min_image_extent.width,
                    caps.max_image_extent.width.max(1),
                ),
                height: size.height.clamp(
                    caps.min_image_extent.height,
                    caps.max_image_extent.height.max(1),
                ),
            }
        };
        // Two halves of at least one pixel each.
        if extent.width < 2 || extent.height == 0 {
            self.extent = vk::Extent2D::default();
            self.stale = true;
            return Ok(false);
        }
        // Not the steady state: a resize may stall once (the old images may still be in use).
        ctx.wait_idle();
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST)
        {
            return Err(RenderError::Unsupported(
                "window images that can be blitted to (TRANSFER_DST)".into(),
            ));
        }
        let formats = unsafe {
            self.surface_fn
                .get_physical_device_surface_formats(ctx.physical, self.surface)
        }
        .map_err(RenderError::vk("vkGetPhysicalDeviceSurfaceFormatsKHR"))?;
        self.format = choose_format(&formats).ok_or_else(|| {
            RenderError::Unsupported("a surface format for the window".to_string())
        })?;
        let dst = unsafe {
            ctx.instance
                .get_physical_device_format_properties(ctx.physical, self.format.format)
        }
        .optimal_tiling_features;
        if !dst.contains(vk::FormatFeatureFlags::BLIT_DST) {
            return Err(RenderError::Unsupported(format!(
                "blits to the window's format {:?}",
                self.format.format
            )));
        }
        self.can_capture = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let mut usage = vk::ImageUsageFlags::TRANSFER_DST;
        if self.can_capture {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        let mut count = caps.min_image_count.max(2) + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let old = self.swapchain;
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface)
            .min_image_count(count)
            .image_format(self.format.format)
            .image_color_space(self.format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old);
        let swapchain = unsafe { self.swapchain_fn.create_swapchain(&info, None) }
            .map_err(RenderError::vk("vkCreateSwapchainKHR"))?;
        let d = &ctx.device;
        unsafe {
            self.swapchain_fn.destroy_swapchain(old, None);
            for s in self.blitted.drain(..) {
                d.destroy_semaphore(s, None);
            }
        }
        self.swapchain = swapchain;
        self.images = unsafe { self.swapchain_fn.get_swapchain_images(swapchain) }
            .map_err(RenderError::vk("vkGetSwapchainImagesKHR"))?;
        for _ in 0..self.images.len() {
            let s = unsafe { d.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .map_err(RenderError::vk("vkCreateSemaphore"))?;
            self.blitted.push(s);
        }
        self.extent = extent;
        self.stale = false;
        log::info!(
            "window swapchain: {}x{} {:?}, {} images, FIFO",
            extent.width,
            extent.height,
            self.format.format,
            self.images.len()
        );
        Ok(true)
    }

    /// Blits both layers of `eyes` (in `COLOR_ATTACHMENT_OPTIMAL`, rendered by earlier
    /// submissions on the same queue, left so) of size `eye` per layer into the next window
    /// image and presents it. `window` is the window's current inner size. With `capture`, the
    /// shown image is also copied to the CPU (waits for it; not for the steady state).
    pub fn present(
        &mut self,
        ctx: &GpuContext,
        eyes: vk::Image,
        eye: vk::Extent2D,
        window: vk::Extent2D,
        capture: bool,
    ) -> Result<Option<Screenshot>, RenderError> {
        if self.stale && !self.recreate(ctx, window)? {
            return Ok(None);
        }
        let d = &ctx.device;
        let f = self.frames[self.frame];
        unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))?;
        let index = match unsafe {
            self.swapchain_fn.acquire_next_image(
                self.swapchain,
                u64::MAX,
                f.acquired,
                vk::Fence::null(),
            )
        } {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                index
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                // The semaphore was not signalled; try again with a new swapchain next frame.
                self.stale = true;
                return Ok(None);
            }
            Err(e) => return Err(RenderError::vk("vkAcquireNextImageKHR")(e)),
        };
        let target = self.images[index as usize];
        let capture = capture && self.can_capture;
        if capture {
            let size = 4 * self.extent.width as u64 * self.extent.height as u64;
            if self.capture.as_ref().is_none_or(|b| b.size < size) {
                if let Some(mut b) = self.capture.take() {
                    b.destroy(ctx);
                }
                self.capture = Some(Buffer::new(
                    ctx,
                    size,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    true,
                )?);
            }
        }
        unsafe {
            d.reset_fences(&[f.fence])
                .map_err(RenderError::vk("vkResetFences"))?;
            d.reset_command_buffer(f.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(RenderError::vk("vkResetCommandBuffer"))?;
            d.begin_command_buffer(
                f.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(RenderError::vk("vkBeginCommandBuffer"))?;
        }
        let readback = if capture {
            self.capture.as_ref().map(|b| b.raw)
        } else {
            None
        };
        self.record_blit(ctx, f.cmd, eyes, eye, target, readback);
        unsafe { d.end_command_buffer(f.cmd) }.map_err(RenderError::vk("vkEndCommandBuffer"))?;

        let waits = [f.acquired];
        let stages = [vk::PipelineStageFlags::TRANSFER];
        let cmds = [f.cmd];
        let signals = [self.blitted[index as usize]];
        let submit = [vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals)];
        unsafe { d.queue_submit(ctx.queue, &submit, f.fence) }
            .map_err(RenderError::vk("vkQueueSubmit"))?;
        let swapchains = [self.swapchain];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&signals)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match unsafe { self.swapchain_fn.queue_present(ctx.queue, &info) } {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(e) => return Err(RenderError::vk("vkQueuePresentKHR")(e)),
        }
        self.frame = (self.frame + 1) % FRAMES_IN_FLIGHT;
        if !capture {
            return Ok(None);
        }
        unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))?;
        let (width, height) = (self.extent.width, self.extent.height);
        let bytes = 4 * width as usize * height as usize;
        let mut rgba = self
            .capture
            .as_ref()
            .map_or_else(Vec::new, |b| b.bytes()[..bytes].to_vec());
        if matches!(
            self.format.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        ) {
            for px in rgba.chunks_exact_mut(4) {
                px.swap(0, 2);
            }
        }
        Ok(Some(Screenshot {
            width,
            height,
            rgba,
        }))
    }

    fn record_blit(
        &self,
        ctx: &GpuContext,
        cmd: vk::CommandBuffer,
        eyes: vk::Image,
        eye: vk::Extent2D,
        target: vk::Image,
        readback: Option<vk::Buffer>,
    ) {
        let d = &ctx.device;
        let colour = vk::ImageAspectFlags::COLOR;
        let to_blit = [
            image_barrier(
                eyes,
                colour,
                2,
                1,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                vk::AccessFlags::TRANSFER_READ,
            ),
            image_barrier(
                target,
                colour,
                1,
                1,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::empty(),
                vk::AccessFlags::TRANSFER_WRITE,
            ),
        ];
        let after_clear = [image_barrier(
            target,
            colour,
            1,
            1,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::AccessFlags::TRANSFER_WRITE,
        )];
        let (window_layout, window_access) = if readback.is_some() {
            (
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::AccessFlags::TRANSFER_READ,
            )
        } else {
            (vk::ImageLayout::PRESENT_SRC_KHR, vk::AccessFlags::empty())
        };
        let after_blit = [
            image_barrier(
                eyes,
                colour,
                2,
                1,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::AccessFlags::TRANSFER_READ,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
            image_barrier(
                target,
                colour,
                1,
                1,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                window_layout,
                vk::AccessFlags::TRANSFER_WRITE,
                window_access,
            ),
        ];
        let range = [vk::ImageSubresourceRange {
            aspect_mask: colour,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        }];
        let rects = eye_rects(self.extent, eye);
        let regions: [vk::ImageBlit; 2] = std::array::from_fn(|layer| vk::ImageBlit {
            src_subresource: layers(layer as u32),
            src_offsets: [
                vk::Offset3D::default(),
                vk::Offset3D {
                    x: eye.width as i32,
                    y: eye.height as i32,
                    z: 1,
                },
            ],
            dst_subresource: layers(0),
            dst_offsets: rects[layer],
        });
        let black = vk::ClearColorValue {
            float32: [0.0, 0.0, 0.0, 1.0],
        };
        unsafe {
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_blit,
            );
            d.cmd_clear_color_image(
                cmd,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &black,
                &range,
            );
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &after_clear,
            );
            d.cmd_blit_image(
                cmd,
                eyes,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
                self.filter,
            );
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                    | vk::PipelineStageFlags::TRANSFER
                    | vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &after_blit,
            );
        }
        if let Some(buffer) = readback {
            let copy = vk::BufferImageCopy {
                buffer_offset: 0,
                buffer_row_length: 0,
                buffer_image_height: 0,
                image_subresource: layers(0),
                image_offset: vk::Offset3D::default(),
                image_extent: vk::Extent3D {
                    width: self.extent.width,
                    height: self.extent.height,
                    depth: 1,
                },
            };
            let to_present = [image_barrier(
                target,
                colour,
                1,
                1,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::ImageLayout::PRESENT_SRC_KHR,
                vk::AccessFlags::TRANSFER_READ,
                vk::AccessFlags::empty(),
            )];
            let to_host = [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::HOST_READ)];
            unsafe {
                d.cmd_copy_image_to_buffer(
                    cmd,
                    target,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buffer,
                    &[copy],
                );
                d.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::BOTTOM_OF_PIPE | vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &to_host,
                    &[],
                    &to_present,
                );
            }
        }
    }

    /// Frees everything, the surface included. Waits for the device first.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        ctx.wait_idle();
        let d = &ctx.device;
        unsafe {
            for f in &self.frames {
                d.destroy_semaphore(f.acquired, None);
                d.destroy_fence(f.fence, None);
            }
            self.frames = [FrameSync::default(); FRAMES_IN_FLIGHT];
            for s in self.blitted.drain(..) {
                d.destroy_semaphore(s, None);
            }
            d.destroy_command_pool(self.pool, None);
            self.pool = vk::CommandPool::null();
            self.swapchain_fn.destroy_swapchain(self.swapchain, None);
            self.swapchain = vk::SwapchainKHR::null();
            self.surface_fn.destroy_surface(self.surface, None);
            self.surface = vk::SurfaceKHR::null();
        }
        if let Some(mut b) = self.capture.take() {
            b.destroy(ctx);
        }
        self.images.clear();
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

/// Prefers an sRGB 8-bit format in the sRGB colour space (the eyes are sRGB, so the blit keeps
/// their values); otherwise the surface's first.
fn choose_format(formats: &[vk::SurfaceFormatKHR]) -> Option<vk::SurfaceFormatKHR> {
    [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB]
        .into_iter()
        .find_map(|want| {
            formats
                .iter()
                .copied()
                .find(|f| f.format == want && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
        })
        .or_else(|| {
            let f = formats.first().copied()?;
            log::warn!(
                "the window offers no sRGB format; using {:?} (colours may look off)",
                f.format
            );
            Some(f)
        })
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
