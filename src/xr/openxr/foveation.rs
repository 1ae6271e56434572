//! Fixed foveation on Vulkan, end to end. Every piece must be there or none is used:
//!
//! - the runtime's `XR_FB_foveation`, `XR_FB_foveation_configuration`,
//!   `XR_FB_foveation_vulkan` and `XR_FB_swapchain_update_state`;
//! - the device's `VK_EXT_fragment_density_map` with non-subsampled images (so neither the
//!   eye images nor the MSAA attachments need `SUBSAMPLED` flags);
//! - the colour swapchain created with `XrSwapchainCreateInfoFoveationFB` (fragment density
//!   map), its density maps enumerated through `XrSwapchainImageFoveationVulkanFB`, and the
//!   render pass reading them (`render::render_pass`);
//! - a profile (`xrCreateFoveationProfileFB`) applied with `xrUpdateSwapchainFB`.
//!
//! Success is logged only when all of it is in place; otherwise one line says what is
//! missing.

use ash::vk;
use ash::vk::Handle as _;
use openxr as xr;

use super::error::check;
use super::quest::Foveation;
use super::swapchain::ArraySwapchain;

/// The runtime's and the device's foveation pieces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FoveationSupport {
    /// `XR_FB_foveation`.
    pub foveation: bool,
    /// `XR_FB_foveation_configuration` (level profiles).
    pub configuration: bool,
    /// `XR_FB_foveation_vulkan` (density map images).
    pub vulkan: bool,
    /// `XR_FB_swapchain_update_state` (applying a profile).
    pub update_state: bool,
    /// `VK_EXT_fragment_density_map` with non-subsampled images, enabled on the device.
    pub device: bool,
}

impl FoveationSupport {
    /// What the runtime lists (the device's part is filled in once the context exists).
    pub fn of_runtime(instance: &xr::Instance) -> Self {
        let e = instance.exts();
        Self {
            foveation: e.fb_foveation.is_some(),
            configuration: e.fb_foveation_configuration.is_some(),
            vulkan: e.fb_foveation_vulkan.is_some(),
            update_state: e.fb_swapchain_update_state.is_some(),
            device: false,
        }
    }

    /// Whether the runtime has every OpenXR piece.
    pub fn runtime_complete(&self) -> bool {
        self.foveation && self.configuration && self.vulkan && self.update_state
    }

    /// `Ok` when `level` can be applied; else why not (one line naming every missing piece).
    pub fn plan(&self, level: Foveation) -> Result<(), String> {
        if level == Foveation::Off {
            return Err("fixed foveation off (asked for)".into());
        }
        let missing: Vec<&str> = [
            (self.foveation, "XR_FB_foveation"),
            (self.configuration, "XR_FB_foveation_configuration"),
            (self.vulkan, "XR_FB_foveation_vulkan"),
            (self.update_state, "XR_FB_swapchain_update_state"),
        ]
        .iter()
        .filter(|(has, _)| !has)
        .map(|(_, name)| *name)
        .collect();
        if !missing.is_empty() {
            return Err(format!(
                "fixed foveation ({level:?}) off: the OpenXR runtime lacks {}",
                missing.join(", ")
            ));
        }
        if !self.device {
            return Err(format!(
                "fixed foveation ({level:?}) off: the Vulkan device lacks \
                 VK_EXT_fragment_density_map with non-subsampled images"
            ));
        }
        Ok(())
    }
}

/// Creates the 2-layer colour swapchain with fragment-density-map foveation and enumerates its
/// colour images and density maps (raw calls: the `openxr` crate chains neither structure).
pub(super) fn create_foveated_swapchain(
    session: &xr::Session<xr::Vulkan>,
    format: vk::Format,
    extent: vk::Extent2D,
    usage: xr::SwapchainUsageFlags,
) -> Result<ArraySwapchain, String> {
    let fp = session.instance().fp();
    let mut foveated = xr::sys::SwapchainCreateInfoFoveationFB {
        ty: xr::sys::SwapchainCreateInfoFoveationFB::TYPE,
        next: std::ptr::null_mut(),
        flags: xr::sys::SwapchainCreateFoveationFlagsFB::FRAGMENT_DENSITY_MAP,
    };
    let info = xr::sys::SwapchainCreateInfo {
        ty: xr::sys::SwapchainCreateInfo::TYPE,
        next: &mut foveated as *mut _ as *const std::ffi::c_void,
        create_flags: xr::SwapchainCreateFlags::EMPTY,
        usage_flags: usage,
        format: format.as_raw() as i64,
        sample_count: 1,
        width: extent.width,
        height: extent.height,
        face_count: 1,
        array_size: 2,
        mip_count: 1,
    };
    let mut raw = <xr::sys::Swapchain as xr::sys::Handle>::NULL;
    // SAFETY: a valid session and create info whose chain lives until the call returns.
    let r = unsafe { (fp.create_swapchain)(session.as_raw(), &info, &mut raw) };
    check(r).map_err(|e| {
        format!(
            "xrCreateSwapchain with foveation ({format:?}, {}x{} x2 layers) failed: {e:?} ({e})",
            extent.width, extent.height
        )
    })?;
    // SAFETY: `raw` was just created by this session and is owned by the wrapper from here.
    let handle = unsafe { xr::Swapchain::from_raw(session.clone(), raw) };
    let (images, density_maps) = enumerate_with_density_maps(fp, raw)?;
    Ok(ArraySwapchain {
        handle,
        images,
        format,
        density_maps,
    })
}

/// The swapchain's colour images and, chained to each, its density map.
fn enumerate_with_density_maps(
    fp: &xr::raw::Instance,
    swapchain: xr::sys::Swapchain,
) -> Result<(Vec<vk::Image>, Vec<vk::Image>), String> {
    let err = |e: xr::sys::Result| format!("xrEnumerateSwapchainImages (foveated): {e:?} ({e})");
    let mut count = 0;
    // SAFETY: a capacity-0 query with a writable count.
    let r =
        unsafe { (fp.enumerate_swapchain_images)(swapchain, 0, &mut count, std::ptr::null_mut()) };
    check(r).map_err(err)?;
    let n = count as usize;
    let mut maps: Vec<xr::sys::SwapchainImageFoveationVulkanFB> = (0..n)
        .map(|_| xr::sys::SwapchainImageFoveationVulkanFB {
            ty: xr::sys::SwapchainImageFoveationVulkanFB::TYPE,
            next: std::ptr::null_mut(),
            image: 0,
            width: 0,
            height: 0,
        })
        .collect();
    let mut images: Vec<xr::sys::SwapchainImageVulkanKHR> = maps
        .iter_mut()
        .map(|m| xr::sys::SwapchainImageVulkanKHR {
            ty: xr::sys::SwapchainImageVulkanKHR::TYPE,
            next: m as *mut _ as *mut std::ffi::c_void,
            image: 0,
        })
        .collect();
    // SAFETY: `images` has room for `count` elements, each chaining its own density map
    // struct, all alive for the call.
    let r = unsafe {
        (fp.enumerate_swapchain_images)(
            swapchain,
            count,
            &mut count,
            images.as_mut_ptr() as *mut xr::sys::SwapchainImageBaseHeader,
        )
    };
    check(r).map_err(err)?;
    let colours: Vec<vk::Image> = images
        .iter()
        .map(|i| vk::Image::from_raw(i.image))
        .collect();
    let densities: Vec<vk::Image> = maps.iter().map(|m| vk::Image::from_raw(m.image)).collect();
    if densities.iter().any(|d| d.is_null()) {
        return Err("the runtime gave no density map with a foveated swapchain image".into());
    }
    if let Some(m) = maps.first() {
        log::info!("fragment density maps: {}x{} texels", m.width, m.height);
    }
    Ok((colours, densities))
}

/// Applies a fixed `level` profile to the foveated colour swapchain. `None` (logged) when the
/// runtime refuses.
pub(super) fn apply_profile(
    instance: &xr::Instance,
    session: &xr::Session<xr::Vulkan>,
    colour: &ArraySwapchain,
    level: Foveation,
) -> Option<xr::FoveationProfileFB> {
    let update = instance.exts().fb_swapchain_update_state.as_ref()?;
    let profile = session
        .create_foveation_profile(Some(xr::FoveationLevelProfile {
            level: level.level(),
            vertical_offset: 0.0,
            dynamic: xr::FoveationDynamicFB::DISABLED,
        }))
        .map_err(|e| log::warn!("xrCreateFoveationProfileFB: {e:?} ({e})"))
        .ok()?;
    let state = xr::sys::SwapchainStateFoveationFB {
        ty: xr::sys::SwapchainStateFoveationFB::TYPE,
        next: std::ptr::null_mut(),
        flags: xr::sys::SwapchainStateFoveationFlagsFB::EMPTY,
        profile: profile.as_raw(),
    };
    // SAFETY: a valid swapchain and a state struct of the extension that outlives the call.
    let r = unsafe {
        (update.update_swapchain)(
            colour.handle.as_raw(),
            &state as *const _ as *const xr::sys::SwapchainStateBaseHeaderFB,
        )
    };
    if let Err(r) = check(r) {
        log::warn!("fixed foveation off: xrUpdateSwapchainFB failed: {r:?} ({r})");
        return None;
    }
    Some(profile)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> FoveationSupport {
        FoveationSupport {
            foveation: true,
            configuration: true,
            vulkan: true,
            update_state: true,
            device: true,
        }
    }

    #[test]
    fn foveation_needs_every_piece_and_names_what_is_missing() {
        assert_eq!(all().plan(Foveation::High), Ok(()));
        assert!(all().plan(Foveation::Off).is_err());
        // Monado: none of the runtime's pieces.
        let e = FoveationSupport::default()
            .plan(Foveation::Medium)
            .unwrap_err();
        assert!(
            e.contains("XR_FB_foveation,")
                && e.contains("XR_FB_foveation_configuration")
                && e.contains("XR_FB_foveation_vulkan")
                && e.contains("XR_FB_swapchain_update_state"),
            "{e}"
        );
        // Each one withheld alone is named alone.
        for (i, name) in [
            "XR_FB_foveation,",
            "XR_FB_foveation_configuration",
            "XR_FB_foveation_vulkan",
            "XR_FB_swapchain_update_state",
        ]
        .iter()
        .enumerate()
        {
            let mut s = all();
            match i {
                0 => s.foveation = false,
                1 => s.configuration = false,
                2 => s.vulkan = false,
                _ => s.update_state = false,
            }
            let e = s.plan(Foveation::Low).unwrap_err();
            assert!(e.contains(name.trim_end_matches(',')), "{e}");
            assert!(!s.runtime_complete());
        }
        let no_device = FoveationSupport {
            device: false,
            ..all()
        };
        assert!(no_device
            .plan(Foveation::High)
            .unwrap_err()
            .contains("VK_EXT_fragment_density_map"));
    }
}
