//! The simulation's laws (the thesis's equations, checked against closed forms) and its
//! derivative modes; also run for aarch64 under qemu (the NEON path).
//!
//! - [`waves`]: one wave's shape and motion (loop period, phase speed, trochoid, crests).
//! - [`spectrum`]: what the spectrum carries (a real field, Parseval's variance, Cox & Munk's
//!   slopes).
//! - [`determinism`]: the same bits for any thread count, SIMD tier, sparse path, float copies.
//! - [`queries`]: height queries land on the surface.
//! - [`foam`]: foam grows where waves break and decays.
//! - [`extremes`]: every valid parameter at its extreme stays finite.
//! - [`derivatives`]: the two derivative modes.
//! - [`helpers`]: what the law tests share (a cascade's spec, one step, an RMS).

#[path = "../common/mod.rs"]
mod common;

mod derivatives;
mod determinism;
mod extremes;
mod foam;
mod helpers;
mod queries;
mod spectrum;
mod waves;
