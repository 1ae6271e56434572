//! The floating bodies: hydrostatics, waves, wakes, the hands, stability in storms, bad input.

#[path = "../common/mod.rs"]
mod common;

mod bad_input;
mod hydrostatics;
mod interact;
mod stability;
mod wakes;
mod waves;
