//! The GPU-time governor's edge in the app: feeds [`GpuGovernor`] the pass's GPU time once a
//! rendered frame, and applies its levels to what the app owns (the renderer's specular AA
//! and render area, the LOD preset) and to the backend (foveation, the shown image rect).
//!
//! The state machine is pure and lives in [`crate::xr::gpu_governor`]; this file only turns
//! its levels into settings. A level is applied whole (every knob set from it), so stepping
//! up and down take the same path. All of it is off unless [`GovernorOptions::enabled`]:
//! the OpenXR path turns it on, the desktop views on request (on lavapipe every frame is far
//! over any headset's budget).

use std::time::Duration;

use crate::lod::QualityPreset;
use crate::render::ocean::{Anisotropy, RendererSettings};
use crate::render::{OceanRenderer, RenderError};
use crate::xr::gpu_governor::{
    render_rect_share, GovernorCaps, GovernorState, GpuGovernor, QualityStep,
};
use crate::xr::render_scale::{scaled_rect, RenderScales};
use crate::xr::{FrameLoop, FrameState};

/// Most level changes a run's history keeps (allocated once; later changes are only logged).
pub const HISTORY: usize = 1024;

/// Whether and how the GPU-time governor runs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GovernorOptions {
    /// Run it (the OpenXR path's default; off in the desktop views unless asked for).
    pub enabled: bool,
    /// The GPU budget per frame; `None`: the frame period the backend reports. The desktop
    /// sets one to test the governor on a device much slower or faster than a headset.
    pub budget: Option<Duration>,
    /// Time added to the measured GPU pass time (a test fault).
    pub fault: Option<GpuFault>,
}

/// Known GPU time added to the measured pass time of frames displayed from `from` to `to`
/// seconds (`--fault-gpu-ms MS@FROM-TO`). It is an injected *measurement*, not GPU work: the
/// governor sees a slower pass, the GPU does nothing more, so a test can script a load and its
/// removal on any device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuFault {
    /// Added to each affected frame's GPU time.
    pub extra: Duration,
    /// First affected display time (s).
    pub from: f64,
    /// End of the affected display times (s, exclusive).
    pub to: f64,
}

/// A `--fault-gpu-ms` value that could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaultSpecError {
    /// What was given.
    pub spec: String,
    /// What is wrong with it.
    pub why: &'static str,
}

impl std::fmt::Display for FaultSpecError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "--fault-gpu-ms {:?}: {} (expected MS@FROM-TO, e.g. 30@2-5: 30 ms added to the \
             measured GPU time of frames shown from 2 s to 5 s)",
            self.spec, self.why
        )
    }
}

impl std::error::Error for FaultSpecError {}

impl GpuFault {
    /// Reads `MS@FROM-TO`: milliseconds in (0, 10000], seconds 0 ≤ FROM < TO.
    pub fn parse(spec: &str) -> Result<Self, FaultSpecError> {
        let err = |why| FaultSpecError {
            spec: spec.to_string(),
            why,
        };
        let (ms, range) = spec.split_once('@').ok_or_else(|| err("no '@'"))?;
        let (from, to) = range
            .split_once('-')
            .ok_or_else(|| err("no '-' in FROM-TO"))?;
        let num = |s: &str, what| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| err(what))
        };
        let ms = num(ms, "MS is not a number")?;
        let (from, to) = (
            num(from, "FROM is not a number")?,
            num(to, "TO is not a number")?,
        );
        if !(ms > 0.0 && ms <= 10_000.0) {
            return Err(err("MS must be in (0, 10000]"));
        }
        if !(from >= 0.0 && from < to) {
            return Err(err("the times must satisfy 0 <= FROM < TO"));
        }
        Ok(Self {
            extra: Duration::from_secs_f64(ms * 1e-3),
            from,
            to,
        })
    }

    /// What it adds to a frame displayed at `time` (s).
    pub fn extra_at(&self, time: f64) -> Duration {
        if (self.from..self.to).contains(&time) {
            self.extra
        } else {
            Duration::ZERO
        }
    }
}

/// One change of level, for the run's report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GovernorChange {
    /// The frame's display time (s).
    pub time: f64,
    /// The frame's number.
    pub frame: u64,
    /// The new level.
    pub level: QualityStep,
}

/// The governor of a run and what its levels are applied from.
pub(super) struct Governed {
    governor: GpuGovernor,
    options: GovernorOptions,
    /// The user's supersampling setting (the level only ever turns it off).
    supersampling: bool,
    /// The user's preset (the level lowers it by one at most).
    pub preset: QualityPreset,
    /// The eye images' and the configured drawn share of the recommended eye size
    /// (`GovernorCaps::render_rect`; whole images where the backend shows no sub-rectangle).
    scales: RenderScales,
    /// The changes so far (capacity [`HISTORY`], never grown).
    pub history: Vec<GovernorChange>,
}

/// The preset below `p` (`None` at the lowest).
pub fn lower_preset(p: QualityPreset) -> Option<QualityPreset> {
    match p {
        QualityPreset::Low => None,
        QualityPreset::Medium => Some(QualityPreset::Low),
        QualityPreset::High => Some(QualityPreset::Medium),
        QualityPreset::Ultra => Some(QualityPreset::High),
    }
}

impl Governed {
    /// The governor for `xr`'s abilities, or `None` when `options` turn it off.
    pub fn new(
        options: GovernorOptions,
        xr: &dyn FrameLoop,
        preset: QualityPreset,
        renderer: &RendererSettings,
    ) -> Option<Self> {
        if !options.enabled {
            return None;
        }
        let caps = GovernorCaps {
            supersampling: renderer.supersampling || renderer.anisotropy != Anisotropy::Off,
            lod: lower_preset(preset).is_some(),
            ..xr.governor_caps()
        };
        log::info!(
            "GPU-time governor on (budget {}; steps: supersampling {}, foveation {}, render \
             scale {}, LOD {})",
            options
                .budget
                .map_or("the frame period".to_string(), |b| format!("{b:?}")),
            caps.supersampling,
            caps.foveation,
            caps.render_rect.map_or("no".to_string(), |s| format!(
                "{} of the recommended size in images of {}",
                s.start, s.images
            )),
            caps.lod
        );
        Some(Self {
            governor: GpuGovernor::new(caps),
            options,
            supersampling: renderer.supersampling,
            preset,
            scales: caps.render_rect.unwrap_or(RenderScales::whole(1.0)),
            history: Vec::with_capacity(HISTORY),
        })
    }

    /// The level now.
    pub fn level(&self) -> QualityStep {
        self.governor.level()
    }

    /// The governor's state (level, changes, whether levels are left).
    pub fn state(&self) -> GovernorState {
        self.governor.state()
    }

    /// Feeds one rendered frame's GPU pass time (plus the fault, if any); the new level
    /// when it changes (logged and kept in the history).
    pub fn observe(&mut self, frame: &FrameState, gpu: Option<Duration>) -> Option<QualityStep> {
        let time = frame.predicted_display_time;
        let gpu = gpu.map(|g| {
            g + self
                .options
                .fault
                .map_or(Duration::ZERO, |f| f.extra_at(time))
        });
        let period = self
            .options
            .budget
            .map_or(frame.period, |b| b.as_secs_f64());
        let before = self.governor.level();
        let level = self.governor.observe(gpu, period, time)?;
        let state = self.governor.state();
        let how = if level > before { "over" } else { "within" };
        log::warn!(
            "GPU time {how} budget: quality {} -> {} at {time:.2} s ({} changes)",
            before.name(),
            level.name(),
            state.changes
        );
        if self.history.len() < self.history.capacity() {
            self.history.push(GovernorChange {
                time,
                frame: frame.index,
                level,
            });
        }
        Some(level)
    }

    /// The preset the level asks for.
    pub fn preset_for(&self, level: QualityStep) -> QualityPreset {
        if level >= QualityStep::LodDown {
            lower_preset(self.preset).unwrap_or(self.preset)
        } else {
            self.preset
        }
    }

    /// Applies the level's renderer and backend settings (the preset is the caller's: it
    /// rebuilds the renderer) and tells the backend the governor's state.
    pub fn apply(
        &self,
        level: QualityStep,
        renderer: &mut OceanRenderer,
        xr: &mut dyn FrameLoop,
    ) -> Result<(), RenderError> {
        renderer.set_supersampling(self.supersampling && level < QualityStep::NoSupersampling);
        renderer.set_anisotropic(level < QualityStep::NoSupersampling);
        let boost = level >= QualityStep::FoveationUp;
        if !xr.set_foveation_boost(boost) && boost && xr.governor_caps().foveation {
            log::warn!("GPU-time governor: the foveation change was not applied");
        }
        let share = render_rect_share(level, self.scales);
        let rect = scaled_rect(xr.targets().extent, share);
        if xr.set_render_rect(rect) {
            renderer.set_render_area(rect)?;
        }
        xr.report_governor(self.governor.state());
        Ok(())
    }
}
