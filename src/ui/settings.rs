//! The user's choices that outlive a run: the sea (wind, its direction, choppiness), the sky
//! (sun, clouds), the quality preset and the sound. Serialized as JSON with every field
//! optional on reading (a file from an older version fills what it lacks with the defaults)
//! and checked against the same ranges the command line checks.

use serde::{Deserialize, Serialize};

use crate::base::ParamError;
use crate::lod::QualityPreset;
use crate::sim::WaveParams;

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
            ..Settings::default()
        };
        assert_eq!(Settings::from_json(&s.to_json()).unwrap(), s);
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
