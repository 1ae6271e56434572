//! The Vulkan instance, device and queue every renderer part shares, with the Khronos validation
//! layer and a messenger that counts its errors (tests fail on any).

use std::ffi::{c_char, c_void, CStr};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use ash::vk;

use super::error::RenderError;
use super::statistics::StatisticsLog;
use super::validation::on_message;
pub use super::validation::ValidationLog;

/// The Khronos validation layer (Debian `vulkan-validationlayers`).
pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Whether to load the validation layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Validation {
    /// Never (release runs: the layer costs a lot of CPU).
    Off,
    /// When installed; a warning otherwise.
    IfAvailable,
    /// Required: an error when the layer is missing (tests).
    Required,
}

/// What a [`GpuContext`] is created with.
#[derive(Clone, Debug)]
pub struct ContextOptions {
    /// Validation layer policy.
    pub validation: Validation,
    /// Extra instance extensions (e.g. the window system's surface extensions).
    pub instance_extensions: Vec<*const c_char>,
    /// Whether the device must be able to present (enables `VK_KHR_swapchain`).
    pub present: bool,
    /// The Vulkan API version asked for (at least 1.1; an OpenXR runtime may need more).
    pub api_version: u32,
    /// Enable `VK_EXT_fragment_density_map` (fixed foveation) when the device has it with
    /// non-subsampled images; [`GpuContext::fragment_density_map`] says whether it did.
    pub fragment_density_map: bool,
    /// Capture every pipeline's compiler statistics (`VK_KHR_pipeline_executable_properties`)
    /// where the device reports them; [`GpuContext::pipeline_statistics`] holds them.
    pub capture_statistics: bool,
}

impl Default for ContextOptions {
    fn default() -> Self {
        Self {
            validation: Validation::IfAvailable,
            instance_extensions: Vec::new(),
            present: false,
            api_version: vk::API_VERSION_1_1,
            fragment_density_map: false,
            capture_statistics: false,
        }
    }
}

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

/// Instance, physical device, logical device and the one graphics queue.
pub struct GpuContext {
    /// The loaded Vulkan entry points.
    pub entry: ash::Entry,
    /// The instance.
    pub instance: ash::Instance,
    /// The chosen physical device.
    pub physical: vk::PhysicalDevice,
    /// The logical device.
    pub device: ash::Device,
    /// The graphics (and present, when asked) queue.
    pub queue: vk::Queue,
    /// Its family.
    pub queue_family: u32,
    /// Whether the device supports multiview (Vulkan 1.1 feature `multiview`).
    pub multiview: bool,
    /// Nanoseconds per timestamp tick, or `None` when the queue has no timestamps.
    pub timestamp_period: Option<f32>,
    /// Sample counts usable for both colour and depth attachments (MSAA).
    pub sample_counts: vk::SampleCountFlags,
    /// Whether `VK_EXT_fragment_density_map` is enabled (asked for, and the device has it with
    /// `fragmentDensityMapNonSubsampledImages`, so no attachment needs subsampling).
    pub fragment_density_map: bool,
    /// Whether `fragmentStoresAndAtomics` and `pipelineStatisticsQuery` are enabled (the device
    /// has both): the GPU budget's counting pass (`render::budget`) needs them.
    pub probes: bool,
    /// Every pipeline's compiler statistics, when asked for
    /// ([`ContextOptions::capture_statistics`]) and the device reports them.
    pub pipeline_statistics: Option<StatisticsLog>,
    /// The largest sampler anisotropy (`maxSamplerAnisotropy`) when `samplerAnisotropy` is
    /// enabled (the device has it); `None` without anisotropic filtering.
    pub max_anisotropy: Option<f32>,
    /// Memory types of the device.
    pub memory: vk::PhysicalDeviceMemoryProperties,
    /// Device name, for logs and reports.
    pub device_name: String,
    /// The "GPU" is the CPU (Mesa lavapipe): rendering competes with the simulation for cores,
    /// and `vkGetQueryPoolResults` idles the whole device there.
    pub cpu_device: bool,
    /// Validation messages, when the layer is loaded.
    pub validation: Option<Arc<ValidationLog>>,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Object creations left before an injected failure ([`GpuContext::fail_creation_after`]);
    /// `u32::MAX`: none planned.
    creations_left: AtomicU32,
}

impl GpuContext {
    /// Loads Vulkan, creates an instance (1.1) and a device with one graphics queue, preferring
    /// a discrete GPU, then an integrated one, then anything (lavapipe).
    pub fn new(opts: &ContextOptions) -> Result<Self, RenderError> {
        Self::with_factory(opts, &DirectVulkan)
    }

    /// Like [`GpuContext::new`], with the instance and device created (and the physical device
    /// possibly chosen) by `factory`.
    pub fn with_factory(
        opts: &ContextOptions,
        factory: &dyn VulkanFactory,
    ) -> Result<Self, RenderError> {
        if opts.api_version < vk::API_VERSION_1_1 {
            return Err(RenderError::Invalid(format!(
                "Vulkan API version {}.{}: the renderer needs 1.1 or later",
                vk::api_version_major(opts.api_version),
                vk::api_version_minor(opts.api_version)
            )));
        }
        // SAFETY: loading the system loader runs its initialisers; nothing else is loaded.
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| RenderError::NoLoader(e.to_string()))?;
        // SAFETY: the entry points were just loaded.
        let has_layer = unsafe { entry.enumerate_instance_layer_properties() }
            .map_err(RenderError::vk("vkEnumerateInstanceLayerProperties"))?
            .iter()
            .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        let validate = match opts.validation {
            Validation::Off => false,
            Validation::IfAvailable => {
                if !has_layer {
                    log::warn!(
                        "Vulkan validation layer not installed (apt install vulkan-validationlayers)"
                    );
                }
                has_layer
            }
            Validation::Required if !has_layer => {
                return Err(RenderError::Unsupported(
                    "the Khronos validation layer: apt install vulkan-validationlayers".into(),
                ))
            }
            Validation::Required => true,
        };
        let app = vk::ApplicationInfo::default()
            .application_name(c"vr-ocean")
            .application_version(1)
            .engine_name(c"vr-ocean")
            .api_version(opts.api_version);
        let layers = [VALIDATION_LAYER.as_ptr()];
        let mut extensions = opts.instance_extensions.clone();
        if validate {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        let log = validate.then(|| Arc::new(ValidationLog::default()));
        let mut messenger_info = log.as_ref().map(|log| {
            vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                        | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                        | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(on_message))
                .user_data(Arc::as_ptr(log) as *mut c_void)
        });
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_extension_names(&extensions);
        if validate {
            info = info.enabled_layer_names(&layers);
        }
        if let Some(m) = messenger_info.as_mut() {
            info = info.push_next(m);
        }
        let raw = factory.create_instance(&entry, &info)?;
        // SAFETY: `raw` was just created from this entry's loader.
        let instance = unsafe { ash::Instance::load(entry.static_fn(), raw) };
        let debug = match messenger_info {
            Some(m) => {
                let du = ash::ext::debug_utils::Instance::new(&entry, &instance);
                // SAFETY: `m` points at the log, which the context keeps alive longer than the
                // messenger.
                let messenger = unsafe { du.create_debug_utils_messenger(&m, None) }
                    .map_err(RenderError::vk("vkCreateDebugUtilsMessengerEXT"))?;
                Some((du, messenger))
            }
            None => None,
        };
        let mut ctx = PartialContext {
            entry,
            instance,
            debug,
        };
        let (physical, queue_family) = match factory.physical_device(&ctx.instance)? {
            Some(p) => (p, graphics_family(&ctx.instance, p)?),
            None => ctx.pick_device()?,
        };
        let instance = &ctx.instance;
        // SAFETY: `physical` came from this instance.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let device_name = props
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        if vk::api_version_major(props.api_version) == 1
            && vk::api_version_minor(props.api_version) < 1
        {
            return Err(RenderError::Unsupported(format!(
                "Vulkan 1.1 ({device_name} has {}.{})",
                vk::api_version_major(props.api_version),
                vk::api_version_minor(props.api_version)
            )));
        }
        let mut mv = vk::PhysicalDeviceMultiviewFeatures::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut mv);
        // SAFETY: `physical` belongs to `instance`; the chain lives on this stack frame.
        unsafe { instance.get_physical_device_features2(physical, &mut f2) };
        let capture_statistics =
            opts.capture_statistics && has_executable_statistics(instance, physical);
        if opts.capture_statistics && !capture_statistics {
            log::warn!(
                "{device_name} reports no compiler statistics (VK_KHR_pipeline_executable_properties)"
            );
        }
        let probes = f2.features.fragment_stores_and_atomics == vk::TRUE
            && f2.features.pipeline_statistics_query == vk::TRUE;
        let anisotropic = f2.features.sampler_anisotropy == vk::TRUE;
        let multiview = mv.multiview == vk::TRUE;
        let max_anisotropy = anisotropic.then_some(props.limits.max_sampler_anisotropy);
        // SAFETY: `physical` belongs to `instance`.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let timestamp_period = (families[queue_family as usize].timestamp_valid_bits > 0
            && props.limits.timestamp_period > 0.0)
            .then_some(props.limits.timestamp_period);
        let sample_counts = props.limits.framebuffer_color_sample_counts
            & props.limits.framebuffer_depth_sample_counts;

        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut dev_ext = Vec::new();
        if opts.present {
            dev_ext.push(ash::khr::swapchain::NAME.as_ptr());
        }
        let fragment_density_map =
            opts.fragment_density_map && has_fragment_density_map(instance, physical);
        if fragment_density_map {
            dev_ext.push(ash::ext::fragment_density_map::NAME.as_ptr());
        }
        if capture_statistics {
            dev_ext.push(ash::khr::pipeline_executable_properties::NAME.as_ptr());
        }
        let mut enable_stats = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
            .pipeline_executable_info(true);
        let mut enable_mv = vk::PhysicalDeviceMultiviewFeatures::default().multiview(multiview);
        let mut enable_fdm = vk::PhysicalDeviceFragmentDensityMapFeaturesEXT::default()
            .fragment_density_map(true)
            .fragment_density_map_non_subsampled_images(true);
        let features = vk::PhysicalDeviceFeatures::default()
            .fragment_stores_and_atomics(probes)
            .pipeline_statistics_query(probes)
            .sampler_anisotropy(anisotropic);
        let mut dinfo = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&dev_ext)
            .enabled_features(&features)
            .push_next(&mut enable_mv);
        if fragment_density_map {
            dinfo = dinfo.push_next(&mut enable_fdm);
        }
        if capture_statistics {
            dinfo = dinfo.push_next(&mut enable_stats);
        }
        let raw = factory.create_device(instance, physical, &dinfo)?;
        // SAFETY: `raw` was just created on `physical` of this instance.
        let device = unsafe { ash::Device::load(instance.fp_v1_0(), raw) };
        // SAFETY: the device was created with one queue of this family.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        // SAFETY: `physical` belongs to `instance`.
        let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
        let (entry, instance, debug) = ctx.take();
        log::info!(
            "Vulkan device: {device_name} (multiview {multiview}, anisotropic filtering {}, \
             validation {})",
            max_anisotropy.map_or("none".to_string(), |a| format!("up to {a}x")),
            log.is_some()
        );
        Ok(Self {
            entry,
            instance,
            physical,
            device,
            queue,
            queue_family,
            multiview,
            timestamp_period,
            sample_counts,
            fragment_density_map,
            probes,
            pipeline_statistics: capture_statistics.then(StatisticsLog::default),
            max_anisotropy,
            memory,
            device_name,
            cpu_device: props.device_type == vk::PhysicalDeviceType::CPU,
            validation: log,
            debug,
            creations_left: AtomicU32::new(u32::MAX),
        })
    }

    /// For tests of the clean-up paths: the renderer's object creations through this context
    /// succeed `successes` more times, then the next one fails with an injected
    /// `ERROR_OUT_OF_DEVICE_MEMORY` (and every one after it, until called again). `u32::MAX`
    /// turns the injection off.
    pub fn fail_creation_after(&self, successes: u32) {
        self.creations_left.store(successes, Ordering::Relaxed);
    }

    /// Runs `create` (a `vkCreate*`/`vkAllocate*` call named `call`) unless an injected
    /// failure is due; maps its error to [`RenderError::Vk`].
    pub fn create<T>(
        &self,
        call: &'static str,
        create: impl FnOnce() -> Result<T, vk::Result>,
    ) -> Result<T, RenderError> {
        let left = self.creations_left.load(Ordering::Relaxed);
        if left != u32::MAX {
            if left == 0 {
                return Err(RenderError::Vk {
                    call,
                    result: vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
                });
            }
            self.creations_left.store(left - 1, Ordering::Relaxed);
        }
        create().map_err(RenderError::vk(call))
    }

    /// Validation errors so far (0 without the layer).
    pub fn validation_errors(&self) -> u32 {
        self.validation.as_ref().map_or(0, |l| l.errors())
    }

    /// Index of a memory type allowed by `type_bits` with all of `flags`.
    pub fn memory_type(&self, type_bits: u32, flags: vk::MemoryPropertyFlags) -> Option<u32> {
        (0..self.memory.memory_type_count).find(|&i| {
            type_bits & (1 << i) != 0
                && self.memory.memory_types[i as usize]
                    .property_flags
                    .contains(flags)
        })
    }

    /// Waits until the device is idle (shutdown and resizes only, never in the frame loop).
    pub fn wait_idle(&self) {
        // SAFETY: the device is alive; errors here mean device loss, reported elsewhere.
        if let Err(e) = unsafe { self.device.device_wait_idle() } {
            log::error!("vkDeviceWaitIdle: {e}");
        }
    }
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

impl Drop for GpuContext {
    fn drop(&mut self) {
        // SAFETY: owners of device objects are dropped before the context (they borrow it).
        unsafe {
            self.device.destroy_device(None);
            if let Some((du, m)) = self.debug.take() {
                du.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
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

/// An instance not yet wrapped in a [`GpuContext`]: destroyed if device set-up fails.
struct PartialContext {
    entry: ash::Entry,
    instance: ash::Instance,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
}

impl PartialContext {
    fn pick_device(&mut self) -> Result<(vk::PhysicalDevice, u32), RenderError> {
        // SAFETY: the instance is alive.
        let devices = unsafe { self.instance.enumerate_physical_devices() }
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
            let props = unsafe { self.instance.get_physical_device_properties(d) };
            // SAFETY: as above.
            let families = unsafe { self.instance.get_physical_device_queue_family_properties(d) };
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

    /// Moves the parts out without running `Drop`.
    #[allow(clippy::type_complexity)]
    fn take(
        self,
    ) -> (
        ash::Entry,
        ash::Instance,
        Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    ) {
        let this = std::mem::ManuallyDrop::new(self);
        // SAFETY: `this` is never used or dropped again, so each field is moved out once.
        unsafe {
            (
                std::ptr::read(&this.entry),
                std::ptr::read(&this.instance),
                std::ptr::read(&this.debug),
            )
        }
    }
}

impl Drop for PartialContext {
    fn drop(&mut self) {
        // SAFETY: only reached when set-up failed before a device existed.
        unsafe {
            if let Some((du, m)) = self.debug.take() {
                du.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
