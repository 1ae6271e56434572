//! What the APK starts with. A Quest app has no command line, so these are the defaults of
//! `vr-ocean xr` with the Quest's choices: the Medium preset (the controller cycles presets),
//! no validation layer (the APK ships none), 256² cascades over a 2048 m ocean.

use crate::app::RunOptions;
use crate::lod::{LodSettings, OceanSize, QualityPreset};
use crate::render::{RendererSettings, Validation};
use crate::sim::{OceanConfig, ParamError};
use crate::xr::openxr::OpenXrOptions;

/// The FFT grid of each cascade on Quest.
pub const QUEST_GRID: u32 = 256;

/// Ocean size S (m) the quadtree covers on Quest.
pub const QUEST_OCEAN_SIZE: f32 = 2048.0;

/// The quality preset the APK starts with.
pub const QUEST_PRESET: QualityPreset = QualityPreset::Medium;

/// Simulation workers when the device does not say how many cores it has.
pub const FALLBACK_THREADS: usize = 2;

/// Frames at the start left out of the timing statistics.
pub const WARMUP_FRAMES: u64 = 10;

/// The frame loop's and the OpenXR backend's settings on Quest; `cores` is what
/// `std::thread::available_parallelism` reported (`None` when it could not tell). The
/// simulation gets one thread per core but one (the render thread's), at least one.
pub fn quest_options(cores: Option<usize>) -> Result<(RunOptions, OpenXrOptions), ParamError> {
    let threads = cores.map_or(FALLBACK_THREADS, |n| n.saturating_sub(1).max(1));
    let run = RunOptions {
        ocean: OceanConfig::default_cascades(QUEST_GRID)?,
        threads,
        lod: LodSettings::new(QUEST_PRESET, OceanSize::new(QUEST_OCEAN_SIZE)?),
        renderer: RendererSettings::default(),
        capture: Vec::new(),
        warmup: WARMUP_FRAMES,
    };
    let xr = OpenXrOptions {
        validation: Validation::Off,
        preset: QUEST_PRESET,
        ..OpenXrOptions::default()
    };
    Ok((run, xr))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quest_options_are_valid_and_consistent() {
        let (run, xr) = quest_options(Some(8)).unwrap();
        run.ocean.validate().unwrap();
        assert_eq!(run.threads, 7);
        assert_eq!(run.lod.preset(), xr.preset);
        assert_eq!(xr.validation, Validation::Off);
        assert_eq!(xr.frames, None, "the headset app runs until the user quits");
        assert!(run.capture.is_empty());
        assert_eq!(quest_options(Some(1)).unwrap().0.threads, 1);
        assert_eq!(quest_options(None).unwrap().0.threads, FALLBACK_THREADS);
    }
}
