//! The physical device ([`Adapter`], as wgpu-hal calls it): which one, with which graphics
//! queue family, and what it can do that the renderer asks about (multiview, MSAA counts,
//! timestamps, anisotropy, the counting pass's features, fixed foveation, compiler statistics).

use ash::vk;

use super::factory::VulkanFactory;
use crate::render::error::RenderError;

/// The chosen physical device and what it offers.
pub(super) struct Adapter {
    pub physical: vk::PhysicalDevice,
    pub queue_family: u32,
    /// Device name, for logs and reports.
    pub name: String,
    /// Whether the device is the CPU (Mesa lavapipe).
    pub cpu: bool,
    /// The multiview feature (Vulkan 1.1).
    pub multiview: bool,
    /// `fragmentStoresAndAtomics` and `pipelineStatisticsQuery` both.
    pub probes: bool,
    /// `samplerAnisotropy`, with `maxSamplerAnisotropy`.
    pub max_anisotropy: Option<f32>,
    /// Nanoseconds per timestamp tick, when the queue has timestamps.
    pub timestamp_period: Option<f32>,
    /// Sample counts usable for both colour and depth attachments.
    pub sample_counts: vk::SampleCountFlags,
    /// `VK_EXT_fragment_density_map` with non-subsampled images.
    pub fragment_density_map: bool,
    /// `VK_KHR_pipeline_executable_properties` with `pipelineExecutableInfo`.
    pub executable_statistics: bool,
    /// Its memory types.
    pub memory: vk::PhysicalDeviceMemoryProperties,
}

impl Adapter {
    /// The device `factory` names (an OpenXR runtime chooses), or the best one of `instance`;
    /// refused when it has no graphics queue or is older than Vulkan 1.1.
    pub fn choose(
        instance: &ash::Instance,
        factory: &dyn VulkanFactory,
    ) -> Result<Self, RenderError> {
        let (physical, queue_family) = match factory.physical_device(instance)? {
            Some(p) => (p, graphics_family(instance, p)?),
            None => pick_device(instance)?,
        };
        // SAFETY: `physical` came from this instance.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let name = props
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        if vk::api_version_major(props.api_version) == 1
            && vk::api_version_minor(props.api_version) < 1
        {
            return Err(RenderError::Unsupported(format!(
                "Vulkan 1.1 ({name} has {}.{})",
                vk::api_version_major(props.api_version),
                vk::api_version_minor(props.api_version)
            )));
        }
        let mut mv = vk::PhysicalDeviceMultiviewFeatures::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut mv);
        // SAFETY: `physical` belongs to `instance`; the chain lives on this stack frame.
        unsafe { instance.get_physical_device_features2(physical, &mut f2) };
        let probes = f2.features.fragment_stores_and_atomics == vk::TRUE
            && f2.features.pipeline_statistics_query == vk::TRUE;
        let anisotropic = f2.features.sampler_anisotropy == vk::TRUE;
        // SAFETY: `physical` belongs to `instance`.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let timestamp_period = (families[queue_family as usize].timestamp_valid_bits > 0
            && props.limits.timestamp_period > 0.0)
            .then_some(props.limits.timestamp_period);
        Ok(Self {
            physical,
            queue_family,
            name,
            cpu: props.device_type == vk::PhysicalDeviceType::CPU,
            multiview: mv.multiview == vk::TRUE,
            probes,
            max_anisotropy: anisotropic.then_some(props.limits.max_sampler_anisotropy),
            timestamp_period,
            sample_counts: props.limits.framebuffer_color_sample_counts
                & props.limits.framebuffer_depth_sample_counts,
            fragment_density_map: has_fragment_density_map(instance, physical),
            executable_statistics: has_executable_statistics(instance, physical),
            // SAFETY: `physical` belongs to `instance`.
            memory: unsafe { instance.get_physical_device_memory_properties(physical) },
        })
    }
}

/// The best device of `instance` with a graphics queue: a discrete GPU, then an integrated one,
/// then a virtual one, then anything (lavapipe); with that queue's family.
fn pick_device(instance: &ash::Instance) -> Result<(vk::PhysicalDevice, u32), RenderError> {
    // SAFETY: the instance is alive.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(|e| RenderError::NoDevice(e.to_string()))?;
    if devices.is_empty() {
        return Err(RenderError::NoDevice("the loader lists no device".into()));
    }
    let rank = |t: vk::PhysicalDeviceType| match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        _ => 3,
    };
    let mut best: Option<(u32, vk::PhysicalDevice, u32)> = None;
    for d in devices {
        // SAFETY: `d` was enumerated from this instance.
        let props = unsafe { instance.get_physical_device_properties(d) };
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(d) };
        let Some(q) = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        else {
            continue;
        };
        let r = rank(props.device_type);
        if best.is_none_or(|(br, _, _)| r < br) {
            best = Some((r, d, q as u32));
        }
    }
    best.map(|(_, d, q)| (d, q))
        .ok_or_else(|| RenderError::NoDevice("no device has a graphics queue".into()))
}

/// The first queue family of `physical` with graphics.
fn graphics_family(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> Result<u32, RenderError> {
    // SAFETY: `physical` came from `instance`.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    families
        .iter()
        .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        .map(|q| q as u32)
        .ok_or_else(|| RenderError::NoDevice("the chosen device has no graphics queue".into()))
}

/// Whether `physical` offers `VK_EXT_fragment_density_map` with the features fixed foveation
/// needs (`fragmentDensityMap`, `fragmentDensityMapNonSubsampledImages`).
fn has_fragment_density_map(instance: &ash::Instance, physical: vk::PhysicalDevice) -> bool {
    // SAFETY: `physical` belongs to `instance`.
    let listed = unsafe { instance.enumerate_device_extension_properties(physical) }
        .unwrap_or_default()
        .iter()
        .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::fragment_density_map::NAME));
    if !listed {
        return false;
    }
    let mut fdm = vk::PhysicalDeviceFragmentDensityMapFeaturesEXT::default();
    let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut fdm);
    // SAFETY: `physical` belongs to `instance`; the chain lives on this stack frame.
    unsafe { instance.get_physical_device_features2(physical, &mut f2) };
    fdm.fragment_density_map == vk::TRUE
        && fdm.fragment_density_map_non_subsampled_images == vk::TRUE
}

/// Whether `physical` offers `VK_KHR_pipeline_executable_properties` with its
/// `pipelineExecutableInfo` feature (compiler statistics per pipeline).
fn has_executable_statistics(instance: &ash::Instance, physical: vk::PhysicalDevice) -> bool {
    // SAFETY: `physical` belongs to `instance`.
    let listed = unsafe { instance.enumerate_device_extension_properties(physical) }
        .unwrap_or_default()
        .iter()
        .any(|e| e.extension_name_as_c_str() == Ok(ash::khr::pipeline_executable_properties::NAME));
    if !listed {
        return false;
    }
    let mut exe = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default();
    let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut exe);
    // SAFETY: `physical` belongs to `instance`; the chain lives on this stack frame.
    unsafe { instance.get_physical_device_features2(physical, &mut f2) };
    exe.pipeline_executable_info == vk::TRUE
}
