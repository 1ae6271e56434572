//! What a viewing command reports at the end: the Vulkan validation errors of the whole session
//! (shutdown included, so leaked objects count) and, for headless runs, `frame_times.json`.

use std::path::Path;
use std::sync::Arc;

use serde::Serialize;

use vr_ocean::app::{FrameTimes, RunReport};
use vr_ocean::export;
use vr_ocean::render::{GpuContext, ValidationLog};

/// What a command returns: an error is printed as one line and the process exits non-zero.
pub type CmdResult = Result<(), Box<dyn std::error::Error>>;

/// The validation log of a session's device, kept past the device's destruction.
pub struct ValidationWatch(Option<Arc<ValidationLog>>);

impl ValidationWatch {
    /// Watches `gpu`'s validation messages (nothing without the layer).
    pub fn of(gpu: &GpuContext) -> Self {
        Self(gpu.validation.clone())
    }

    /// An error when the layer reported any; call after the device is gone.
    pub fn check(&self) -> CmdResult {
        let errors = self.0.as_ref().map_or(0, |v| v.errors());
        if errors > 0 {
            return Err(format!("{errors} Vulkan validation errors").into());
        }
        Ok(())
    }
}

/// `frame_times.json` of a headless run.
#[derive(Serialize)]
struct FrameTimesFile<'a> {
    device: &'a str,
    frames: u64,
    stereo: &'a str,
    max_draws: u32,
    mean_triangles: f64,
    timings_ms: &'a FrameTimes,
}

/// Writes `frame_times.json` for `report` into `path`, atomically.
pub fn write_frame_times(path: &Path, report: &RunReport, stereo: &str) -> CmdResult {
    let file = FrameTimesFile {
        device: &report.device,
        frames: report.frames,
        stereo,
        max_draws: report.max_draws,
        mean_triangles: report.mean_triangles,
        timings_ms: &report.times,
    };
    let mut json = serde_json::to_string_pretty(&file)?;
    json.push('\n');
    export::write_bytes(path, json.as_bytes())?;
    Ok(())
}
