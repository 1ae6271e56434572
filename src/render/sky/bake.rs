//! The sky's environment map: a map of the upper hemisphere, level 0 the radiance and level m
//! of M prefiltered for GGX roughness r = m / (M − 1) (α = r²), as in split-sum prefiltering
//! (normal = view = reflection). The sun disc is left out (shade it analytically); its Preetham
//! glow is in.
//!
//! Mapping (u right, v up the texture; rows stored horizon first), chosen so that the shader
//! finds a direction's texel without inverse trigonometry (issue 28: `atan2` + `asin` cost
//! ~80 FP32 operations a lookup on a mobile GPU, 2-5 lookups a pixel):
//!
//! ```text
//! u = diamond(x, z) / 4   the "diamond angle" of the horizontal direction, in [0, 1): it runs
//!                         0, 1, 2, 3 at +x, +z, −x, −z and is z/(|x| + |z|) rotated per quadrant
//!                         (monotonic in the azimuth; 1-2 columns per degree of azimuth vary 2x)
//! v = sqrt(y)             y = sin(elevation) in [0, 1]   (0 horizon, 1 zenith)
//! ```
//!
//! The square root gives the horizon, where the sky changes fastest, the finest rows. Texel
//! (col, row) of a w × h level is centred at ((col + 0.5) / w, (row + 0.5) / h); row 0 is the
//! lowest and texture coordinate t = v (Vulkan's first row is t = 0). Sizes follow Vulkan's mip
//! chain, max(1, w >> m) × max(1, h >> m), so the levels upload as mips of one image; sample
//! with u REPEAT, v CLAMP_TO_EDGE and an explicit level roughness · (M − 1). In GLSL
//! (`shaders/common.glsl`, `sky_uv`):
//!
//! ```glsl
//! // Unit direction (y up) -> env-map uv; below the horizon reads the horizon row.
//! vec2 sky_uv(vec3 d) {
//!     float s = abs(d.x) + abs(d.z);
//!     float t = s > 0.0 ? d.z / s : 0.0;                   // in [-1, 1]
//!     float q = d.x >= 0.0 ? (d.z >= 0.0 ? t : 4.0 + t)   // quadrants +x+z, +x-z
//!                          : 2.0 - t;                      // quadrants -x±z
//!     return vec2(q * 0.25, sqrt(clamp(d.y, 0.0, 1.0)));
//! }
//! // textureLod(skyEnv, sky_uv(reflect(-v, n)), roughness * float(SKY_LEVELS - 1))
//! ```
//!
//! The prefilter integrates the analytic sky (not level 0), so no level aliases: per texel
//! direction n, L_m(n) = Σ L(l_i) (n·l_i) / Σ (n·l_i) over l_i = reflect(−n, h_i), with h_i the
//! GGX-distributed half vectors of a fixed Hammersley set (Karis 2013). Directions below the
//! horizon read the horizon ([`Sky::radiance`]).

use std::f32::consts::TAU;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::Sky;

/// Hammersley samples of the GGX lobe per prefiltered texel.
pub const PREFILTER_SAMPLES: usize = 128;

/// A baked environment map: `levels[m]` holds level m's texels, row-major, row 0 at the
/// horizon, RGBA with A = 1 (linear sRGB radiance in kcd/m²).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    /// Level 0's width (texels along the azimuth).
    pub width: u32,
    /// Level 0's height (texels from horizon to zenith).
    pub height: u32,
    /// The levels, level m sized [`EnvMap::level_size`]`(m)`.
    pub levels: Vec<Vec<[f32; 4]>>,
}

impl EnvMap {
    /// An all-zero map of `levels` levels (at least 1, at most the full mip chain) of a
    /// `width` × `height` level 0 (each at least 1).
    pub fn new(width: u32, height: u32, levels: u32) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let full_chain = 32 - width.max(height).leading_zeros();
        let count = levels.clamp(1, full_chain) as usize;
        let levels = (0..count)
            .map(|m| {
                let (w, h) = mip_size(width, height, m);
                vec![[0.0; 4]; (w * h) as usize]
            })
            .collect();
        Self {
            width,
            height,
            levels,
        }
    }

    /// Level `level`'s size, Vulkan's mip rule: (max(1, width >> level), max(1, height >> level)).
    pub fn level_size(&self, level: usize) -> (u32, u32) {
        mip_size(self.width, self.height, level)
    }

    /// The GGX roughness level `level` is prefiltered for: level / (levels − 1) (0 for level 0).
    pub fn roughness(&self, level: usize) -> f32 {
        roughness(level, self.levels.len())
    }

    /// Texel (`col`, `row`) of `level` as RGB.
    pub fn texel(&self, level: usize, col: u32, row: u32) -> Vec3 {
        let (w, _) = self.level_size(level);
        let t = self.levels[level][(row * w + col) as usize];
        Vec3::new(t[0], t[1], t[2])
    }
}

/// The diamond angle of horizontal direction (`x`, `z`) (not both 0), in [0, 4): 0, 1, 2, 3
/// toward +x, +z, −x, −z, continuous and increasing with the azimuth atan2(z, x) mod 2π.
pub fn diamond(x: f32, z: f32) -> f32 {
    let s = x.abs() + z.abs();
    let t = if s > 0.0 { z / s } else { 0.0 };
    let q = if x >= 0.0 {
        if z >= 0.0 {
            t
        } else {
            4.0 + t
        }
    } else {
        2.0 - t
    };
    if q >= 4.0 {
        0.0
    } else {
        q
    }
}

/// The horizontal unit direction (x, z) of diamond angle `q` in [0, 4) (the inverse of
/// [`diamond`]).
fn from_diamond(q: f32) -> (f32, f32) {
    let q = q.rem_euclid(4.0);
    // Quadrant k's points are those of quadrant 0, (1 − f, f), turned k quarter turns.
    let k = (q.floor() as u32).min(3);
    let f = q - k as f32;
    let (x, z) = (1.0 - f, f);
    let (x, z) = match k {
        0 => (x, z),
        1 => (-z, x),
        2 => (-x, -z),
        _ => (z, -x),
    };
    let l = (x * x + z * z).sqrt();
    (x / l, z / l)
}

/// Unit direction of env-map coordinates (u, v) (see the module doc): horizontal direction of
/// diamond angle 4u, sin(elevation) = v².
pub fn direction(u: f32, v: f32) -> Vec3 {
    let (x, z) = from_diamond(4.0 * u);
    let y = (v * v).clamp(0.0, 1.0);
    let c = (1.0 - y * y).max(0.0).sqrt();
    Vec3::new(c * x, y, c * z)
}

/// Env-map coordinates of `dir` (any length > 0), the inverse of [`direction`]: u in [0, 1),
/// v in [0, 1]; below the horizon v = 0.
pub fn uv(dir: Vec3) -> (f32, f32) {
    let d = dir.normalize_or(Vec3::Y);
    let u = diamond(d.x, d.z) / 4.0;
    (if u >= 1.0 { 0.0 } else { u }, d.y.clamp(0.0, 1.0).sqrt())
}

/// Bakes `sky` into a new map: a `width` × `height` level 0 and `levels` levels in all (see
/// [`EnvMap::new`] for the clamps). 128 × 32 × 6 took ~20 ms on two busy cores (opt-level 2).
pub fn bake(sky: &Sky, width: u32, height: u32, levels: u32) -> EnvMap {
    let mut map = EnvMap::new(width, height, levels);
    bake_into(sky, &mut map);
    map
}

/// Bakes `sky` into `map`'s existing levels, in parallel over rows, allocating nothing of its
/// own: for a sun that moves while the map stays.
pub fn bake_into(sky: &Sky, map: &mut EnvMap) {
    let count = map.levels.len();
    let (width, height) = (map.width, map.height);
    for (m, level) in map.levels.iter_mut().enumerate() {
        let (w, h) = mip_size(width, height, m);
        let alpha = roughness(m, count).powi(2);
        let lobe = (m > 0).then(|| GgxLobe::new(alpha));
        level
            .par_chunks_mut(w as usize)
            .enumerate()
            .for_each(|(row, out)| {
                let v = (row as f32 + 0.5) / h as f32;
                for (col, texel) in out.iter_mut().enumerate() {
                    let n = direction((col as f32 + 0.5) / w as f32, v);
                    let rgb = match &lobe {
                        None => sky.radiance(n),
                        Some(lobe) => lobe.integrate(sky, n),
                    };
                    *texel = [rgb.x, rgb.y, rgb.z, 1.0];
                }
            });
    }
}

/// (max(1, w >> m), max(1, h >> m)).
fn mip_size(width: u32, height: u32, level: usize) -> (u32, u32) {
    let shift = level.min(31) as u32;
    ((width >> shift).max(1), (height >> shift).max(1))
}

/// Roughness of level `level` of `count`: level / (count − 1).
fn roughness(level: usize, count: usize) -> f32 {
    if count > 1 {
        level as f32 / (count - 1) as f32
    } else {
        0.0
    }
}

/// Solid angle (sr) of texel (`col`, `row`) of a `w` × `h` level: the azimuth the column
/// spans times (sin e₁ − sin e₀) = v₁² − v₀² between the row's edges.
#[cfg(test)]
fn texel_solid_angle(col: u32, row: u32, w: u32, h: u32) -> f32 {
    let azimuth = |c: u32| {
        let (x, z) = from_diamond(4.0 * c as f32 / w as f32);
        z.atan2(x).rem_euclid(TAU)
    };
    let (a0, a1) = (azimuth(col), azimuth(col + 1));
    let span = if col + 1 == w { TAU - a0 } else { a1 - a0 };
    let y = |r: u32| (r as f32 / h as f32).powi(2);
    span * (y(row + 1) - y(row))
}

/// The GGX lobe's reflected directions in the tangent frame of n (z = n), with their weight
/// n·l, for the Hammersley points that reflect above the surface.
struct GgxLobe {
    /// (l_x, l_y, l_z, n·l = l_z), only l_z > 0; `len` of them are used.
    samples: [Vec4; PREFILTER_SAMPLES],
    /// Number of valid entries in `samples`.
    len: usize,
}

impl GgxLobe {
    /// Samples h with the GGX distribution of `alpha` (importance sampling, Karis 2013):
    /// φ = 2π ξ₁, cos θ_h = sqrt((1 − ξ₂) / (1 + (α² − 1) ξ₂)); then l = 2 (n·h) h − n with
    /// n = view, so l = (2 h_z h_x, 2 h_z h_y, 2 h_z² − 1) in the tangent frame.
    fn new(alpha: f32) -> Self {
        let mut samples = [Vec4::ZERO; PREFILTER_SAMPLES];
        let mut len = 0;
        let a2 = alpha * alpha;
        for i in 0..PREFILTER_SAMPLES {
            let (xi1, xi2) = hammersley(i as u32, PREFILTER_SAMPLES as u32);
            let cos_t = ((1.0 - xi2) / (1.0 + (a2 - 1.0) * xi2)).sqrt();
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let (sp, cp) = (TAU * xi1).sin_cos();
            let h = Vec3::new(sin_t * cp, sin_t * sp, cos_t);
            let l = 2.0 * h.z * h - Vec3::Z;
            if l.z > 0.0 {
                samples[len] = l.extend(l.z);
                len += 1;
            }
        }
        Self { samples, len }
    }

    /// Σ L(l_i) (n·l_i) / Σ (n·l_i) around `n`.
    fn integrate(&self, sky: &Sky, n: Vec3) -> Vec3 {
        let (t, b) = tangent_frame(n);
        let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
        for s in &self.samples[..self.len] {
            let l = t * s.x + b * s.y + n * s.z;
            sum += sky.radiance(l) * s.w;
            weight += s.w;
        }
        sum / weight
    }
}

/// Point i of an n-point Hammersley set: (i / n, radical inverse of i in base 2).
fn hammersley(i: u32, n: u32) -> (f32, f32) {
    (
        i as f32 / n as f32,
        i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0),
    )
}

/// An orthonormal (t, b) with t × b ⟂ n, smooth over the whole upper hemisphere (Frisvad 2012
/// with y as the pole, singular only at the nadir), so neighbouring texels get nearly the same
/// sample pattern and the prefiltered map has no seams.
fn tangent_frame(n: Vec3) -> (Vec3, Vec3) {
    let a = 1.0 / (1.0 + n.y).max(1e-6);
    let t = Vec3::new(1.0 - n.x * n.x * a, -n.x, -n.x * n.z * a);
    let b = Vec3::new(-n.x * n.z * a, -n.z, 1.0 - n.z * n.z * a);
    (t, b)
}

#[cfg(test)]
mod tests {
    use super::super::{SunSky, LUMINANCE};
    use super::*;

    fn sky(elevation_deg: f32, azimuth_deg: f32) -> Sky {
        Sky::new(&SunSky {
            elevation_deg,
            azimuth_deg,
            turbidity: 2.5,
            clouds: 0.0,
        })
    }

    /// Solid-angle-weighted mean luminance and coefficient of variation of a level.
    fn stats(map: &EnvMap, level: usize) -> (f32, f32) {
        let (w, h) = map.level_size(level);
        let (mut s, mut s2, mut total) = (0.0f64, 0.0f64, 0.0f64);
        for row in 0..h {
            for col in 0..w {
                let omega = texel_solid_angle(col, row, w, h) as f64;
                let y = LUMINANCE.dot(map.texel(level, col, row)) as f64;
                s += y * omega;
                s2 += y * y * omega;
                total += omega;
            }
        }
        let mean = s / total;
        (
            mean as f32,
            ((s2 / total - mean * mean).max(0.0).sqrt() / mean) as f32,
        )
    }

    #[test]
    fn uv_and_direction_round_trip() {
        for i in 0..64 {
            for j in 0..=32 {
                let (u, v) = (i as f32 / 64.0, j as f32 / 32.0);
                let d = direction(u, v);
                assert!((d.length() - 1.0).abs() < 1e-5);
                let (u2, v2) = uv(d);
                assert!((v2 - v).abs() < 2e-3, "v {v} -> {v2}");
                if j < 32 {
                    let du = (u2 - u).abs();
                    assert!(du.min(1.0 - du) < 1e-4, "u {u} -> {u2} at v {v}");
                }
                let (u3, v3) = uv(d);
                assert!(direction(u3, v3).abs_diff_eq(d, 1e-4));
            }
        }
        assert_eq!(uv(Vec3::new(1.0, -0.5, 0.0)), (0.0, 0.0));
        assert_eq!(uv(Vec3::new(0.0, 2.0, 0.0)).1, 1.0);
        let total: f32 = (0..32)
            .flat_map(|r| (0..128).map(move |c| texel_solid_angle(c, r, 128, 32)))
            .sum();
        assert!((total - TAU).abs() < 1e-3, "{total}");
        // The diamond angle rises with the azimuth and matches it at the axes.
        let mut last = -1.0;
        for i in 0..720 {
            let a = (i as f32 * 0.5).to_radians();
            let q = diamond(a.cos(), a.sin());
            assert!(q > last || i == 0, "azimuth {i}/2 deg: {q} after {last}");
            last = q;
        }
        for (k, (x, z)) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)]
            .iter()
            .enumerate()
        {
            assert_eq!(diamond(*x, *z), k as f32);
        }
    }

    #[test]
    fn levels_follow_the_mip_chain() {
        let map = EnvMap::new(128, 32, 6);
        let sizes: Vec<_> = (0..6).map(|m| map.level_size(m)).collect();
        assert_eq!(
            sizes,
            [(128, 32), (64, 16), (32, 8), (16, 4), (8, 2), (4, 1)]
        );
        for (m, level) in map.levels.iter().enumerate() {
            let (w, h) = sizes[m];
            assert_eq!(level.len(), (w * h) as usize);
        }
        assert_eq!(map.roughness(5), 1.0);
        assert_eq!(EnvMap::new(4, 2, 10).levels.len(), 3);
        assert_eq!(EnvMap::new(0, 0, 0).levels.len(), 1);
    }

    #[test]
    fn clouds_add_detail_that_the_prefilter_smooths() {
        let cloudy = Sky::new(&SunSky {
            elevation_deg: 40.0,
            azimuth_deg: 75.0,
            turbidity: 2.5,
            clouds: 0.5,
        });
        let start = std::time::Instant::now();
        let map = bake(&cloudy, 320, 128, 7);
        println!(
            "bake 320x128x7 with clouds 0.5: {:.1} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
        let clear = bake(&sky(40.0, 75.0), 320, 128, 7);
        let (_, cv_cloudy) = stats(&map, 0);
        let (_, cv_clear) = stats(&clear, 0);
        let (_, cv_rough) = stats(&map, 6);
        println!(
            "level 0 cv: clear {cv_clear:.3}, cloudy {cv_cloudy:.3}; cloudy level 6 {cv_rough:.3}"
        );
        assert!(cv_rough < 0.5 * cv_cloudy, "{cv_rough} vs {cv_cloudy}");
        // Half the sky cloud: cloud edges against the blue make neighbouring texels differ far
        // more than the clear sky's smooth gradients (its sun glow included).
        let spread = |m: &EnvMap| {
            let level = &m.levels[0];
            let lum = |i: usize| LUMINANCE.dot(Vec3::new(level[i][0], level[i][1], level[i][2]));
            let (mut change, mut total) = (0.0f32, 0.0f32);
            for i in level.len() / 4..level.len() - 1 {
                change += (lum(i + 1) - lum(i)).abs();
                total += lum(i);
            }
            change / total
        };
        assert!(
            spread(&map) > 1.5 * spread(&clear),
            "{} vs {}",
            spread(&map),
            spread(&clear)
        );
    }

    #[test]
    fn prefilter_smooths_and_conserves_energy() {
        let s = sky(40.0, 75.0);
        let start = std::time::Instant::now();
        let map = bake(&s, 160, 64, 6);
        println!(
            "bake 160x64x6, {PREFILTER_SAMPLES} samples: {:.1} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
        let (mean0, cv0) = stats(&map, 0);
        for m in 1..6 {
            let (mean, cv) = stats(&map, m);
            println!(
                "level {m}: mean {mean:.3} (level 0 {mean0:.3}) kcd/m², cv {cv:.3} ({cv0:.3})"
            );
            assert!(
                (mean / mean0 - 1.0).abs() < 0.1,
                "level {m}: {mean} vs {mean0}"
            );
        }
        let (_, cv_rough) = stats(&map, 5);
        assert!(cv_rough < 0.5 * cv0, "{cv_rough} vs {cv0}");
        // Each texel is a finite, non-negative radiance with A = 1.
        for level in &map.levels {
            assert!(level
                .iter()
                .all(|t| t[3] == 1.0 && t[..3].iter().all(|c| c.is_finite() && *c >= 0.0)));
        }
    }

    #[test]
    fn the_sun_glow_shows_in_level_0() {
        let s = sky(30.0, 200.0);
        let map = bake(&s, 128, 32, 2);
        let (w, h) = map.level_size(0);
        let brightest = (0..h)
            .flat_map(|row| (0..w).map(move |col| (col, row)))
            .max_by(|a, b| {
                let y = |(c, r)| LUMINANCE.dot(map.texel(0, c, r));
                y(*a).total_cmp(&y(*b))
            })
            .unwrap();
        let d = direction(
            (brightest.0 as f32 + 0.5) / w as f32,
            (brightest.1 as f32 + 0.5) / h as f32,
        );
        let angle = d.dot(s.sun_direction()).acos().to_degrees();
        assert!(angle < 5.0, "brightest texel {angle}° from the sun");
        // The texel toward the sun outshines the one opposite it at the same elevation.
        let (u, v) = uv(s.sun_direction());
        let texel = |u: f32| {
            let col = ((u.rem_euclid(1.0) * w as f32) as u32).min(w - 1);
            LUMINANCE.dot(map.texel(0, col, ((v * h as f32) as u32).min(h - 1)))
        };
        assert!(
            texel(u) > 3.0 * texel(u + 0.5),
            "{} vs {}",
            texel(u),
            texel(u + 0.5)
        );
    }

    #[test]
    fn bake_into_matches_bake_and_frames_are_orthonormal() {
        let s = sky(10.0, -30.0);
        let mut map = EnvMap::new(32, 8, 3);
        bake_into(&s, &mut map);
        assert_eq!(map, bake(&s, 32, 8, 3));
        for (u, v) in [(0.0, 0.0), (0.3, 0.5), (0.7, 0.99), (0.5, 1.0)] {
            let n = direction(u, v);
            let (t, b) = tangent_frame(n);
            assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5);
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }
}
