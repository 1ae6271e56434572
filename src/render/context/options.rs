//! What a [`GpuContext`](super::GpuContext) is created with: the validation policy and the
//! options the instance and the device are made from.

use std::ffi::c_char;

use ash::vk;

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

/// What a [`GpuContext`](super::GpuContext) is created with.
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
    /// non-subsampled images; [`GpuContext::fragment_density_map`](super::GpuContext::fragment_density_map) says whether it did.
    pub fragment_density_map: bool,
    /// Capture every pipeline's compiler statistics (`VK_KHR_pipeline_executable_properties`)
    /// where the device reports them; [`GpuContext::pipeline_statistics`](super::GpuContext::pipeline_statistics) holds them.
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
