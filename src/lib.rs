//! vr-ocean: an endless FFT ocean for OpenXR headsets.
//!
//! Layers, each naming only those before it (`tests/tidy.rs` checks): [`base`] (vocabulary);
//! [`sim`] (the CPU ocean) and [`lod`] (quadtree geometry, on `base` alone); [`physics`] (the
//! bodies floating on the sea) and [`audio`] (its synthesized sound), both reading [`sim`];
//! [`ui`] (the settings kept and the panel); [`render`] (Vulkan); [`xr`] (the frame loop's
//! backends: OpenXR, the window, headless); [`app`] ties them into one loop. [`android`] is
//! the Quest APK's edge (`android_main`); [`export`] and [`bench`](mod@bench) are the command line's tools
//! on [`sim`]. See `ARCHITECTURE.md`.

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
