//! The user's choices that outlive a run: the sea (wind, its direction, choppiness), the sky
//! (sun, clouds), the quality preset, the sound and comfort (turning, seated, the deck). Serialized as JSON with every field
//! optional on reading (a file from an older version fills what it lacks with the defaults)
//! and checked against the same ranges the command line checks.

use serde::{Deserialize, Serialize};

use crate::base::ParamError;
use crate::lod::QualityPreset;
use crate::sim::WaveParams;
use crate::ui::panel::Comfort;

/// The file format's version.
pub const SETTINGS_VERSION: u32 = 1;

/// What is kept between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// The format's version ([`SETTINGS_VERSION`]).
    pub version: u32,
    /// Wind speed at 10 m (m/s).
    pub wind_speed: f32,
    /// Direction the wind blows toward (degrees from +x toward +z).
    pub wind_direction_deg: f32,
    /// Choppiness λ, 0 to 2.
    pub choppiness: f32,
    /// Quality preset: "low", "medium", "high" or "ultra".
    pub preset: String,
    /// Sun elevation (degrees, −10 to 90); `None`: the default sun.
    pub sun_elevation_deg: Option<f32>,
    /// Sun azimuth (degrees from +x toward +z); `None`: the default.
    pub sun_azimuth_deg: Option<f32>,
    /// Share of the sky under cloud, 0 to 1; `None`: the default.
    pub clouds: Option<f32>,
    /// Master volume, 0 to 1.
    pub volume: f32,
    /// Whether the sound plays.
    pub audio: bool,
    /// One snap turn (degrees, 15 to 90).
    pub snap_turn_deg: f32,
    /// Turn smoothly instead of in snaps.
    pub smooth_turn: bool,
    /// Seated: the floor raised to a standing eye height.
    pub seated: bool,
    /// The headset's deck height above the mean sea level (m, 0.5 to 10); `None`: the
    /// default.
    pub deck_height_m: Option<f32>,
    /// In the water, the head rides the waves (false: a fixed height).
    pub ride_waves: bool,
    /// The comfort vignette while the view is moved for the user.
    pub vignette: bool,
}

impl Default for Settings {
    fn default() -> Self {
        let waves = WaveParams::default();
        Self {
            version: SETTINGS_VERSION,
            wind_speed: waves.wind_speed,
            wind_direction_deg: waves.wind_direction_deg,
            choppiness: waves.choppiness,
            preset: QualityPreset::High.name().into(),
            sun_elevation_deg: None,
            sun_azimuth_deg: None,
            clouds: None,
            volume: 1.0,
            audio: true,
            snap_turn_deg: Comfort::default().snap_turn_deg,
            smooth_turn: false,
            seated: false,
            deck_height_m: None,
            ride_waves: true,
            vignette: true,
        }
    }
}

impl Settings {
    /// The preset named, if it is one.
    pub fn quality_preset(&self) -> Option<QualityPreset> {
        QualityPreset::ALL
            .into_iter()
            .find(|p| p.name() == self.preset)
    }

    /// Checks every field against its range: the waves as the simulation checks them, the
    /// rest as the command line does.
    pub fn validate(&self) -> Result<(), ParamError> {
        let waves = WaveParams {
            wind_speed: self.wind_speed,
            wind_direction_deg: self.wind_direction_deg,
            choppiness: self.choppiness,
            ..WaveParams::default()
        };
        waves.validate()?;
        if self.quality_preset().is_none() {
            return Err(ParamError::new(
                "preset",
                f64::NAN,
                "one of low, medium, high, ultra",
            ));
        }
        let within = |v: Option<f32>, lo: f32, hi: f32| v.is_none_or(|v| (lo..=hi).contains(&v));
        if !within(self.sun_elevation_deg, -10.0, 90.0) {
            let v = self.sun_elevation_deg.unwrap_or_default() as f64;
            return Err(ParamError::new("sun-elevation", v, "degrees in [-10, 90]"));
        }
        if !self.sun_azimuth_deg.is_none_or(f32::is_finite) {
            let v = self.sun_azimuth_deg.unwrap_or_default() as f64;
            return Err(ParamError::new("sun-azimuth", v, "finite degrees"));
        }
        if !within(self.clouds, 0.0, 1.0) {
            let v = self.clouds.unwrap_or_default() as f64;
            return Err(ParamError::new("clouds", v, "a share of the sky in [0, 1]"));
        }
        if !(15.0..=90.0).contains(&self.snap_turn_deg) {
            return Err(ParamError::new(
                "snap-turn",
                self.snap_turn_deg as f64,
                "degrees in [15, 90]",
            ));
        }
        if !within(self.deck_height_m, 0.5, 10.0) {
            let v = self.deck_height_m.unwrap_or_default() as f64;
            return Err(ParamError::new("deck-height", v, "metres in [0.5, 10]"));
        }
        if !(0.0..=1.0).contains(&self.volume) {
            return Err(ParamError::new(
                "volume",
                self.volume as f64,
                "0 (silent) to 1 (full)",
            ));
        }
        Ok(())
    }

    /// The settings read from JSON `text`: `Err` names what is wrong (a syntax error, a value
    /// out of range); fields missing from the text take their defaults.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let s: Settings = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if s.version > SETTINGS_VERSION {
            return Err(format!(
                "written by a newer vr-ocean (settings version {}, this one reads {})",
                s.version, SETTINGS_VERSION
            ));
        }
        s.validate().map_err(|e| e.to_string())?;
        Ok(s)
    }

    /// The comfort options kept (the deck at `default_deck` m when none was kept).
    pub fn comfort(&self, default_deck: f32) -> Comfort {
        Comfort {
            snap_turn_deg: self.snap_turn_deg,
            smooth_turn: self.smooth_turn,
            deck_height_m: self.deck_height_m.unwrap_or(default_deck),
            seated: self.seated,
            ride_waves: self.ride_waves,
            vignette: self.vignette,
        }
    }

    /// Pretty JSON, as saved.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("settings are plain data")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_round_trip_and_old_files_fill_in_defaults() {
        let s = Settings {
            wind_speed: 17.5,
            preset: "medium".into(),
            sun_elevation_deg: Some(3.0),
            snap_turn_deg: 45.0,
            smooth_turn: true,
            seated: true,
            deck_height_m: Some(4.5),
            ..Settings::default()
        };
        assert_eq!(Settings::from_json(&s.to_json()).unwrap(), s);
        let c = s.comfort(2.9);
        assert_eq!(
            (c.snap_turn_deg, c.smooth_turn, c.seated, c.deck_height_m),
            (45.0, true, true, 4.5)
        );
        assert_eq!(Settings::default().comfort(3.3).deck_height_m, 3.3);
        let partial = Settings::from_json(r#"{"wind_speed": 4.0}"#).unwrap();
        assert_eq!(partial.wind_speed, 4.0);
        assert_eq!(partial.preset, "high");
    }

    #[test]
    fn bad_values_and_syntax_are_named() {
        for (text, what) in [
            (r#"{"wind_speed": -3}"#, "wind"),
            (r#"{"volume": 7}"#, "volume"),
            (r#"{"preset": "max"}"#, "preset"),
            (r#"{"clouds": 1.5}"#, "clouds"),
            (r#"{"sun_elevation_deg": 95}"#, "sun-elevation"),
            (r#"{"snap_turn_deg": 5}"#, "snap-turn"),
            (r#"{"deck_height_m": 40}"#, "deck-height"),
            (r#"{"version": 99}"#, "newer"),
            (r#"{"wind_speed": 4.0"#, "EOF"),
            ("", "EOF"),
            (r#"{"wind_speed": "fast"}"#, "invalid type"),
        ] {
            let e = Settings::from_json(text).unwrap_err();
            assert!(e.contains(what), "{text}: {e}");
        }
    }
}
