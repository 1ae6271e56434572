//! The CPU ocean core: spectrum, time evolution, inverse FFT, surface fields, mips, cascades,
//! height queries. No Vulkan or XR here; the outputs are plain buffers in GPU upload formats.
//!
//! Stages (thesis Table 1): [`spectrum`] (1, on demand) → [`evolve`] (2) → [`fft`] (3-4) →
//! [`surface`] (5-6+, with [`pack`]), scheduled by [`step`].

pub mod dispersion;
pub mod evolve;
pub mod fft;
pub mod grid;
pub mod pack;
pub mod params;
pub mod query;
pub mod simd;
pub mod spectrum;
pub mod step;
pub mod surface;
pub mod trig;
pub mod workers;

pub use grid::{AlignedBuf, GridSize, SplitField};
pub use params::{FoamParams, OceanConfig, SpectrumKind, WaveParams};
pub use step::{SimCore, SimError, Simulation, StageTimes, Surfaces};
