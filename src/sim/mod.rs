//! The CPU ocean core: spectrum, time evolution, inverse FFT, surface fields, mips, cascades.
//! No Vulkan or XR here; the outputs are plain buffers in GPU upload formats.

pub mod error;
pub mod fft;
pub mod grid;

pub use error::ParamError;
pub use grid::{AlignedBuf, GridSize, SplitField};
pub mod dispersion;
pub mod params;
pub mod spectrum;

pub use params::{FoamParams, OceanConfig, SpectrumKind, WaveParams};
pub mod evolve;
pub mod trig;
