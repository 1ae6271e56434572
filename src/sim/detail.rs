//! Detail slopes (issue 29, item 2): one tiling tile of the short waves no cascade shows, for
//! the renderer to draw near the viewer, where the finest cascade's texels (about 6 cm) are
//! many pixels wide and its bilinear normals look like smooth blobs.
//!
//! The band runs from the finest cascade's Nyquist wave number to the gravity-capillary
//! minimum ([`CAPILLARY_K`], λ ≈ 1.7 cm): the waves whose slope variance the renderer otherwise
//! only widens the highlight with (`spectrum::unresolved_slope_variance`). In the spectra's
//! saturation range the slope spectrum falls as k⁻², i.e. every octave of the band holds the
//! same slope variance (Phillips 1958, the thesis's eq. 5 tail), and short waves are close to
//! isotropic (issue 29, item 1). The tile is therefore a sum of [`COMPONENTS`] sinusoids of equal
//! slope amplitude, their wave numbers log-uniform over the band, directions uniform, on the
//! tile's lattice (whole cycles per tile, so it repeats seamlessly), scaled to a unit total
//! slope variance: the renderer multiplies by the sea's unresolved slope deviation.

use crate::sim::spectrum::rng::gaussian_pair;
use crate::sim::spectrum::CAPILLARY_K;

/// Texels per side of the tile.
pub const DETAIL_TEXELS: usize = 256;
/// The tile's side (m): 3.9 mm texels, Nyquist 7.8 mm, under the band's shortest wave.
pub const DETAIL_TILE_M: f32 = 1.0;
/// Sinusoids summed: enough that the field is close to Gaussian and shows no single wave.
pub const COMPONENTS: usize = 160;

/// The tile's slopes (∂h/∂x, ∂h/∂z), row-major (row = z), for the band from `k_lo` (rad/m, the
/// finest cascade's Nyquist) to [`CAPILLARY_K`], scaled so that the mean of sx² + sz² is 1.
/// Deterministic for a `seed`.
pub fn detail_slopes(k_lo: f64, seed: u64) -> Vec<[f32; 2]> {
    let n = DETAIL_TEXELS;
    let mut out = vec![[0.0f32; 2]; n * n];
    let step = std::f64::consts::TAU / n as f64;
    for (m, l, phase) in components(k_lo, seed) {
        let norm = (m * m + l * l).sqrt();
        let (ux, uz) = ((m / norm) as f32, (l / norm) as f32);
        // Along a row each component's phase advances by a fixed step per texel: a rotation.
        let (ds, dc) = (m * step).sin_cos();
        for row in 0..n {
            let (mut s, mut c) = (l * step * row as f64 + phase).sin_cos();
            for texel in &mut out[row * n..(row + 1) * n] {
                // h = A cos(k·x + φ): ∇h = −A k sin(k·x + φ) k̂; the amplitude is set below.
                texel[0] -= ux * s as f32;
                texel[1] -= uz * s as f32;
                (s, c) = (s * dc + c * ds, c * dc - s * ds);
            }
        }
    }
    let variance = out
        .iter()
        .map(|s| (s[0] * s[0] + s[1] * s[1]) as f64)
        .sum::<f64>()
        / out.len() as f64;
    let scale = (1.0 / variance).sqrt() as f32;
    for s in &mut out {
        s[0] *= scale;
        s[1] *= scale;
    }
    out
}

/// The sinusoids of the tile: (cycles per tile along x, along z, phase), wave numbers
/// log-uniform from `k_lo` to [`CAPILLARY_K`], directions uniform.
fn components(k_lo: f64, seed: u64) -> Vec<(f64, f64, f64)> {
    let lattice = std::f64::consts::TAU / DETAIL_TILE_M as f64;
    let k_hi = CAPILLARY_K.max(k_lo * 1.5);
    let mut waves = Vec::with_capacity(COMPONENTS);
    for c in 0..COMPONENTS as u32 {
        let (g0, g1) = gaussian_pair(seed, 0x0de7, c);
        let (g2, _) = gaussian_pair(seed, 0x0de8, c);
        let u = |g: f64| 0.5 * (1.0 + libm::erf(g / std::f64::consts::SQRT_2));
        let k = k_lo * (k_hi / k_lo).powf(u(g0));
        let theta = std::f64::consts::TAU * u(g1);
        // The nearest lattice vector (whole cycles per tile), never zero.
        let mut m = (k * theta.cos() / lattice).round();
        let l = (k * theta.sin() / lattice).round();
        if m == 0.0 && l == 0.0 {
            m = 1.0;
        }
        let phase = std::f64::consts::TAU * u(g2);
        waves.push((m, l, phase));
    }
    waves
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tile_has_unit_variance_tiles_and_is_isotropic() {
        let s = detail_slopes(50.0, 7);
        let n = DETAIL_TEXELS;
        let (mut xx, mut zz, mut mean) = (0.0f64, 0.0f64, [0.0f64; 2]);
        for v in &s {
            xx += (v[0] * v[0]) as f64;
            zz += (v[1] * v[1]) as f64;
            mean[0] += v[0] as f64;
            mean[1] += v[1] as f64;
        }
        let len = s.len() as f64;
        assert!(((xx + zz) / len - 1.0).abs() < 1e-3);
        assert!(mean[0].abs() / len < 0.02 && mean[1].abs() / len < 0.02);
        let ratio = xx / zz;
        assert!((0.7..1.4).contains(&ratio), "x/z slope variance {ratio}");
        // Seamless: the step across the tile's edge is like a step inside it.
        let step =
            |a: [f32; 2], b: [f32; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)) as f64;
        let (mut inside, mut across) = (0.0, 0.0);
        for row in 0..n {
            inside += step(s[row * n + n / 2], s[row * n + n / 2 - 1]);
            across += step(s[row * n], s[row * n + n - 1]);
        }
        assert!(across < 2.0 * inside, "edge {across} vs inside {inside}");
        // Another seed, another tile.
        assert_ne!(s[12345], detail_slopes(50.0, 8)[12345]);
    }

    #[test]
    fn every_octave_of_the_band_holds_slope_variance() {
        // Equal slope amplitudes, so the variance per octave is the share of components in
        // it: the default band (50 rad/m, the finest cascade's Nyquist, to 370) spans 2.9
        // octaves, each holding about a third of them (the last, 0.9 octave, less).
        let lattice = std::f64::consts::TAU / DETAIL_TILE_M as f64;
        let mut octaves = [0usize; 3];
        for (m, l, _) in components(50.0, 3) {
            let k = lattice * (m * m + l * l).sqrt();
            // Rounded to the tile's lattice: within one lattice step of the band.
            assert!(
                (50.0 - lattice..=CAPILLARY_K + lattice).contains(&k),
                "k {k} outside the band"
            );
            let octave = (k / 50.0).log2().floor().clamp(0.0, 2.0);
            octaves[octave as usize] += 1;
        }
        let share = |o: usize| octaves[o] as f64 / COMPONENTS as f64;
        assert!(
            share(0) > 0.25 && share(1) > 0.25 && share(2) > 0.2,
            "{octaves:?}"
        );
        // Short waves: a texel's step changes the slope by a good share of its deviation (a
        // single wave at 50 rad/m, 8 cycles per tile, would change by ~0.04 squared).
        let s = detail_slopes(50.0, 3);
        let n = DETAIL_TEXELS;
        let mut d = 0.0f64;
        for row in 0..n {
            for col in 1..n {
                let (a, b) = (s[row * n + col], s[row * n + col - 1]);
                d += ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)) as f64;
            }
        }
        let per_texel = d / (n * (n - 1)) as f64;
        assert!((0.1..1.5).contains(&per_texel), "{per_texel}");
    }
}
