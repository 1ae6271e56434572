//! The simulation's laws (the thesis's equations, checked against closed forms) and its derivative modes; also run for aarch64 under qemu (the NEON path).

#[path = "../common/mod.rs"]
mod common;

mod derivatives;
mod physics;
