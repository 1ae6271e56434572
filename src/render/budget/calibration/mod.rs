//! The measured side of the cost model: a device's costs fitted from its calibration passes
//! ([`DeviceRates::fit`]), and the ocean pass's GPU time predicted from them and the counts of a
//! view ([`predict`]). Pure arithmetic; the passes themselves are `render::calibration`'s.
//!
//! The model of one pass, each term measured by a calibration pass of its own:
//!
//! ```text
//! T = T_pass                           (clear, resolve, store at this size: the empty pass)
//!   + Σ_a n_a · t_fragment(a)          (set-up, rasterization, tests and writes per fragment
//!                                       of a triangle of a pixels: the base shader's grids)
//!   + w · (max(A, X) + κ · min(A, X))  (the shading: ALU and texture work, overlapped as the
//!                                       mixed kernel shows)
//!   + vertices · (the vertex shader's work at the fragment rates)
//! A = (1 − σ) Σ_paths n_p · a(path) + σ · N · a(union)
//! X = (1 − σ) Σ_paths n_p · x(path) + σ · N · x(union) + taps · t_tap
//! a(c) = alu · t_alu + relaxed · t_relaxed + special · t_special
//! x(c) = Σ_kinds samples_kind · t_kind  (implicit, explicit level, gradients, queries)
//! w = lanes_B / N                      (lanes shaded per fragment in the device's B×B blocks:
//!                                       the counting pass's estimate for B, the B that explains
//!                                       the arithmetic shader's grids best)
//! ```
//!
//! σ is the share of a branch's work the lanes that do not take it pay anyway (the branch
//! kernel: about 0 on a GPU, whose waves skip a branch none of their lanes takes; 1 on
//! lavapipe, which masks lanes and runs both sides), N every fragment, `union` the shader with
//! every branch taken (`cost_union.frag`).
//!
//! `n_a` are the fragments whose triangle covers about `a` pixels (the counting pass sizes
//! each fragment's triangle, [`PathCounts::by_area`](super::PathCounts::by_area)). Small triangles cost more than their
//! pixels: each is set up, and a GPU shades 2×2 quads and lavapipe 4×4 blocks, partly empty
//! along every edge (the far sea's slivers most); the counting pass estimates the lanes of
//! each block side ([`PathCounts::quarter_lanes`](super::PathCounts::quarter_lanes)) and the grids of 1- to 32-pixel cells
//! tell which side the device shades in, and what set-up costs it per fragment.
//!
//! - this file: the passes as measured ([`KernelMeasurement`]);
//! - `rates`: the device's costs fitted to them ([`DeviceRates`]);
//! - `predict`: the ocean pass from the costs and a view's counts ([`predict`]);
//! - `grid`: the geometry of the calibration's grids of small triangles (their fragments and
//!   the lanes each block side shades them on).

mod grid;
mod predict;
mod rates;
#[cfg(test)]
mod tests;

use super::spirv::InstructionCounts;
pub use grid::{fragments_per_pixel, grid_lanes_per_fragment, triangle_lanes, BLOCK_SHRINK};
pub use predict::{predict, Prediction};
pub use rates::{AreaCost, DeviceRates, FitError};

/// How a calibration pass was drawn: full-screen, empty, or a grid of cells.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KernelKind {
    /// Nothing drawn: the pass's fixed cost.
    Empty,
    /// The base shader over the viewport.
    Base,
    /// FP32 arithmetic.
    Alu,
    /// Relaxed-precision arithmetic.
    Relaxed,
    /// Special functions.
    Special,
    /// Trilinear samples.
    Trilinear,
    /// Anisotropic samples.
    Anisotropic,
    /// Samples and arithmetic mixed.
    Mixed,
    /// Samples at an explicit level of detail.
    Lod,
    /// Samples with explicit gradients.
    Grad,
    /// Level-of-detail queries.
    Query,
    /// The explicit-level samples behind a branch no lane takes.
    Branch,
    /// The base shader on a grid of small triangles (`cell` pixels a side).
    GridBase,
    /// A heavy shader (explicit-level samples) on a grid of small triangles.
    GridShaded,
}

/// One calibration pass as measured on the device.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KernelMeasurement {
    /// The pass's name ("alu", "base on 4 px cells").
    pub name: String,
    /// What it measures.
    pub kind: KernelKind,
    /// Median GPU time of the pass (ms).
    pub ms: f64,
    /// Every repetition's time (ms).
    pub runs_ms: Vec<f64>,
    /// Fragments shaded, both eyes (each covered pixel once).
    pub fragments: f64,
    /// Triangles drawn, both eyes.
    pub triangles: f64,
    /// A grid's cell (pixels a side; 0 for the full-screen and empty passes).
    pub cell: u32,
    /// The anisotropic sampler's taps per sample in this pass (1 but for the anisotropic
    /// kernel).
    pub taps: f64,
    /// Its fragment shader's counts (`render::budget::spirv`).
    pub counts: InstructionCounts,
}
