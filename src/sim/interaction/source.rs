//! What disturbs the layer: a pressure patch (a body's weight on the water), an impulse (the
//! water pushed down by an entry) and foam, each over one footprint.
//!
//! # Footprint
//! A volume at depth d moves the surface above it as the Poisson kernel
//! d/(2π·(r² + d²)^{3/2}), whose transform is e^{−k·d}: a submerged body makes long waves
//! well and short ones poorly, and its source has no spectral zeros (a flat disc's would
//! silence some wavelengths, the Kelvin cusp's among them). The kernel's depth is
//! d_e = √(d² + (R/2)²) for a body of radius R whose volume's centroid is d deep, widened to
//! 1.5 cells; it is tapered by (1 − u²)² to zero at ρ = 4·d_e (u = r/ρ) and normalized.

/// One disturbance of the layer for one step. Plain data: `physics` makes one per floating
/// body (and the app one per hand in the water).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WaveSource {
    /// Centre, world x (m).
    pub x: f32,
    /// Centre, world z (m).
    pub z: f32,
    /// Horizontal radius of the body (m).
    pub radius: f32,
    /// Depth of the centroid of the displaced volume below the surface (m).
    pub depth: f32,
    /// Volume the body displaces now (m³): the pressure head P over the footprint integrates
    /// to it, so a body at rest sits in a hollow of its own volume.
    pub volume: f32,
    /// Velocity potential pushed into the water this step at the footprint's centre (m²/s):
    /// about the entry speed times the radius for a body plunging in (positive = down).
    pub impulse: f32,
    /// Foam added at the footprint's centre this step (0..1).
    pub foam: f32,
}

impl WaveSource {
    /// A sphere of `diameter` (m) and `density` (kg/m³, below sea water's 1025) floating at
    /// rest at (x, z): its draft from the spherical cap's volume, the cap's centroid depth.
    pub fn floating_sphere(x: f32, z: f32, diameter: f32, density: f32) -> Self {
        let r = 0.5 * diameter as f64;
        let volume = (density as f64 / 1025.0).clamp(0.0, 1.0)
            * std::f64::consts::PI
            * diameter.powi(3) as f64
            / 6.0;
        let cap = |h: f64| std::f64::consts::PI * h * h * (3.0 * r - h) / 3.0;
        // Bisection on the draft: the cap's volume grows monotonically with it.
        let (mut lo, mut hi) = (0.0, 2.0 * r);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if cap(mid) < volume {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let h = 0.5 * (lo + hi);
        // The cap's centroid lies 3(2R − h)²/(4(3R − h)) from the sphere's centre, whose
        // waterline is R − h above it.
        let depth = if h > 0.0 {
            3.0 * (2.0 * r - h).powi(2) / (4.0 * (3.0 * r - h)) - (r - h)
        } else {
            0.0
        };
        Self {
            x,
            z,
            radius: r as f32,
            depth: depth as f32,
            volume: volume as f32,
            impulse: 0.0,
            foam: 0.0,
        }
    }

    /// Whether every field is finite and the radius and volume are not negative: a source
    /// that is not is skipped by the layer (a lost body must not poison the sea).
    pub fn is_valid(&self) -> bool {
        [
            self.x,
            self.z,
            self.radius,
            self.depth,
            self.volume,
            self.impulse,
            self.foam,
        ]
        .iter()
        .all(|v| v.is_finite())
            && self.radius >= 0.0
            && self.depth >= 0.0
            && self.volume >= 0.0
    }

    /// The footprint's reach ρ = 4·d_e (m) with d_e at least `min_depth` (see the module doc).
    pub fn reach(&self, min_depth: f32) -> f32 {
        4.0 * (self.depth * self.depth + 0.25 * self.radius * self.radius)
            .sqrt()
            .max(min_depth)
    }

    /// The pressure head (m) this source puts at world (x, z) (`min_depth` as in
    /// [`WaveSource::reach`]): the hollow it holds at rest. A body adds its own back to the
    /// heights it reads.
    pub fn head_at(&self, x: f32, z: f32, min_depth: f32) -> f32 {
        let reach = self.reach(min_depth);
        let d = ((x - self.x).powi(2) + (z - self.z).powi(2)).sqrt();
        self.volume * footprint(d / reach) / (FOOTPRINT_AREA * reach * reach)
    }
}

/// ∫ footprint over the plane for a unit reach: 2π∫₀¹ footprint(u)·u du.
pub const FOOTPRINT_AREA: f32 = 0.208_241_8;

/// The tapered Poisson kernel (1 + 16u²)^{−3/2}·(1 − u²)² for u = r/ρ < 1, else 0; 1 at the
/// centre.
#[inline]
pub fn footprint(u: f32) -> f32 {
    if u < 1.0 {
        let q = 1.0 + 16.0 * u * u;
        let t = 1.0 - u * u;
        t * t / (q * q.sqrt())
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A half-dense sphere floats half under: draft R, centroid 3R/8 deep.
    #[test]
    fn a_half_dense_sphere_floats_half_under() {
        let s = WaveSource::floating_sphere(0.0, 0.0, 1.0, 512.5);
        let half = std::f32::consts::PI / 12.0;
        assert!((s.volume - half).abs() < 1e-5, "{}", s.volume);
        assert!((s.depth - 0.1875).abs() < 1e-4, "{}", s.depth);
    }

    /// [`FOOTPRINT_AREA`] is the footprint's integral (midpoint rule on 10⁵ rings).
    #[test]
    fn footprint_area_is_its_integral() {
        let n = 100_000;
        let sum: f64 = (0..n)
            .map(|i| {
                let u = (i as f64 + 0.5) / n as f64;
                footprint(u as f32) as f64 * u / n as f64
            })
            .sum();
        let area = 2.0 * std::f64::consts::PI * sum;
        assert!((area as f32 / FOOTPRINT_AREA - 1.0).abs() < 1e-4, "{area}");
    }
}
