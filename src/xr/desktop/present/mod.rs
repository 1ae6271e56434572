//! Showing the desktop backend's eye images in a window: a `VkSwapchainKHR` on the window's surface (FIFO,
//! sRGB when offered) and, per frame, one command buffer that blits layer 0 of the rendered
//! array image to the left half and layer 1 to the right half of the acquired window image,
//! keeping the eyes' aspect ratio (black bars around).
//!
//! The control panel, when open, is blitted over the eyes (`overlay`).
//!
//! Two frames may be in flight: each has its own command buffer, acquire semaphore and fence,
//! and each window image its own "blit done" semaphore (a present may wait on it after the
//! frame slot is reused). Nothing waits for the whole device except swapchain re-creation.

use ash::vk;

mod blit;
mod overlay;
mod swapchain;

pub use overlay::OverlayPlacement;

use super::COLOUR_FORMAT;
use crate::render::memory::Buffer;
use crate::render::{commands, GpuContext, RenderError};
use crate::ui::panel::Panel;

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
    /// The control panel's image, once it was first shown.
    overlay: Option<overlay::Overlay>,
    /// Where the last presented frame showed the panel.
    placement: Option<OverlayPlacement>,
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
            overlay: None,
            placement: None,
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
        // SAFETY: the physical device belongs to the context's instance.
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
            // SAFETY: a valid create info on a live device.
            f.acquired = unsafe { d.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .map_err(RenderError::vk("vkCreateSemaphore"))?;
            f.fence = commands::fence(ctx, true)?;
        }
        self.recreate(ctx, size)?;
        Ok(())
    }

    /// Paints `panel` into the overlay's image when it drew a new one (see
    /// [`Presenter::present`]'s `panel`).
    pub fn paint_panel(&mut self, ctx: &GpuContext, panel: &mut Panel) -> Result<(), RenderError> {
        self.overlay
            .get_or_insert_with(overlay::Overlay::default)
            .paint(ctx, panel)
    }

    /// Where the last presented frame showed the panel (window pixels), if it did.
    pub fn panel_placement(&self) -> Option<OverlayPlacement> {
        self.placement
    }

    /// Marks the swapchain for re-creation before the next frame (the window was resized).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Blits both layers of `eyes` (in `COLOR_ATTACHMENT_OPTIMAL`, rendered by earlier
    /// submissions on the same queue, left so) of size `eye` per layer into the next window
    /// image and presents it. `window` is the window's current inner size; with `panel`, the
    /// last painted panel goes over the eyes, centred ([`Presenter::panel_placement`]). With
    /// `capture`, the shown image is also copied to the CPU (waits for it; not for the steady
    /// state).
    pub fn present(
        &mut self,
        ctx: &GpuContext,
        eyes: vk::Image,
        eye: vk::Extent2D,
        window: vk::Extent2D,
        panel: bool,
        capture: bool,
    ) -> Result<Option<Screenshot>, RenderError> {
        if self.stale && !self.recreate(ctx, window)? {
            return Ok(None);
        }
        let d = &ctx.device;
        let f = self.frames[self.frame];
        // SAFETY: the fence is alive.
        unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX) }
            .map_err(RenderError::vk("vkWaitForFences"))?;
        // SAFETY: the swapchain is current (re-created when stale) and the semaphore unsignalled
        // (its previous wait was submitted before this slot's fence signalled).
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
        // SAFETY: the slot's fence signalled, so its command buffer is not pending.
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
        let overlay = self
            .overlay
            .as_ref()
            .filter(|_| panel)
            .and_then(|o| o.blit(self.extent));
        self.placement = overlay.map(|o| o.placement);
        let readback = if capture {
            self.capture.as_ref().map(|b| b.raw)
        } else {
            None
        };
        blit::Blit {
            device: &ctx.device,
            cmd: f.cmd,
            eyes,
            eye,
            target,
            window: self.extent,
            filter: self.filter,
            overlay,
        }
        .record(readback);
        // SAFETY: `f.cmd` is recording.
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
        // SAFETY: the command buffer is executable, the fence reset, the semaphores alive.
        unsafe { d.queue_submit(ctx.queue, &submit, f.fence) }
            .map_err(RenderError::vk("vkQueueSubmit"))?;
        let swapchains = [self.swapchain];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&signals)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired from this swapchain and its blit signals `signals`.
        match unsafe { self.swapchain_fn.queue_present(ctx.queue, &info) } {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(e) => return Err(RenderError::vk("vkQueuePresentKHR")(e)),
        }
        self.frame = (self.frame + 1) % FRAMES_IN_FLIGHT;
        if !capture {
            return Ok(None);
        }
        // SAFETY: the fence is alive.
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

    /// Frees everything, the surface included. Waits for the device first.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        ctx.wait_idle();
        let d = &ctx.device;
        // SAFETY: the device is idle; null handles (parts never made) are no-ops.
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
        if let Some(mut o) = self.overlay.take() {
            o.destroy(ctx);
        }
        self.images.clear();
    }
}
