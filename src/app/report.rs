//! What a run measured and ended with ([`RunReport`]), returned by [`crate::app::run`].

use super::chosen;
use super::govern::GovernorChange;
use super::sound::SoundReport;
use super::timing::FrameTimes;

/// What a run measured.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Frames rendered.
    pub frames: u64,
    /// Per-frame timings (warm-up frames excluded).
    pub times: FrameTimes,
    /// Most draws recorded in one frame.
    pub max_draws: u32,
    /// Mean triangles drawn per timed frame (patches and skirt, both eyes' union), from the
    /// LOD: a measure of geometry cost that does not depend on the machine.
    pub mean_triangles: f64,
    /// Device memory of the renderer's transient attachments (multisampled colour and depth,
    /// or the depth alone), bytes.
    pub attachment_bytes: u64,
    /// Validation errors reported during the run (0 without the layer).
    pub validation_errors: u32,
    /// The device's name.
    pub device: String,
    /// The GPU-time governor's level changes, in order (empty when it is off).
    pub governor: Vec<GovernorChange>,
    /// The shading paths and invocations counted per frame, when the renderer counted them
    /// ([`crate::render::RendererSettings::count_paths`]).
    pub paths: Option<crate::render::budget::PathCounts>,
    /// What the sound output did, when the run had sound.
    pub audio: Option<SoundReport>,
    /// What the user had chosen by the end (waves, preset, sky).
    pub chosen: chosen::Chosen,
}
