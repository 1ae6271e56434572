//! `XR_KHR_vulkan_enable2`: the runtime creates our Vulkan instance and device from our create
//! infos (adding the extensions its compositor needs) and chooses the physical device. The
//! older `XR_KHR_vulkan_enable` is not used: it fails on lavapipe, which lacks
//! `VK_KHR_external_semaphore_fd`.

use std::cell::Cell;

use ash::vk;
use ash::vk::Handle as _;
use openxr as xr;

use crate::render::{RenderError, VulkanFactory};

/// A [`VulkanFactory`] that asks the OpenXR runtime.
pub struct RuntimeVulkan<'a> {
    /// The instance with `XR_KHR_vulkan_enable2` enabled.
    pub instance: &'a xr::Instance,
    /// The HMD system.
    pub system: xr::SystemId,
    /// The loader's `vkGetInstanceProcAddr`, as OpenXR spells its type (set with the instance).
    get_instance_proc_addr: Cell<Option<xr::sys::platform::VkGetInstanceProcAddr>>,
}

impl<'a> RuntimeVulkan<'a> {
    /// A factory for `system` of `instance`.
    pub fn new(instance: &'a xr::Instance, system: xr::SystemId) -> Self {
        Self {
            instance,
            system,
            get_instance_proc_addr: Cell::new(None),
        }
    }
}

fn xr_err(call: &'static str, e: xr::sys::Result) -> RenderError {
    RenderError::Unsupported(format!("the OpenXR runtime's {call} failed: {e:?} ({e})"))
}

impl VulkanFactory for RuntimeVulkan<'_> {
    fn create_instance(
        &self,
        entry: &ash::Entry,
        info: &vk::InstanceCreateInfo<'_>,
    ) -> Result<vk::Instance, RenderError> {
        // SAFETY: the two function pointer types differ only in how the handle types are
        // spelled.
        let gipa = unsafe {
            std::mem::transmute::<
                vk::PFN_vkGetInstanceProcAddr,
                xr::sys::platform::VkGetInstanceProcAddr,
            >(entry.static_fn().get_instance_proc_addr)
        };
        self.get_instance_proc_addr.set(Some(gipa));
        // SAFETY: `info` is a valid create info whose pointers outlive the call; the runtime
        // calls `gipa` (the loader's) to reach Vulkan.
        let raw = unsafe {
            self.instance.create_vulkan_instance(
                self.system,
                gipa,
                info as *const vk::InstanceCreateInfo<'_> as *const _,
            )
        }
        .map_err(|e| xr_err("xrCreateVulkanInstanceKHR", e))?
        .map_err(|r| RenderError::Vk {
            call: "vkCreateInstance (through xrCreateVulkanInstanceKHR)",
            result: vk::Result::from_raw(r),
        })?;
        Ok(vk::Instance::from_raw(raw as u64))
    }

    fn physical_device(
        &self,
        instance: &ash::Instance,
    ) -> Result<Option<vk::PhysicalDevice>, RenderError> {
        // SAFETY: the instance was created through xrCreateVulkanInstanceKHR above.
        let raw = unsafe {
            self.instance
                .vulkan_graphics_device(self.system, instance.handle().as_raw() as _)
        }
        .map_err(|e| xr_err("xrGetVulkanGraphicsDevice2KHR", e))?;
        Ok(Some(vk::PhysicalDevice::from_raw(raw as u64)))
    }

    fn create_device(
        &self,
        _instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        info: &vk::DeviceCreateInfo<'_>,
    ) -> Result<vk::Device, RenderError> {
        let gipa = self
            .get_instance_proc_addr
            .get()
            .ok_or_else(|| RenderError::Invalid("device created before the instance".into()))?;
        // SAFETY: as for the instance; `physical` is the runtime's choice.
        let raw = unsafe {
            self.instance.create_vulkan_device(
                self.system,
                gipa,
                physical.as_raw() as _,
                info as *const vk::DeviceCreateInfo<'_> as *const _,
            )
        }
        .map_err(|e| xr_err("xrCreateVulkanDeviceKHR", e))?
        .map_err(|r| RenderError::Vk {
            call: "vkCreateDevice (through xrCreateVulkanDeviceKHR)",
            result: vk::Result::from_raw(r),
        })?;
        Ok(vk::Device::from_raw(raw as u64))
    }
}

/// The Vulkan version to ask the runtime for: 1.1 (multiview, core there), or the runtime's
/// minimum when that is higher. Only the minimum binds: the maximum is the highest version the
/// runtime "has been tested on" (the `XR_KHR_vulkan_enable2` specification; Meta's PC runtime
/// has reported 1.0 and works with 1.1), so asking above it is a warning, not an error. Whether
/// the device really offers multiview is checked when the context is made.
pub fn api_version(req: &xr::vulkan::Requirements) -> VersionChoice {
    let ours = xr::Version::new(1, 1, 0);
    let min = req.min_api_version_supported;
    let max = req.max_api_version_supported;
    let pick = if min > ours { min } else { ours };
    // Patch numbers do not matter for compatibility.
    let (pm, pn) = (pick.major(), pick.minor());
    let above_tested = (pm, pn) > (max.major(), max.minor());
    VersionChoice {
        version: vk::make_api_version(0, pm as u32, pn as u32, 0),
        warning: above_tested.then(|| {
            format!(
                "the OpenXR runtime was tested with Vulkan {}.{} to {}.{}; asking for {pm}.{pn} \
                 anyway (the maximum is not a limit)",
                min.major(),
                min.minor(),
                max.major(),
                max.minor()
            )
        }),
    }
}

/// What [`api_version`] chose.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VersionChoice {
    /// The Vulkan API version to create the instance with.
    pub version: u32,
    /// Set when the version is above the runtime's tested maximum (log it once).
    pub warning: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(min: (u16, u16), max: (u16, u16)) -> xr::vulkan::Requirements {
        xr::vulkan::Requirements {
            min_api_version_supported: xr::Version::new(min.0, min.1, 0),
            max_api_version_supported: xr::Version::new(max.0, max.1, 0),
        }
    }

    #[test]
    fn version_range_is_honoured() {
        // Monado: 1.0 to 1023.1023.
        let monado = api_version(&req((1, 0), (1023, 1023)));
        assert_eq!(monado.version, vk::API_VERSION_1_1);
        assert_eq!(monado.warning, None);
        // A runtime that needs 1.2 gets 1.2.
        assert_eq!(
            api_version(&req((1, 2), (1, 3))).version,
            vk::API_VERSION_1_2
        );
        // One tested only with 1.0 (Meta's PC runtime has said so) still gets 1.1, with a
        // warning: the maximum is what the runtime was tested with, not a limit.
        let tested_1_0 = api_version(&req((1, 0), (1, 0)));
        assert_eq!(tested_1_0.version, vk::API_VERSION_1_1);
        let w = tested_1_0.warning.unwrap();
        assert!(w.contains("1.0 to 1.0") && w.contains("1.1"), "{w}");
    }
}
