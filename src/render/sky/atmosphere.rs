//! The clear atmosphere: single scattering by air (Rayleigh) and aerosol (Mie) with ozone
//! absorption in a spherical shell, integrated numerically on the CPU (after Nishita et al.
//! 1993 and Bruneton & Neyret 2008; Hillaire 2020's sky-view parametrization), so the sky holds
//! at a low sun, below the horizon (twilight) and in haze, where Preetham's fit did not (issue
//! 29: tan at turbidity 10, lavender antisolar horizon, a sun only 17x its sky at 1°).
//!
//! Two tables are made per sun and turbidity (a few ms, [`Atmosphere::new`]): the
//! transmittance from any height toward any zenith angle to space, and the sky's radiance seen
//! from sea level as a function of the view's elevation and its azimuth from the sun (the clear
//! sky is symmetric about the sun's vertical). [`Atmosphere::radiance`] reads the second.
//!
//! Constants (SI, per metre; channels at the dominant wavelengths of the Rec.709 primaries,
//! 612 / 549 / 465 nm):
//! - Earth radius 6360 km, atmosphere top 6420 km (Bruneton & Neyret 2008).
//! - Rayleigh: vertical optical depth 0.008735 λ^−4.08 (λ in µm; Leckner 1978 as in Preetham
//!   et al. 1999's appendix: 0.100 at 550 nm, measured 0.097), exponential profile, scale
//!   height 8 km (Bruneton & Neyret).
//! - Aerosol: optical depth at 550 nm from the turbidity T as in Preetham's appendix (Ångström
//!   β λ^−1.3, β = 0.04608 T − 0.04586: 0.15 at T 2.5, 0.91 at T 10), spread over the channels
//!   with the open ocean's Ångström exponent 0.6 (sea salt's coarse particles: the Maritime
//!   Aerosol Network measures 0.3-0.7 over the open sea, Smirnov et al. 2011; Preetham's 1.3 is
//!   continental haze's and reddened the sun and the hazy horizon), scale height 1.2 km, single-
//!   scattering albedo 0.9 (Hillaire 2020: 3.996 / 4.40 per Mm) and Cornette-Shanks phase with
//!   g = 0.72 (AERONET's oceanic sites: asymmetry 0.68-0.75 over the visible, Dubovik et al.
//!   2002; Bruneton's 0.76 and Hillaire's 0.8 are continental).
//! - Ozone: absorption (0.650, 1.881, 0.085) per Mm at its peak (Hillaire 2020, given at 680 /
//!   550 / 440 nm and used for our three channels as they are), a tent 30 km wide around 25 km.
//! - The sun above the atmosphere: 127.5 klux (IES), the chromaticity of a 5778 K black body.
//!
//! Multiple scattering is approximated: each point also scatters an isotropic light field made
//! of the sunlight the air above it has scattered out of the beam (what the direct beam lost on
//! its way down, 1 − T, is not gone but diffuse: bluish where Rayleigh took it, grey where the
//! aerosol did), a share `MULTIPLE_SCATTERING` of it (after Bird & Hulstrom 1981's diffuse
//! irradiance: half of Rayleigh's loss and 0.84 of the aerosol's go down). Without it a hazy
//! sky turns orange (single scattering by reddened sunlight) where real haze is white. A model,
//! not a measurement: its clear midday sky sits within the range of measured clear skies
//! (tests), and its colours follow from the coefficients, not a fit.

use glam::{Vec2, Vec3};

use super::colour::{xyy_to_rgb, SUN_CHROMATICITY};

/// Earth's radius (m).
pub const EARTH_RADIUS: f32 = 6_360e3;
/// Radius of the atmosphere's top (m).
pub const TOP_RADIUS: f32 = 6_420e3;
/// Wavelength (µm) standing for each channel: the Rec.709 primaries' dominant wavelengths.
pub const CHANNEL_WAVELENGTH_UM: [f32; 3] = [0.612, 0.549, 0.465];
/// Rayleigh vertical optical depth `[scale, exponent]`: scale · λ^−exponent (λ in µm).
const RAYLEIGH_DEPTH: [f32; 2] = [0.008735, 4.08];
/// Rayleigh scale height (m).
const RAYLEIGH_HEIGHT: f32 = 8_000.0;
/// Ångström β = slope · T + offset of the turbidity T (Preetham's appendix).
const ANGSTROM_BETA: [f32; 2] = [0.046_083_66, -0.045_860_26];
/// Ångström wavelength exponent of Preetham's turbidity (to its depth at 550 nm)...
const ANGSTROM_ALPHA: f32 = 1.3;
/// ...and of the open ocean's aerosol (from 550 nm to each channel).
const MARITIME_ALPHA: f32 = 0.6;
/// Aerosol scale height (m).
const MIE_HEIGHT: f32 = 1_200.0;
/// Aerosol single-scattering albedo.
const MIE_ALBEDO: f32 = 0.9;
/// Aerosol phase asymmetry (Cornette-Shanks g).
const MIE_G: f32 = 0.72;
/// Ozone absorption at its peak (1/m).
const OZONE_ABSORPTION: Vec3 = Vec3::new(0.650e-6, 1.881e-6, 0.085e-6);
/// Ozone layer centre and half-width (m).
const OZONE_CENTRE: f32 = 25_000.0;
const OZONE_HALF_WIDTH: f32 = 15_000.0;
/// Sun illuminance above the atmosphere at normal incidence (klux; IES: 127.5).
pub const SOLAR_ILLUMINANCE_KLUX: f32 = 127.5;
/// Share of the light scattered out of the sun's beam above a point that comes down to it as
/// diffuse light: Bird & Hulstrom's 0.5 (Rayleigh) to 0.84 (aerosol) downward shares, taken as
/// one value; it lights the point as a radiance E_d / π from the upper hemisphere and nothing
/// from the lower (the sea returns a few %), i.e. E_d / (2π) averaged over the sphere. An
/// assumption, stated.
const MULTIPLE_SCATTERING: f32 = 0.7;

/// Transmittance table: heights × cosines of the zenith angle.
const T_HEIGHTS: usize = 32;
const T_COSINES: usize = 128;
/// Sky-view table: view elevations (square-root spaced from the horizon) × azimuths from the
/// sun (square-root spaced from it, 0 to π).
const VIEW_ELEVATIONS: usize = 64;
const VIEW_AZIMUTHS: usize = 96;
/// Integration steps along a view ray and toward space.
const VIEW_STEPS: usize = 48;
const TRANSMITTANCE_STEPS: usize = 40;

/// Scattering and extinction coefficients at sea level (1/m) for one turbidity.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Medium {
    rayleigh: Vec3,
    mie_scattering: Vec3,
    mie_extinction: Vec3,
}

impl Medium {
    fn new(turbidity: f32) -> Self {
        let beta = ANGSTROM_BETA[0] * turbidity + ANGSTROM_BETA[1];
        let per = |f: &dyn Fn(f32) -> f32| Vec3::from_array(CHANNEL_WAVELENGTH_UM.map(f));
        let rayleigh = per(&|l| RAYLEIGH_DEPTH[0] * l.powf(-RAYLEIGH_DEPTH[1]) / RAYLEIGH_HEIGHT);
        let depth_550 = beta * 0.55f32.powf(-ANGSTROM_ALPHA);
        let mie_extinction = per(&|l| depth_550 * (l / 0.55).powf(-MARITIME_ALPHA) / MIE_HEIGHT);
        Self {
            rayleigh,
            mie_scattering: mie_extinction * MIE_ALBEDO,
            mie_extinction,
        }
    }

    /// (Rayleigh density, Mie density, extinction) at height `h` (m).
    fn at(&self, h: f32) -> (f32, f32, Vec3) {
        let h = h.max(0.0);
        let r = (-h / RAYLEIGH_HEIGHT).exp();
        let m = (-h / MIE_HEIGHT).exp();
        let o = (1.0 - (h - OZONE_CENTRE).abs() / OZONE_HALF_WIDTH).max(0.0);
        (
            r,
            m,
            self.rayleigh * r + self.mie_extinction * m + OZONE_ABSORPTION * o,
        )
    }
}

/// The clear sky for one sun and turbidity, tabulated.
#[derive(Clone, Debug)]
pub struct Atmosphere {
    medium: Medium,
    sun: Vec3,
    /// Sun illuminance above the atmosphere (klux, linear sRGB).
    solar: Vec3,
    /// Transmittance to space, [height][cosine].
    transmittance: Vec<Vec3>,
    /// Sky radiance (kcd/m²) seen from sea level, [elevation][azimuth from the sun].
    view: Vec<Vec3>,
}

impl Atmosphere {
    /// Tabulates the sky for the unit `sun` direction and `turbidity` (meant to be in
    /// [`super::TURBIDITY_RANGE`]).
    pub fn new(sun: Vec3, turbidity: f32) -> Self {
        let [x, y] = SUN_CHROMATICITY;
        let mut atmosphere = Self {
            medium: Medium::new(turbidity),
            sun,
            solar: xyy_to_rgb(x, y, 1.0) * SOLAR_ILLUMINANCE_KLUX,
            transmittance: Vec::with_capacity(T_HEIGHTS * T_COSINES),
            view: Vec::with_capacity(VIEW_ELEVATIONS * VIEW_AZIMUTHS),
        };
        for i in 0..T_HEIGHTS {
            let h = table_height(i as f32 / (T_HEIGHTS - 1) as f32);
            for j in 0..T_COSINES {
                let mu = table_cosine(j as f32 / (T_COSINES - 1) as f32);
                let t = atmosphere.march_transmittance(h, mu);
                atmosphere.transmittance.push(t);
            }
        }
        for i in 0..VIEW_ELEVATIONS {
            let v = i as f32 / (VIEW_ELEVATIONS - 1) as f32;
            let sin_e = v * v;
            let cos_e = (1.0 - sin_e * sin_e).max(0.0).sqrt();
            for j in 0..VIEW_AZIMUTHS {
                let u = j as f32 / (VIEW_AZIMUTHS - 1) as f32;
                let azimuth = std::f32::consts::PI * u * u;
                let d = view_direction(sun, cos_e, sin_e, azimuth);
                let l = atmosphere.march_view(d);
                atmosphere.view.push(l);
            }
        }
        atmosphere
    }

    /// Sun illuminance above the atmosphere at normal incidence (klux).
    pub fn solar_illuminance(&self) -> Vec3 {
        self.solar
    }

    /// The air's single-scattering albedo at `height` (m) per channel: the share of what it
    /// takes out of a ray that it scatters (the aerosol absorbs a tenth of its share).
    pub fn scattering_albedo(&self, height: f32) -> Vec3 {
        let (r, m, extinction) = self.medium.at(height);
        (self.medium.rayleigh * r + self.medium.mie_scattering * m) / extinction
    }

    /// The share of diffuse light sent up from `height` (m) that the air above returns down
    /// (its spherical albedo, per channel): for a thin layer about its Rayleigh optical depth
    /// (half scattered back, over a diffuse path twice the vertical) and a sixth of its aerosol
    /// scattering depth (aerosol scatters mostly forward). What makes light trapped between a
    /// cloud deck and the sky bluer.
    pub fn spherical_albedo(&self, height: f32) -> Vec3 {
        let r = (-height / RAYLEIGH_HEIGHT).exp() * RAYLEIGH_HEIGHT;
        let m = (-height / MIE_HEIGHT).exp() * MIE_HEIGHT;
        (self.medium.rayleigh * r + self.medium.mie_scattering * (m / 6.0)).min(Vec3::splat(0.5))
    }

    /// Transmittance from height `h` (m) along a ray of zenith cosine `mu` to space; 0 where
    /// the ray meets the ground.
    pub fn transmittance(&self, h: f32, mu: f32) -> Vec3 {
        let r = EARTH_RADIUS + h.max(0.0);
        if hits_ground(r, mu) {
            return Vec3::ZERO;
        }
        let a = inverse_table_height(h) * (T_HEIGHTS - 1) as f32;
        let b = inverse_table_cosine(mu) * (T_COSINES - 1) as f32;
        bilinear(&self.transmittance, T_COSINES, a, b)
    }

    /// The clear sky's radiance (kcd/m², linear sRGB) seen from sea level along unit `d`; below
    /// the horizon, the horizon's at the same azimuth.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let sin_e = d.y.clamp(0.0, 1.0);
        let v = sin_e.sqrt();
        let horizontal = Vec2::new(d.x, d.z);
        let sun_h = Vec2::new(self.sun.x, self.sun.z);
        let azimuth = match (horizontal.try_normalize(), sun_h.try_normalize()) {
            (Some(a), Some(b)) => a.dot(b).clamp(-1.0, 1.0).acos(),
            _ => 0.0,
        };
        let u = (azimuth / std::f32::consts::PI).sqrt();
        bilinear(
            &self.view,
            VIEW_AZIMUTHS,
            v * (VIEW_ELEVATIONS - 1) as f32,
            u * (VIEW_AZIMUTHS - 1) as f32,
        )
    }

    /// Whether the sun (zenith cosine `mu_sun` at radius `r`) is above that point's horizon.
    fn sun_visible(&self, r: f32, mu_sun: f32) -> bool {
        !hits_ground(r, mu_sun)
    }

    /// Transmittance integrated numerically from height `h` along zenith cosine `mu`, in steps
    /// growing quadratically (the dense air near the sea in short ones).
    fn march_transmittance(&self, h: f32, mu: f32) -> Vec3 {
        let r = EARTH_RADIUS + h;
        if hits_ground(r, mu) {
            return Vec3::ZERO;
        }
        let length = distance_to_top(r, mu);
        let mut depth = Vec3::ZERO;
        let mut previous = 0.0;
        for i in 0..TRANSMITTANCE_STEPS {
            let x = (i as f32 + 1.0) / TRANSMITTANCE_STEPS as f32;
            let t = length * x * x;
            let mid = 0.5 * (previous + t);
            let hh = (r * r + mid * mid + 2.0 * r * mu * mid).sqrt() - EARTH_RADIUS;
            depth += self.medium.at(hh).2 * (t - previous);
            previous = t;
        }
        (-depth).exp()
    }

    /// Single scattering (plus the isotropic multiple-scattering share) along unit `d` from
    /// sea level to space.
    fn march_view(&self, d: Vec3) -> Vec3 {
        let mu = d.y.max(0.0);
        let length = distance_to_top(EARTH_RADIUS, mu);
        let nu = d.dot(self.sun);
        let rayleigh_phase = 3.0 / (16.0 * std::f32::consts::PI) * (1.0 + nu * nu);
        let mie_phase = cornette_shanks(nu, MIE_G);
        let iso = 1.0 / (2.0 * std::f32::consts::PI);
        let mut throughput = Vec3::ONE;
        let mut sum = Vec3::ZERO;
        let mut previous = 0.0;
        for i in 0..VIEW_STEPS {
            // Quadratic spacing: the dense air near the sea gets the short steps.
            let x = (i as f32 + 1.0) / VIEW_STEPS as f32;
            let t = length * x * x;
            let dt = t - previous;
            let mid = previous + 0.5 * dt;
            previous = t;
            let p = Vec3::new(0.0, EARTH_RADIUS, 0.0) + d * mid;
            let r = p.length();
            let (rd, md, extinction) = self.medium.at(r - EARTH_RADIUS);
            let mu_sun = p.dot(self.sun) / r;
            let sun = self.transmittance(r - EARTH_RADIUS, mu_sun);
            let step = (-extinction * dt).exp();
            let rayleigh = self.medium.rayleigh * rd;
            let mie = self.medium.mie_scattering * md;
            let single = rayleigh * rayleigh_phase + mie * mie_phase;
            // The diffuse field: what the beam lost above this point per unit of horizontal area
            // (its cosine), where the sun is up there.
            let lost = if self.sun_visible(r, mu_sun) {
                (Vec3::ONE - sun) * mu_sun.max(0.0)
            } else {
                Vec3::ZERO
            };
            let multiple = (rayleigh + mie) * lost * (MULTIPLE_SCATTERING * iso);
            // Light scattered in this step, attenuated through it (exact for a constant step).
            let source = self.solar * (sun * single + multiple);
            let scattered = source * (Vec3::ONE - step) / extinction.max(Vec3::splat(1e-12));
            sum += throughput * scattered;
            throughput *= step;
        }
        sum
    }
}

/// Whether a ray from radius `r` with zenith cosine `mu` meets the ground.
fn hits_ground(r: f32, mu: f32) -> bool {
    mu < 0.0 && r * r * (mu * mu - 1.0) + EARTH_RADIUS * EARTH_RADIUS >= 0.0
}

/// Distance from radius `r` along zenith cosine `mu` to the atmosphere's top.
fn distance_to_top(r: f32, mu: f32) -> f32 {
    let disc = r * r * (mu * mu - 1.0) + TOP_RADIUS * TOP_RADIUS;
    (-r * mu + disc.max(0.0).sqrt()).max(0.0)
}

/// The direction at elevation (cos, sin) and `azimuth` (rad) from the sun's azimuth.
fn view_direction(sun: Vec3, cos_e: f32, sin_e: f32, azimuth: f32) -> Vec3 {
    let forward = Vec2::new(sun.x, sun.z).try_normalize().unwrap_or(Vec2::X);
    let (s, c) = azimuth.sin_cos();
    let h = Vec2::new(forward.x * c - forward.y * s, forward.x * s + forward.y * c);
    Vec3::new(h.x * cos_e, sin_e, h.y * cos_e)
}

/// Cornette-Shanks phase function (1/sr) of scattering-angle cosine `nu`.
fn cornette_shanks(nu: f32, g: f32) -> f32 {
    let g2 = g * g;
    3.0 * (1.0 - g2) * (1.0 + nu * nu)
        / (8.0 * std::f32::consts::PI * (2.0 + g2) * (1.0 + g2 - 2.0 * g * nu).powf(1.5))
}

/// The transmittance table's height at coordinate `x` in [0, 1] (square-root spaced).
fn table_height(x: f32) -> f32 {
    x * x * (TOP_RADIUS - EARTH_RADIUS)
}

fn inverse_table_height(h: f32) -> f32 {
    (h / (TOP_RADIUS - EARTH_RADIUS)).clamp(0.0, 1.0).sqrt()
}

/// The transmittance table's zenith cosine at coordinate `x` in [0, 1]: −0.2..1, the grazing
/// cosines (where the optical depth changes fastest) finest.
fn table_cosine(x: f32) -> f32 {
    let s = 2.0 * x - 1.0;
    let c = s.signum() * s * s;
    (c * 0.6 + 0.4).clamp(-0.2, 1.0)
}

fn inverse_table_cosine(mu: f32) -> f32 {
    let c = ((mu - 0.4) / 0.6).clamp(-1.0, 1.0);
    0.5 * (c.signum() * c.abs().sqrt() + 1.0)
}

/// Bilinear lookup at fractional (row `a`, column `b`) of a row-major table `columns` wide.
fn bilinear(table: &[Vec3], columns: usize, a: f32, b: f32) -> Vec3 {
    let rows = table.len() / columns;
    let a = a.clamp(0.0, (rows - 1) as f32);
    let b = b.clamp(0.0, (columns - 1) as f32);
    let (i, j) = (a.floor() as usize, b.floor() as usize);
    let (i1, j1) = ((i + 1).min(rows - 1), (j + 1).min(columns - 1));
    let (fa, fb) = (a - i as f32, b - j as f32);
    let at = |r: usize, c: usize| table[r * columns + c];
    let top = at(i, j).lerp(at(i, j1), fb);
    let bottom = at(i1, j).lerp(at(i1, j1), fb);
    top.lerp(bottom, fa)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sun_at(elevation_deg: f32) -> Vec3 {
        let (s, c) = elevation_deg.to_radians().sin_cos();
        Vec3::new(c, s, 0.0)
    }

    #[test]
    fn the_tables_invert() {
        for x in [0.0, 0.1, 0.5, 0.77, 1.0] {
            assert!((inverse_table_height(table_height(x)) - x).abs() < 1e-5);
            assert!(
                (inverse_table_cosine(table_cosine(x)) - x).abs() < 1e-4,
                "{x}"
            );
        }
    }

    #[test]
    fn vertical_optical_depth_is_rayleigh_aerosol_and_ozone() {
        // Straight up from the sea, T = 2.5: τ = 0.0997 (Rayleigh) + 0.150 (aerosol) + ozone
        // 0.028 at 549 nm.
        let a = Atmosphere::new(sun_at(60.0), 2.5);
        let tau = -a.transmittance(0.0, 1.0).y.ln();
        let aerosol = 0.069 * 0.55f32.powf(-1.3) * (0.549f32 / 0.55).powf(-0.6);
        let expected = 0.008735 * 0.549f32.powf(-4.08) + aerosol + 0.0282;
        assert!((tau / expected - 1.0).abs() < 0.03, "{tau} vs {expected}");
        // Toward the horizon the path is ~38 air masses of Rayleigh.
        assert!(a.transmittance(0.0, 0.0).y < 0.01);
        assert_eq!(a.transmittance(0.0, -0.1), Vec3::ZERO);
    }
}
