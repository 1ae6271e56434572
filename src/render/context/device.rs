//! The logical device on the chosen [`Adapter`]: the extensions and features the options ask
//! for and the adapter has, one graphics queue.

use ash::vk;

use super::adapter::Adapter;
use super::factory::VulkanFactory;
use super::options::ContextOptions;
use crate::render::error::RenderError;

/// A device, its queue, and what was enabled on it.
pub(super) struct Device {
    pub raw: ash::Device,
    pub queue: vk::Queue,
    /// `VK_EXT_fragment_density_map` (asked for, and the adapter has it).
    pub fragment_density_map: bool,
    /// `VK_KHR_pipeline_executable_properties` (asked for, and the adapter has it).
    pub capture_statistics: bool,
}

impl Device {
    /// Creates the device through `factory` with one queue of the adapter's graphics family,
    /// the swapchain when `opts.present`, and every feature the renderer can use that the
    /// adapter has (multiview, the counting pass's, anisotropy) or `opts` asks for.
    pub fn new(
        instance: &ash::Instance,
        adapter: &Adapter,
        opts: &ContextOptions,
        factory: &dyn VulkanFactory,
    ) -> Result<Self, RenderError> {
        let capture_statistics = opts.capture_statistics && adapter.executable_statistics;
        if opts.capture_statistics && !capture_statistics {
            log::warn!(
                "{} reports no compiler statistics (VK_KHR_pipeline_executable_properties)",
                adapter.name
            );
        }
        let fragment_density_map = opts.fragment_density_map && adapter.fragment_density_map;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(adapter.queue_family)
            .queue_priorities(&priorities)];
        let mut extensions = Vec::new();
        if opts.present {
            extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        if fragment_density_map {
            extensions.push(ash::ext::fragment_density_map::NAME.as_ptr());
        }
        if capture_statistics {
            extensions.push(ash::khr::pipeline_executable_properties::NAME.as_ptr());
        }
        let mut enable_stats = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
            .pipeline_executable_info(true);
        let mut enable_mv =
            vk::PhysicalDeviceMultiviewFeatures::default().multiview(adapter.multiview);
        let mut enable_fdm = vk::PhysicalDeviceFragmentDensityMapFeaturesEXT::default()
            .fragment_density_map(true)
            .fragment_density_map_non_subsampled_images(true);
        let features = vk::PhysicalDeviceFeatures::default()
            .fragment_stores_and_atomics(adapter.probes)
            .pipeline_statistics_query(adapter.probes)
            .sampler_anisotropy(adapter.max_anisotropy.is_some());
        let mut info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&extensions)
            .enabled_features(&features)
            .push_next(&mut enable_mv);
        if fragment_density_map {
            info = info.push_next(&mut enable_fdm);
        }
        if capture_statistics {
            info = info.push_next(&mut enable_stats);
        }
        let handle = factory.create_device(instance, adapter.physical, &info)?;
        // SAFETY: `handle` was just created on the adapter's device of this instance.
        let raw = unsafe { ash::Device::load(instance.fp_v1_0(), handle) };
        // SAFETY: the device was created with one queue of this family.
        let queue = unsafe { raw.get_device_queue(adapter.queue_family, 0) };
        Ok(Self {
            raw,
            queue,
            fragment_density_map,
            capture_statistics,
        })
    }
}
