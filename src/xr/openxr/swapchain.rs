//! The colour swapchain (2 array layers, sRGB, drawn by the multiview pass) and the optional
//! depth swapchain handed to the compositor through `XR_KHR_composition_layer_depth`.

use ash::vk;
use ash::vk::Handle as _;
use openxr as xr;

use crate::render::DEPTH_FORMAT;

/// sRGB colour formats, best first. The runtime's own order is not a preference (Monado lists
/// 16-bit UNORM formats first).
pub const COLOUR_FORMATS: [vk::Format; 2] = [vk::Format::R8G8B8A8_SRGB, vk::Format::B8G8R8A8_SRGB];

/// Picks the colour format from what the runtime offers; an error names what it offered.
pub fn choose_colour_format(offered: &[i64]) -> Result<vk::Format, String> {
    COLOUR_FORMATS
        .iter()
        .copied()
        .find(|f| offered.contains(&(f.as_raw() as i64)))
        .ok_or_else(|| {
            let names: Vec<String> = offered
                .iter()
                .map(|&f| format!("{:?}", vk::Format::from_raw(f as i32)))
                .collect();
            format!(
                "the OpenXR runtime offers no sRGB swapchain format (wanted {:?}; offered: {})",
                COLOUR_FORMATS,
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )
        })
}

/// Whether the runtime offers the renderer's depth format.
pub fn offers_depth(offered: &[i64]) -> bool {
    offered.contains(&(DEPTH_FORMAT.as_raw() as i64))
}

/// Per-eye size: the recommended size scaled, checked against the maximum (never clamped).
pub fn eye_extent(view: &xr::ViewConfigurationView, scale: f32) -> Result<vk::Extent2D, String> {
    let side = |rec: u32, max: u32, what: &str| -> Result<u32, String> {
        let s = (rec as f32 * scale).round();
        if s < 1.0 {
            return Err(format!(
                "resolution scale {scale}: the {what} ({rec} px recommended) would be empty"
            ));
        }
        if s > max as f32 {
            return Err(format!(
                "resolution scale {scale}: {what} {s} px exceeds the runtime's maximum of {max} \
                 (recommended {rec})"
            ));
        }
        Ok(s as u32)
    };
    Ok(vk::Extent2D {
        width: side(
            view.recommended_image_rect_width,
            view.max_image_rect_width,
            "width",
        )?,
        height: side(
            view.recommended_image_rect_height,
            view.max_image_rect_height,
            "height",
        )?,
    })
}

/// A swapchain with 2 array layers and its images.
pub struct ArraySwapchain {
    /// The runtime's swapchain.
    pub handle: xr::Swapchain<xr::Vulkan>,
    /// Its images, as Vulkan handles.
    pub images: Vec<vk::Image>,
    /// Their format.
    pub format: vk::Format,
    /// One fragment density map per image (fixed foveation); empty without.
    pub density_maps: Vec<vk::Image>,
}

impl ArraySwapchain {
    /// Creates a 2-layer swapchain of `format` and `extent` for `usage`.
    pub fn new(
        session: &xr::Session<xr::Vulkan>,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: xr::SwapchainUsageFlags,
    ) -> Result<Self, String> {
        let handle = session
            .create_swapchain(&xr::SwapchainCreateInfo {
                create_flags: xr::SwapchainCreateFlags::EMPTY,
                usage_flags: usage,
                format: format.as_raw() as u32,
                sample_count: 1,
                width: extent.width,
                height: extent.height,
                face_count: 1,
                array_size: 2,
                mip_count: 1,
            })
            .map_err(|e| {
                format!(
                    "xrCreateSwapchain ({format:?}, {}x{} x2 layers) failed: {e:?} ({e})",
                    extent.width, extent.height
                )
            })?;
        let images = handle
            .enumerate_images()
            .map_err(|e| format!("xrEnumerateSwapchainImages failed: {e:?} ({e})"))?
            .into_iter()
            .map(vk::Image::from_raw)
            .collect();
        Ok(Self {
            handle,
            images,
            format,
            density_maps: Vec::new(),
        })
    }

    /// Acquires the next image and waits until it may be written; returns its index.
    pub fn acquire(&mut self) -> Result<u32, xr::sys::Result> {
        let i = self.handle.acquire_image()?;
        self.handle.wait_image(xr::Duration::INFINITE)?;
        Ok(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_is_chosen_by_our_order_not_the_runtimes() {
        // Monado 25.0's order: 16-bit formats first, sRGB third.
        let monado = [91, 97, 43, 50, 37, 44, 4, 100, 126, 124, 125, 129, 130, 127];
        assert_eq!(choose_colour_format(&monado), Ok(vk::Format::R8G8B8A8_SRGB));
        assert!(offers_depth(&monado));
        // Only BGRA sRGB: the fallback.
        assert_eq!(
            choose_colour_format(&[37, 50]),
            Ok(vk::Format::B8G8R8A8_SRGB)
        );
    }

    #[test]
    fn no_srgb_is_an_error_naming_the_offer() {
        let e = choose_colour_format(&[37, 44]).unwrap_err();
        assert!(e.contains("no sRGB") && e.contains("R8G8B8A8_UNORM"), "{e}");
        let e = choose_colour_format(&[]).unwrap_err();
        assert!(e.contains("offered: none"), "{e}");
        assert!(!offers_depth(&[37]));
    }

    #[test]
    fn eye_size_scales_and_refuses_past_the_maximum() {
        let v = xr::ViewConfigurationView {
            recommended_image_rect_width: 1680,
            max_image_rect_width: 2048,
            recommended_image_rect_height: 1760,
            max_image_rect_height: 2048,
            recommended_swapchain_sample_count: 1,
            max_swapchain_sample_count: 1,
        };
        assert_eq!(
            eye_extent(&v, 1.0),
            Ok(vk::Extent2D {
                width: 1680,
                height: 1760
            })
        );
        assert_eq!(
            eye_extent(&v, 0.5),
            Ok(vk::Extent2D {
                width: 840,
                height: 880
            })
        );
        let e = eye_extent(&v, 1.2).unwrap_err();
        assert!(e.contains("2016") || e.contains("2112"), "{e}");
        assert!(e.contains("maximum of 2048"), "{e}");
        assert!(eye_extent(&v, 0.0001).is_err());
    }
}
