//! Renderer errors: each says what is missing and how to get it, never a bare result code.

use ash::vk;

/// Why the renderer could not start or continue.
#[derive(Debug)]
pub enum RenderError {
    /// The Vulkan loader (`libvulkan.so.1`) could not be loaded.
    NoLoader(String),
    /// The loader works but no usable device (driver) is installed.
    NoDevice(String),
    /// A device lacks something the renderer needs.
    Unsupported(String),
    /// A Vulkan call failed.
    Vk {
        /// The failing call.
        call: &'static str,
        /// Its result code.
        result: vk::Result,
    },
    /// A setting the caller passed is out of range.
    Invalid(String),
}

impl RenderError {
    /// Maps a failed `call` to [`RenderError::Vk`], for `map_err`.
    pub fn vk(call: &'static str) -> impl FnOnce(vk::Result) -> RenderError {
        move |result| RenderError::Vk { call, result }
    }
}

/// The package advice every "no Vulkan" message carries.
pub const DRIVER_ADVICE: &str = "install a Vulkan driver: on Debian/Ubuntu \
    `apt install libvulkan1 mesa-vulkan-drivers` (Mesa lavapipe, CPU Vulkan) or your GPU's driver";

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RenderError::NoLoader(e) => {
                write!(f, "cannot load the Vulkan loader ({e}); {DRIVER_ADVICE}")
            }
            RenderError::NoDevice(e) => write!(f, "no Vulkan device found ({e}); {DRIVER_ADVICE}"),
            RenderError::Unsupported(what) => write!(f, "the Vulkan device lacks {what}"),
            RenderError::Vk { call, result } => write!(f, "{call} failed: {result}"),
            RenderError::Invalid(what) => f.write_str(what),
        }
    }
}

impl std::error::Error for RenderError {}
