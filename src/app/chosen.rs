//! What the user has chosen ([`Chosen`]): the waves, the preset, the sky and the comfort
//! options as a run ends or a change settles, and the settings they are kept as.

use crate::lod::QualityPreset;
use crate::render::sky::SunSky;
use crate::sim::WaveParams;
use crate::ui::panel::Comfort;
use crate::ui::Settings;

/// What the user has chosen by the end of a run (the front ends keep it as settings): the
/// waves, the quality preset (the user's, not a step the GPU governor took) and the sky.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    /// Wind, direction, choppiness and the rest of the waves.
    pub waves: WaveParams,
    /// The quality preset.
    pub preset: QualityPreset,
    /// Sun and clouds.
    pub sun: SunSky,
    /// Comfort options, the deck's height included (as the panel left them, else as the run
    /// started).
    pub comfort: Comfort,
}

impl Chosen {
    /// The settings to keep: these choices, and the sound as the run had it (`volume`,
    /// `audio` on or off).
    pub fn settings(&self, volume: f32, audio: bool) -> Settings {
        Settings {
            wind_speed: self.waves.wind_speed,
            wind_direction_deg: self.waves.wind_direction_deg,
            choppiness: self.waves.choppiness,
            preset: self.preset.name().into(),
            sun_elevation_deg: Some(self.sun.elevation_deg),
            sun_azimuth_deg: Some(self.sun.azimuth_deg),
            clouds: Some(self.sun.clouds),
            volume,
            audio,
            snap_turn_deg: self.comfort.snap_turn_deg,
            smooth_turn: self.comfort.smooth_turn,
            seated: self.comfort.seated,
            deck_height_m: Some(self.comfort.deck_height_m),
            ride_waves: self.comfort.ride_waves,
            vignette: self.comfort.vignette,
            ..Settings::default()
        }
    }
}
