//! The app's ears (issue 32): each frame, the sea round the head is read into a sound frame
//! ([`crate::audio::listen::SeaProbe`]) and the frame's impacts become splashes; an output
//! takes them: the audio device (or its silent stand-in) fed lock-free, or a WAV file rendered
//! in step with the frames (`--audio-out`: deterministic, the same path and seed the same
//! bytes).

use std::path::PathBuf;

use glam::Vec2;

use super::floating::Afloat;
use super::AppError;
use crate::audio::device::BUFFER_FRAMES;
use crate::audio::link::Scheduling;
use crate::audio::listen::{DeckOutline, ProbeInput, SeaProbe};
use crate::audio::{AudioOutput, Listener, Sink, SoundConfig, Splash, WavRecorder};
use crate::physics::impacts::MAX_IMPACTS;
use crate::sim::Surfaces;
use crate::xr::FrameState;

/// Where a run's sound goes.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum SoundSink {
    /// No sound at all (tests, benchmarks).
    #[default]
    Off,
    /// The default audio device; without one, a warning and a silent run.
    Device,
    /// A 16-bit stereo WAV file rendered in step with the drawn frames, starting at the
    /// first (`headless --audio-out`).
    File(PathBuf),
}

/// A run's sound.
#[derive(Clone, Debug, PartialEq)]
pub struct SoundOptions {
    /// Where it goes.
    pub sink: SoundSink,
    /// Master volume, 0 to 1.
    pub volume: f32,
    /// Seed of its noises.
    pub seed: u64,
}

impl Default for SoundOptions {
    fn default() -> Self {
        Self {
            sink: SoundSink::Off,
            volume: 1.0,
            seed: 1,
        }
    }
}

/// What the sound output did over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct SoundReport {
    /// The device's name, "silent clock" or the file.
    pub sink: String,
    /// Buffers rendered by the callback (0 for a file).
    pub buffers: u64,
    /// Frames per buffer asked of the device.
    pub buffer_frames: u32,
    /// Buffers the device under-ran (or the clock finished late).
    pub underruns: u64,
    /// Seconds of sound made.
    pub seconds: f64,
    /// Rendering time over sound time: the share of one core the sound costs.
    pub load: f64,
    /// The longest callback (ms).
    pub worst_ms: f64,
    /// Under-runs the silent clock saw whose rendering fitted: the thread woke too late.
    pub late_wakes: u64,
    /// The audio thread's scheduling.
    pub scheduling: Scheduling,
    /// Seconds the sound was paused (the user away): the device's silence, or for a file the
    /// world's stillness.
    pub paused_s: f64,
    /// Streams opened again after the device was lost (headphones in or out).
    pub reopened: u64,
}

impl std::fmt::Display for SoundReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "audio ({}): {:.1} s of sound, {} buffers of {} frames, {} under-runs ({} late \
             wakes), {:.2} % of one core (longest callback {:.2} ms), {} scheduling, reopened {} \
             times, paused {:.1} s",
            self.sink,
            self.seconds,
            self.buffers,
            self.buffer_frames,
            self.underruns,
            self.late_wakes,
            100.0 * self.load,
            self.worst_ms,
            self.scheduling,
            self.reopened,
            self.paused_s
        )
    }
}

enum Output {
    Device(AudioOutput),
    File(Box<WavRecorder>),
}

/// The run's ears.
pub(crate) struct Ears {
    probe: SeaProbe,
    output: Output,
    splashes: Vec<Splash>,
    /// File output: time spent rendering (ns).
    render_ns: u64,
    /// Display seconds the world stood still (the user away), as of the last frame.
    away_s: f64,
}

impl Ears {
    /// The ears `opts` ask for; `None` when the sound is off. A missing device is not an
    /// error (a warning and the silent clock); an unwritable file is.
    pub(crate) fn new(opts: &SoundOptions) -> Result<Option<Self>, AppError> {
        let config = SoundConfig {
            volume: opts.volume,
            seed: opts.seed,
            ..SoundConfig::default()
        };
        let output = match &opts.sink {
            SoundSink::Off => return Ok(None),
            SoundSink::Device => Output::Device(AudioOutput::open(config).map_err(io)?),
            SoundSink::File(path) => {
                Output::File(Box::new(WavRecorder::create(path, config).map_err(io)?))
            }
        };
        Ok(Some(Self {
            probe: SeaProbe::new(),
            output,
            splashes: Vec::with_capacity(MAX_IMPACTS + 2),
            render_ns: 0,
            away_s: 0.0,
        }))
    }

    /// Pauses or resumes the sound (the user away or back): a device's stream fades out to
    /// silence; a file, which holds the world's sound, just hears no frame meanwhile.
    /// `away_s`: the display seconds the world has stood still so far.
    pub(crate) fn set_paused(&mut self, paused: bool, away_s: f64) {
        self.away_s = away_s;
        if let Output::Device(out) = &mut self.output {
            out.sender().set_paused(paused);
        }
    }

    /// Hears `frame`: the sea of `surfaces` (with the interaction layer of `afloat`) and its
    /// wind ([`heard_wind`]), the frame's impacts.
    pub(crate) fn hear(
        &mut self,
        frame: &FrameState,
        surfaces: &Surfaces,
        afloat: Option<&Afloat>,
    ) -> Result<(), AppError> {
        // A file holds the drawn frames only (a headless run's settling is not heard).
        if matches!(self.output, Output::File(_)) && !frame.should_render {
            return Ok(());
        }
        let start = std::time::Instant::now();
        let world = afloat.and_then(|a| a.world());
        let deck = world.and_then(|w| w.deck()).map(|d| DeckOutline {
            centre: Vec2::from(d.centre),
            half: Vec2::from(d.size) * 0.5,
            underside: d.height - d.thickness,
        });
        let (wind_speed, wind_toward_deg) = heard_wind(surfaces);
        let sound = self.probe.probe(&ProbeInput {
            time: frame.predicted_display_time,
            listener: Listener {
                position: (frame.views[0].position + frame.views[1].position) * 0.5,
                orientation: frame.views[0].orientation,
            },
            surfaces,
            layer: world.and_then(|w| w.interaction()),
            wind_speed,
            wind_toward_deg,
            deck,
        });
        if frame.index.is_multiple_of(72) {
            let (made, foam) = sound
                .breaking
                .iter()
                .fold((0.0, 0.0), |(m, f), b| (m + b.production, f + b.foam));
            log::debug!(
                "sound at {:.2} s: whitecaps made {made:.4}/s, lying {foam:.4} (area/r² sums)",
                frame.predicted_display_time
            );
        }
        self.splashes.clear();
        for hit in afloat.map_or(&[][..], |a| a.impacts()) {
            self.splashes.push(Splash {
                time: hit.time,
                position: hit.position,
                speed: hit.speed,
                mass: hit.mass,
                radius: hit.radius,
            });
            log::info!(
                "splash at {:.3} s: {:.1} kg at {:.1} m/s, ({:.1}, {:.1}, {:.1})",
                hit.time,
                hit.mass,
                hit.speed,
                hit.position.x,
                hit.position.y,
                hit.position.z
            );
        }
        match &mut self.output {
            Output::Device(out) => {
                let link = out.sender();
                link.publish(&sound);
                for s in &self.splashes {
                    link.splash(*s);
                }
            }
            Output::File(wav) => {
                wav.frame(&sound, &self.splashes).map_err(io)?;
                self.render_ns += start.elapsed().as_nanos() as u64;
            }
        }
        Ok(())
    }

    /// What the output did (the file is finished here).
    pub(crate) fn finish(&mut self) -> Result<SoundReport, AppError> {
        Ok(match &mut self.output {
            Output::Device(out) => {
                let (c, _) = out.counters();
                let seconds = c.frames as f64 / crate::audio::SAMPLE_RATE as f64;
                SoundReport {
                    sink: match out.sink() {
                        Sink::Device(name) => name.clone(),
                        Sink::Clock => "no device: silent clock".into(),
                    },
                    buffers: c.callbacks,
                    buffer_frames: out.buffer_frames(),
                    underruns: c.underruns,
                    seconds,
                    load: c.busy_ns as f64 * 1e-9 / seconds.max(1e-9),
                    worst_ms: c.worst_ns as f64 * 1e-6,
                    late_wakes: c.late_wakes,
                    scheduling: c.scheduling,
                    paused_s: c.paused_frames as f64 / crate::audio::SAMPLE_RATE as f64,
                    reopened: c.reopened,
                }
            }
            Output::File(wav) => {
                wav.finish().map_err(io)?;
                let stats = wav.soundscape().stats();
                let seconds = stats.frames as f64 / crate::audio::SAMPLE_RATE as f64;
                SoundReport {
                    sink: wav.path().display().to_string(),
                    buffers: 0,
                    buffer_frames: BUFFER_FRAMES,
                    underruns: 0,
                    seconds,
                    load: self.render_ns as f64 * 1e-9 / seconds.max(1e-9),
                    worst_ms: 0.0,
                    late_wakes: 0,
                    scheduling: Scheduling::Unknown,
                    paused_s: self.away_s,
                    reopened: 0,
                }
            }
        })
    }
}

fn io(e: crate::audio::AudioError) -> AppError {
    AppError::Io(e.to_string())
}

/// The wind the sound blows with: the shown sea's ([`Surfaces::wind`]: speed in m/s, and the
/// direction it blows toward in degrees from +x toward +z), so that during a sea-state change
/// (a build, then a 5 s blend) the wind is heard changing with the waves, not before them.
pub(crate) fn heard_wind(surfaces: &Surfaces) -> (f32, f32) {
    let (speed, [x, z]) = surfaces.wind;
    (speed, z.atan2(x).to_degrees())
}

#[cfg(test)]
mod wind_tests {
    use super::heard_wind;
    use crate::sim::{OceanConfig, Simulation, WaveParams};

    #[test]
    fn during_a_sea_state_change_the_wind_heard_follows_the_shown_sea() {
        let cfg = OceanConfig::default_cascades(32).unwrap();
        let before = cfg.waves;
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let dt = 1.0 / 72.0;
        sim.step_blocking(0.0);
        let after = WaveParams {
            wind_speed: before.wind_speed + 8.0,
            wind_direction_deg: before.wind_direction_deg + 90.0,
            ..before
        };
        sim.set_waves(crate::sim::SeaState::new(after).unwrap())
            .unwrap();
        let (mut mid_speed, mut mid_dir) = (None, None);
        let mut t = 0.0;
        for _ in 0..(12.0 / dt) as usize {
            t += dt;
            sim.step_blocking(t);
            let (speed, toward) = heard_wind(sim.surfaces());
            // Never ahead of the waves: between the old wind and the new, in speed and
            // direction.
            assert!(
                speed >= before.wind_speed - 1e-3 && speed <= after.wind_speed + 1e-3,
                "{speed}"
            );
            let turned = (toward - before.wind_direction_deg).rem_euclid(360.0);
            assert!(turned <= 90.0 + 1e-2, "turned {turned}");
            if speed > before.wind_speed + 1.0 && speed < after.wind_speed - 1.0 {
                mid_speed = Some(speed);
                mid_dir = Some(turned);
            }
        }
        // Heard in between while the sea blended, and at the new wind once it has.
        let (mid_speed, mid_dir) = (mid_speed.expect("a blend"), mid_dir.unwrap());
        assert!(
            mid_dir > 1.0 && mid_dir < 89.0,
            "mid-blend direction {mid_dir}"
        );
        let (speed, toward) = heard_wind(sim.surfaces());
        assert!(
            (speed - after.wind_speed).abs() < 1e-3,
            "{speed} (mid {mid_speed})"
        );
        let off = (toward - after.wind_direction_deg).rem_euclid(360.0);
        assert!(!(1e-2..=360.0 - 1e-2).contains(&off), "{toward}");
    }
}
