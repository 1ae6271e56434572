//! The Vulkan instance, device and queue every renderer part shares ([`GpuContext`]), with the
//! Khronos validation layer and a messenger that counts its errors (tests fail on any). Files
//! follow the objects' lifetimes, as in wgpu-hal: `instance.rs` (loader, layer, messenger),
//! `adapter.rs` (which physical device, and what it offers), `device.rs` (what is enabled, the
//! queue); `factory.rs` is who creates them (the app, or an OpenXR runtime).

mod adapter;
mod device;
mod factory;
mod instance;
mod options;

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use ash::vk;

use self::adapter::Adapter;
use self::device::Device;
pub use self::factory::{DirectVulkan, VulkanFactory};
pub use self::instance::VALIDATION_LAYER;
use self::instance::{Instance, InstanceParts, Messenger};
pub use self::options::{ContextOptions, Validation};
use super::error::RenderError;
use super::statistics::StatisticsLog;
pub use super::validation::ValidationLog;

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
    debug: Option<Messenger>,
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
        // Each part is destroyed by its own `Drop` if a later one fails.
        let instance = Instance::new(opts, factory)?;
        let adapter = Adapter::choose(&instance.raw, factory)?;
        let device = Device::new(&instance.raw, &adapter, opts, factory)?;
        let InstanceParts {
            entry,
            raw: instance,
            messenger,
            log,
        } = instance.into_parts();
        log::info!(
            "Vulkan device: {} (multiview {}, anisotropic filtering {}, validation {})",
            adapter.name,
            adapter.multiview,
            adapter
                .max_anisotropy
                .map_or("none".to_string(), |a| format!("up to {a}x")),
            log.is_some()
        );
        Ok(Self {
            entry,
            instance,
            physical: adapter.physical,
            device: device.raw,
            queue: device.queue,
            queue_family: adapter.queue_family,
            multiview: adapter.multiview,
            timestamp_period: adapter.timestamp_period,
            sample_counts: adapter.sample_counts,
            fragment_density_map: device.fragment_density_map,
            probes: adapter.probes,
            pipeline_statistics: device.capture_statistics.then(StatisticsLog::default),
            max_anisotropy: adapter.max_anisotropy,
            memory: adapter.memory,
            device_name: adapter.name,
            cpu_device: adapter.cpu,
            validation: log,
            debug: messenger,
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
