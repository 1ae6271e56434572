//! The app as a user drives it: the command line, the settings kept, the panel, pauses, sea-state changes, the window (under xvfb-run), the GPU-time governor.

#[path = "../common/mod.rs"]
mod common;

mod audio_cli;
mod cli;
mod gpu_governor;
mod keep;
mod panel;
mod pause;
mod sea_state;
mod sea_state_blend;
mod settings;
mod window;
mod xr_cli;
