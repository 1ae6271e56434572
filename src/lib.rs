//! vr-ocean: an endless FFT ocean for OpenXR headsets.
//!
//! Data flows one way: [`sim`] (CPU ocean fields) → [`lod`] (quadtree geometry) → [`render`]
//! (Vulkan) → [`xr`] (the frame loop's backends), tied together by [`app`]. See
//! `ARCHITECTURE.md`.

#![warn(missing_docs)]

pub mod app;
pub mod bench;
pub mod export;
pub mod lod;
pub mod render;
pub mod sim;
pub mod xr;
