//! Frame-time samples and their percentiles, collected without allocating per frame and
//! written as `frame_times.json`, and the run's other counts (`RunStats`).

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use crate::lod::QualityPreset;
use crate::sim::WaveParams;
use crate::xr::gpu_governor::QualityStep;

/// What the loop measures: the timings, draws and the window's statistics line.
pub(super) struct RunStats {
    pub times: FrameTimes,
    pub max_draws: u32,
    /// Triangles drawn over the timed frames, and how many frames that is.
    pub triangles: u64,
    pub triangle_frames: u64,
    pub frames: u64,
    pub recent: RecentFrames,
    pub text: String,
    pub shown_at: Instant,
}

impl RunStats {
    /// Nothing measured yet; room for 16,384 frames' timings.
    pub fn new() -> Self {
        Self {
            times: FrameTimes::with_capacity(16_384),
            max_draws: 0,
            triangles: 0,
            triangle_frames: 0,
            frames: 0,
            recent: RecentFrames::default(),
            text: String::with_capacity(256),
            shown_at: Instant::now(),
        }
    }
}

/// The timings each frame records.
pub const TIMINGS: [&str; 7] = [
    "frame_total",
    "sim_step",
    "sim_wait",
    "lod",
    "record",
    "submit",
    "gpu_pass",
];

/// Index into [`TIMINGS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timing {
    /// From the start of `begin_frame` to the end of `end_frame`.
    FrameTotal,
    /// The simulation worker's step (runs in parallel with rendering).
    SimStep,
    /// How long the render thread waited for the step to finish.
    SimWait,
    /// LOD update (traversal, culling, batching).
    Lod,
    /// Uniforms, instances, staging copies and command recording.
    Record,
    /// `vkQueueSubmit`.
    Submit,
    /// GPU time of the ocean pass (timestamps).
    GpuPass,
}

/// Up to `capacity` samples per timing, in milliseconds; later samples overwrite the oldest.
#[derive(Clone, Debug)]
pub struct FrameTimes {
    samples: Vec<Vec<f64>>,
    capacity: usize,
    next: [usize; 7],
    count: [u64; 7],
}

/// Percentiles of one timing (ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Samples behind them.
    pub samples: usize,
}

impl FrameTimes {
    /// Room for `capacity` frames, allocated now.
    pub fn with_capacity(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            samples: (0..TIMINGS.len())
                .map(|_| Vec::with_capacity(capacity))
                .collect(),
            capacity,
            next: [0; 7],
            count: [0; 7],
        }
    }

    /// Records one sample.
    pub fn push(&mut self, t: Timing, d: Duration) {
        let i = t as usize;
        let ms = d.as_secs_f64() * 1e3;
        let v = &mut self.samples[i];
        if v.len() < self.capacity {
            v.push(ms);
        } else {
            v[self.next[i]] = ms;
        }
        self.next[i] = (self.next[i] + 1) % self.capacity;
        self.count[i] += 1;
    }

    /// The samples of timing `t` (ms), oldest first until the buffer wraps.
    pub fn samples(&self, t: Timing) -> &[f64] {
        &self.samples[t as usize]
    }

    /// Adds every sample of `other` (e.g. several runs of one scenario).
    pub fn merge(&mut self, other: &FrameTimes) {
        use Timing::*;
        for t in [FrameTotal, SimStep, SimWait, Lod, Record, Submit, GpuPass] {
            for &ms in other.samples(t) {
                self.push(t, std::time::Duration::from_secs_f64(ms / 1e3));
            }
        }
    }

    /// Percentiles of timing `t` (nearest rank); all zero without samples.
    pub fn percentiles(&self, t: Timing) -> Percentiles {
        let mut v = self.samples[t as usize].clone();
        if v.is_empty() {
            return Percentiles::default();
        }
        v.sort_by(f64::total_cmp);
        let at = |p: f64| v[((p * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
        Percentiles {
            p50: at(0.50),
            p95: at(0.95),
            p99: at(0.99),
            samples: v.len(),
        }
    }

    /// Every timing's percentiles, in [`TIMINGS`] order.
    pub fn all(&self) -> [Percentiles; 7] {
        use Timing::*;
        [FrameTotal, SimStep, SimWait, Lod, Record, Submit, GpuPass].map(|t| self.percentiles(t))
    }
}

/// Serialized as `{"frame_total": {"p50": …, "p95": …, "p99": …, "samples": …}, …}` (ms).
impl serde::Serialize for FrameTimes {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(TIMINGS.len()))?;
        for (name, p) in TIMINGS.iter().zip(self.all()) {
            map.serialize_entry(name, &p)?;
        }
        map.end()
    }
}

/// Samples kept for the title statistics.
const RECENT: usize = 64;

/// The last `RECENT` frames' timings (ms) and draw counts, for a live summary.
#[derive(Clone, Debug)]
pub struct RecentFrames {
    frame: [f64; RECENT],
    sim: [f64; RECENT],
    gpu: [f64; RECENT],
    draws: [u32; RECENT],
    len: usize,
    next: usize,
}

impl Default for RecentFrames {
    fn default() -> Self {
        Self {
            frame: [0.0; RECENT],
            sim: [0.0; RECENT],
            gpu: [0.0; RECENT],
            draws: [0; RECENT],
            len: 0,
            next: 0,
        }
    }
}

fn median(samples: &[f64]) -> f64 {
    let mut v = [0.0; RECENT];
    let v = &mut v[..samples.len()];
    v.copy_from_slice(samples);
    v.sort_unstable_by(f64::total_cmp);
    v.get(v.len().saturating_sub(1) / 2).copied().unwrap_or(0.0)
}

impl RecentFrames {
    /// Records one frame: total, simulation step, GPU pass (when timed) and draws.
    pub fn push(&mut self, frame: Duration, sim: Duration, gpu: Option<Duration>, draws: u32) {
        let i = self.next;
        self.frame[i] = frame.as_secs_f64() * 1e3;
        self.sim[i] = sim.as_secs_f64() * 1e3;
        self.gpu[i] = gpu.map_or(f64::NAN, |g| g.as_secs_f64() * 1e3);
        self.draws[i] = draws;
        self.next = (i + 1) % RECENT;
        self.len = (self.len + 1).min(RECENT);
    }

    /// The medians of the recent frames' total time and GPU pass time (ms; the GPU's `None`
    /// when no frame was timed), for the panel's performance line. Allocates nothing.
    pub fn medians(&self) -> (f64, Option<f64>) {
        let n = self.len;
        let gpu = median(&self.gpu[..n]);
        (
            median(&self.frame[..n]),
            (n > 0 && !gpu.is_nan()).then_some(gpu),
        )
    }

    /// Writes a one-line summary (p50 of each timing) into `out`, replacing its contents;
    /// allocates nothing once `out` has room for about 200 bytes.
    /// With the GPU-time governor on, `governor` is its level, shown after the preset.
    pub fn summarise(
        &self,
        out: &mut String,
        preset: QualityPreset,
        waves: &WaveParams,
        governor: Option<QualityStep>,
    ) {
        out.clear();
        let n = self.len;
        if n == 0 {
            out.push_str("warming up");
        } else {
            let frame = median(&self.frame[..n]);
            let fps = if frame > 0.0 { 1e3 / frame } else { 0.0 };
            let gpu = median(&self.gpu[..n]);
            let draws = self.draws[(self.next + RECENT - 1) % RECENT];
            let _ = write!(
                out,
                "frame {frame:.1} ms ({fps:.0} fps) | sim {:.1} ms | GPU ",
                median(&self.sim[..n])
            );
            let _ = if gpu.is_nan() {
                write!(out, "-")
            } else {
                write!(out, "{gpu:.1} ms")
            };
            let _ = write!(out, " | {draws} draws");
        }
        let _ = write!(
            out,
            " | {} | wind {:.0} m/s {:.0} deg | chop {:.2}",
            preset.name(),
            waves.wind_speed,
            waves.wind_direction_deg,
            waves.choppiness
        );
        if let Some(level) = governor {
            let _ = write!(out, " | GPU governor: {}", level.name());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_use_nearest_rank_and_keep_the_newest_samples() {
        let mut t = FrameTimes::with_capacity(100);
        for i in 1..=100 {
            t.push(Timing::Lod, Duration::from_millis(i));
        }
        let p = t.percentiles(Timing::Lod);
        assert_eq!((p.p50, p.p95, p.p99, p.samples), (50.0, 95.0, 99.0, 100));
        for _ in 0..100 {
            t.push(Timing::Lod, Duration::from_millis(1000));
        }
        assert_eq!(t.percentiles(Timing::Lod).p50, 1000.0);
        assert_eq!(t.percentiles(Timing::GpuPass), Percentiles::default());
        let json = serde_json::to_value(&t).unwrap();
        assert_eq!(json["lod"]["p50"], 1000.0);
        assert_eq!(json["lod"]["samples"], 100);
    }

    #[test]
    fn summary_shows_medians_of_recent_frames() {
        let mut r = RecentFrames::default();
        let mut s = String::with_capacity(256);
        let waves = WaveParams::default();
        r.summarise(&mut s, QualityPreset::High, &waves, None);
        assert!(s.starts_with("warming up | high"), "{s}");
        for ms in [10, 30, 20] {
            let d = Duration::from_millis(ms);
            r.push(d, d / 10, None, 12);
        }
        r.summarise(&mut s, QualityPreset::Low, &waves, None);
        assert!(!s.contains("governor"), "{s}");
        assert!(s.starts_with("frame 20.0 ms (50 fps) | sim 2.0 ms | GPU - | 12 draws | low"));
        for _ in 0..RECENT {
            r.push(
                Duration::from_millis(5),
                Duration::ZERO,
                Some(Duration::from_millis(3)),
                7,
            );
        }
        r.summarise(
            &mut s,
            QualityPreset::Low,
            &waves,
            Some(QualityStep::Scale85),
        );
        assert!(s.ends_with("| GPU governor: scale-0.85"), "{s}");
        assert!(
            s.contains("frame 5.0 ms") && s.contains("GPU 3.0 ms | 7 draws"),
            "{s}"
        );
    }
}
