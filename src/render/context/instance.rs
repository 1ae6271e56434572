//! The Vulkan instance: the loader, the validation layer when the policy wants it, and the
//! messenger that counts its messages. [`Instance`] owns them until a [`GpuContext`] takes
//! them over, and destroys them if the device's set-up fails first.
//!
//! [`GpuContext`]: super::GpuContext

use std::ffi::{c_void, CStr};
use std::sync::Arc;

use ash::vk;

use super::factory::VulkanFactory;
use super::options::{ContextOptions, Validation};
use crate::render::error::RenderError;
use crate::render::validation::{on_message, ValidationLog};

/// The Khronos validation layer (Debian `vulkan-validationlayers`).
pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// The debug-utils functions and the messenger made with them.
pub(super) type Messenger = (ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT);

/// An instance not yet wrapped in a [`GpuContext`](super::GpuContext): destroyed if device
/// set-up fails.
pub(super) struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    messenger: Option<Messenger>,
    /// Validation messages, when the layer is loaded.
    pub log: Option<Arc<ValidationLog>>,
}

impl Instance {
    /// Loads Vulkan and creates an instance of `opts.api_version` through `factory`, with the
    /// validation layer and its messenger when `opts.validation` wants them.
    pub fn new(opts: &ContextOptions, factory: &dyn VulkanFactory) -> Result<Self, RenderError> {
        // SAFETY: loading the system loader runs its initialisers; nothing else is loaded.
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| RenderError::NoLoader(e.to_string()))?;
        let validate = wants_validation(&entry, opts.validation)?;
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
        let handle = factory.create_instance(&entry, &info)?;
        // SAFETY: `handle` was just created from this entry's loader.
        let raw = unsafe { ash::Instance::load(entry.static_fn(), handle) };
        let mut instance = Self {
            entry,
            raw,
            messenger: None,
            log,
        };
        if let Some(m) = messenger_info {
            let du = ash::ext::debug_utils::Instance::new(&instance.entry, &instance.raw);
            // SAFETY: `m` points at the log, which the context keeps alive longer than the
            // messenger.
            let messenger = unsafe { du.create_debug_utils_messenger(&m, None) }
                .map_err(RenderError::vk("vkCreateDebugUtilsMessengerEXT"))?;
            instance.messenger = Some((du, messenger));
        }
        Ok(instance)
    }

    /// Moves the parts out without running `Drop`: the context owns them from here.
    pub fn into_parts(self) -> InstanceParts {
        let this = std::mem::ManuallyDrop::new(self);
        // SAFETY: `this` is never used or dropped again, so each field is moved out once.
        unsafe {
            InstanceParts {
                entry: std::ptr::read(&this.entry),
                raw: std::ptr::read(&this.raw),
                messenger: std::ptr::read(&this.messenger),
                log: std::ptr::read(&this.log),
            }
        }
    }
}

/// An [`Instance`]'s parts, owned by the context from its creation on.
pub(super) struct InstanceParts {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    pub messenger: Option<Messenger>,
    pub log: Option<Arc<ValidationLog>>,
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: only reached when set-up failed before a device existed.
        unsafe {
            if let Some((du, m)) = self.messenger.take() {
                du.destroy_debug_utils_messenger(m, None);
            }
            self.raw.destroy_instance(None);
        }
    }
}

/// Whether to load the validation layer under `policy`, given whether it is installed.
fn wants_validation(entry: &ash::Entry, policy: Validation) -> Result<bool, RenderError> {
    // SAFETY: the entry points were just loaded.
    let has_layer = unsafe { entry.enumerate_instance_layer_properties() }
        .map_err(RenderError::vk("vkEnumerateInstanceLayerProperties"))?
        .iter()
        .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
    match policy {
        Validation::Off => Ok(false),
        Validation::IfAvailable => {
            if !has_layer {
                log::warn!(
                    "Vulkan validation layer not installed (apt install vulkan-validationlayers)"
                );
            }
            Ok(has_layer)
        }
        Validation::Required if !has_layer => Err(RenderError::Unsupported(
            "the Khronos validation layer: apt install vulkan-validationlayers".into(),
        )),
        Validation::Required => Ok(true),
    }
}
