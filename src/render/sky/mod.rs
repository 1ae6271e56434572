//! The sky: a clear atmosphere of air, aerosol and ozone (single scattering plus an isotropic
//! multiple-scattering share, integrated numerically), a cloud layer over it, the sun's disc
//! after both, and a GGX-prefiltered environment map of the upper hemisphere, all made on the
//! CPU when the sun, the haze or the clouds change (never per frame). Pure math: no Vulkan here;
//! the renderer uploads [`EnvMap`]'s levels as a mip chain.
//!
//! Conventions: y up; the sun's azimuth is in degrees from +x toward +z (the wind direction's
//! convention), so the sun at elevation e, azimuth a lies along (cos e cos a, sin e, cos e sin a).
//! Units are photometric and absolute: radiance (luminance per channel) in kcd/m², illuminance in
//! klux, colours in linear Rec.709/sRGB primaries (D65 white), luminance = 0.2126 R + 0.7152 G +
//! 0.0722 B. [`exposure`] turns them into the ~[0, 1] range a tonemapper expects.
//!
//! - [`atmosphere`]: the clear sky's radiance and transmittance, tabulated per sun and haze.
//! - [`clouds`]: the cloud layer (`--clouds`) and its light.
//! - [`dome`]: [`Sky`], the two together with the sun's disc and the illuminance of both.
//! - [`colour`]: the colour space and luminance.
//! - [`bake`](mod@bake): [`EnvMap`], its (u, v) mapping and the GGX prefilter.
//!
//! The model before issue 29 was Preetham et al. 1999's clear-sky fit, which turned tan in haze,
//! lavender away from a midday sun and too bright around a sun under 10° (see `atmosphere`).

pub mod atmosphere;
pub mod bake;
pub mod clouds;
pub mod colour;
pub mod dome;

pub use bake::{bake, bake_into, direction, uv, EnvMap, PREFILTER_SAMPLES};
pub use colour::LUMINANCE;
pub use dome::Sky;

use glam::Vec3;

use crate::base::ParamError;

/// The sun's angular radius (degrees): half its mean apparent diameter of 0.533°.
pub const SUN_ANGULAR_RADIUS_DEG: f32 = 0.2665;

/// The sun disc's solid angle (sr): 2π(1 − cos r) for r = [`SUN_ANGULAR_RADIUS_DEG`].
pub const SUN_SOLID_ANGLE: f32 = 6.7966e-5;

/// Lowest sun elevation accepted (degrees): a little below the horizon, for dusk.
pub const MIN_SUN_ELEVATION_DEG: f32 = -10.0;

/// Turbidity range accepted: 1.7 (very clear) to 10 (hazy): the Ångström aerosol depth of
/// Preetham's appendix, 0.04 to 0.41 (×λ^−1.3, λ in µm).
pub const TURBIDITY_RANGE: [f32; 2] = [1.7, 10.0];

/// Film speed of the exposure model (ISO 100, hence EV100).
const ISO: f32 = 100.0;

/// Incident-light meter calibration constant C for a flat receptor (lux·s; ISO 2720 allows
/// 240 to 400): EV100 = log2(E · S / C) puts a mid-grey card at the meter's grey.
const INCIDENT_METER_C: f32 = 250.0;

/// Saturation-based speed factor 78 / (0.65 · 100) = 1.2 (Frostbite's exposure): a scene
/// luminance of 1.2 · 2^EV100 cd/m² saturates the sensor.
const SATURATION_FACTOR: f32 = 1.2;

/// Reflected-light meter calibration constant K (cd·s/m², ISO 2720: 12.5 for most makers):
/// EV100 = log2(L · S / K) renders a scene of mean luminance L as a mid-grey one.
const REFLECTED_METER_K: f32 = 12.5;

/// What open water sends back toward a viewer looking at the horizon, as shares of the sky
/// band it mirrors (Fresnel averaged over grazing to 45° views) and of the illuminance
/// (the body's back-scattered light, luminance-weighted).
const SEA_SKY_REFLECTANCE: f32 = 0.1;
const SEA_BODY_REFLECTANCE: f32 = 0.012;

/// How far (stops) the metered exposure may stray from the incident reading: enough to hold a
/// glaring low sun's sky, never so far as to turn dusk into day or day into dusk.
const METER_RANGE_EV: (f32, f32) = (-2.0, 2.0);

/// Stops between the metered mean and the saturation-based mapping's mid-grey: with it the
/// scene's mean luminance lands at 0.29 of the tonemapper's input instead of 0.10, which made a
/// sunny midday sea read dark (half of an ocean view is water returning a few % of the light,
/// so the mean sits well below what a viewer takes as the scene's grey).
pub const KEY_EV: f32 = 1.5;

/// Mean luminance (kcd/m²) of what a viewer looking at the horizon sees: half the view is the
/// sky from the horizon to 40° up (averaged over every azimuth, by solid angle), half is sea.
pub fn scene_luminance(sky: &Sky) -> f32 {
    let (mut sum, mut weight) = (0.0f32, 0.0f32);
    for e in 0..20 {
        let elevation = 1.0 + 2.0 * e as f32;
        let w = elevation.to_radians().cos();
        for a in 0..36 {
            let d = direction_at(elevation, 10.0 * a as f32);
            sum += w * LUMINANCE.dot(sky.radiance(d));
            weight += w;
        }
    }
    let band = sum / weight;
    let sea = SEA_SKY_REFLECTANCE * band
        + SEA_BODY_REFLECTANCE * sky.horizontal_illuminance() / std::f32::consts::PI;
    0.5 * (band + sea)
}

/// Darkest EV100 the auto exposure goes to, about a bright sunset. Below it the scene dims
/// instead of being pushed up to daylight brightness in twilight.
pub const EV100_MIN: f32 = 6.0;

/// Where the sun is, how hazy the air is and how cloudy the sky: everything the sky depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunSky {
    /// Sun elevation above the horizon (degrees, in [-10, 90]; below 0 is twilight).
    pub elevation_deg: f32,
    /// Sun azimuth (degrees from +x toward +z, any finite value).
    pub azimuth_deg: f32,
    /// Atmospheric turbidity T in [1.7, 10] (2–3: clear maritime air; 10: haze).
    pub turbidity: f32,
    /// Share of the sky covered by cloud, in [0, 1] (0 clear, 1 overcast).
    pub clouds: f32,
}

impl Default for SunSky {
    /// A clear afternoon: sun 35° high along +x, T = 2.5.
    fn default() -> Self {
        Self {
            elevation_deg: 35.0,
            azimuth_deg: 0.0,
            turbidity: 2.5,
            clouds: 0.0,
        }
    }
}

impl SunSky {
    /// Checks every field against its range; the error names the CLI flag.
    pub fn validate(&self) -> Result<(), ParamError> {
        let e = self.elevation_deg;
        if !(MIN_SUN_ELEVATION_DEG..=90.0).contains(&e) {
            return Err(ParamError::new(
                "sun-elevation",
                e as f64,
                "degrees in [-10, 90]",
            ));
        }
        if !self.azimuth_deg.is_finite() {
            return Err(ParamError::new(
                "sun-azimuth",
                self.azimuth_deg as f64,
                "a finite angle (degrees)",
            ));
        }
        let t = self.turbidity;
        if !(TURBIDITY_RANGE[0]..=TURBIDITY_RANGE[1]).contains(&t) {
            return Err(ParamError::new(
                "turbidity",
                t as f64,
                "a number in [1.7, 10]",
            ));
        }
        if !(0.0..=1.0).contains(&self.clouds) {
            return Err(ParamError::new(
                "clouds",
                self.clouds as f64,
                "a share of the sky in [0, 1] (0 clear, 1 overcast)",
            ));
        }
        Ok(())
    }

    /// Unit vector toward the sun's centre: (cos e cos a, sin e, cos e sin a).
    pub fn sun_direction(&self) -> Vec3 {
        direction_at(self.elevation_deg, self.azimuth_deg)
    }
}

/// Unit vector at `elevation_deg` above the horizon and `azimuth_deg` from +x toward +z.
fn direction_at(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    Vec3::new(ce * ca, se, ce * sa)
}

/// Suggested EV100 for the scene: a reflected-light reading of its mean luminance
/// ([`scene_luminance`]), EV100 = log2(L · S / K) with L in cd/m², held within 2 stops of an
/// incident-light reading of the horizontal illuminance of sun plus sky (log2(E · S / C), E in lux,
/// C = 250: sun 60° high at T = 2.5, E ≈ 110 klux, EV100 ≈ 15.4, the "sunny 16" value), not
/// below [`EV100_MIN`].
pub fn ev100(sky: &Sky) -> f32 {
    let incident = incident_ev100(sky);
    let metered = (1000.0 * scene_luminance(sky) * ISO / REFLECTED_METER_K)
        .max(f32::MIN_POSITIVE)
        .log2();
    metered
        .clamp(incident + METER_RANGE_EV.0, incident + METER_RANGE_EV.1)
        .max(EV100_MIN)
}

/// EV100 of an incident-light reading of the horizontal illuminance of sun plus sky.
pub fn incident_ev100(sky: &Sky) -> f32 {
    let e_lux = 1000.0 * sky.horizontal_illuminance();
    (e_lux.max(f32::MIN_POSITIVE) * ISO / INCIDENT_METER_C).log2()
}

/// Multiplier from this module's kcd/m² to the tonemapper's input, where 1.0 is the luminance
/// that saturates a camera exposed at [`ev100`] (Frostbite's convention, per cd/m²
/// 1 / (1.2 · 2^EV100)): exposure = 1000 / (1.2 · 2^EV100) per kcd/m².
///
/// At midday (sun 60°, T 2.5: the reading equals the incident one) mid-grey (18 % under the
/// light) lands near 0.34 and the 60° zenith sky (8 kcd/m²) near 0.42, in the linear part of
/// PBR Neutral (below 0.76); white foam under sun plus sky is compressed toward white, the
/// sun's glint far above it. [`KEY_EV`] opens it up.
pub fn exposure(sky: &Sky) -> f32 {
    1000.0 / (SATURATION_FACTOR * (ev100(sky) - KEY_EV).exp2())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sun(elevation_deg: f32) -> SunSky {
        SunSky {
            elevation_deg,
            ..SunSky::default()
        }
    }

    #[test]
    fn validate_names_the_flag() {
        assert!(SunSky::default().validate().is_ok());
        assert!(sun(-10.0).validate().is_ok() && sun(90.0).validate().is_ok());
        for (bad, name) in [
            (sun(-10.5), "sun-elevation"),
            (sun(90.5), "sun-elevation"),
            (sun(f32::NAN), "sun-elevation"),
            (
                SunSky {
                    azimuth_deg: f32::INFINITY,
                    ..SunSky::default()
                },
                "sun-azimuth",
            ),
            (
                SunSky {
                    turbidity: 1.6,
                    ..SunSky::default()
                },
                "turbidity",
            ),
            (
                SunSky {
                    turbidity: f32::NAN,
                    ..SunSky::default()
                },
                "turbidity",
            ),
            (
                SunSky {
                    clouds: 1.2,
                    ..SunSky::default()
                },
                "clouds",
            ),
            (
                SunSky {
                    clouds: f32::NAN,
                    ..SunSky::default()
                },
                "clouds",
            ),
        ] {
            assert_eq!(bad.validate().unwrap_err().parameter, name, "{bad:?}");
        }
    }

    #[test]
    fn sun_direction_follows_the_wind_convention() {
        let d = |e, a| {
            SunSky {
                elevation_deg: e,
                azimuth_deg: a,
                turbidity: 2.5,
                clouds: 0.0,
            }
            .sun_direction()
        };
        assert!(d(0.0, 0.0).abs_diff_eq(Vec3::X, 1e-6));
        assert!(d(0.0, 90.0).abs_diff_eq(Vec3::Z, 1e-6));
        assert!(d(90.0, 37.0).abs_diff_eq(Vec3::Y, 1e-6));
        let v = d(30.0, 200.0);
        assert!((v.length() - 1.0).abs() < 1e-6 && (v.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn solid_angle_matches_the_radius() {
        let r = (SUN_ANGULAR_RADIUS_DEG as f64).to_radians();
        let omega = 2.0 * std::f64::consts::PI * (1.0 - r.cos());
        assert!(
            (SUN_SOLID_ANGLE as f64 / omega - 1.0).abs() < 1e-4,
            "{omega}"
        );
    }

    #[test]
    fn the_meter_follows_the_incident_reading_at_midday_and_holds_a_low_suns_sky() {
        let mut readings = Vec::new();
        for (e, t) in [
            (60.0, 2.5),
            (35.0, 10.0),
            (12.0, 2.2),
            (4.0, 3.0),
            (1.5, 4.0),
        ] {
            let sky = Sky::new(&SunSky {
                elevation_deg: e,
                azimuth_deg: 0.0,
                turbidity: t,
                clouds: 0.0,
            });
            let (incident, metered) = (incident_ev100(&sky), ev100(&sky));
            println!(
                "sun {e:>4}°, T {t:>4}: scene {:.3} kcd/m², incident EV100 {incident:.2}, \
                 metered {metered:.2}",
                scene_luminance(&sky)
            );
            let (lo, hi) = (incident + METER_RANGE_EV.0, incident + METER_RANGE_EV.1);
            assert!(
                (lo..=hi).contains(&metered),
                "sun {e}°: {metered} outside [{lo}, {hi}]"
            );
            readings.push(metered - incident);
        }
        // A high sun over a clear sky: the scene's mean reads near the incident light (within
        // 1.5 stops: the atmosphere's clear sky, 17 klux on a horizontal surface at 60° as
        // measured clear skies are, is darker than Preetham's 27 klux, and the meter opens up
        // about 1.2 stops on it; the midday images keep the sky and the sea in the tone map's
        // linear range, tested below and in `tests/render/look.rs`).
        assert!(readings[0].abs() < 1.5, "midday: {readings:?}");
        // A low sun: the bright sky band dominates the view, so the meter stops down (a
        // darker image than the incident reading's, which washed the sky out).
        assert!(
            readings[2..].iter().all(|&d| d > 0.5),
            "low suns: {readings:?}"
        );
    }

    #[test]
    fn exposure_is_sunny_16_at_high_sun_and_brightens_at_dusk() {
        let high = Sky::new(&sun(60.0));
        let (ev, k) = (ev100(&high), exposure(&high));
        println!("sun 60°: EV100 {ev:.2}, exposure {k:.4} per kcd/m²");
        // Sunny 16 is EV100 15; the sea and sky read ~1.2 stops darker than a grey card.
        assert!((13.5..16.0).contains(&ev), "{ev}");
        // The 60° zenith sky lands in the tonemapper's linear range.
        let zenith = LUMINANCE.dot(high.radiance(Vec3::Y)) * k;
        assert!((0.2..0.7).contains(&zenith), "{zenith}");
        let low = Sky::new(&sun(5.0));
        assert!(exposure(&low) > k);
        let night = Sky::new(&sun(-10.0));
        assert_eq!(ev100(&night), EV100_MIN);
    }
}
