//! The soundscape: every voice, placed round the head and mixed, then a peak limiter. One
//! [`Soundscape`] renders the sound both for a device's callback and for `--audio-out`; it
//! never allocates, locks or blocks after [`Soundscape::new`], and for a seed and the same
//! frames and splashes it makes the same samples.
//!
//! Time: the soundscape keeps its own clock (the time of its next sample, on the frames'
//! clock). A splash is placed at its own time, to the sample, when it falls in the block being
//! rendered; one already past sounds at the block's start.

use glam::Vec3;

use super::scene::{Listener, SoundFrame, Splash, BREAK_SECTORS, WASH_POINTS};
use super::spatial::{place, Spatializer};
use super::submerged::Submerged;
use super::voices::breaking::Crackle;
use super::voices::splash::SplashVoice;
use super::voices::water::{Rumble, Wash};
use super::voices::wind::{Wind, WindInput};
use super::AudioError;

/// Frames rendered per block: parameters and placements are updated once per block
/// (1.3 ms at 48 kHz).
pub const BLOCK: usize = 64;

/// Splashes sounding at once (a new one beyond replaces the quietest).
pub const SPLASH_VOICES: usize = 6;

/// Splashes waiting for their time.
pub const MAX_PENDING: usize = 16;

/// The limiter's ceiling: −1 dBFS. No sample leaves louder.
pub const CEILING: f32 = 0.891;

/// The limiter's release time (s).
const RELEASE: f32 = 0.15;

/// How a soundscape renders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoundConfig {
    /// Samples per second (8 000 to 192 000).
    pub sample_rate: u32,
    /// Master volume, 0 (silent) to 1.
    pub volume: f32,
    /// Seed of every noise (the same seed renders the same sound).
    pub seed: u64,
}

impl Default for SoundConfig {
    fn default() -> Self {
        Self {
            sample_rate: super::SAMPLE_RATE,
            volume: 1.0,
            seed: 1,
        }
    }
}

impl SoundConfig {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), AudioError> {
        if !(8_000..=192_000).contains(&self.sample_rate) {
            return Err(AudioError::Param(format!(
                "sample rate {} Hz: expected 8000 to 192000",
                self.sample_rate
            )));
        }
        if !(0.0..=1.0).contains(&self.volume) {
            return Err(AudioError::Param(format!(
                "volume {}: expected 0 (silent) to 1 (full)",
                self.volume
            )));
        }
        Ok(())
    }
}

/// What the soundscape has done so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoundStats {
    /// Frames (sample pairs) rendered.
    pub frames: u64,
    /// Splashes started.
    pub splashes: u64,
    /// Splashes dropped (the queue was full or they were invalid).
    pub dropped: u64,
    /// The loudest sample before the limiter.
    pub peak: f32,
}

/// Every voice and its ears.
pub struct Soundscape {
    rate: f32,
    volume: f32,
    time: f64,
    frame: SoundFrame,
    wind: Wind,
    rumble: Rumble,
    wash: [(Wash, Spatializer); WASH_POINTS],
    breaking: [(Crackle, Spatializer); BREAK_SECTORS],
    splashes: [(SplashVoice, Spatializer); SPLASH_VOICES],
    pending: [Option<Splash>; MAX_PENDING],
    submerged: Submerged,
    mono: [f32; BLOCK],
    stereo: [f32; 2 * BLOCK],
    gain: f32,
    release: f32,
    stats: SoundStats,
}

impl Soundscape {
    /// A silent sea at time 0 (see [`Soundscape::set_time`]).
    pub fn new(config: SoundConfig) -> Result<Self, AudioError> {
        config.validate()?;
        let rate = config.sample_rate as f32;
        let seed = config.seed;
        let voice = |k: u64| seed.wrapping_mul(0x1000_0000_01B3).wrapping_add(k);
        Ok(Self {
            rate,
            volume: config.volume,
            time: 0.0,
            frame: SoundFrame::default(),
            wind: Wind::new(rate, voice(1)),
            rumble: Rumble::new(rate, voice(2)),
            wash: std::array::from_fn(|i| {
                (
                    Wash::new(rate, voice(10 + i as u64)),
                    Spatializer::new(rate),
                )
            }),
            breaking: std::array::from_fn(|i| {
                (
                    Crackle::new(rate, voice(20 + i as u64)),
                    Spatializer::new(rate),
                )
            }),
            splashes: std::array::from_fn(|i| {
                (
                    SplashVoice::new(rate, voice(30 + i as u64)),
                    Spatializer::new(rate),
                )
            }),
            pending: [None; MAX_PENDING],
            submerged: Submerged::new(rate),
            mono: [0.0; BLOCK],
            stereo: [0.0; 2 * BLOCK],
            gain: 1.0,
            release: 1.0 - (-1.0 / (RELEASE * rate)).exp(),
            stats: SoundStats::default(),
        })
    }

    /// Samples per second.
    pub fn sample_rate(&self) -> u32 {
        self.rate as u32
    }

    /// The time of the next sample (s, the frames' clock).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Sets the clock: the next sample is at `time` (s).
    pub fn set_time(&mut self, time: f64) {
        self.time = time;
    }

    /// The master volume, 0 to 1 (out of range is clamped: callers validate first).
    pub fn set_volume(&mut self, volume: f32) {
        self.volume = volume.clamp(0.0, 1.0);
    }

    /// What has been rendered so far.
    pub fn stats(&self) -> SoundStats {
        self.stats
    }

    /// The sea from now on (voices ease toward it); values no sea has are made harmless
    /// ([`SoundFrame::sanitized`]).
    pub fn set_frame(&mut self, frame: &SoundFrame) {
        self.frame = frame.sanitized();
    }

    /// Queues a splash for its time (dropped, and counted, when invalid or the queue is full).
    pub fn splash(&mut self, splash: Splash) {
        match self.pending.iter_mut().find(|p| p.is_none()) {
            Some(slot) if splash.is_valid() => *slot = Some(splash),
            _ => self.stats.dropped += 1,
        }
    }

    /// Renders `out.len() / 2` frames of interleaved stereo into `out` (overwriting it) and
    /// advances the clock.
    pub fn render(&mut self, out: &mut [f32]) {
        for chunk in out.chunks_mut(2 * BLOCK) {
            let n = chunk.len() / 2;
            self.block(n);
            let mut peak = 0.0f32;
            for (o, s) in chunk.chunks_exact_mut(2).zip(self.stereo.chunks_exact(2)) {
                let (l, r) = (s[0], s[1]);
                let p = l.abs().max(r.abs());
                peak = peak.max(p);
                // Instant attack, exponential release: never above the ceiling.
                self.gain += (1.0 - self.gain) * self.release;
                if p * self.gain > CEILING {
                    self.gain = CEILING / p;
                }
                let g = self.gain * self.volume;
                o[0] = (l * g).clamp(-CEILING, CEILING);
                o[1] = (r * g).clamp(-CEILING, CEILING);
            }
            if peak.is_finite() {
                self.stats.peak = self.stats.peak.max(peak);
            }
            self.stats.frames += n as u64;
            self.time += n as f64 / self.rate as f64;
        }
    }

    /// One block of `n` frames into `self.stereo`, before the limiter.
    fn block(&mut self, n: usize) {
        let stereo = &mut self.stereo[..2 * n];
        stereo.fill(0.0);
        let frame = &self.frame;
        let head: &Listener = &frame.listener;
        let rate = self.rate;

        // Splashes due in this block start on their sample.
        let end = self.time + n as f64 / rate as f64;
        for k in 0..MAX_PENDING {
            let Some(s) = self.pending[k] else { continue };
            if s.time >= end {
                continue;
            }
            self.pending[k] = None;
            let wait = ((s.time - self.time) * rate as f64).round().max(0.0) as usize;
            let voice = self
                .splashes
                .iter_mut()
                .min_by(|a, b| a.0.loudness().total_cmp(&b.0.loudness()))
                .expect("SPLASH_VOICES > 0");
            voice.0.start(&s, wait.min(n - 1));
            self.stats.splashes += 1;
        }

        // The wind, diffuse, from where it blows.
        let toward = Vec3::new(frame.wind_toward.x, 0.0, frame.wind_toward.y);
        let from = (head.orientation.inverse() * -toward).normalize_or_zero();
        self.wind.render(
            &WindInput {
                speed: frame.wind_speed,
                from,
            },
            stereo,
        );
        // Under the water the surface turns the air's sound away.
        let air = self.submerged.air_gain();
        if air < 1.0 {
            stereo.iter_mut().for_each(|s| *s *= air);
        }

        // The swell under everything, the same at both ears.
        let mono = &mut self.mono[..n];
        mono.fill(0.0);
        let heave =
            (frame.wash.iter().map(|w| w.rise * w.rise).sum::<f32>() / WASH_POINTS as f32).sqrt();
        self.rumble.render(frame.significant_height, heave, mono);
        for (s, m) in stereo.chunks_exact_mut(2).zip(mono.iter()) {
            s[0] += m;
            s[1] += m;
        }

        // Point sources: wash round the deck, breaking sectors, splashes.
        for ((voice, ears), w) in self.wash.iter_mut().zip(&frame.wash) {
            mono.fill(0.0);
            let sounded = voice.render(w.rise, w.clearance, mono);
            ears.render(mono, place(head, w.position, rate), !sounded, stereo);
        }
        for ((voice, ears), b) in self.breaking.iter_mut().zip(&frame.breaking) {
            mono.fill(0.0);
            let d = (b.position - head.position).length();
            let sounded = voice.render(b.production, b.foam, d, mono);
            ears.render(mono, place(head, b.position, rate), !sounded, stereo);
        }
        for (voice, ears) in self.splashes.iter_mut() {
            mono.fill(0.0);
            let at = voice.position();
            let sounded = voice.render(mono);
            if let Some(p) = at {
                ears.render(mono, place(head, p, rate), !sounded, stereo);
            }
        }

        // A diver's ears when the head is under the water.
        self.submerged.process(frame.submersion > 0.0, stereo);
    }
}
