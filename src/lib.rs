//! vr-ocean: an endless FFT ocean for OpenXR headsets.
//!
//! Data flows one way: [`sim`] (CPU ocean fields) → [`lod`] (quadtree geometry) → render → xr. See `ARCHITECTURE.md`.

pub mod app;
pub mod bench;
pub mod export;
pub mod lod;
pub mod render;
pub mod sim;
pub mod xr;
