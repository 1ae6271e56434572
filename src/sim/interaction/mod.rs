//! The interaction layer: a second, local wave field around the viewer that bodies, hands and
//! throws disturb (splashes, rings, wakes), added to the FFT sea for drawing, height queries
//! and foam. Pure: sources are plain data ([`WaveSource`]); `physics` makes them from bodies
//! and reads the heights, `render` uploads [`InteractionLayer::texels`].
//!
//! # Model: linear deep-water waves, propagated exactly per Fourier mode
//! The state is the surface elevation h and the surface velocity potential φ on N × N cells.
//! Linearized deep water (potential flow, infinitely deep) gives per wave vector k, with
//! ω² = g·|k| + (σ/ρ)·|k|³ (gravity and surface tension):
//!
//! ```text
//! ∂ĥ/∂t = |k|·φ̂          ∂φ̂/∂t = −(ω²/|k|)·ĥ − p̂/ρ
//! ```
//!
//! Without forcing each mode is a rotation by ω·dt, applied exactly (`modes.rs`): no CFL
//! limit, no numerical dispersion at any resolved wavelength, energy kept to rounding. A step
//! is: the sources' pressure (φ −= g·dt·P, P a pressure head in metres) and impulses in space;
//! this project's own FFT to the modes; the rotation; the FFT back; an absorbing band
//! (sponge) at the edges. h and φ travel as one complex field h + iφ (both real), so a step is
//! two complex transforms; the forward transform is the inverse one of the conjugate
//! (between steps the field holds h − iφ).
//!
//! Why this and not iWave's convolution or wave particles: both approximate the dispersion
//! (iWave with a truncated kernel, particles with a fixed speed per particle), and the issue's
//! first test is the dispersion itself (Cauchy-Poisson rings, the Kelvin angle, which both
//! come from ω² = g·k alone). The FFT is this project's fastest kernel; at the default 256²
//! a step is two transforms and four element-wise passes.
//!
//! # Sources
//! A floating body presses the water with its weight: a pressure head whose integral is the
//! displaced volume, over a raised-cosine footprint of its radius ([`WaveSource`]). Steady,
//! it sits in its own hollow (h = −P); moved, it makes a Kelvin wake; its draft changed (a
//! drop, a heave) it rings. An entry adds an impulse to φ (the water pushed down under it) and
//! foam. A body reading heights adds its own hollow back ([`WaveSource::head_at`]) so it does
//! not sink into it.
//!
//! # Frame and edges
//! Cell (col, row) is at world (x, z) = ((ox + col)·cell, (oz + row)·cell) with integer
//! (ox, oz): the layer follows the viewer by whole cells ([`InteractionLayer::recentre`]), so
//! its waves never swim. A band [`SPONGE_FRACTION`] of the side wide at every edge damps the
//! waves (a quadratic ramp of damping rate, little reflection); the periodic transform's
//! wrap-around passes through two bands. What is drawn and queried is faded to zero across the
//! same band, so the layer meets the FFT sea without a seam.
//!
//! # Guarantees
//! No allocation per step (every buffer is made in [`InteractionLayer::new`]). A step runs on
//! the caller's thread, Rayon-free: our FFT's single-field transform is sequential anyway, and
//! the physics steps the layer on the frame thread, where a parallel pass would push its jobs
//! into Rayon's global injector, whose queue allocates a block every 63 jobs (18 allocations
//! in 240 frames, `tests/no_alloc/render.rs`). It is the same bits on any thread count.

mod layer;
pub mod measure;
mod modes;
pub mod scenario;
mod source;
#[cfg(test)]
mod tests;

pub use layer::{InteractionLayer, InteractionStats};
pub use scenario::{Scenario, ScenarioRun};
pub use source::WaveSource;

use crate::base::ParamError;
use crate::sim::grid::GridSize;

/// Surface tension over density of sea water (m³/s²): σ ≈ 0.074 N/m, ρ = 1025 kg/m³.
pub const SURFACE_TENSION: f32 = 0.074 / 1025.0;

/// Width of the absorbing band at each edge, as a fraction of the side.
pub const SPONGE_FRACTION: f32 = 0.125;

/// Foam's e-folding time (s): whitewater from a splash lasts a few seconds.
pub const FOAM_LIFETIME_S: f32 = 3.0;

/// Slope of the layer's waves above which they whiten (steep ripples breaking).
pub const FOAM_SLOPE: f32 = 0.35;

/// The layer's size, resolution and step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InteractionConfig {
    /// Cells a side (a power of two, 64..=512).
    pub cells: GridSize,
    /// Side of one cell (m).
    pub cell_m: f32,
    /// Fixed step (s): the physics step where bodies drive it.
    pub dt: f32,
    /// Gravity (m/s²).
    pub gravity: f32,
}

impl InteractionConfig {
    /// The default layer: 256² cells of 0.16 m (41 m a side: waves down to 0.32 m, a thrown
    /// crate's rings and a boat's wake within ~15 m of the viewer), stepped at `dt`.
    pub fn default_with_dt(dt: f32) -> Result<Self, ParamError> {
        Self::new(256, 0.16, dt)
    }

    /// Checks and builds a configuration.
    pub fn new(cells: u32, cell_m: f32, dt: f32) -> Result<Self, ParamError> {
        let grid = GridSize::new(cells)?;
        if !(64..=512).contains(&cells) {
            return Err(ParamError::new(
                "interaction cells",
                cells as f64,
                "a power of two from 64 to 512",
            ));
        }
        if !(cell_m.is_finite() && (0.02..=2.0).contains(&cell_m)) {
            return Err(ParamError::new(
                "interaction cell size",
                cell_m as f64,
                "0.02 to 2 (m)",
            ));
        }
        if !(dt.is_finite() && dt > 0.0 && dt <= 0.1) {
            return Err(ParamError::new(
                "interaction step",
                dt as f64,
                "a time step > 0 and <= 0.1 (s)",
            ));
        }
        Ok(Self {
            cells: grid,
            cell_m,
            dt,
            gravity: 9.81,
        })
    }

    /// Side of the layer (m).
    pub fn side_m(&self) -> f32 {
        self.cells.n() as f32 * self.cell_m
    }

    /// Width of the absorbing band (cells).
    pub fn sponge_cells(&self) -> usize {
        ((self.cells.n() as f32 * SPONGE_FRACTION).round() as usize).max(4)
    }
}
