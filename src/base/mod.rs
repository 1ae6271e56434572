//! Vocabulary shared by every layer (sim, lod, render, xr, app): the typed parameter error and
//! the eye views. Nothing here depends on any layer, so every layer may use it.

pub mod param;
pub mod view;

pub use param::ParamError;
pub use view::{EyeView, Fov};
