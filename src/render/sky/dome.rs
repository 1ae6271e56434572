//! [`Sky`]: everything the renderer needs of the sky for one [`SunSky`]: the clear atmosphere
//! ([`super::atmosphere`]), the cloud layer over it ([`super::clouds`]), the sun's disc after
//! both, and the illuminance of sun and sky on the sea. Made when the sun, the haze or the
//! clouds change (a few ms), never per frame.

use glam::Vec3;

use super::atmosphere::Atmosphere;
use super::clouds::CloudLayer;
use super::colour::LUMINANCE;
use super::{SunSky, SUN_ANGULAR_RADIUS_DEG, SUN_SOLID_ANGLE, TURBIDITY_RANGE};

/// Elevation × azimuth cells of the midpoint rule for the sky's illuminance.
const ILLUMINANCE_CELLS: [usize; 2] = [32, 64];

/// The sky and the sun for one [`SunSky`].
#[derive(Clone, Debug)]
pub struct Sky {
    /// The sun as given (out-of-range values clamped into range).
    sun: SunSky,
    /// Unit vector toward the sun.
    sun_dir: Vec3,
    atmosphere: Atmosphere,
    clouds: CloudLayer,
    /// Radiance of the sun disc (kcd/m²).
    sun_radiance: Vec3,
    /// Horizontal illuminance of the sky dome alone, clouds included (klux).
    sky_illuminance: Vec3,
}

impl Sky {
    /// Precomputes the sky for `sun` (meant to be validated; out-of-range values are clamped).
    pub fn new(sun: &SunSky) -> Self {
        let sun = SunSky {
            elevation_deg: sun.elevation_deg.clamp(super::MIN_SUN_ELEVATION_DEG, 90.0),
            azimuth_deg: sun.azimuth_deg,
            turbidity: sun.turbidity.clamp(TURBIDITY_RANGE[0], TURBIDITY_RANGE[1]),
            clouds: sun.clouds.clamp(0.0, 1.0),
        };
        let sun_dir = sun.sun_direction();
        let atmosphere = Atmosphere::new(sun_dir, sun.turbidity);
        let clear_sky = integrate_dome(|d| atmosphere.radiance(d));
        let clouds = CloudLayer::new(sun.clouds, sun_dir, &atmosphere, clear_sky);
        let r = SUN_ANGULAR_RADIUS_DEG;
        let visible = ((sun.elevation_deg + r) / (2.0 * r)).clamp(0.0, 1.0);
        let above = atmosphere.solar_illuminance() / SUN_SOLID_ANGLE;
        let through =
            atmosphere.transmittance(0.0, sun_dir.y.max(0.0)) * clouds.sun_transmittance();
        let mut sky = Self {
            sun,
            sun_dir,
            atmosphere,
            clouds,
            sun_radiance: above * through * visible,
            sky_illuminance: Vec3::ZERO,
        };
        sky.sky_illuminance = integrate_dome(|d| sky.radiance(d));
        sky
    }

    /// The sun, haze and clouds this sky was made for (clamped into range).
    pub fn sun(&self) -> &SunSky {
        &self.sun
    }

    /// Unit vector toward the sun's centre.
    pub fn sun_direction(&self) -> Vec3 {
        self.sun_dir
    }

    /// Sky radiance seen along `dir` (any length > 0; y up), linear sRGB in kcd/m², clouds
    /// included, without the sun disc. Below the horizon it returns the horizon at the same
    /// azimuth.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let d = Vec3::new(dir.x, dir.y.max(0.0), dir.z)
            .try_normalize()
            .unwrap_or(Vec3::X);
        let clear = self.atmosphere.radiance(d);
        self.clouds.over(d, clear, &self.atmosphere)
    }

    /// Radiance of the sun disc after the atmosphere and the clouds (linear sRGB, kcd/m²),
    /// scaled by the fraction of the disc above the horizon (0 once it has set).
    pub fn sun_radiance(&self) -> Vec3 {
        self.sun_radiance
    }

    /// Sun illuminance at normal incidence (klux): [`Sky::sun_radiance`] × the disc's solid angle.
    pub fn sun_illuminance(&self) -> Vec3 {
        self.sun_radiance * SUN_SOLID_ANGLE
    }

    /// Illuminance of the sky dome alone on a horizontal surface (klux): ∫ L cos θ dω over the
    /// upper hemisphere (midpoint rule, computed once in [`Sky::new`]).
    pub fn sky_illuminance(&self) -> Vec3 {
        self.sky_illuminance
    }

    /// Luminance on a horizontal surface from sun plus sky (klux): the exposure's meter reading.
    pub fn horizontal_illuminance(&self) -> f32 {
        let sun = LUMINANCE.dot(self.sun_illuminance()) * self.sun_dir.y.max(0.0);
        sun + LUMINANCE.dot(self.sky_illuminance)
    }
}

/// ∫ radiance · cos θ dω over the upper hemisphere, midpoint rule in (elevation, azimuth).
fn integrate_dome(radiance: impl Fn(Vec3) -> Vec3) -> Vec3 {
    let [ne, na] = ILLUMINANCE_CELLS;
    let de = std::f32::consts::FRAC_PI_2 / ne as f32;
    let da = std::f32::consts::TAU / na as f32;
    let mut sum = Vec3::ZERO;
    for i in 0..ne {
        let (se, ce) = ((i as f32 + 0.5) * de).sin_cos();
        let mut ring = Vec3::ZERO;
        for j in 0..na {
            let (sa, ca) = ((j as f32 + 0.5) * da).sin_cos();
            ring += radiance(Vec3::new(ce * ca, se, ce * sa));
        }
        // cos θ = sin e, dω = cos e de da.
        sum += ring * (se * ce * de * da);
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::super::direction_at;
    use super::*;

    fn sky(elevation_deg: f32, turbidity: f32, clouds: f32) -> Sky {
        Sky::new(&SunSky {
            elevation_deg,
            azimuth_deg: 30.0,
            turbidity,
            clouds,
        })
    }

    fn at(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
        direction_at(elevation_deg, azimuth_deg)
    }

    /// HSV saturation of a linear colour.
    fn saturation(c: Vec3) -> f32 {
        1.0 - c.min_element() / c.max_element().max(1e-9)
    }

    #[test]
    fn sun_and_sky_illuminance_of_a_clear_day() {
        for elevation in [60.0, 20.0, 4.0, 1.5] {
            let s = sky(elevation, 2.5, 0.0);
            let sun = LUMINANCE.dot(s.sun_illuminance());
            let dome = LUMINANCE.dot(s.sky_illuminance());
            let zenith = s.radiance(Vec3::Y);
            println!(
                "sun {elevation}°, T 2.5: sun {sun:.2} klux (normal), sky {dome:.2} klux \
                 (horizontal), sun rgb {:.3}, zenith {zenith:.3} kcd/m²",
                s.sun_illuminance(),
            );
        }
        let s = sky(60.0, 2.5, 0.0);
        let sun = LUMINANCE.dot(s.sun_illuminance());
        let dome = LUMINANCE.dot(s.sky_illuminance());
        // Measured clear skies: direct normal 80-100 klux at 60°, the dome 10-25 klux.
        assert!((75.0..105.0).contains(&sun), "{sun}");
        assert!((8.0..28.0).contains(&dome), "{dome}");
        // Haze dims the sun and brightens the dome.
        let hazy = sky(60.0, 8.0, 0.0);
        assert!(LUMINANCE.dot(hazy.sun_illuminance()) < 0.7 * sun);
        assert!(LUMINANCE.dot(hazy.sky_illuminance()) > dome);
    }

    #[test]
    fn the_clear_sky_is_blue_above_and_paler_at_the_horizon() {
        // (A sun near the zenith has a white aureole there.)
        for e in [10.0, 45.0] {
            let s = sky(e, 2.5, 0.0);
            let ratio = |v: Vec3| v.z / v.x;
            let zenith = ratio(s.radiance(Vec3::Y));
            let horizon = ratio(s.radiance(at(0.5, 120.0)));
            assert!(
                zenith > horizon && zenith > 1.0,
                "{e}: {zenith} vs {horizon}"
            );
        }
        // Never lavender: away from the sun at midday the horizon's green is above its red.
        let s = sky(60.0, 2.5, 0.0);
        let anti = s.radiance(at(3.0, 210.0));
        assert!(anti.y >= anti.x && anti.z >= anti.y, "{anti}");
        // Brighter near the sun than opposite.
        let near = LUMINANCE.dot(sky(30.0, 2.5, 0.0).radiance(at(35.0, 30.0)));
        let opposite = LUMINANCE.dot(sky(30.0, 2.5, 0.0).radiance(at(35.0, 210.0)));
        assert!(near > 2.0 * opposite, "{near} vs {opposite}");
    }

    #[test]
    fn haze_is_pale_not_tan() {
        // Turbidity 10 (Preetham's sky was tan there: saturation 0.34, red > green > blue).
        let s = sky(35.0, 10.0, 0.0);
        for a in [120.0, 210.0, 300.0] {
            let c = s.radiance(at(5.0, a));
            println!(
                "T 10, 5° up at {a}°: {c:.3}, saturation {:.2}",
                saturation(c)
            );
            assert!(saturation(c) < 0.15, "{a}: {c}");
        }
    }

    #[test]
    fn overcast_is_grey_and_hides_the_sun() {
        let s = sky(35.0, 2.5, 1.0);
        for e in [2.0, 6.0, 10.0, 45.0, 90.0] {
            let c = |a| s.radiance(at(e, a));
            println!(
                "overcast {e}°: {:.3} {:.3} {:.3}",
                c(30.0),
                c(120.0),
                c(210.0)
            );
        }
        println!(
            "sun {:.2} sky {:.2}",
            s.sun_illuminance(),
            s.sky_illuminance()
        );
        let clear = sky(35.0, 2.5, 0.0);
        println!(
            "clear: sun {:.2} sky {:.2}",
            clear.sun_illuminance(),
            clear.sky_illuminance()
        );
        // Grey (the image test holds the rendered sky to blue ≥ red; here the model's light,
        // before the tone map, is allowed the few % of red the distant deck keeps through the
        // air in front of it).
        for e in [2.0, 6.0, 10.0, 45.0, 90.0] {
            for a in [30.0, 120.0, 210.0] {
                let c = s.radiance(at(e, a));
                assert!(saturation(c) <= 0.1 && c.z >= 0.9 * c.x, "{e}° {a}°: {c}");
            }
        }
        let zenith = LUMINANCE.dot(s.radiance(Vec3::Y));
        let horizon = LUMINANCE.dot(s.radiance(at(2.0, 120.0)));
        let dome = LUMINANCE.dot(s.sky_illuminance());
        println!("overcast: zenith {zenith:.2} kcd/m², 2° up {horizon:.2}, dome {dome:.1} klux");
        // Measured overcast skies: 5-25 klux, the zenith brighter than the horizon (CIE: 3x).
        assert!((4.0..30.0).contains(&dome), "{dome}");
        assert!(zenith > 1.2 * horizon, "{zenith} vs {horizon}");
        assert!(LUMINANCE.dot(s.sun_illuminance()) < 1e-3);
        // The deck lets through a fraction of a clear day's light (measured: 10-40 %).
        let clear = sky(35.0, 2.5, 0.0).horizontal_illuminance();
        assert!(
            (0.1..0.45).contains(&(s.horizontal_illuminance() / clear)),
            "{} of {clear} klux",
            s.horizontal_illuminance()
        );
    }

    #[test]
    fn a_low_sun_outshines_its_sky_and_reddens() {
        for e in [1.5, 4.0] {
            let s = sky(e, 2.5, 0.0);
            let sun = LUMINANCE.dot(s.sun_radiance());
            let beside = LUMINANCE.dot(s.radiance(at(e + 1.0, 30.0)));
            println!(
                "sun {e}°: disc {sun:.0} kcd/m², sky 1° above {beside:.2}: {:.0}x",
                sun / beside
            );
            assert!(sun > 300.0 * beside, "{e}: {sun} vs {beside}");
            let c = s.sun_radiance();
            assert!(c.x > 2.0 * c.z, "{c}");
        }
    }

    #[test]
    fn twilight_fades_and_the_sun_sets() {
        let lum = |e| LUMINANCE.dot(sky(e, 2.5, 0.0).sky_illuminance());
        let (zero, below, night) = (lum(0.0), lum(-4.0), lum(-10.0));
        println!("sky illuminance: sun 0° {zero:.4} klux, -4° {below:.5}, -10° {night:.6}");
        assert!(
            below < 0.2 * zero && night < 0.05 * below,
            "{zero} {below} {night}"
        );
        assert_eq!(sky(-1.0, 2.5, 0.0).sun_radiance(), Vec3::ZERO);
    }

    #[test]
    fn every_sun_haze_and_cloud_stays_finite() {
        for t in [1.7, 2.5, 10.0] {
            for e in [-10.0, 0.0, 1.0, 45.0, 90.0] {
                for c in [0.0, 0.5, 1.0] {
                    let s = sky(e, t, c);
                    for d in [Vec3::Y, at(0.0, 0.0), at(20.0, 30.0), -Vec3::Y] {
                        let v = s.radiance(d);
                        assert!(
                            v.is_finite() && v.min_element() >= 0.0,
                            "{t} {e} {c} {d}: {v}"
                        );
                    }
                    assert!(s.sun_radiance().is_finite() && s.sky_illuminance().is_finite());
                }
            }
        }
    }
}
