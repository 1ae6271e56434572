//! The window's `VkSwapchainKHR`: (re-)created for the window's size with an sRGB format,
//! FIFO presentation and one "blit done" semaphore per image.

use ash::vk;

use super::Presenter;
use crate::render::{GpuContext, RenderError};

impl Presenter {
    /// Re-creates the swapchain for a window of `size`; false when it has no area (minimised).
    pub(super) fn recreate(
        &mut self,
        ctx: &GpuContext,
        size: vk::Extent2D,
    ) -> Result<bool, RenderError> {
        // SAFETY: the surface and the physical device belong to the context's instance.
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
        // SAFETY: as above.
        let formats = unsafe {
            self.surface_fn
                .get_physical_device_surface_formats(ctx.physical, self.surface)
        }
        .map_err(RenderError::vk("vkGetPhysicalDeviceSurfaceFormatsKHR"))?;
        self.format = choose_format(&formats).ok_or_else(|| {
            RenderError::Unsupported("a surface format for the window".to_string())
        })?;
        // SAFETY: the physical device belongs to the context's instance.
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
        // SAFETY: the surface is alive; the old swapchain (or null) is retired by this call.
        let swapchain = unsafe { self.swapchain_fn.create_swapchain(&info, None) }
            .map_err(RenderError::vk("vkCreateSwapchainKHR"))?;
        let d = &ctx.device;
        // SAFETY: the device is idle (waited above), so the old swapchain's images and the
        // semaphores are unused.
        unsafe {
            self.swapchain_fn.destroy_swapchain(old, None);
            for s in self.blitted.drain(..) {
                d.destroy_semaphore(s, None);
            }
        }
        self.swapchain = swapchain;
        // SAFETY: the swapchain was just created.
        self.images = unsafe { self.swapchain_fn.get_swapchain_images(swapchain) }
            .map_err(RenderError::vk("vkGetSwapchainImagesKHR"))?;
        for _ in 0..self.images.len() {
            // SAFETY: a valid create info on a live device.
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
