//! Long runs that watch a process for growth (resident memory, open files): each measures the
//! whole process, so they live in a target of their own, where nothing else runs beside them.
//! `render`: ten thousand headless frames (the host step); `monado`: the OpenXR session soak
//! against Monado (`#[ignore]`d, the Monado step).

#[path = "../common/mod.rs"]
mod common;

mod monado;
mod render;
