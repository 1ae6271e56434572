//! What the APK starts with. A Quest app has no command line: the headset's defaults
//! (`xr::openxr::quest::Headset::defaults`: preset, grid, refresh cap, foveation, chosen from the
//! runtime's system name), no validation layer (the APK ships none), cascades over a 2048 m
//! ocean, and as many simulation workers as the performance cores allow (`sim::workers`).

use crate::app::{
    interaction_for, DeckPlacement, FloatOptions, GovernorOptions, RunOptions, SoundOptions,
    SoundSink,
};
use crate::base::ParamError;
use crate::lod::{LodSettings, OceanSize, QualityPreset};
use crate::physics::{BodyCount, DEFAULT_DECK_HEIGHT};
use crate::render::ocean::Anisotropy;
use crate::render::{RendererSettings, Validation};
use crate::sim::workers::recommended_workers;
use crate::sim::OceanConfig;
use crate::ui::Settings;
use crate::xr::openxr::quest::DeviceDefaults;
use crate::xr::openxr::OpenXrOptions;

/// Ocean size S (m) the quadtree covers on Quest.
pub const QUEST_OCEAN_SIZE: f32 = 2048.0;

/// Cores assumed when the device does not say how many it has.
pub const FALLBACK_CORES: usize = 3;

/// Frames at the start left out of the timing statistics.
pub const WARMUP_FRAMES: u64 = 10;

/// The OpenXR backend's settings on Quest: validation off, everything else the headset's
/// defaults (resolved once the runtime names the headset).
pub fn xr_options() -> OpenXrOptions {
    OpenXrOptions {
        validation: Validation::Off,
        ..OpenXrOptions::default()
    }
}

/// The frame loop's settings for a headset with `defaults`, starting at `preset`; `max_khz`
/// are the cores' maximum clocks (`sim::workers::core_max_khz`) and `cores` what
/// `std::thread::available_parallelism` reported (`None` when it could not tell).
pub fn run_options(
    defaults: &DeviceDefaults,
    preset: QualityPreset,
    max_khz: &[u64],
    cores: Option<usize>,
) -> Result<RunOptions, ParamError> {
    let threads = recommended_workers(
        max_khz,
        cores.unwrap_or(FALLBACK_CORES),
        defaults.workers_cap,
    );
    Ok(RunOptions {
        ocean: OceanConfig::default_cascades(defaults.grid as u32)?,
        threads,
        lod: LodSettings::new(preset, OceanSize::new(QUEST_OCEAN_SIZE)?),
        renderer: RendererSettings {
            anisotropy: Anisotropy::X4,
            // The filtered lobe with anisotropic filtering holds the aliasing gate alone;
            // supersampling would cost the headset a third of its pass (issue 43).
            supersampling: false,
            ..RendererSettings::default()
        },
        capture: Vec::new(),
        warmup: WARMUP_FRAMES,
        floating: Some(FloatOptions {
            bodies: BodyCount::DEFAULT,
            deck: DeckPlacement::At(DEFAULT_DECK_HEIGHT),
            interaction: Some(interaction_for(preset)),
        }),
        // On a headset the GPU-time governor is always on, its budget the frame period.
        governor: GovernorOptions {
            enabled: true,
            ..GovernorOptions::default()
        },
        // The sea's sound on the headset's speakers (AAudio).
        audio: SoundOptions {
            sink: SoundSink::Device,
            ..SoundOptions::default()
        },
        // Closed until the menu button opens it.
        panel_open: false,
        comfort: Default::default(),
    })
}

/// Starts `options` from the kept `settings` (the user's wind, preset, sky and sound of the
/// last session); a kept sky the renderer refuses is left at the default, with a warning.
pub fn apply_settings(options: &mut RunOptions, settings: &Settings) -> Result<(), ParamError> {
    let waves = &mut options.ocean.waves;
    waves.wind_speed = settings.wind_speed;
    waves.wind_direction_deg = settings.wind_direction_deg;
    waves.choppiness = settings.choppiness;
    if let Some(p) = settings.quality_preset() {
        options.lod = LodSettings::new(p, OceanSize::new(options.lod.size())?);
        if let Some(f) = options.floating.as_mut() {
            f.interaction = f.interaction.map(|_| interaction_for(p));
        }
    }
    let mut sun = options.renderer.sun;
    sun.elevation_deg = settings.sun_elevation_deg.unwrap_or(sun.elevation_deg);
    sun.azimuth_deg = settings.sun_azimuth_deg.unwrap_or(sun.azimuth_deg);
    sun.clouds = settings.clouds.unwrap_or(sun.clouds);
    match sun.validate() {
        Ok(()) => options.renderer.sun = sun,
        Err(e) => log::warn!("kept sky refused ({e}): the default sky"),
    }
    options.audio.volume = settings.volume;
    if !settings.audio {
        options.audio.sink = SoundSink::Off;
    }
    // Comfort: turning and seated for the backend, the kept deck for the bodies' world.
    options.comfort = settings.comfort(DEFAULT_DECK_HEIGHT);
    if let (Some(h), Some(f)) = (settings.deck_height_m, options.floating.as_mut()) {
        f.deck = DeckPlacement::At(h);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xr::openxr::quest::Headset;

    #[test]
    fn quest_options_are_valid_and_follow_the_headset() {
        let xr = xr_options();
        assert_eq!(xr.validation, Validation::Off);
        assert_eq!(xr.frames, None, "the headset app runs until the user quits");
        assert_eq!(xr.preset, None, "the headset's default");
        // Quest 2: XR2 Gen 1 clusters, 8 cores.
        let gen1 = [
            1_804_800, 1_804_800, 1_804_800, 1_804_800, 2_419_200, 2_419_200, 2_419_200, 2_841_600,
        ];
        let d = Headset::Quest2.defaults();
        let run = run_options(&d, d.preset, &gen1, Some(8)).unwrap();
        run.ocean.validate().unwrap();
        assert_eq!(run.threads, 3);
        assert!(
            run.governor.enabled,
            "the GPU-time governor is on on a headset"
        );
        assert_eq!(run.lod.preset(), QualityPreset::Medium);
        assert!(run.capture.is_empty());
        // No cpufreq data: the reported core count minus the render thread.
        let run = run_options(&d, d.preset, &[], Some(2)).unwrap();
        assert_eq!(run.threads, 1);
        let run = run_options(&d, d.preset, &[], None).unwrap();
        assert_eq!(run.threads, FALLBACK_CORES - 1);
        // Quest 3 starts at High.
        let d3 = Headset::Quest3.defaults();
        let run = run_options(&d3, d3.preset, &gen1, Some(8)).unwrap();
        assert_eq!(run.lod.preset(), QualityPreset::High);
    }
}
