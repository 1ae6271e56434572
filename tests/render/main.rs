//! The renderer on lavapipe with the validation layer: the images it makes and judges, its clean-up on every error path, its command line and shaders. The `#[ignore]`d tests run in the Monado step's trixie root (Mesa 25).

#[path = "../common/mod.rs"]
mod common;

mod aliasing;
mod anisotropy;
mod bodies;
mod cleanup;
mod cli;
mod foam;
mod images;
mod interaction;
mod look;
mod panel;
mod shaders;
mod sky;
mod underwater;
mod water;
