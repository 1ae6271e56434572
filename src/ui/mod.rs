//! What the user chooses and keeps (issue 31): the settings model ([`settings::Settings`]),
//! the Beaufort scale the sea states are offered by ([`beaufort`]), and the file they are kept
//! in ([`store::SettingsFile`]: atomic saves; a missing, partial or corrupt file is the
//! defaults and one warning). Pure: no Vulkan, no XR; the front ends (the window's keys, the
//! headset's controllers, and later the panel) apply and change them.
//!
//! `ui` sits above `sim`, `lod` and `physics` and below `render`, `xr` and `app`
//! (`tests/tidy.rs`).

pub mod beaufort;
pub mod panel;
pub mod settings;
pub mod store;

pub use beaufort::{Beaufort, BEAUFORT};
pub use settings::Settings;
pub use store::{Loaded, SettingsFile};

/// Why settings could not be kept.
#[derive(Debug, Clone, PartialEq)]
pub enum UiError {
    /// The settings file (or its directory) could not be written.
    Io(String),
}

impl std::fmt::Display for UiError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UiError::Io(e) => write!(f, "settings: {e}"),
        }
    }
}

impl std::error::Error for UiError {}
