//! Start-up of the Quest extensions, each only when the runtime lists it: fixed foveation on
//! the colour swapchain (`XR_FB_foveation` + `XR_FB_swapchain_update_state`), the display
//! refresh rate (`XR_FB_display_refresh_rate`, with the governor of [`super::refresh`]) and the
//! CPU/GPU performance levels (`XR_EXT_performance_settings`) and the colour space
//! (`XR_FB_color_space`: Rec. 709, the gamut of sRGB content, instead of the runtime's
//! default). A missing or failing extension is logged and skipped: none of them is needed to
//! show the ocean.

use openxr as xr;

use super::error::check;
use super::foveation;
use super::quest::{Foveation, PerfLevel};
use super::refresh::RefreshGovernor;
use super::session::Session;

/// What the Quest extensions were started with.
pub(super) struct QuestSettings {
    /// Fixed foveation level.
    pub foveation: Foveation,
    /// Highest refresh rate to ask for (Hz).
    pub max_refresh_rate: f32,
    /// CPU and GPU levels.
    pub perf_levels: (PerfLevel, PerfLevel),
}

/// Starts every extension the runtime offers on `session`; returns the refresh-rate governor
/// when the rate can be chosen.
pub(super) fn start(
    instance: &xr::Instance,
    session: &mut Session,
    settings: &QuestSettings,
) -> Option<RefreshGovernor> {
    session.foveation = foveation(instance, session, settings.foveation);
    perf_levels(instance, &session.session, settings.perf_levels);
    colour_space(instance, &session.session);
    refresh_rate(instance, &session.session, settings.max_refresh_rate)
}

/// The foveation profile on the colour swapchain, when it was created with density maps
/// (every piece there: see `foveation`).
fn foveation(
    instance: &xr::Instance,
    session: &Session,
    level: Foveation,
) -> Option<xr::FoveationProfileFB> {
    if session.colour.density_maps.is_empty() {
        return None;
    }
    let profile = foveation::apply_profile(instance, &session.session, &session.colour, level)?;
    log::info!("fixed foveation: {level:?} (fragment density maps, profile applied)");
    Some(profile)
}

/// Changes the fixed foveation of a session started with it to `level` (the GPU-time
/// governor's foveation step and its undoing). False when the swapchain has no foveation
/// profile or the runtime refuses (logged); the old profile then stays.
pub(super) fn set_foveation(
    instance: &xr::Instance,
    session: &mut Session,
    level: Foveation,
) -> bool {
    if session.foveation.is_none() {
        return false;
    }
    match foveation::apply_profile(instance, &session.session, &session.colour, level) {
        Some(profile) => {
            session.foveation = Some(profile);
            log::info!("fixed foveation: {level:?} (GPU-time governor)");
            true
        }
        None => false,
    }
}

/// CPU and GPU performance levels.
fn perf_levels(
    instance: &xr::Instance,
    session: &xr::Session<xr::Vulkan>,
    (cpu, gpu): (PerfLevel, PerfLevel),
) {
    let Some(perf) = instance.exts().ext_performance_settings.as_ref() else {
        return;
    };
    for (domain, level, name) in [
        (xr::sys::PerfSettingsDomainEXT::CPU, cpu, "CPU"),
        (xr::sys::PerfSettingsDomainEXT::GPU, gpu, "GPU"),
    ] {
        // SAFETY: a valid session and enum values of the extension.
        let r = unsafe {
            (perf.perf_settings_set_performance_level)(session.as_raw(), domain, level.raw())
        };
        match check(r) {
            Err(r) => log::warn!("xrPerfSettingsSetPerformanceLevelEXT({name}): {r:?} ({r})"),
            Ok(()) => log::info!("{name} performance level: {level:?}"),
        }
    }
}

/// Asks for the highest offered refresh rate at or under `cap`; the governor steps down from
/// there when frames miss their budget.
fn refresh_rate(
    instance: &xr::Instance,
    session: &xr::Session<xr::Vulkan>,
    cap: f32,
) -> Option<RefreshGovernor> {
    instance.exts().fb_display_refresh_rate.as_ref()?;
    let rates = session
        .enumerate_display_refresh_rates()
        .map_err(|e| log::warn!("xrEnumerateDisplayRefreshRatesFB: {e:?} ({e})"))
        .ok()?;
    let Some(g) = RefreshGovernor::new(&rates, cap) else {
        log::warn!(
            "the runtime offers no display refresh rate from {} to {cap} Hz ({rates:?}); \
             leaving its own rate",
            RefreshGovernor::MIN_RATE
        );
        return None;
    };
    log::info!("display refresh rates {rates:?}: asking for {}", g.rate());
    if let Err(e) = session.request_display_refresh_rate(g.rate()) {
        log::warn!("xrRequestDisplayRefreshRateFB: {e:?} ({e})");
    }
    Some(g)
}

/// The gamut of our sRGB content, Rec. 709, set explicitly: runtimes disagree on the default
/// (the specification names Rift CV1's for Oculus headsets; Quest documents say Rec. 2020 or
/// Rec. 709 by model), and a wider default gamut would oversaturate every colour.
fn colour_space(instance: &xr::Instance, session: &xr::Session<xr::Vulkan>) {
    if instance.exts().fb_color_space.is_none() {
        return;
    }
    let offered = match session.enumerate_color_spaces() {
        Ok(c) => c,
        Err(e) => {
            log::warn!("xrEnumerateColorSpacesFB: {e:?} ({e})");
            return;
        }
    };
    if !offered.contains(&xr::ColorSpaceFB::REC709) {
        log::warn!(
            "the runtime offers no Rec. 709 colour space ({offered:?}); keeping its default"
        );
        return;
    }
    match session.set_color_space(xr::ColorSpaceFB::REC709) {
        Ok(()) => log::info!("colour space: Rec. 709 (sRGB primaries)"),
        Err(e) => log::warn!("xrSetColorSpaceFB(REC709): {e:?} ({e})"),
    }
}

/// The runtime's current display refresh rate (Hz), when it says (`XR_FB_display_refresh_rate`).
pub(super) fn current_refresh_rate(
    instance: &xr::Instance,
    session: &xr::Session<xr::Vulkan>,
) -> Option<f32> {
    instance.exts().fb_display_refresh_rate.as_ref()?;
    session.get_display_refresh_rate().ok()
}
