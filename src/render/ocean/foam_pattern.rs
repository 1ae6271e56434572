//! The foam pattern (issue 14, item 4): a tiling texture made at start-up that the water shader
//! thresholds with the whitecap coverage, so a coverage c turns a share c of the surface white
//! and rising coverage eats into the pattern instead of greying it.
//!
//! The pattern is the lacework of decaying sea foam: the borders of two octaves of tiling
//! Worley cells (high on the borders, low at the cells' hearts), so thin coverage shows a web
//! of streaks and dense coverage leaves only the cells' hearts open. Its values are then
//! equalized (replaced by their rank): uniform over [0, 1], which is what makes the share of
//! texels above 1 − c exactly c. R8 with box-filtered mips, each mip equalized again (a
//! box filter pulls values toward the mean, so a plain mip would turn thin coverage into none
//! and dense coverage into all), sampled with REPEAT.
//!
//! The same image carries the detail slopes (issue 29, item 2; `sim::detail`) in G and B: a
//! tile of the waves shorter than the finest cascade, unit slope variance, box-filtered mips
//! (slopes average linearly), for the water shader to draw near the viewer. One image, one
//! binding: both are tiling patterns made at start-up and sampled with REPEAT.

use ash::vk;

use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Image, ImageDesc};
use crate::render::sampler::sampler;
use crate::render::upload::{upload_levels, Level};
use crate::sim::grid::GridSize;
use crate::sim::pack;

/// Texels per side of the pattern.
pub const FOAM_PATTERN_TEXELS: u32 = 256;
const _: () = assert!(FOAM_PATTERN_TEXELS as usize == crate::sim::detail::DETAIL_TEXELS);

/// The detail slopes' range in the G and B codes: ±this (unit total variance, so about ±4.2
/// standard deviations of each component); the shader gets it in `Globals::detail`.
pub const DETAIL_RANGE: f32 = 3.0;

/// Worley cells per tile side of the two octaves (whole numbers: the pattern tiles).
const CELLS: [u32; 2] = [11, 27];

/// Weight of each octave's border distance (the fine one breaks the coarse web's edges).
const OCTAVE_WEIGHTS: [f32; 2] = [0.72, 0.28];

/// The pattern's grid.
fn grid() -> GridSize {
    GridSize::new(FOAM_PATTERN_TEXELS).expect("a power of two")
}

/// The pattern with its mip chain (the eq. 55 layout), level 0 uniform over the 256 codes.
pub fn generate(seed: u32) -> Vec<u8> {
    let g = grid();
    let n = g.n();
    let mut value = vec![0.0f32; g.texels()];
    for (o, (&cells, &weight)) in CELLS.iter().zip(&OCTAVE_WEIGHTS).enumerate() {
        let points = feature_points(cells, seed.wrapping_add(o as u32 * 0x9e37_79b9));
        for (i, v) in value.iter_mut().enumerate() {
            let p = [
                ((i % n) as f32 + 0.5) * cells as f32 / n as f32,
                ((i / n) as f32 + 0.5) * cells as f32 / n as f32,
            ];
            *v += weight * border(&points, cells, p);
        }
    }
    let mut chain = vec![0u8; pack::mip_chain_len(g)];
    equalize(&value, &mut chain[..g.texels()]);
    pack::build_r8_mips(g, &mut chain);
    for m in 1..g.mip_levels() {
        let at = pack::mip_offset(g, m);
        let level = &mut chain[at..at + (n >> m) * (n >> m)];
        let values: Vec<f32> = level.iter().map(|&v| v as f32).collect();
        equalize(&values, level);
    }
    chain
}

/// The RGBA8 image with its mip chain: R the foam pattern ([`generate`]), G and B the detail
/// slopes of the band from `k_lo` (rad/m, the finest cascade's Nyquist), A unused (255).
pub fn generate_rgba(seed: u32, k_lo: f64) -> Vec<u8> {
    let g = grid();
    let foam = generate(seed);
    let slopes = crate::sim::detail::detail_slopes(k_lo, seed as u64);
    let len = pack::mip_chain_len(g);
    let mut channels = [vec![0u8; len], vec![0u8; len]];
    for (c, chain) in channels.iter_mut().enumerate() {
        for (code, s) in chain[..g.texels()].iter_mut().zip(&slopes) {
            let v = (s[c] / DETAIL_RANGE).clamp(-1.0, 1.0) * 0.5 + 0.5;
            *code = (v * 255.0).round() as u8;
        }
        pack::build_r8_mips(g, chain);
    }
    let mut rgba = vec![255u8; 4 * len];
    for (i, texel) in rgba.chunks_exact_mut(4).enumerate() {
        texel[0] = foam[i];
        texel[1] = channels[0][i];
        texel[2] = channels[1][i];
    }
    rgba
}

/// One feature point per cell of a `cells`² tiling lattice, in cell units.
fn feature_points(cells: u32, seed: u32) -> Vec<[f32; 2]> {
    (0..cells * cells)
        .map(|c| {
            let h = hash(c ^ seed.rotate_left(7));
            let (x, y) = (c % cells, c / cells);
            let fx = (h & 0xffff) as f32 / 65536.0;
            let fy = (h >> 16) as f32 / 65536.0;
            [x as f32 + 0.1 + 0.8 * fx, y as f32 + 0.1 + 0.8 * fy]
        })
        .collect()
}

/// Closeness to a cell border at `p` (cell units): 1 − (F2 − F1) of the wrapped lattice, in
/// [0, 1]; 1 on a border, lowest at a feature point.
fn border(points: &[[f32; 2]], cells: u32, p: [f32; 2]) -> f32 {
    let (cx, cy) = (p[0].floor() as i32, p[1].floor() as i32);
    let c = cells as i32;
    let (mut f1, mut f2) = (f32::MAX, f32::MAX);
    for dy in -2..=2 {
        for dx in -2..=2 {
            let (x, y) = (cx + dx, cy + dy);
            let q = points[(y.rem_euclid(c) * c + x.rem_euclid(c)) as usize];
            // The point's copy in the tile next door when the cell index wrapped.
            let qx = q[0] + (x - x.rem_euclid(c)) as f32;
            let qy = q[1] + (y - y.rem_euclid(c)) as f32;
            let d = ((qx - p[0]).powi(2) + (qy - p[1]).powi(2)).sqrt();
            if d < f1 {
                f2 = f1;
                f1 = d;
            } else if d < f2 {
                f2 = d;
            }
        }
    }
    (1.0 - (f2 - f1)).clamp(0.0, 1.0)
}

/// Integer hash (a 32-bit finalizer): well spread bits from consecutive inputs.
fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// Writes each value's rank as a code in [0, 255], centred in its share: every code holds the
/// same share of texels (levels of 256 texels or more), and the mean stays 127.5. Ties keep
/// their order in memory (a stable sort), so the result is deterministic.
fn equalize(value: &[f32], out: &mut [u8]) {
    let mut order: Vec<u32> = (0..value.len() as u32).collect();
    order.sort_by(|&a, &b| value[a as usize].total_cmp(&value[b as usize]));
    let len = value.len();
    for (rank, &i) in order.iter().enumerate() {
        out[i as usize] = ((2 * rank + 1) * 256 / (2 * len)) as u8;
    }
}

/// The pattern on the GPU (binding 5).
pub(super) struct FoamPattern {
    image: Image,
    sampler: vk::Sampler,
}

impl FoamPattern {
    /// Generates and uploads the pattern (waits for the copy: set-up only). Nothing is left
    /// behind when a step fails.
    /// `k_lo`: the finest cascade's Nyquist wave number (rad/m), where the detail band starts.
    pub fn new(ctx: &GpuContext, k_lo: f64) -> Result<Self, RenderError> {
        let mut this = Self {
            image: Image::null(),
            sampler: vk::Sampler::null(),
        };
        if let Err(e) = this.create(ctx, k_lo) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext, k_lo: f64) -> Result<(), RenderError> {
        let g = grid();
        let side = FOAM_PATTERN_TEXELS;
        self.image = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R8G8B8A8_UNORM,
                extent: vk::Extent2D {
                    width: side,
                    height: side,
                },
                layers: 1,
                mips: g.mip_levels(),
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        self.sampler = sampler(ctx, g.mip_levels() as f32)?;
        let chain = generate_rgba(0x5eaf_0a11, k_lo);
        let levels: Vec<Level<'_>> = (0..g.mip_levels())
            .map(|m| {
                let s = side >> m;
                let at = pack::mip_offset(g, m);
                Level {
                    bytes: &chain[4 * at..4 * (at + (s * s) as usize)],
                    width: s,
                    height: s,
                }
            })
            .collect();
        upload_levels(ctx, &self.image, &levels)
    }

    /// The descriptor of the pattern (binding 5).
    pub fn descriptor(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }
    }

    /// Frees what was made. The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the sampler; a null handle is a no-op.
        unsafe { ctx.device.destroy_sampler(self.sampler, None) };
        self.sampler = vk::Sampler::null();
        self.image.destroy(ctx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_zero_is_uniform_and_the_pattern_tiles() {
        let chain = generate(7);
        let n = FOAM_PATTERN_TEXELS as usize;
        let mut histogram = [0usize; 256];
        for &v in &chain[..n * n] {
            histogram[v as usize] += 1;
        }
        // Equalized: every code holds n²/256 texels, so P(v > 1 − c) = c.
        assert!(histogram.iter().all(|&h| h == n * n / 256), "{histogram:?}");
        // Tiling: the step across the wrap is no larger than steps inside the tile.
        let at = |x: usize, y: usize| chain[(y % n) * n + x % n] as i32;
        let step = |x0: usize, x1: usize| -> f64 {
            (0..n)
                .map(|y| (at(x0, y) - at(x1, y)).abs() as f64)
                .sum::<f64>()
                / n as f64
        };
        let inside = (1..n - 1).map(|x| step(x, x + 1)).sum::<f64>() / (n - 2) as f64;
        let across = step(n - 1, n);
        assert!(
            across < 2.0 * inside,
            "wrap step {across} vs {inside} inside"
        );
    }

    #[test]
    fn the_detail_channels_hold_slopes_centred_on_the_middle_code() {
        let rgba = generate_rgba(7, 50.0);
        let n = FOAM_PATTERN_TEXELS as usize;
        let foam = generate(7);
        for c in 1..3 {
            let codes: Vec<f64> = rgba[..4 * n * n]
                .chunks_exact(4)
                .map(|t| t[c] as f64)
                .collect();
            let mean = codes.iter().sum::<f64>() / codes.len() as f64;
            let sd =
                (codes.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / codes.len() as f64).sqrt();
            // Unit total variance: each component's deviation about 0.71, i.e. 0.71 / 3 of the
            // half range (127.5 codes).
            assert!((mean - 127.5).abs() < 2.0, "channel {c}: mean {mean}");
            assert!(
                (20.0..40.0).contains(&sd),
                "channel {c}: deviation {sd} codes"
            );
        }
        // R is the foam pattern, unchanged, through the whole chain.
        assert!(rgba
            .chunks_exact(4)
            .zip(&foam)
            .all(|(t, &f)| t[0] == f && t[3] == 255));
    }

    #[test]
    fn borders_are_high_and_hearts_low() {
        let points = feature_points(4, 3);
        let heart = border(&points, 4, points[5]);
        // Halfway between two neighbouring points lies on or near their border.
        let mid = [
            (points[5][0] + points[6][0]) / 2.0,
            (points[5][1] + points[6][1]) / 2.0,
        ];
        let mid = border(&points, 4, mid);
        assert!(heart < mid && mid > 0.6, "heart {heart}, border {mid}");
    }

    #[test]
    fn every_mip_keeps_the_shares() {
        let chain = generate(1);
        let g = grid();
        for m in 1..g.mip_levels() {
            let side = g.n() >> m;
            let at = pack::mip_offset(g, m);
            let level = &chain[at..at + side * side];
            let mean = level.iter().map(|&v| v as f64).sum::<f64>() / level.len() as f64;
            assert!((mean - 127.5).abs() < 1.0, "mip {m}: mean {mean}");
            if level.len() >= 256 {
                // A share c of texels lies above 1 − c at every level (16 bins equal).
                let mut bins = [0usize; 16];
                for &v in level {
                    bins[v as usize / 16] += 1;
                }
                assert!(
                    bins.iter().all(|&b| b == level.len() / 16),
                    "mip {m}: {bins:?}"
                );
            }
        }
    }
}
