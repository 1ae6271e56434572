//! The OpenXR instance: the loader, the active runtime, and the extensions we enable
//! (`XR_KHR_vulkan_enable2` always; each optional one only when the runtime lists it). Every
//! failure names what to install or start.

use openxr as xr;

use super::error::backend;
use super::OpenXrOptions;
use crate::xr::XrError;

/// Loads the OpenXR loader (the system's, or the APK's on Android).
pub(super) fn load_entry(platform: &dyn xr::PlatformInfo) -> Result<xr::Entry, XrError> {
    // SAFETY: loads the system's OpenXR loader, which follows the specification.
    unsafe { xr::Entry::load(platform) }.map_err(|e| {
        backend(format!(
            "no OpenXR loader could be loaded ({e}). Install the Khronos OpenXR loader \
             (Debian/Ubuntu: apt install libopenxr-loader1) and an OpenXR runtime: Monado \
             (apt install monado-service, then start monado-service), SteamVR or WiVRn"
        ))
    })
}

/// Creates the instance with the extensions we use that the runtime lists (`android`: with
/// `XR_KHR_android_create_instance`, required there).
pub(super) fn create_instance(
    entry: &xr::Entry,
    platform: &dyn xr::PlatformInfo,
    android: bool,
) -> Result<xr::Instance, XrError> {
    let available = entry.enumerate_extensions().map_err(|e| {
        backend(format!(
            "no active OpenXR runtime ({e:?} ({e})). Install one and make it active: Monado (apt \
             install monado-service, then run monado-service), SteamVR (set it as the OpenXR \
             runtime in its settings) or WiVRn; or point XR_RUNTIME_JSON at a runtime's manifest"
        ))
    })?;
    if !available.khr_vulkan_enable2 {
        return Err(backend(
            "the active OpenXR runtime does not support XR_KHR_vulkan_enable2, which vr-ocean \
             needs to render with Vulkan (the older XR_KHR_vulkan_enable is not used)",
        ));
    }
    let mut enabled = xr::ExtensionSet::default();
    enabled.khr_vulkan_enable2 = true;
    enabled.khr_composition_layer_depth = available.khr_composition_layer_depth;
    enabled.fb_display_refresh_rate = available.fb_display_refresh_rate;
    // Fixed foveation on Vulkan needs all four (see `foveation`); any one missing means none.
    let foveation = available.fb_foveation
        && available.fb_swapchain_update_state
        && available.fb_foveation_configuration
        && available.fb_foveation_vulkan;
    enabled.fb_foveation = foveation;
    enabled.fb_swapchain_update_state = foveation;
    enabled.fb_foveation_configuration = foveation;
    enabled.fb_foveation_vulkan = foveation;
    enabled.ext_performance_settings = available.ext_performance_settings;
    // LOCAL_FLOOR (core in OpenXR 1.1; this instance is 1.0): the floor under a recentrable
    // origin.
    enabled.ext_local_floor = available.ext_local_floor;
    // Exact bindings for Quest 3/3S and Quest Pro controllers (both extend the Touch profile).
    enabled.meta_touch_controller_plus = available.meta_touch_controller_plus;
    enabled.fb_touch_controller_pro = available.fb_touch_controller_pro;
    // The colour gamut of sRGB content set explicitly (Rec. 709).
    enabled.fb_color_space = available.fb_color_space;
    // The panel's text filtered by the compositor (`layers::panel_filter`).
    enabled.fb_composition_layer_settings = available.fb_composition_layer_settings;
    enabled.meta_automatic_layer_filter =
        available.fb_composition_layer_settings && available.meta_automatic_layer_filter;
    #[cfg(target_os = "android")]
    if android {
        if !available.khr_android_create_instance {
            return Err(backend(
                "the OpenXR loader lacks XR_KHR_android_create_instance (an outdated loader: \
                 ship the Khronos loader 1.0.34 or later)",
            ));
        }
        enabled.khr_android_create_instance = true;
        enabled.khr_android_thread_settings = available.khr_android_thread_settings;
    }
    #[cfg(not(target_os = "android"))]
    let _ = android;
    let listed: Vec<&str> = [
        (
            "XR_KHR_composition_layer_depth",
            enabled.khr_composition_layer_depth,
        ),
        (
            "XR_FB_display_refresh_rate",
            enabled.fb_display_refresh_rate,
        ),
        ("XR_FB_foveation", enabled.fb_foveation),
        ("XR_EXT_local_floor", enabled.ext_local_floor),
        (
            "XR_META_touch_controller_plus",
            enabled.meta_touch_controller_plus,
        ),
        (
            "XR_FB_touch_controller_pro",
            enabled.fb_touch_controller_pro,
        ),
        ("XR_FB_color_space", enabled.fb_color_space),
        (
            "XR_FB_composition_layer_settings",
            enabled.fb_composition_layer_settings,
        ),
        (
            "XR_META_automatic_layer_filter",
            enabled.meta_automatic_layer_filter,
        ),
        (
            "XR_EXT_performance_settings",
            enabled.ext_performance_settings,
        ),
    ]
    .iter()
    .filter(|(_, on)| *on)
    .map(|(n, _)| *n)
    .collect();
    log::info!(
        "OpenXR extensions: XR_KHR_vulkan_enable2 {}",
        listed.join(" ")
    );
    let app = xr::ApplicationInfo {
        application_name: "vr-ocean",
        application_version: 1,
        engine_name: "vr-ocean",
        engine_version: 1,
        api_version: xr::Version::new(1, 0, 0),
    };
    entry
        .create_instance(&app, &enabled, &[], platform)
        .map_err(|e| match e {
            xr::sys::Result::ERROR_EXTENSION_NOT_PRESENT => backend(
                "the active OpenXR runtime refused XR_KHR_vulkan_enable2 \
                 (XR_ERROR_EXTENSION_NOT_PRESENT), which vr-ocean needs to render with Vulkan",
            ),
            xr::sys::Result::ERROR_RUNTIME_FAILURE | xr::sys::Result::ERROR_RUNTIME_UNAVAILABLE => {
                backend(format!(
                    "the OpenXR runtime failed to start ({e:?} ({e})); for Monado, is monado-service \
                     running?"
                ))
            }
            e => backend(format!("xrCreateInstance: {e:?} ({e})")),
        })
}

/// Checks the options before the runtime is touched.
pub(super) fn validate(options: &OpenXrOptions) -> Result<(), XrError> {
    if let Some(s) = options.resolution_scale {
        if !(s.is_finite() && (0.1..=4.0).contains(&s)) {
            return Err(backend(format!(
                "resolution scale {s}: must be in [0.1, 4]"
            )));
        }
    }
    if let Some(r) = options.max_refresh_rate {
        if !(r.is_finite() && r >= 1.0) {
            return Err(backend(format!(
                "maximum refresh rate {r}: must be at least 1 Hz"
            )));
        }
    }
    if !(options.deck_height.is_finite() && options.deck_height.abs() <= 1000.0) {
        return Err(backend(format!(
            "deck height {}: must be within ±1000 m",
            options.deck_height
        )));
    }
    Ok(())
}
