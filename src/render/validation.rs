//! The validation layer's messages: a debug messenger callback (`on_message`) that counts
//! the layer's errors and warnings into a [`ValidationLog`] (tests fail on any error) and logs
//! them.

use std::ffi::c_void;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use ash::vk;

/// Errors and warnings the validation layer reported.
#[derive(Debug, Default)]
pub struct ValidationLog {
    errors: AtomicU32,
    warnings: AtomicU32,
    first: Mutex<Vec<String>>,
}

impl ValidationLog {
    /// Validation errors so far.
    pub fn errors(&self) -> u32 {
        self.errors.load(Ordering::Relaxed)
    }

    /// Validation warnings so far.
    pub fn warnings(&self) -> u32 {
        self.warnings.load(Ordering::Relaxed)
    }

    /// The first few error messages (for test failures).
    pub fn messages(&self) -> Vec<String> {
        self.first.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

/// The messenger's callback: `user` is the [`ValidationLog`] it counts into.
pub(super) unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: `user` is the `ValidationLog` the context keeps alive while the messenger exists.
    let log = unsafe { &*(user as *const ValidationLog) };
    // SAFETY: the layer passes a valid callback data pointer (or null) for the call's duration,
    // and its message, when present, is a NUL-terminated string.
    let msg = unsafe { data.as_ref() }
        // SAFETY: as above.
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        log.errors.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut first) = log.first.lock() {
            if first.len() < 8 {
                first.push(msg.clone());
            }
        }
        log::error!("Vulkan validation: {msg}");
    } else {
        log.warnings.fetch_add(1, Ordering::Relaxed);
        log::warn!("Vulkan validation: {msg}");
    }
    vk::FALSE
}
