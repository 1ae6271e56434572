//! What the window mode changes while running: live [`Tweak`]s of the waves (validated by the
//! simulation; refused values are logged, never fatal) and the recent-frame statistics shown
//! in the title. Nothing here allocates per frame.

use std::fmt::Write as _;
use std::time::Duration;

use crate::lod::QualityPreset;
use crate::render::sky::SunSky;
use crate::sim::{SeaState, Simulation, WaveParams};
use crate::ui::panel::Comfort;
use crate::ui::{Beaufort, Settings};
use crate::xr::gpu_governor::QualityStep;
use crate::xr::Tweak;

/// What the user has chosen by the end of a run (the front ends keep it as settings): the
/// waves, the quality preset (the user's, not a step the GPU governor took) and the sky.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    /// Wind, direction, choppiness and the rest of the waves.
    pub waves: WaveParams,
    /// The quality preset.
    pub preset: QualityPreset,
    /// Sun and clouds.
    pub sun: SunSky,
    /// Comfort options, the deck's height included (as the panel left them, else as the run
    /// started).
    pub comfort: Comfort,
}

impl Chosen {
    /// The settings to keep: these choices, and the sound as the run had it (`volume`,
    /// `audio` on or off).
    pub fn settings(&self, volume: f32, audio: bool) -> Settings {
        Settings {
            wind_speed: self.waves.wind_speed,
            wind_direction_deg: self.waves.wind_direction_deg,
            choppiness: self.waves.choppiness,
            preset: self.preset.name().into(),
            sun_elevation_deg: Some(self.sun.elevation_deg),
            sun_azimuth_deg: Some(self.sun.azimuth_deg),
            clouds: Some(self.sun.clouds),
            volume,
            audio,
            snap_turn_deg: self.comfort.snap_turn_deg,
            smooth_turn: self.comfort.smooth_turn,
            seated: self.comfort.seated,
            deck_height_m: Some(self.comfort.deck_height_m),
            ride_waves: self.comfort.ride_waves,
            vignette: self.comfort.vignette,
            ..Settings::default()
        }
    }
}

/// Applies a wave tweak (wind speed, direction, choppiness) through
/// [`Simulation::set_waves`]; logs the new value, or why it was refused. Preset tweaks are
/// the caller's (they rebuild the LOD and renderer) and are ignored here.
pub fn apply_wave_tweak(sim: &mut Simulation, tweak: Tweak) {
    let mut waves: WaveParams = sim.config().waves;
    let what = match tweak {
        Tweak::WindSpeed(d) => {
            waves.wind_speed += d;
            "wind speed"
        }
        Tweak::WindDirection(d) => {
            waves.wind_direction_deg = (waves.wind_direction_deg + d).rem_euclid(360.0);
            "wind direction"
        }
        Tweak::SeaState(d) => {
            let now = Beaufort::of_wind(waves.wind_speed).map_or(0, Beaufort::number);
            let to = (now as i32 + d as i32).clamp(0, crate::ui::beaufort::MAX_PRESET as i32);
            let force = Beaufort::new(to as u8).expect("clamped to the scale");
            waves.wind_speed = force.wind_speed();
            log::info!("sea state: Beaufort {to}, {}", force.force().name);
            "sea state"
        }
        Tweak::Choppiness(d) => {
            // Rounded to the step so repeated presses land on 0 and 2 exactly.
            waves.choppiness = ((waves.choppiness + d) * 100.0).round() / 100.0;
            "choppiness"
        }
        Tweak::Preset(_)
        | Tweak::NextPreset
        | Tweak::Throw
        | Tweak::LaunchBoat(_)
        | Tweak::Sun { .. } => return,
    };
    match SeaState::new(waves).and_then(|sea| sim.set_waves(sea)) {
        Ok(()) => log::info!(
            "{what}: wind {:.1} m/s from {:.0} deg, choppiness {:.2}",
            waves.wind_speed,
            waves.wind_direction_deg,
            waves.choppiness
        ),
        Err(e) => log::warn!("{what} change refused: {e}"),
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
    fn wave_tweaks_apply_and_out_of_range_values_are_refused() {
        let cfg = crate::sim::OceanConfig::single(16, 50.0).unwrap();
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let w0 = sim.config().waves;
        apply_wave_tweak(&mut sim, Tweak::WindSpeed(2.0));
        assert_eq!(sim.config().waves.wind_speed, w0.wind_speed + 2.0);
        apply_wave_tweak(&mut sim, Tweak::WindSpeed(-1000.0));
        assert_eq!(sim.config().waves.wind_speed, w0.wind_speed + 2.0);
        apply_wave_tweak(&mut sim, Tweak::WindDirection(-15.0));
        assert_eq!(
            sim.config().waves.wind_direction_deg,
            (w0.wind_direction_deg - 15.0).rem_euclid(360.0)
        );
        for _ in 0..40 {
            apply_wave_tweak(&mut sim, Tweak::Choppiness(0.1));
        }
        assert_eq!(sim.config().waves.choppiness, 2.0);
        // Sea states by Beaufort force: 12 m/s is force 6; up two is a gale's middle.
        apply_wave_tweak(&mut sim, Tweak::SeaState(2));
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(8).unwrap().wind_speed()
        );
        for _ in 0..20 {
            apply_wave_tweak(&mut sim, Tweak::SeaState(-1));
        }
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(0).unwrap().wind_speed()
        );
        apply_wave_tweak(&mut sim, Tweak::SeaState(4));
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(4).unwrap().wind_speed()
        );
        apply_wave_tweak(&mut sim, Tweak::Preset(QualityPreset::Low));
        assert_eq!(sim.config().waves.choppiness, 2.0);
        // The simulation still steps with the new waves.
        assert!(sim.step_blocking(0.5).max_displacement()[1] > 0.0);
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
