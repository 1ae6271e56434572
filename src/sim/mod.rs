//! The CPU ocean core: spectrum, time evolution, inverse FFT, surface fields, mips, cascades,
//! height queries. No Vulkan or XR here; the outputs are plain buffers in GPU upload formats.
//!
//! Stages (thesis Table 1): [`spectrum`] (1, on demand) → [`evolve`] (2) → [`fft`] (3-4) →
//! [`surface`] (5-6+, with [`pack`]), scheduled by [`step`].
//!
//! # Conventions
//! - Texel (col, row) of a cascade sits at world (x, z) = (col, row)·L/N; its wave vector is
//!   k = 2π/L·(col − N/2, row − N/2) (eq. 2), the centring undone by (−1)^(x+y) after the FFT,
//!   which computes Σ X·e^{+ik·x} unnormalized. DC and the Nyquist row and column are zero, so
//!   every field spectrum is exactly Hermitian.
//! - Each wave component travels along +k (the thesis's S' of eq. 22 evaluates eq. 17 at −φ; a
//!   single-mode test pins this), and choppy displacement gathers points under the crests
//!   ([`evolve`]).
//! - Cascades own disjoint wave-number bands ([`spectrum::cascade_bands`]), so summing them
//!   never double-counts energy; patch sizes are strictly decreasing.
//!
//! # Determinism
//! Spectra are generated per index (integer hash + software `libm`), so a seed gives
//! bit-identical h₀ on every platform and thread count (a fingerprint test runs on x86-64 and
//! aarch64). Every parallel stage is element-wise or writes disjoint rows; the one reduction
//! (max displacement) is order-independent: output is bit-identical for 1, 2 and 4 threads.
//! Element-wise kernels use no FMA and only correctly rounded operations (magic-number
//! rounding instead of `round`), so every [`simd`] tier gives the same bits; the FFT backends
//! may differ in the last bits (FMA on AVX2/AVX-512/NEON).
//!
//! # No allocation per step
//! [`SimCore`] owns every buffer; [`Simulation`] runs its worker as one long-lived job in its
//! Rayon pool and hands the two [`Surfaces`] back and forth through a mutex/condvar slot.
//!
//! # Threads
//! A step's fork-joins are short (20-50 µs each at N = 256), so [`SimCore::step`] keeps the
//! pool's other threads awake for its length ([`awake`]) instead of letting each fork-join wake
//! a sleeping worker.

pub mod awake;
mod cascade;
pub mod config;
pub mod detail;
pub mod dispersion;
pub mod drift;
pub mod evolve;
pub mod fft;
pub mod grid;
pub mod interaction;
pub mod output;
pub mod pack;
pub mod params;
pub mod query;
pub mod retune;
pub mod simd;
pub mod spectrum;
pub mod step;
pub mod surface;
pub mod trig;
mod tuning;
pub mod whitecaps;
pub mod workers;

pub use cascade::StageTimes;
pub use config::{OceanConfig, PatchFit, DEFAULT_PATCH_SIZES};
pub use dispersion::GRAVITY;
pub use grid::{AlignedBuf, GridSize, SplitField, Support};
pub use params::{
    Derivatives, FoamParams, SeaState, SpectrumKind, WaveParams, DEFAULT_DERIVATIVES,
    DEFAULT_FETCH_KM, DEFAULT_GAMMA,
};
pub use step::{SimCore, SimError, Simulation, Surfaces};
