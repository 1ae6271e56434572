//! The headset estimate from the calibrated model's structure (`render::budget::calibration`):
//! the terms that predicted the GPU here (an NVIDIA H200: within 8 % in 12 views), with the
//! Adreno's own compiler's counts (ir3 on turnip, [`super::adreno`]) and the headsets'
//! published rates ([`super::GpuFigures`]) in place of the measured costs:
//!
//! ```text
//! T = store                                  (the resolved eye images to DRAM; a tiler clears,
//!                                             tests and resolves on the tile)
//!   + fragments / pixel rate                 (the render back-ends)
//!   + triangles · 2 / triangle rate          (set-up, binning pass and drawing pass)
//!   + vertices · (binning + drawing VS slots) / ALU rate  (each as ir3 compiled it)
//!   + max(A, X)                              (shading: a GPU's waves hide the smaller, κ = 0
//!                                             as measured; branches no lane of a wave takes
//!                                             skipped, σ = 0 as measured)
//! A = q · Σ_paths n_p · (slots_p + 3 · special_p) / (ALU rate · (1 - foveation saving))
//! X = q · (Σ_paths n_p · texture_p + taps) / (trilinear rate) · (1 - foveation saving)
//! ```
//!
//! `slots` are ir3's instruction count (every issue slot of a wave's pass, its `nop`s
//! included: the latency a wave waits where the compiler found nothing to fill it), `special`
//! its special-function instructions (a quarter of the FP32 rate: Adreno 640 measured 55 G
//! reciprocals against 204 G FMAs a second, chipsandcheese 2024), `texture` its texture
//! instructions, `q` the lanes per fragment of 2×2 quads (`PathCounts::lanes_per_fragment`, as
//! the H200 measured). The bar on it is not the calibrations' residuals alone: the rates are
//! published figures, never timed here.

use super::adreno::{AdrenoPath, ShaderStats};
use super::{HeadsetModel, PathCounts};

/// Extra issue slots of a special-function instruction beyond its own (a quarter rate).
pub const SPECIAL_EXTRA_SLOTS: f64 = 3.0;

/// A shader's issue slots: its instructions, and the special-function ones' extra slots.
fn slots(s: ShaderStats) -> f64 {
    f64::from(s.instructions) + SPECIAL_EXTRA_SLOTS * f64::from(s.special)
}

/// A shader's texture instructions.
fn texture(s: ShaderStats) -> f64 {
    f64::from(s.texture)
}

/// The estimate of one view on a headset's Adreno, with its terms (ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct AdrenoEstimate {
    /// The whole pass.
    pub ms: f64,
    /// Storing the resolved eye images.
    pub store_ms: f64,
    /// The render back-ends' pixel writes.
    pub fragments_ms: f64,
    /// Triangle set-up (binning and drawing).
    pub triangles_ms: f64,
    /// The vertex shaders (binning and drawing).
    pub vertex_ms: f64,
    /// The fragment shaders' ALU issue.
    pub alu_ms: f64,
    /// Their texture work.
    pub texture_ms: f64,
    /// `ms` over the headset's frame budget.
    pub share: f64,
}

/// The estimate of a frame that measured `counts` on `headset`, with ir3's `paths`
/// ([`super::adreno::water_paths`]); `None` when a path is missing.
pub fn adreno_estimate(
    headset: &HeadsetModel,
    counts: &PathCounts,
    paths: &[AdrenoPath],
) -> Option<AdrenoEstimate> {
    let get = |name: &str| paths.iter().find(|p| p.path == name).map(|p| p.stats);
    let (sky, single, ss0, ss1) = (
        get("sky")?,
        get("single")?,
        get("supersampled")?,
        get("supersampled_resampled")?,
    );
    let (foam, plain, detail, vertex) =
        (get("foam")?, get("plain")?, get("detail")?, get("vertex")?);
    let knee = get("knee")?;
    // The view from under the water: needed only where a view drew it (reports recorded
    // before issue 45 have no such paths).
    let under = |count: u64, name: &str| match get(name) {
        Some(s) => Some((count as f64, slots(s), texture(s))),
        None if count == 0 => Some((0.0, 0.0, 0.0)),
        None => None,
    };
    let (below, depths) = (
        under(counts.below, "below")?,
        under(counts.depths, "depths")?,
    );
    let n = |x: u64| x as f64;
    // (fragments, slots, texture instructions): whole paths, then what the extras add.
    let extra = |a: ShaderStats, b: ShaderStats, f: fn(ShaderStats) -> f64| (f(a) - f(b)).max(0.0);
    // `count` fragments paying what `with` adds to `base`.
    let adds = |count: u64, with: ShaderStats, base: ShaderStats| {
        (
            n(count),
            extra(with, base, slots),
            extra(with, base, texture),
        )
    };
    let work = [
        (n(counts.sky), slots(sky), texture(sky)),
        (n(counts.single), slots(single), texture(single)),
        (n(counts.supersampled), slots(ss0), texture(ss0)),
        (n(counts.plain), slots(plain), texture(plain)),
        // Each cascade sampled again: a third of what the finest one's costs (three are
        // counted per supersampled fragment when every cascade is).
        adds(counts.resamples, ss1, ss0),
        adds(counts.foam, foam, single),
        adds(counts.detail, detail, single),
        // The tone curve's knee, where the light reaches it (the paths leave it out).
        adds(counts.knee, knee, single),
        below,
        depths,
    ];
    let gpu = &headset.gpu;
    let kept = 1.0 - headset.foveation.saving();
    let q = counts.lanes_per_fragment(2).unwrap_or(1.0);
    let alu_s: f64 = q * kept * work.iter().map(|(k, s, _)| k * s).sum::<f64>() / gpu.alu_per_s;
    let texture_s: f64 =
        q * kept * (work.iter().map(|(k, _, t)| k * t).sum::<f64>() + n(counts.aniso_taps))
            / gpu.samples_per_s;
    let (width, height) = headset.eye();
    let pixels = 2.0 * width as f64 * height as f64;
    let store_s = pixels * 4.0 / gpu.bytes_per_s;
    let fragments_s = kept * n(counts.tallied()) / gpu.pixels_per_s;
    let triangles_s = 2.0 * n(counts.clipped_primitives) / gpu.triangles_per_s;
    // The binning pass runs its own (position-only) vertex shader: ir3's statistics of it
    // where turnip reports them, else taken as long as the drawing pass's (reports recorded
    // before it was read).
    let binning = get("binning").unwrap_or(vertex);
    let vertex_s = n(counts.vertex_invocations) * (slots(vertex) + slots(binning)) / gpu.alu_per_s;
    let ms = 1e3 * (store_s + fragments_s + triangles_s + vertex_s + alu_s.max(texture_s));
    Some(AdrenoEstimate {
        ms,
        store_ms: 1e3 * store_s,
        fragments_ms: 1e3 * fragments_s,
        triangles_ms: 1e3 * triangles_s,
        vertex_ms: 1e3 * vertex_s,
        alu_ms: 1e3 * alu_s,
        texture_ms: 1e3 * texture_s,
        share: ms / headset.budget_ms(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::budget::paths::WATER_PATHS;
    use crate::render::budget::{QUEST_2, QUEST_3};

    fn paths(instructions: u32) -> Vec<AdrenoPath> {
        WATER_PATHS
            .iter()
            .map(|p| p.name)
            .chain(["pipeline", "vertex"])
            .map(|p| AdrenoPath {
                path: p.into(),
                stats: ShaderStats {
                    instructions,
                    special: 10,
                    texture: 8,
                    ..Default::default()
                },
            })
            .collect()
    }

    #[test]
    fn more_slots_more_time_a_faster_gpu_less_and_missing_paths_none() {
        let counts = PathCounts {
            sky: 1_000_000,
            single: 3_000_000,
            clipped_primitives: 100_000,
            vertex_invocations: 100_000,
            ..Default::default()
        };
        let small = adreno_estimate(&QUEST_2, &counts, &paths(500)).unwrap();
        let big = adreno_estimate(&QUEST_2, &counts, &paths(2000)).unwrap();
        assert!(big.alu_ms > 3.5 * small.alu_ms && big.ms > small.ms);
        // 4M fragments × 530 slots, less a quarter (high foveation), at 512 lanes × 490 MHz.
        let by_hand = 1e3 * 0.75 * 4e6 * 530.0 / (512.0 * 490e6);
        assert!(
            (small.alu_ms - by_hand).abs() < 1e-9,
            "{} vs {by_hand}",
            small.alu_ms
        );
        let mut q3 = QUEST_3;
        q3.foveation = QUEST_2.foveation;
        assert!(adreno_estimate(&q3, &counts, &paths(500)).unwrap().alu_ms < small.alu_ms);
        assert!(adreno_estimate(&QUEST_2, &counts, &paths(500)[1..]).is_none());
        // A binning pass's vertex shader of its own, shorter than the drawn one: less vertex
        // time, by its slots; without it, the drawn one's counted twice.
        let mut with_binning = paths(500);
        with_binning.push(AdrenoPath {
            path: "binning".into(),
            stats: ShaderStats {
                instructions: 300,
                special: 10,
                ..Default::default()
            },
        });
        let binned = adreno_estimate(&QUEST_2, &counts, &with_binning).unwrap();
        let by_hand = 1e3 * 100_000.0 * ((500.0 + 30.0) + (300.0 + 30.0)) / (512.0 * 490e6);
        assert!(
            (binned.vertex_ms - by_hand).abs() < 1e-9,
            "{}",
            binned.vertex_ms
        );
        assert!(binned.vertex_ms < small.vertex_ms);
    }
}
