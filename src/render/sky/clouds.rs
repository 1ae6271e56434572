//! A cloud layer for the baked sky (`--clouds 0..1`, clear to overcast): a horizontal slab at
//! [`CLOUD_BASE`] whose optical thickness varies over a fractal pattern, thresholded so that
//! a share `coverage` of the sky is cloud (from 0.9 up, one unbroken deck).
//!
//! Its light, per view ray that meets it (all grey: droplets scatter every wavelength alike):
//! - the sun's and the clear sky's light diffusely transmitted through the slab, two-stream
//!   (Bohren 1987: T = 1 / (1 + ¾ (1 − g) τ) for a conservative slab, g = 0.85 for droplets),
//!   less the share that passes unscattered (the sun seen through it, the sky behind);
//! - forward scattering of the sun by the thin edges (single scattering, Henyey-Greenstein);
//! - the air in front of it: lit by the sun where the clouds let it through, by the deck's
//!   diffuse light under it, attenuated by the clear atmosphere.
//!
//! An overcast deck of optical thickness 30 (stratus: 10-40) lets through ~17 % of the light;
//! its zenith luminance at a 35° sun is ~6 kcd/m² (measured overcast skies: 2-8), its horizon
//! about half that (the CIE overcast sky: a third).

use glam::{Vec2, Vec3};

use super::atmosphere::{Atmosphere, EARTH_RADIUS};

/// Height of the layer (m): a stratocumulus / stratus base.
pub const CLOUD_BASE: f32 = 1_500.0;
/// Diffuse albedo of the sea under the deck (Payne 1972: 0.06 under overcast skies).
const SEA_ALBEDO: f32 = 0.06;
/// Height (m) whose air stands for the air under the deck.
const AIR_BELOW: f32 = 500.0;
/// Vertical optical thickness of the densest cloud.
const FULL_THICKNESS: f32 = 30.0;
/// Asymmetry of cloud droplets' scattering.
const DROPLET_G: f32 = 0.85;
/// Forward-scattering lobe of the thin edges (a broader g than the droplets' own: several
/// scatterings widen it).
const EDGE_G: f32 = 0.6;
/// Size (m) of the largest cloud cells of the pattern.
const CELL: f32 = 4_000.0;
/// Octaves of the pattern.
const OCTAVES: usize = 5;
/// Half-width of the threshold's soft edge (pattern units).
const EDGE: f32 = 0.12;
/// Coverage from which the layer is one unbroken deck.
const DECK_FROM: f32 = 0.9;

/// The layer for one coverage and one atmosphere's light.
#[derive(Clone, Debug)]
pub struct CloudLayer {
    coverage: f32,
    /// The pattern value below which there is no cloud.
    threshold: f32,
    /// How far the deck is closed (0 below [`DECK_FROM`], 1 at full cover).
    deck: f32,
    sun: Vec3,
    /// Sun illuminance at the layer, normal incidence, and its cosine to the vertical.
    sun_at_layer: Vec3,
    mu_sun: f32,
    /// Illuminance of the clear sky on the layer's top (klux, horizontal).
    sky_on_layer: Vec3,
    /// The air's spherical albedo above the layer (per channel).
    air_albedo: Vec3,
    /// What returns light sent down from the deck's underside: the sea and the air under it.
    below_albedo: Vec3,
    /// The scattering albedo of the air under the deck.
    air_scattering: Vec3,
    /// The mean light under the deck (kcd/m²): what lights the air below it.
    ambient: Vec3,
}

impl CloudLayer {
    /// The layer covering a share `coverage` in [0, 1] of the sky, lit by `atmosphere`'s sun
    /// (unit direction `sun`) and by its clear sky of horizontal illuminance `clear_sky`.
    pub fn new(coverage: f32, sun: Vec3, atmosphere: &Atmosphere, clear_sky: Vec3) -> Self {
        let coverage = coverage.clamp(0.0, 1.0);
        let mu_sun = sun.y;
        let sun_at_layer =
            atmosphere.solar_illuminance() * atmosphere.transmittance(CLOUD_BASE, mu_sun);
        let deck = ((coverage - DECK_FROM) / (1.0 - DECK_FROM)).clamp(0.0, 1.0);
        let threshold = threshold_for(coverage);
        let mut layer = Self {
            coverage,
            threshold,
            deck,
            sun,
            sun_at_layer,
            mu_sun,
            sky_on_layer: clear_sky,
            air_albedo: atmosphere.spherical_albedo(CLOUD_BASE),
            below_albedo: Vec3::splat(SEA_ALBEDO) + atmosphere.spherical_albedo(0.0)
                - atmosphere.spherical_albedo(CLOUD_BASE),
            air_scattering: atmosphere.scattering_albedo(AIR_BELOW),
            ambient: Vec3::ZERO,
        };
        let tau = FULL_THICKNESS * layer.mean_density();
        layer.ambient = 0.5 * coverage * layer.diffuse(tau);
        layer
    }

    /// The layer's radiance over the clear sky along unit `d` (elevation ≥ 0): `clear` is the
    /// clear sky's radiance there (the atmosphere's, whole path), `atmosphere` gives the air in
    /// front. Rays below the horizon read the horizon.
    pub fn over(&self, d: Vec3, clear: Vec3, atmosphere: &Atmosphere) -> Vec3 {
        if self.coverage <= 0.0 {
            return clear;
        }
        let d = Vec3::new(d.x, d.y.max(0.0), d.z).normalize_or(Vec3::X);
        let (distance, point) = hit(d);
        let density = self.density(point);
        let mu = d.y.max(0.02);
        let tau_v = FULL_THICKNESS * density;
        let tau = tau_v / mu;
        // The air in front: the share of the clear path's light scattered before the cloud,
        // under a sun the clouds let through, plus the deck's light scattered by that air.
        let front = air_transmittance(atmosphere, d, distance);
        let whole = atmosphere.transmittance(0.0, d.y.max(0.0));
        let before = (Vec3::ONE - front) / (Vec3::ONE - whole).max(Vec3::splat(1e-4));
        let lit = 1.0 - self.coverage * (1.0 - (-FULL_THICKNESS / self.mu_sun.max(0.05)).exp());
        let air = clear * before.min(Vec3::ONE) * lit
            + self.ambient * self.air_scattering * (Vec3::ONE - front);
        // The cloud: diffuse light through it, the bright edges toward the sun, and the clear
        // sky above it seen through it.
        let nu = d.dot(self.sun);
        let edge = self.sun_at_layer * henyey_greenstein(nu, EDGE_G) * tau * (-tau).exp();
        let behind = clear * (Vec3::ONE - before.min(Vec3::ONE)) * (-tau).exp();
        // A thick cloud's base is brighter overhead than toward the horizon: diffusion's
        // transmitted radiance goes as 1 + 3/2 μ (Eddington), (1 + 1.5 μ) / 2 of the mean
        // (its cosine-weighted mean is 1: the light through the deck is kept); a thin one
        // transmits as it is lit.
        let limb = 1.0 + (-tau_v).exp_m1().abs() * (0.5 + 0.75 * d.y.max(0.0) - 1.0);
        let cloud = self.diffuse(tau_v) * limb + edge * self.mu_sun.max(0.0).sqrt() + behind;
        air + front * cloud
    }

    /// The transmittance of the direct sun through the layer (its disc behind the clouds).
    pub fn sun_transmittance(&self) -> f32 {
        if self.coverage <= 0.0 || self.mu_sun <= 0.0 {
            return 1.0;
        }
        let (_, point) = hit(self.sun);
        (-FULL_THICKNESS * self.density(point) / self.mu_sun.max(0.02)).exp()
    }

    /// Light (kcd/m²) leaving the underside of cloud of vertical optical thickness `tau`:
    /// the sun's and the clear sky's diffusely transmitted share, less the unscattered one,
    /// with the light trapped between the cloud and what returns it (1 / (1 − A S), A the
    /// cloud's albedo, S the spherical albedo of the air above its top, and of the sea and the
    /// air under its base: bluer, as Rayleigh returns the blue).
    fn diffuse(&self, tau: f32) -> Vec3 {
        let t = 1.0 / (1.0 + 0.75 * (1.0 - DROPLET_G) * tau);
        let sun = (t - (-tau / self.mu_sun.max(0.05)).exp()).max(0.0);
        let sky = (t - (-2.0 * tau).exp()).max(0.0);
        let horizontal_sun = self.sun_at_layer * self.mu_sun.max(0.0);
        let albedo = 1.0 - t;
        let trapped = Vec3::ONE / (Vec3::ONE - albedo * self.air_albedo);
        let under = Vec3::ONE / (Vec3::ONE - albedo * self.below_albedo);
        (horizontal_sun * sun + self.sky_on_layer * sky) * trapped * under / std::f32::consts::PI
    }

    /// The cloud's share of the full thickness at point `p` (m) of the layer, in [0, 1].
    fn density(&self, p: Vec2) -> f32 {
        let n = pattern(p / CELL);
        let broken = smoothstep(self.threshold - EDGE, self.threshold + EDGE, n);
        broken + (1.0 - broken) * self.deck
    }

    /// The mean density over the pattern (sampled).
    fn mean_density(&self) -> f32 {
        let mut sum = 0.0;
        for i in 0..16 {
            for j in 0..16 {
                sum += self.density(Vec2::new(i as f32, j as f32) * (CELL * 0.37));
            }
        }
        sum / 256.0
    }
}

/// The pattern value a share `coverage` of the layer exceeds: the (1 − coverage) quantile of
/// the pattern over a 64 × 64 sample of it (spaced off its lattice).
fn threshold_for(coverage: f32) -> f32 {
    let mut values: Vec<f32> = (0..64 * 64)
        .map(|i| pattern(Vec2::new((i % 64) as f32, (i / 64) as f32) * 0.731 + 0.13))
        .collect();
    values.sort_by(f32::total_cmp);
    let at = ((1.0 - coverage) * (values.len() - 1) as f32).round() as usize;
    values[at.min(values.len() - 1)]
}

/// Where unit `d` (elevation ≥ 0) from the sea meets the layer: distance (m) and the point's
/// horizontal position (m) relative to the viewer.
fn hit(d: Vec3) -> (f32, Vec2) {
    let r = EARTH_RADIUS;
    let top = EARTH_RADIUS + CLOUD_BASE;
    let mu = d.y;
    let t = -r * mu + (r * r * (mu * mu - 1.0) + top * top).max(0.0).sqrt();
    (t, Vec2::new(d.x, d.z) * t)
}

/// The clear atmosphere's transmittance over the first `distance` m along `d` from the sea: the
/// ratio of the transmittances to space from its two ends.
fn air_transmittance(atmosphere: &Atmosphere, d: Vec3, distance: f32) -> Vec3 {
    let p = Vec3::new(0.0, EARTH_RADIUS, 0.0) + d * distance;
    let r = p.length();
    let whole = atmosphere.transmittance(0.0, d.y);
    let rest = atmosphere.transmittance(r - EARTH_RADIUS, p.dot(d) / r);
    (whole / rest.max(Vec3::splat(1e-6))).min(Vec3::ONE)
}

/// Henyey-Greenstein phase (1/sr) of scattering-angle cosine `nu`.
fn henyey_greenstein(nu: f32, g: f32) -> f32 {
    let g2 = g * g;
    (1.0 - g2) / (4.0 * std::f32::consts::PI * (1.0 + g2 - 2.0 * g * nu).powf(1.5))
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Fractal value noise in [0, 1] (octaves of lattice noise, each turned and halved).
fn pattern(p: Vec2) -> f32 {
    let (mut sum, mut weight, mut amplitude) = (0.0, 0.0, 1.0);
    let mut q = p;
    let (s, c) = 0.6f32.sin_cos();
    for octave in 0..OCTAVES {
        sum += amplitude * value_noise(q, octave as u32);
        weight += amplitude;
        amplitude *= 0.5;
        q = Vec2::new(c * q.x - s * q.y, s * q.x + c * q.y) * 2.03;
    }
    sum / weight
}

/// Smoothly interpolated lattice noise in [0, 1].
fn value_noise(p: Vec2, seed: u32) -> f32 {
    let i = p.floor();
    let f = p - i;
    let u = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x, y) = (i.x as i32, i.y as i32);
    let h = |dx: i32, dy: i32| lattice(x.wrapping_add(dx), y.wrapping_add(dy), seed);
    let a = h(0, 0) + (h(1, 0) - h(0, 0)) * u.x;
    let b = h(0, 1) + (h(1, 1) - h(0, 1)) * u.x;
    a + (b - a) * u.y
}

/// A hash of a lattice point to [0, 1].
fn lattice(x: i32, y: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^= h >> 15;
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_is_the_share_of_sky_covered() {
        let atmosphere = Atmosphere::new(Vec3::new(0.8, 0.6, 0.0), 2.5);
        for c in [0.2f32, 0.5, 0.8] {
            let layer = CloudLayer::new(c, Vec3::new(0.8, 0.6, 0.0), &atmosphere, Vec3::ONE);
            let mut covered = 0;
            for i in 0..100 {
                for j in 0..100 {
                    let p = Vec2::new(i as f32, j as f32) * 531.0;
                    covered += (layer.density(p) > 0.5) as u32;
                }
            }
            let share = covered as f32 / 1e4;
            println!("coverage {c}: {share:.3} of the layer cloud");
            assert!((share - c).abs() < 0.12, "{c}: {share}");
        }
    }
}
