//! vr-ocean: an endless FFT ocean for OpenXR headsets.
//!
//! Data flows one way: [`sim`] (CPU ocean fields) → [`lod`] (quadtree geometry) → [`render`]
//! (Vulkan) → [`xr`] (the frame loop's backends), tied together by [`app`]; [`physics`] (the
//! bodies floating on the sea) reads [`sim`] beside [`lod`]. [`android`] is the Quest APK's
//! edge (`android_main`). See `ARCHITECTURE.md`.

#![warn(missing_docs)]
#![warn(clippy::undocumented_unsafe_blocks)]

pub mod android;
pub mod app;
pub mod audio;
pub mod base;
pub mod bench;
pub mod export;
pub mod lod;
pub mod physics;
pub mod render;
pub mod sim;
pub mod ui;
pub mod xr;
