//! The GPU cost model behind `vr-ocean gpu-budget`: what the ocean pass would cost a Quest's
//! GPU, without a headset.
//!
//! Measured here: how many fragment-shader invocations each shading path took in a frame of
//! a standard view at the headset's eye size and settings ([`PathCounts`], from the counting
//! variant of the ocean's fragment shader and Vulkan pipeline-statistics queries, on any
//! Vulkan device, lavapipe included), and what one invocation of each path costs in scalar
//! ALU operations, special-function operations and texture samples ([`spirv`], counted in the
//! optimized SPIR-V of the cost variants). Modelled: the GPUs' throughput from published
//! figures ([`GpuFigures`]), the share of shading fixed foveation saves, and a stated
//! utilization. Every constant and its source: `docs/notes/gpu-cost-model.md`.
//!
//! The estimate is a model (good to perhaps ±50 %), not a measurement; on the headset the GPU
//! governor (`xr::gpu_governor`) steps quality down from the pass's real timestamps when it is
//! wrong.

pub mod adreno;
pub mod calibration;
pub mod headset;
pub mod paths;
pub mod spirv;
mod views;
pub use views::{budget_views, StandardView, STRESS_VIEW, TOP_DECK, UNDER, VIEWS, WATERLINE};

use self::spirv::InstructionCounts;
use crate::render::shaders::cost;

/// A special-function operation (reciprocal, square root, exp2, log2, sin, cos) takes this many
/// ALU issue slots: Adreno's special-function unit runs at a quarter of the FP32 rate
/// (assumption; the usual ratio of mobile GPUs).
pub const SPECIAL_COST: f64 = 4.0;

/// Share of the shader core's peak that a fragment-bound pass achieves (latency, register
/// pressure, partial quads the helper lanes fill): an assumption, stated, not measured.
pub const UTILIZATION: f64 = 0.7;

/// A tiler runs the vertex shader once to bin and once to draw (assumption: no position-only
/// variant; an upper bound).
pub const VERTEX_PASSES: f64 = 2.0;

/// The gate `vr-ocean gpu-budget` is tested against: a standard view's estimate within this
/// share of its headset's frame budget.
pub const GATE_SHARE: f64 = 0.75;

/// One GPU's published throughput.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GpuFigures {
    /// The GPU's name.
    pub name: &'static str,
    /// FP32 operations per second the shader cores issue at the clock used (lanes × clock).
    pub alu_per_s: f64,
    /// How many FP16 operations the cores issue in the time of one FP32 operation: what a
    /// `mediump` (RelaxedPrecision) operation costs is `1 / fp16_rate` of a full one.
    pub fp16_rate: f64,
    /// Trilinear texture samples per second at that clock.
    pub samples_per_s: f64,
    /// DRAM bandwidth (bytes/s) the resolved eye images are stored through.
    pub bytes_per_s: f64,
    /// The clock (Hz) the figures are at.
    pub clock_hz: f64,
    /// Pixels its render back-ends write per second (colour and depth of all samples on the
    /// tile).
    pub pixels_per_s: f64,
    /// Triangles its front end sets up per second.
    pub triangles_per_s: f64,
}

/// Fixed foveation's level, with the share of fragment shading it saves (modelled).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum FoveationLevel {
    /// Full rate.
    Off,
    /// Slight.
    Low,
    /// Moderate.
    Medium,
    /// Strong.
    High,
}

impl FoveationLevel {
    /// The share of fragment invocations the level saves: Meta quotes savings of up to about a
    /// quarter of shading at the highest fixed level; the lower levels are interpolated
    /// (assumption).
    pub fn saving(self) -> f64 {
        match self {
            FoveationLevel::Off => 0.0,
            FoveationLevel::Low => 0.10,
            FoveationLevel::Medium => 0.18,
            FoveationLevel::High => 0.25,
        }
    }
}

/// A headset at its default settings in this app (`xr::openxr::quest::Headset::defaults`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct HeadsetModel {
    /// The headset.
    pub name: &'static str,
    /// Its GPU at the clock apps get by default.
    pub gpu: GpuFigures,
    /// The runtime's recommended eye-buffer size (pixels), render scale 1.
    pub recommended_eye: (u32, u32),
    /// The app's default resolution scale on this headset (`Headset::defaults`).
    pub resolution_scale: f32,
    /// Display refresh rate (Hz) the app asks for.
    pub refresh_hz: f64,
    /// MSAA samples.
    pub msaa: u32,
    /// Fixed foveation level.
    pub foveation: FoveationLevel,
    /// LOD quality preset, as `QualityPreset::name` spells it.
    pub preset: &'static str,
    /// Its Adreno GPU (650 or 740: turnip's `FD_GPU_ID`, whose compiler `gpu-budget` reads).
    pub adreno: u32,
}

impl HeadsetModel {
    /// Eye-buffer size (pixels) the app draws by default: the runtime's recommended size times
    /// the headset's default resolution scale, each side rounded as the swapchain's and the
    /// drawn rectangle's are (`xr::openxr::swapchain::eye_extent`, `xr::render_scale`).
    pub fn eye(&self) -> (u32, u32) {
        let side = |rec: u32| (rec as f32 * self.resolution_scale).round() as u32;
        (side(self.recommended_eye.0), side(self.recommended_eye.1))
    }

    /// The frame budget (ms): one refresh period.
    pub fn budget_ms(&self) -> f64 {
        1000.0 / self.refresh_hz
    }
}

/// Quest 2: Adreno 650 (512 FP32 lanes, FP16 at twice the rate) at 490 MHz (GPU level 3, Meta's
/// CPU and GPU levels page), 32 bilinear texels a clock (16 trilinear), 24 pixels a clock
/// (third-party listings of its render back-ends), a triangle a clock (assumption), LPDDR4X at
/// 34 GB/s; 1440 × 1584 eye buffers recommended, rendered at 0.89 of that (1282 × 1410: the
/// standing eye on the top deck did not fit the 75 % goal at full size, issue 43), 72 Hz, MSAA 4,
/// high foveation, the medium preset.
pub const QUEST_2: HeadsetModel = HeadsetModel {
    name: "Quest 2",
    gpu: GpuFigures {
        name: "Adreno 650 @ 490 MHz",
        alu_per_s: 512.0 * 490e6,
        fp16_rate: 2.0,
        samples_per_s: 16.0 * 490e6,
        bytes_per_s: 34.1e9,
        clock_hz: 490e6,
        pixels_per_s: 24.0 * 490e6,
        triangles_per_s: 490e6,
    },
    recommended_eye: (1440, 1584),
    resolution_scale: 0.89,
    refresh_hz: 72.0,
    msaa: 4,
    foveation: FoveationLevel::High,
    preset: "medium",
    adreno: 650,
};

/// Quest 3: Adreno 740 at 599 MHz (the default maximum since a 2024 firmware, UploadVR), taken
/// as Qualcomm's "up to 2.5x" the XR2 Gen 1's peak (512 lanes at 587 MHz) for ALU, texture,
/// pixel and triangle rate, LPDDR5 at 51 GB/s; 1680 × 1760 eye buffers at 90 Hz, MSAA 4, medium foveation, the
/// high preset.
pub const QUEST_3: HeadsetModel = HeadsetModel {
    name: "Quest 3",
    gpu: GpuFigures {
        name: "Adreno 740 @ 599 MHz",
        alu_per_s: 2.5 * 512.0 * 587e6,
        fp16_rate: 2.0,
        samples_per_s: 2.5 * 16.0 * 587e6,
        bytes_per_s: 51.2e9,
        clock_hz: 599e6,
        pixels_per_s: 2.5 * 24.0 * 587e6,
        triangles_per_s: 2.5 * 587e6,
    },
    recommended_eye: (1680, 1760),
    resolution_scale: 1.0,
    refresh_hz: 90.0,
    msaa: 4,
    foveation: FoveationLevel::Medium,
    preset: "high",
    adreno: 740,
};

/// The headsets `gpu-budget` models.
pub const HEADSETS: [HeadsetModel; 2] = [QUEST_2, QUEST_3];

/// Quest 3 at 120 Hz (8.3 ms), which the app does not ask for (its default is 90 Hz): the same
/// frames as [`QUEST_3`]'s (its eye size and defaults), so `gpu-budget` prices them from those
/// counts against the shorter budget, to say what that rate would need.
pub const QUEST_3_120: HeadsetModel = HeadsetModel {
    name: "Quest 3 120 Hz",
    refresh_hz: 120.0,
    ..QUEST_3
};

/// Headsets priced from another's frames (same eye size and settings, another refresh rate):
/// each with the one whose counts it takes.
pub const RATE_VARIANTS: [(HeadsetModel, &str); 1] = [(QUEST_3_120, QUEST_3.name)];

/// What one frame of a view measured, both eyes together.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathCounts {
    /// Sky fragments.
    pub sky: u64,
    /// Water fragments shaded once (the highlight not supersampled).
    pub single: u64,
    /// Water fragments whose highlight was supersampled.
    pub supersampled: u64,
    /// Cascades sampled again at the sub-pixel positions, summed over supersampled fragments.
    pub resamples: u64,
    /// Water fragments with foam (coverage above zero): the pattern and bubbles looked at.
    pub foam: u64,
    /// Water fragments without anti-aliasing.
    pub plain: u64,
    /// Water fragments near the viewer with detail slopes (`sim::detail`) looked at.
    pub detail: u64,
    /// The taps the anisotropic sampler adds to the pixels' own normal-map samples (each one
    /// more trilinear sample; `render::ocean::anisotropy`), summed over fragments.
    pub aniso_taps: u64,
    /// The tallied fragments by the area of their triangle on the screen
    /// ([`PathCounts::area_of_bin`]): a small triangle's set-up is shared by few fragments.
    pub by_area: [u64; PathCounts::AREA_BINS],
    /// The lanes the tallied fragments would be shaded on, in quarters, were the device to
    /// shade in blocks of [`PathCounts::BLOCK_SIDES`] pixels a side: a triangle's blocks are
    /// partly empty along its edges, and their empty lanes shade too (`shaders/ocean.frag`,
    /// `count_size`).
    #[serde(default)]
    pub quarter_lanes: [u64; 3],
    /// The tallied fragments by the thickness of their triangle (twice its area over its
    /// longest edge; bin 0 under a quarter pixel, bin k in [2^(k-3), 2^(k-2)) pixels, the last,
    /// the sky's, from 4096): recorded for other models of small triangles' waste.
    #[serde(default)]
    pub by_thickness: [u64; PathCounts::AREA_BINS],
    /// Fragments (sky and water) whose colour went through the tone curve's knee (the bright
    /// ones: `tonemap` in `shaders/common.glsl`); the paths' costs leave the knee out.
    #[serde(default)]
    pub knee: u64,
    /// Water fragments drawn from under the water: the surface seen from below (issue 45).
    #[serde(default)]
    pub below: u64,
    /// Fragments where a ray from under the water meets nothing: the depths (the sky's
    /// fragments under the water).
    #[serde(default)]
    pub depths: u64,
    /// Triangles out of the clipper (pipeline statistics: those the rasterizer set up, the
    /// solids' included); 0 when unavailable.
    pub clipped_primitives: u64,
    /// Fragment-shader invocations of the whole pass (pipeline statistics; helper lanes and
    /// the solids' fragments included where the device counts them); 0 when unavailable.
    pub fragment_invocations: u64,
    /// Vertex-shader invocations of the whole pass (pipeline statistics); 0 when unavailable.
    pub vertex_invocations: u64,
}

impl PathCounts {
    /// Bins of [`PathCounts::by_area`]: bin 0 under half a pixel, bin k in [2^(k-2),
    /// 2^(k-1)) pixels, the last from 8192 pixels up, the sky's (`shaders/ocean.frag`,
    /// `count_area`).
    pub const AREA_BINS: usize = 16;

    /// The area (pixels) a bin stands for: the geometric middle of its range (a quarter pixel
    /// for bin 0; a million, a full-screen triangle's order, for the last).
    pub fn area_of_bin(bin: usize) -> f64 {
        match bin {
            0 => 0.25,
            b if b >= Self::AREA_BINS - 1 => 1048576.0,
            b => 2f64.powf(b as f64 - 1.5),
        }
    }

    /// The block sides of [`PathCounts::quarter_lanes`] (pixels): 2, a GPU's quads; 4,
    /// lavapipe's blocks; 8.
    pub const BLOCK_SIDES: [u32; 3] = [2, 4, 8];

    /// Lanes per tallied fragment were the device to shade in blocks of `side` pixels (1: no
    /// lane wasted); `None` for a side not tallied or before anything was.
    pub fn lanes_per_fragment(&self, side: u32) -> Option<f64> {
        if side == 1 {
            return Some(1.0);
        }
        let i = Self::BLOCK_SIDES.iter().position(|&s| s == side)?;
        let tallied = self.tallied();
        (tallied > 0 && self.quarter_lanes[i] > 0)
            .then(|| self.quarter_lanes[i] as f64 / (4.0 * tallied as f64))
    }

    /// Fragments the counting shader tallied (sky and water).
    pub fn tallied(&self) -> u64 {
        self.sky + self.single + self.supersampled + self.plain + self.below + self.depths
    }
}

/// What one invocation of each path costs (from the cost variants' SPIR-V).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathCosts {
    /// The sky.
    pub sky: InstructionCounts,
    /// Water shaded once.
    pub single: InstructionCounts,
    /// Water with its highlight supersampled, no cascade sampled again.
    pub supersampled: InstructionCounts,
    /// What each cascade sampled again adds.
    pub resample: InstructionCounts,
    /// What foam adds to a water fragment.
    pub foam: InstructionCounts,
    /// Water without anti-aliasing.
    pub plain: InstructionCounts,
    /// What the detail near the viewer adds to a water fragment.
    pub detail: InstructionCounts,
    /// The ocean's vertex shader.
    pub vertex: InstructionCounts,
    /// Every path at once (each branch taken): what a fragment costs a device that runs both
    /// sides of every branch.
    pub union: InstructionCounts,
    /// What the tone curve's knee adds to a fragment whose colour reaches it.
    #[serde(default)]
    pub knee: InstructionCounts,
    /// The surface seen from under the water.
    #[serde(default)]
    pub below: InstructionCounts,
    /// The water where a ray from under it meets nothing.
    #[serde(default)]
    pub depths: InstructionCounts,
}

/// The cost variants' module names (`COST_SHADERS` in `shaders/shader_table.rs`), in the order
/// [`PathCosts::of_modules`] takes them.
pub const COST_MODULES: [&str; 12] = [
    "cost_sky.frag",
    "cost_single.frag",
    "cost_super0.frag",
    "cost_super1.frag",
    "cost_foam.frag",
    "cost_plain.frag",
    "cost_ocean.vert",
    "cost_detail.frag",
    "cost_union.frag",
    "cost_knee.frag",
    "cost_below.frag",
    "cost_depths.frag",
];

impl PathCosts {
    /// Counts the cost variants built into this binary.
    pub fn of_shaders() -> Result<Self, spirv::CountError> {
        Self::of_modules([
            cost::SKY,
            cost::SINGLE,
            cost::SUPERSAMPLED,
            cost::SUPERSAMPLED_RESAMPLE,
            cost::FOAM,
            cost::PLAIN,
            cost::VERTEX,
            cost::DETAIL,
            cost::UNION,
            cost::KNEE,
            cost::BELOW,
            cost::DEPTHS,
        ])
    }

    /// Counts cost variants given in [`COST_MODULES`] order (e.g. those of another version of
    /// the shaders, to compare).
    pub fn of_modules(m: [&[u32]; 12]) -> Result<Self, spirv::CountError> {
        let single = spirv::count(m[1])?;
        let supersampled = spirv::count(m[2])?;
        Ok(Self {
            sky: spirv::count(m[0])?,
            single,
            supersampled,
            resample: spirv::count(m[3])?.minus(supersampled),
            foam: spirv::count(m[4])?.minus(single),
            plain: spirv::count(m[5])?,
            vertex: spirv::count(m[6])?,
            detail: spirv::count(m[7])?.minus(single),
            union: spirv::count(m[8])?,
            knee: spirv::count(m[9])?.minus(single),
            below: spirv::count(m[10])?,
            depths: spirv::count(m[11])?,
        })
    }
}

/// One row of the report: a headset in a view.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ViewEstimate {
    /// The headset's name.
    pub headset: &'static str,
    /// The view's name.
    pub view: &'static str,
    /// Fragment invocations per eye-buffer pixel (tallied, before foveation).
    pub invocations_per_pixel: f64,
    /// Share of water fragments whose highlight was supersampled.
    pub supersampled_share: f64,
    /// ALU issue slots per pixel (special operations weighted by [`SPECIAL_COST`], relaxed-
    /// precision ones by 1 / [`GpuFigures::fp16_rate`]), after foveation.
    pub alu_per_pixel: f64,
    /// Texture samples per pixel, after foveation.
    pub samples_per_pixel: f64,
    /// Estimated GPU time of the frame (ms): the Adreno estimate (`adreno_estimate`) where the
    /// Adreno statistics were read (`model` "adreno"), else the SPIR-V model's
    /// (`spirv_estimated_ms`, `model` "spirv").
    pub estimated_ms: f64,
    /// Which model `estimated_ms` and `share` are from: "adreno" or "spirv".
    pub model: &'static str,
    /// The SPIR-V model's estimate (issue 28: lavapipe's instruction counts at the published
    /// rates, utilization 0.7): vertex + fragment (the larger of ALU and texture time) +
    /// storing the resolved eye images.
    pub spirv_estimated_ms: f64,
    /// Its parts (ms): vertex work, fragment ALU, texture, store.
    pub parts_ms: [f64; 4],
    /// The frame budget (ms).
    pub budget_ms: f64,
    /// `estimated_ms / budget_ms`.
    pub share: f64,
    /// The GPU time the counting pass took on the device that counted (median, ms). Its
    /// tally's atomics serialize on a real GPU, so this includes the counting's own cost (on an
    /// H200 it rose to 31 ms 25 m up, from 6 ms looking down); lavapipe's is no headset's.
    pub measured_gpu_ms: Option<f64>,
    /// What was measured for it.
    pub counts: PathCounts,
    /// The headset's GPU whose compiler (ir3 on turnip) `adreno_paths` are from ("a650",
    /// "a740"); `None` when left out.
    pub adreno_gpu: Option<String>,
    /// Each water path, and the drawn pipeline's fragment and vertex shaders, as ir3 compiled
    /// them for that GPU.
    pub adreno_paths: Vec<adreno::AdrenoPath>,
    /// The estimate from the calibrated structure with ir3's counts and the published rates
    /// (`render::budget::headset`); `None` without the Adreno statistics.
    pub adreno_estimate: Option<headset::AdrenoEstimate>,
}

/// The estimate for `headset` of a frame that measured `counts`, with `costs` per invocation.
pub fn estimate(
    headset: &HeadsetModel,
    view: &StandardView,
    costs: &PathCosts,
    counts: &PathCounts,
) -> ViewEstimate {
    let gpu = &headset.gpu;
    let slots = |c: InstructionCounts| {
        let relaxed = c.relaxed.min(c.alu) as f64;
        (c.alu as f64 - relaxed) + relaxed / gpu.fp16_rate + SPECIAL_COST * c.special as f64
    };
    let n = |x: u64| x as f64;
    let paths = [
        (n(counts.sky), costs.sky),
        (n(counts.single), costs.single),
        (n(counts.supersampled), costs.supersampled),
        (n(counts.resamples), costs.resample),
        (n(counts.foam), costs.foam),
        (n(counts.plain), costs.plain),
        (n(counts.detail), costs.detail),
        (n(counts.knee), costs.knee),
        (n(counts.below), costs.below),
        (n(counts.depths), costs.depths),
    ];
    let kept = 1.0 - headset.foveation.saving();
    let alu: f64 = paths.iter().map(|(k, c)| k * slots(*c)).sum::<f64>() * kept;
    // Each anisotropic tap past the first is one more trilinear sample's texture work.
    let taps = n(counts.aniso_taps);
    let samples: f64 = (paths.iter().map(|(k, c)| k * c.samples as f64).sum::<f64>() + taps) * kept;
    let vertex_ms =
        1e3 * VERTEX_PASSES * n(counts.vertex_invocations) * slots(costs.vertex) / gpu.alu_per_s;
    let alu_ms = 1e3 * alu / (gpu.alu_per_s * UTILIZATION);
    let texture_ms = 1e3 * samples / (gpu.samples_per_s * UTILIZATION);
    let (width, height) = headset.eye();
    let pixels = 2.0 * width as f64 * height as f64;
    let store_ms = 1e3 * pixels * 4.0 / gpu.bytes_per_s;
    let estimated_ms = vertex_ms + alu_ms.max(texture_ms) + store_ms;
    let water = n(counts.single + counts.supersampled + counts.plain).max(1.0);
    ViewEstimate {
        headset: headset.name,
        view: view.name,
        invocations_per_pixel: n(counts.tallied()) / pixels,
        supersampled_share: n(counts.supersampled) / water,
        alu_per_pixel: alu / pixels,
        samples_per_pixel: samples / pixels,
        estimated_ms,
        model: "spirv",
        spirv_estimated_ms: estimated_ms,
        parts_ms: [vertex_ms, alu_ms, texture_ms, store_ms],
        budget_ms: headset.budget_ms(),
        share: estimated_ms / headset.budget_ms(),
        measured_gpu_ms: None,
        counts: *counts,
        adreno_gpu: None,
        adreno_paths: Vec::new(),
        adreno_estimate: None,
    }
}

impl ViewEstimate {
    /// Takes ir3's `paths` for `headset`'s Adreno: the Adreno estimate, which becomes
    /// `estimated_ms` and `share` when it can be made.
    pub fn with_adreno(&mut self, headset: &HeadsetModel, paths: &[adreno::AdrenoPath]) {
        self.adreno_gpu = Some(format!("a{}", headset.adreno));
        self.adreno_paths = paths.to_vec();
        self.adreno_estimate = headset::adreno_estimate(headset, &self.counts, paths);
        if let Some(e) = self.adreno_estimate {
            self.estimated_ms = e.ms;
            self.share = e.share;
            self.model = "adreno";
        }
    }
}

/// The report as a table, one line per headset and view.
pub fn table(rows: &[ViewEstimate]) -> String {
    let mut out = String::from(
        "headset        view     inv/px  ss%   ALU/px  tex/px  vert ms  ALU ms  tex ms  store ms  \
         spirv ms  budget ms  ir3 ms  share\n",
    );
    for r in rows {
        out.push_str(&format!(
            "{:<14} {:<8} {:>6.2} {:>4.0} {:>7.0} {:>7.1} {:>8.2} {:>7.2} {:>7.2} {:>9.2} {:>9.2} \
             {:>10.1} {:>7} {:>5.0}%\n",
            r.headset,
            r.view,
            r.invocations_per_pixel,
            100.0 * r.supersampled_share,
            r.alu_per_pixel,
            r.samples_per_pixel,
            r.parts_ms[0],
            r.parts_ms[1],
            r.parts_ms[2],
            r.parts_ms[3],
            r.spirv_estimated_ms,
            r.budget_ms,
            r.adreno_estimate
                .map_or("-".to_string(), |e| format!("{:.2}", e.ms)),
            100.0 * r.share,
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn costs() -> PathCosts {
        PathCosts::of_shaders().unwrap()
    }

    #[test]
    fn more_supersampled_fragments_cost_more_and_foveation_saves() {
        let view = &VIEWS[0];
        let (width, height) = QUEST_2.eye();
        let pixels = 2 * width as u64 * height as u64;
        let mut counts = PathCounts {
            sky: pixels / 3,
            single: pixels / 2,
            supersampled: pixels / 6,
            resamples: pixels / 6,
            foam: pixels / 20,
            vertex_invocations: 300_000,
            ..Default::default()
        };
        let base = estimate(&QUEST_2, view, &costs(), &counts);
        assert!(base.estimated_ms > 0.0 && base.estimated_ms.is_finite());
        assert!((base.invocations_per_pixel - 1.0).abs() < 1e-3);
        counts.supersampled *= 2;
        let more = estimate(&QUEST_2, view, &costs(), &counts);
        assert!(more.estimated_ms > base.estimated_ms);
        let mut unfoveated = QUEST_2;
        unfoveated.foveation = FoveationLevel::Off;
        let off = estimate(&unfoveated, view, &costs(), &counts);
        assert!(off.parts_ms[1] > more.parts_ms[1] * 1.3);
        // The same work on the faster GPU at the same size takes less time.
        let mut q3 = QUEST_3;
        q3.recommended_eye = QUEST_2.eye();
        q3.resolution_scale = 1.0;
        q3.foveation = FoveationLevel::High;
        assert!(estimate(&q3, view, &costs(), &counts).estimated_ms < more.estimated_ms);
        let text = table(&[base, more]);
        assert_eq!(text.lines().count(), 3);
    }

    #[test]
    fn the_drawn_eye_is_the_recommended_one_scaled() {
        assert_eq!(QUEST_2.eye(), (1282, 1410));
        assert_eq!(QUEST_3.eye(), QUEST_3.recommended_eye);
    }

    #[test]
    fn budgets_follow_the_refresh_rate() {
        assert!((QUEST_2.budget_ms() - 13.889).abs() < 1e-3);
        assert!((QUEST_3.budget_ms() - 11.111).abs() < 1e-3);
    }
}
