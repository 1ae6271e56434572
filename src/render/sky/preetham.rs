//! Preetham, Shirley & Smits 1999: the clear sky's luminance Y and chromaticity (x, y), each the
//! zenith value times a Perez distribution (`docs/notes/sea-look-research.md` section 3.1):
//!
//! ```text
//! F(θ, γ) = (1 + A·exp(B / cos θ)) · (1 + C·exp(D·γ) + E·cos²γ)
//! Y(θ, γ) = Y_z · F_Y(θ, γ) / F_Y(0, θ_s)        (and likewise x, y)
//! ```
//!
//! with θ the view's zenith angle, γ its angle to the sun, θ_s the sun's zenith angle, and
//! [A..E] and the zenith values functions of the turbidity T and θ_s (tables below). xyY goes to
//! linear sRGB through XYZ (D65), so the sky keeps its absolute, slightly blue chromaticity.
//!
//! Where the model breaks down:
//! - Views below the horizon read the horizon (the view's elevation clamped to 0), cos θ is
//!   clamped to ≥ 1e-3.
//! - The sun: Preetham is fitted for a sun above the horizon and is weak below ~10°. The model
//!   uses the sun's elevation clamped to ≥ 1°; below 0° the whole sky fades by
//!   10^(elevation / 2°) (1/10 per 2° of depression; at −10°, 1e-5 of the sunset sky, ≈ 0.1 lux:
//!   nautical twilight), keeping the 1° sky's colours and shape.
//!
//! The sun disc (not in Preetham's sky) is the extraterrestrial sun, 127.5 klux (the IES solar
//! illuminance constant) with the chromaticity of a 5778 K black body, attenuated per channel by
//! Preetham's appendix optical depths, Rayleigh 0.008735 λ^−4.08 plus Ångström aerosol
//! β(T) λ^−1.3 (λ in µm at each primary's dominant wavelength, no ozone or water vapour), along
//! the Kasten-Young (1989) relative air mass. It gives ≈ 96 klux at 60° for T = 2.5.

use glam::Vec3;

use super::{direction_at, SunSky, SUN_ANGULAR_RADIUS_DEG, SUN_SOLID_ANGLE, TURBIDITY_RANGE};

/// Rec.709 luminance weights: Y = LUMINANCE · (R, G, B), the Y row of sRGB → XYZ.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Perez coefficients [A, B, C, D, E] of luminance Y, each `[slope, offset]`: c = slope·T + offset.
const PEREZ_Y: [[f32; 2]; 5] = [
    [0.1787, -1.4630],
    [-0.3554, 0.4275],
    [-0.0227, 5.3251],
    [0.1206, -2.5771],
    [-0.0670, 0.3703],
];

/// Perez coefficients of chromaticity x, as [`PEREZ_Y`].
const PEREZ_X: [[f32; 2]; 5] = [
    [-0.0193, -0.2592],
    [-0.0665, 0.0008],
    [-0.0004, 0.2125],
    [-0.0641, -0.8989],
    [-0.0033, 0.0452],
];

/// Perez coefficients of chromaticity y, as [`PEREZ_Y`].
const PEREZ_Y_CHROMA: [[f32; 2]; 5] = [
    [-0.0167, -0.2608],
    [-0.0950, 0.0092],
    [-0.0079, 0.2102],
    [-0.0441, -1.6537],
    [-0.0109, 0.0529],
];

/// Zenith x = [T², T, 1] · M · [θ_s³, θ_s², θ_s, 1]ᵀ (θ_s in radians).
const ZENITH_X: [[f32; 4]; 3] = [
    [0.00166, -0.00375, 0.00209, 0.0],
    [-0.02903, 0.06377, -0.03202, 0.00394],
    [0.11693, -0.21196, 0.06052, 0.25886],
];

/// Zenith y, as [`ZENITH_X`].
const ZENITH_Y: [[f32; 4]; 3] = [
    [0.00275, -0.00610, 0.00317, 0.0],
    [-0.04214, 0.08970, -0.04153, 0.00516],
    [0.15346, -0.26756, 0.06670, 0.26688],
];

/// XYZ → linear sRGB (D65), rows R, G, B.
const XYZ_TO_RGB: [[f32; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// Lowest sun elevation the Perez model is evaluated at (degrees).
const MODEL_MIN_ELEVATION_DEG: f32 = 1.0;

/// Degrees of sun depression per factor 10 of twilight fade.
const TWILIGHT_DECADE_DEG: f32 = 2.0;

/// Smallest cos θ the Perez function divides by (the horizon).
const COS_THETA_MIN: f32 = 1e-3;

/// Sun illuminance above the atmosphere at normal incidence (klux; IES: 127.5).
const SOLAR_ILLUMINANCE_KLUX: f32 = 127.5;

/// Chromaticity (x, y) of the sun above the atmosphere: a 5778 K black body (Kim et al.'s
/// Planckian-locus fit), slightly warmer than D65.
const SUN_CHROMATICITY: [f32; 2] = [0.3263, 0.3358];

/// Wavelength (µm) standing for each channel: the dominant wavelengths of the Rec.709 primaries.
const CHANNEL_WAVELENGTH_UM: [f32; 3] = [0.612, 0.549, 0.465];

/// Rayleigh optical depth at air mass 1: `[scale, exponent]` in scale · λ^−exponent (λ in µm).
const RAYLEIGH: [f32; 2] = [0.008735, 4.08];

/// Ångström aerosol turbidity β = slope·T + offset (Preetham's appendix).
const ANGSTROM_BETA: [f32; 2] = [0.046_083_66, -0.045_860_26];

/// Ångström wavelength exponent α of the aerosol optical depth β λ^−α.
const ANGSTROM_ALPHA: f32 = 1.3;

/// Elevation × azimuth cells of the midpoint rule for the sky's illuminance.
const ILLUMINANCE_CELLS: [usize; 2] = [64, 128];

/// The sky and the sun for one [`SunSky`], with everything precomputed so that
/// [`Sky::radiance`] costs a few exponentials and one `acos`.
#[derive(Clone, Debug)]
pub struct Sky {
    /// The sun as given (validated ranges are clamped into range).
    sun: SunSky,
    /// Unit vector toward the true sun.
    sun_dir: Vec3,
    /// Unit vector toward the sun the Perez model sees (elevation ≥ 1°).
    model_sun_dir: Vec3,
    /// [A, B, C, D, E] of Y, x and y.
    perez: [[f32; 5]; 3],
    /// Zenith (Y [kcd/m²], x, y).
    zenith: [f32; 3],
    /// Zenith value / F(0, θ_s) for Y, x and y: the factor that multiplies F(θ, γ).
    scale: [f32; 3],
    /// Twilight factor on the whole sky (1 with the sun above the horizon).
    fade: f32,
    /// Radiance of the sun disc (kcd/m²).
    sun_radiance: Vec3,
    /// Horizontal illuminance of the sky dome alone (klux).
    sky_illuminance: Vec3,
}

impl Sky {
    /// Precomputes the sky for `sun` (meant to be validated; out-of-range values are clamped).
    /// Costs ~10⁴ radiance evaluations (the dome's illuminance): call it when the sun changes.
    pub fn new(sun: &SunSky) -> Self {
        let t = sun.turbidity.clamp(TURBIDITY_RANGE[0], TURBIDITY_RANGE[1]);
        let elevation = sun.elevation_deg.clamp(super::MIN_SUN_ELEVATION_DEG, 90.0);
        let sun = SunSky {
            elevation_deg: elevation,
            azimuth_deg: sun.azimuth_deg,
            turbidity: t,
        };
        let model_elevation = elevation.max(MODEL_MIN_ELEVATION_DEG);
        let theta_s = (90.0 - model_elevation).to_radians();
        let perez = [PEREZ_Y, PEREZ_X, PEREZ_Y_CHROMA].map(|c| c.map(|[s, o]| s * t + o));
        let zenith = zenith_xyy(t, theta_s);
        let scale = std::array::from_fn(|i| zenith[i] / perez_f(&perez[i], 1.0, theta_s));
        let fade = if elevation < 0.0 {
            10f32.powf(elevation / TWILIGHT_DECADE_DEG)
        } else {
            1.0
        };
        let mut sky = Self {
            sun,
            sun_dir: sun.sun_direction(),
            model_sun_dir: direction_at(model_elevation, sun.azimuth_deg),
            perez,
            zenith,
            scale,
            fade,
            sun_radiance: sun_radiance(t, elevation),
            sky_illuminance: Vec3::ZERO,
        };
        sky.sky_illuminance = sky.integrate_dome();
        sky
    }

    /// The sun and turbidity this sky was made for (clamped into range).
    pub fn sun(&self) -> &SunSky {
        &self.sun
    }

    /// Unit vector toward the sun's centre.
    pub fn sun_direction(&self) -> Vec3 {
        self.sun_dir
    }

    /// Sky radiance seen along `dir` (any length > 0; y up), linear sRGB in kcd/m², without
    /// the sun disc. Below the horizon it returns the horizon at the same azimuth.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let d = Vec3::new(dir.x, dir.y.max(0.0), dir.z)
            .try_normalize()
            .unwrap_or(Vec3::X);
        let cos_theta = d.y.max(COS_THETA_MIN);
        let cos_gamma = d.dot(self.model_sun_dir).clamp(-1.0, 1.0);
        let gamma = cos_gamma.acos();
        let [y, cx, cy] = std::array::from_fn(|i| {
            self.scale[i] * perez_f_cos(&self.perez[i], cos_theta, gamma, cos_gamma)
        });
        xyy_to_rgb(cx, cy, y * self.fade)
    }

    /// Zenith luminance Y_z (kcd/m²) and chromaticity (x_z, y_z) of Preetham's formulas,
    /// before the twilight fade.
    pub fn zenith_xyy(&self) -> [f32; 3] {
        self.zenith
    }

    /// Factor on the whole sky for a sun below the horizon: 10^(elevation / 2°), 1 above it.
    pub fn twilight_fade(&self) -> f32 {
        self.fade
    }

    /// Radiance of the sun disc after the atmosphere (linear sRGB, kcd/m²), scaled by the
    /// fraction of the disc above the horizon (0 once it has set).
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

    /// ∫ radiance · cos θ dω over the upper hemisphere, midpoint rule in (elevation, azimuth).
    fn integrate_dome(&self) -> Vec3 {
        let [ne, na] = ILLUMINANCE_CELLS;
        let de = std::f32::consts::FRAC_PI_2 / ne as f32;
        let da = std::f32::consts::TAU / na as f32;
        let mut sum = Vec3::ZERO;
        for i in 0..ne {
            let (se, ce) = ((i as f32 + 0.5) * de).sin_cos();
            let mut ring = Vec3::ZERO;
            for j in 0..na {
                let (sa, ca) = ((j as f32 + 0.5) * da).sin_cos();
                ring += self.radiance(Vec3::new(ce * ca, se, ce * sa));
            }
            // cos θ = sin e, dω = cos e de da.
            sum += ring * (se * ce * de * da);
        }
        sum
    }
}

/// The Perez function F(θ, γ) with cos γ computed from γ.
fn perez_f(c: &[f32; 5], cos_theta: f32, gamma: f32) -> f32 {
    perez_f_cos(c, cos_theta, gamma, gamma.cos())
}

/// The Perez function F(θ, γ) = (1 + A e^{B / cos θ}) (1 + C e^{D γ} + E cos²γ).
fn perez_f_cos(c: &[f32; 5], cos_theta: f32, gamma: f32, cos_gamma: f32) -> f32 {
    let [a, b, cc, d, e] = *c;
    (1.0 + a * (b / cos_theta).exp()) * (1.0 + cc * (d * gamma).exp() + e * cos_gamma * cos_gamma)
}

/// Preetham's zenith (Y [kcd/m²], x, y) for turbidity `t` and sun zenith angle `theta_s` (rad).
fn zenith_xyy(t: f32, theta_s: f32) -> [f32; 3] {
    let chi = (4.0 / 9.0 - t / 120.0) * (std::f32::consts::PI - 2.0 * theta_s);
    let y = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
    let tt = [t * t, t, 1.0];
    let th = [theta_s.powi(3), theta_s * theta_s, theta_s, 1.0];
    let poly = |m: &[[f32; 4]; 3]| -> f32 {
        (0..3)
            .map(|r| tt[r] * (0..4).map(|k| m[r][k] * th[k]).sum::<f32>())
            .sum()
    };
    [y, poly(&ZENITH_X), poly(&ZENITH_Y)]
}

/// xyY → linear sRGB (D65), negative channels (outside the gamut) clamped to 0.
fn xyy_to_rgb(x: f32, y: f32, lum: f32) -> Vec3 {
    let xyz = Vec3::new(x * lum / y, lum, (1.0 - x - y) * lum / y);
    Vec3::from_array(XYZ_TO_RGB.map(|row| Vec3::from_array(row).dot(xyz))).max(Vec3::ZERO)
}

/// Kasten & Young (1989) relative air mass for a sun `elevation_deg` ≥ 0 above the horizon:
/// m = 1 / (cos z + 0.50572 (96.07995° − z)^−1.6364), z the zenith angle in degrees (≈ 38 at 0°).
fn air_mass(elevation_deg: f32) -> f32 {
    let z = 90.0 - elevation_deg.clamp(0.0, 90.0);
    1.0 / (z.to_radians().cos() + 0.50572 * (96.07995 - z).powf(-1.6364))
}

/// The sun disc's radiance (kcd/m²): extraterrestrial illuminance / solid angle, times the
/// per-channel transmittance exp(−τ m) and the fraction of the disc above the horizon.
fn sun_radiance(t: f32, elevation_deg: f32) -> Vec3 {
    let beta = ANGSTROM_BETA[0] * t + ANGSTROM_BETA[1];
    let m = air_mass(elevation_deg);
    let transmittance = Vec3::from_array(CHANNEL_WAVELENGTH_UM.map(|l| {
        let tau = RAYLEIGH[0] * l.powf(-RAYLEIGH[1]) + beta * l.powf(-ANGSTROM_ALPHA);
        (-tau * m).exp()
    }));
    let r = SUN_ANGULAR_RADIUS_DEG;
    let visible = ((elevation_deg + r) / (2.0 * r)).clamp(0.0, 1.0);
    let [x, y] = SUN_CHROMATICITY;
    // Luminance 1 by construction (the matrix's Y row is LUMINANCE).
    let colour = xyy_to_rgb(x, y, 1.0);
    colour * transmittance * (SOLAR_ILLUMINANCE_KLUX / SUN_SOLID_ANGLE * visible)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(elevation_deg: f32, turbidity: f32) -> Sky {
        Sky::new(&SunSky {
            elevation_deg,
            azimuth_deg: 30.0,
            turbidity,
        })
    }

    fn at(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
        direction_at(elevation_deg, azimuth_deg)
    }

    #[test]
    fn zenith_matches_preetham() {
        // Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192 in f64, T = 2.5, θ_s = 30°.
        let (t, ts) = (2.5f64, 30f64.to_radians());
        let chi = (4.0 / 9.0 - t / 120.0) * (std::f64::consts::PI - 2.0 * ts);
        let yz = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
        let s = sky(60.0, 2.5);
        let lum = LUMINANCE.dot(s.radiance(Vec3::Y)) as f64;
        let [_, x, y] = s.zenith_xyy();
        println!("zenith 60°, T 2.5: Y {lum:.3} (formula {yz:.3}) kcd/m², x {x:.4} y {y:.4}");
        assert!((lum / yz - 1.0).abs() < 2e-3, "{lum} vs {yz}");
        assert!((x - 0.2524).abs() < 1e-3 && (y - 0.2578).abs() < 1e-3);
    }

    #[test]
    fn sun_and_sky_illuminance() {
        for elevation in [60.0, 20.0] {
            let s = sky(elevation, 2.5);
            let sun = LUMINANCE.dot(s.sun_illuminance());
            let dome = LUMINANCE.dot(s.sky_illuminance());
            println!(
                "sun {elevation}°, T 2.5: sun {sun:.1} klux (normal), sky {dome:.1} klux \
                 (horizontal), ratio {:.2}, sun rgb {:.1}, sky rgb {:.1}",
                sun / dome,
                s.sun_illuminance(),
                s.sky_illuminance()
            );
        }
        let s = sky(60.0, 2.5);
        let sun = LUMINANCE.dot(s.sun_illuminance());
        let dome = LUMINANCE.dot(s.sky_illuminance());
        assert!((80.0..110.0).contains(&sun), "{sun}");
        // Preetham's own dome is 27 klux here (research note 3.1), above measured clear skies.
        assert!((15.0..30.0).contains(&dome), "{dome}");
        assert!((3.0..10.0).contains(&(sun / dome)), "{}", sun / dome);
        // Haze dims the sun.
        let hazy = LUMINANCE.dot(sky(60.0, 8.0).sun_illuminance());
        assert!(hazy < 0.7 * sun, "{hazy}");
    }

    #[test]
    fn brighter_near_the_sun_than_opposite() {
        let s = sky(30.0, 2.5);
        let near = LUMINANCE.dot(s.radiance(at(35.0, 30.0)));
        let opposite = LUMINANCE.dot(s.radiance(at(35.0, 210.0)));
        assert!(near > 3.0 * opposite, "{near} vs {opposite}");
    }

    #[test]
    fn bluer_at_the_zenith_than_at_the_horizon() {
        for e in [10.0, 45.0, 80.0] {
            let s = sky(e, 2.5);
            let ratio = |v: Vec3| v.z / v.x;
            let zenith = ratio(s.radiance(Vec3::Y));
            let horizon = ratio(s.radiance(at(0.0, 120.0)));
            assert!(
                zenith > horizon && zenith > 1.0,
                "{e}: {zenith} vs {horizon}"
            );
        }
    }

    #[test]
    fn continuous_across_the_horizon() {
        let s = sky(15.0, 3.0);
        for a in [0.0, 30.0, 100.0, 210.0] {
            let up = s.radiance(at(0.05, a));
            let down = s.radiance(at(-0.05, a));
            assert!(
                (up - down).abs().max_element() < 1e-2 * up.max_element(),
                "{a}"
            );
            assert_eq!(s.radiance(at(-40.0, a)), s.radiance(at(0.0, a)));
        }
        assert!(s.radiance(-Vec3::Y).is_finite());
    }

    #[test]
    fn twilight_fades_and_the_sun_sets() {
        let lum = |e| LUMINANCE.dot(sky(e, 2.5).sky_illuminance());
        let (above, zero, below) = (lum(0.5), lum(0.0), lum(-4.0));
        assert_eq!(above, zero, "the model clamps the sun to 1°");
        assert!((below / zero - 0.01).abs() < 1e-4, "{below} vs {zero}");
        assert!(lum(-10.0) < 1e-3, "{}", lum(-10.0));
        assert_eq!(sky(-1.0, 2.5).sun_radiance(), Vec3::ZERO);
        // The low sun reddens.
        let red = |e| {
            let v = sky(e, 2.5).sun_radiance();
            v.x / v.z
        };
        assert!(red(3.0) > 2.0 * red(60.0), "{} vs {}", red(3.0), red(60.0));
    }

    #[test]
    fn zenith_sun_and_haze_stay_finite() {
        for t in [1.7, 2.5, 10.0] {
            for e in [-10.0, 0.0, 1.0, 45.0, 90.0] {
                let s = sky(e, t);
                for d in [Vec3::Y, at(0.0, 0.0), at(20.0, 30.0), at(45.0, 210.0)] {
                    let v = s.radiance(d);
                    assert!(v.is_finite() && v.min_element() >= 0.0, "{t} {e} {d}: {v}");
                }
                assert!(s.sun_radiance().is_finite() && s.sky_illuminance().is_finite());
            }
        }
    }
}
