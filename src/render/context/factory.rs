//! Who creates the Vulkan instance and device: the app itself, or an OpenXR runtime.

use ash::vk;

use crate::render::error::RenderError;

/// Who creates the Vulkan instance and device from our create infos: the app itself
/// ([`DirectVulkan`]), or an OpenXR runtime (`XR_KHR_vulkan_enable2` creates both, adding what its
/// compositor needs, and chooses the physical device).
pub trait VulkanFactory {
    /// Creates the instance described by `info`.
    fn create_instance(
        &self,
        entry: &ash::Entry,
        info: &vk::InstanceCreateInfo<'_>,
    ) -> Result<vk::Instance, RenderError>;

    /// The physical device to use, or `None` to let the context pick the best one.
    fn physical_device(
        &self,
        instance: &ash::Instance,
    ) -> Result<Option<vk::PhysicalDevice>, RenderError>;

    /// Creates the device described by `info` on `physical`.
    fn create_device(
        &self,
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        info: &vk::DeviceCreateInfo<'_>,
    ) -> Result<vk::Device, RenderError>;
}

/// Plain Vulkan: the app creates its own instance and device.
pub struct DirectVulkan;

impl VulkanFactory for DirectVulkan {
    fn create_instance(
        &self,
        entry: &ash::Entry,
        info: &vk::InstanceCreateInfo<'_>,
    ) -> Result<vk::Instance, RenderError> {
        // Only the handle: the context loads the instance's function table once, for both
        // factories.
        let mut raw = vk::Instance::null();
        // SAFETY: every pointer in `info` outlives the call (the caller's contract).
        unsafe { (entry.fp_v1_0().create_instance)(info, std::ptr::null(), &mut raw) }
            .result_with_success(raw)
            .map_err(|e| match e {
                vk::Result::ERROR_INCOMPATIBLE_DRIVER => RenderError::NoDevice(e.to_string()),
                e => RenderError::Vk {
                    call: "vkCreateInstance",
                    result: e,
                },
            })
    }

    fn physical_device(
        &self,
        _instance: &ash::Instance,
    ) -> Result<Option<vk::PhysicalDevice>, RenderError> {
        Ok(None)
    }

    fn create_device(
        &self,
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        info: &vk::DeviceCreateInfo<'_>,
    ) -> Result<vk::Device, RenderError> {
        // Only the handle, as for the instance.
        let mut raw = vk::Device::null();
        // SAFETY: `physical` came from `instance`; `info`'s pointers outlive the call.
        unsafe { (instance.fp_v1_0().create_device)(physical, info, std::ptr::null(), &mut raw) }
            .result_with_success(raw)
            .map_err(RenderError::vk("vkCreateDevice"))
    }
}
