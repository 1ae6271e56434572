//! Frame statistics of a session: how often `xrWaitFrame` returned, the spacing of predicted
//! display times, frames submitted and skipped, and the session's [`Summary`] line that logs
//! and tests read.

use std::time::Instant;

use openxr as xr;

use super::lifecycle::{ExitReason, Lifecycle};
use crate::xr::gpu_governor::QualityStep;

/// What a session did, for logs and tests.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// `xrWaitFrame` calls that returned.
    pub frames_waited: u64,
    /// Frames ended with a projection layer.
    pub frames_submitted: u64,
    /// Frames the runtime did not want rendered (`shouldRender` false or poses invalid).
    pub frames_not_rendered: u64,
    /// The session states in order, `IDLE>READY>...`.
    pub states: String,
    /// Mean spacing of predicted display times (ms).
    pub mean_period_ms: f64,
    /// Median wall time between `xrWaitFrame` returns (ms).
    pub wait_p50_ms: f64,
    /// 99th percentile of the same (ms).
    pub wait_p99_ms: f64,
    /// Why the session ended (`None`: still running or set-up failed).
    pub exit: Option<ExitReason>,
    /// The runtime's name and version.
    pub runtime: String,
    /// Per-eye image size.
    pub eye_size: (u32, u32),
    /// Colour format.
    pub colour_format: String,
    /// Whether depth is submitted.
    pub depth: bool,
    /// The reference space (STAGE or LOCAL).
    pub space: String,
    /// Display refresh rate asked for, if the runtime supports choosing.
    pub refresh_rate: Option<f32>,
    /// The GPU-time governor's level (`None`: off).
    pub governor: Option<QualityStep>,
    /// The GPU-time governor's level changes.
    pub governor_changes: u32,
    /// Frames submitted with the control panel's quad layer.
    pub frames_with_panel: u64,
    /// Images of the panel's swapchain acquired (once per change of the panel).
    pub panel_images: u64,
    /// The user floating in the water (`FloatStats`).
    pub afloat: FloatStats,
}

/// Frames shown with the user in the water, and how the eyes rode the sea: the eyes' mean
/// height over the sea under the head, and over the mean level (both in cm, least and most),
/// after the first [`FloatStats::SETTLE`] frames in the water (the ride settles from the
/// deck's height).
#[derive(Clone, Copy, Debug, Default)]
pub struct FloatStats {
    /// Rendered frames in the water.
    pub frames: u64,
    /// Eyes over the sea under the head (cm), least and most.
    pub over_water_cm: Option<(f32, f32)>,
    /// Eyes over the mean level (cm), least and most.
    pub height_cm: Option<(f32, f32)>,
}

impl FloatStats {
    /// Frames in the water only counted: a second at 72 Hz.
    pub const SETTLE: u64 = 72;

    /// A rendered frame in the water: the eyes at `eyes` m, the sea under the head at
    /// `surface` m (when reported).
    pub fn observe(&mut self, eyes: f32, surface: Option<f32>) {
        let settled = self.frames >= Self::SETTLE;
        self.frames += 1;
        let widen = |r: Option<(f32, f32)>, v: f32| {
            Some(r.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
        };
        if let (true, Some(s)) = (settled, surface) {
            self.over_water_cm = widen(self.over_water_cm, 100.0 * (eyes - s));
            self.height_cm = widen(self.height_cm, 100.0 * eyes);
        }
    }

    /// `lo..hi` in cm, or `n/a`.
    fn range(r: Option<(f32, f32)>) -> String {
        r.map_or("n/a".to_string(), |(lo, hi)| format!("{lo:.1}..{hi:.1}"))
    }
}

impl Summary {
    /// One line for the log: `key=value` pairs.
    pub fn line(&self) -> String {
        format!(
            "frames_waited={} frames_submitted={} frames_not_rendered={} states={} \
             mean_period_ms={:.3} wait_p50_ms={:.3} wait_p99_ms={:.3} exit={:?} eye={}x{} \
             format={} depth={} space={} refresh_hz={} gpu_governor={} \
             gpu_governor_changes={} frames_with_panel={} panel_images={} afloat_frames={} \
             eyes_over_water_cm={} eye_height_cm={} runtime=\"{}\"",
            self.frames_waited,
            self.frames_submitted,
            self.frames_not_rendered,
            self.states,
            self.mean_period_ms,
            self.wait_p50_ms,
            self.wait_p99_ms,
            self.exit,
            self.eye_size.0,
            self.eye_size.1,
            self.colour_format,
            self.depth,
            self.space,
            self.refresh_rate
                .map_or("n/a".to_string(), |r| format!("{r}")),
            self.governor.map_or("off", |g| g.name()),
            self.governor_changes,
            self.frames_with_panel,
            self.panel_images,
            self.afloat.frames,
            FloatStats::range(self.afloat.over_water_cm),
            FloatStats::range(self.afloat.height_cm),
            self.runtime
        )
    }
}

/// Sample capacity for the frame spacing statistics (preallocated: no allocation per frame).
const WAIT_SAMPLES: usize = 1 << 16;

/// Running statistics of the frame loop.
pub(super) struct FrameStats {
    /// What the summary says besides the computed figures.
    pub summary: Summary,
    waits_ms: Vec<f64>,
    last_wait: Option<Instant>,
    first_time: Option<xr::Time>,
    last_time: Option<xr::Time>,
    period_sum: f64,
    period_count: u64,
}

impl FrameStats {
    /// Empty statistics, with the session's fixed facts in `summary`.
    pub fn new(summary: Summary) -> Self {
        Self {
            summary,
            waits_ms: Vec::with_capacity(WAIT_SAMPLES),
            last_wait: None,
            first_time: None,
            last_time: None,
            period_sum: 0.0,
            period_count: 0,
        }
    }

    /// `xrWaitFrame` returned now.
    pub fn waited(&mut self) {
        let now = Instant::now();
        if let Some(last) = self.last_wait {
            if self.waits_ms.len() < WAIT_SAMPLES {
                self.waits_ms
                    .push(now.duration_since(last).as_secs_f64() * 1e3);
            }
        }
        self.last_wait = Some(now);
        self.summary.frames_waited += 1;
    }

    /// A frame begun for display at `time`; returns the seconds since the first frame's
    /// display time (the simulation time).
    pub fn display_time(&mut self, time: xr::Time) -> f64 {
        let first = *self.first_time.get_or_insert(time);
        if let Some(last) = self.last_time {
            let d = (time.as_nanos() - last.as_nanos()) as f64 * 1e-9;
            if d > 0.0 {
                self.period_sum += d;
                self.period_count += 1;
            }
        }
        self.last_time = Some(time);
        (time.as_nanos() - first.as_nanos()) as f64 * 1e-9
    }

    /// The summary so far, with the state history of `lifecycle`.
    pub fn summary(&self, lifecycle: &Lifecycle) -> Summary {
        let mut s = self.summary.clone();
        let mut states = String::new();
        lifecycle.history_text(&mut states);
        s.states = states;
        s.mean_period_ms = if self.period_count > 0 {
            self.period_sum / self.period_count as f64 * 1e3
        } else {
            0.0
        };
        let mut w = self.waits_ms.clone();
        w.sort_by(f64::total_cmp);
        let pick = |q: f64| {
            if w.is_empty() {
                0.0
            } else {
                w[((w.len() - 1) as f64 * q).round() as usize]
            }
        };
        s.wait_p50_ms = pick(0.5);
        s.wait_p99_ms = pick(0.99);
        s
    }
}
