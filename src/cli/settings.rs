//! The kept settings at the command line's edge (issue 31): `window` and `xr` start from the
//! saved choices, except where a flag says otherwise, and save what the user ended with
//! (the window's keys and the controllers change the wind, the preset and the sun while
//! running). `--reset-settings` forgets them first. `headless` never reads or writes them:
//! its images depend on its flags alone.

use vr_ocean::app::keep::SettingsKeeper;
use vr_ocean::ui::{Settings, SettingsFile};

use super::args::{OnOff, PresetArg, ViewArgs};

/// The settings file for this run, after `--reset-settings`; `None` when there is nowhere to
/// keep it (no `$HOME`), said once.
pub fn open(view: &ViewArgs) -> Result<Option<SettingsFile>, Box<dyn std::error::Error>> {
    let Some(file) = SettingsFile::desktop() else {
        log::warn!("settings: neither XDG_CONFIG_HOME nor HOME is set: choices are not kept");
        return Ok(None);
    };
    if view.reset_settings {
        file.reset()?;
        println!("settings forgotten ({})", file.path().display());
    }
    Ok(Some(file))
}

/// Applies the saved settings of `file` to `view` where no flag was given; returns them (the
/// comfort options and the deck are the command's to apply).
pub fn apply_saved(file: &SettingsFile, view: &mut ViewArgs) -> Settings {
    let loaded = file.load();
    if let Some(w) = &loaded.warning {
        log::warn!("settings: {w}");
    }
    let s = loaded.settings;
    if !view.given.has("wind") {
        view.ocean.wind = s.wind_speed;
    }
    if !view.given.has("wind_dir") {
        view.ocean.wind_dir = s.wind_direction_deg;
    }
    if !view.given.has("choppiness") {
        view.ocean.choppiness = s.choppiness;
    }
    if !view.given.has("preset") {
        if let Some(p) = s.quality_preset() {
            view.preset = PresetArg::from(p);
        }
    }
    view.sun_elevation = view.sun_elevation.or(s.sun_elevation_deg);
    view.sun_azimuth = view.sun_azimuth.or(s.sun_azimuth_deg);
    view.clouds = view.clouds.or(s.clouds);
    if !view.given.has("volume") {
        view.volume = s.volume;
    }
    // Kept off stays off; kept on leaves each command's own default (the window plays it, the
    // headless fallback of a run without a display writes it to a file).
    if view.audio.is_none() && !s.audio {
        view.audio = Some(OnOff::Off);
    }
    if loaded.warning.is_none() {
        log::info!(
            "settings from {}: wind {:.1} m/s toward {:.0}°, preset {}",
            file.path().display(),
            view.ocean.wind,
            view.ocean.wind_dir,
            s.preset
        );
    }
    s
}

/// The hooks that keep the run's choices in `file` (none: nothing kept), with the sound as
/// asked.
pub fn keeper<'a>(file: Option<&'a SettingsFile>, view: &ViewArgs) -> SettingsKeeper<'a> {
    SettingsKeeper::new(file, view.volume, view.audio != Some(OnOff::Off))
}
