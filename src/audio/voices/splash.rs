//! A splash: something hits the water. Three sounds in order (the classic account of a drop's
//! impact, Franz 1959, scaled up to a body): the slap of the first contact (a burst of noise,
//! lower and longer for a bigger body), the thump of the air cavity it drags down as it pinches
//! off (a large bubble ringing at Minnaert's frequency for the cavity's radius, a few tens of
//! milliseconds later), and a spray of small bubbles as the crown and the jet fall back,
//! thinning out over a second.
//!
//! Loudness follows the impact's kinetic energy as E^0.35 (radiated power grows roughly with
//! E, loudness as its cube root) times v/(v + 1.5 m/s): a slow entry is gentle whatever the
//! mass (a heavy boat settling back at 0.5 m/s slaps softly). The exponents and scale are our
//! choice, tested for order and not for decibels.

use glam::Vec3;

use super::bubbles::{poisson, Bubbles, Sizes, MINNAERT};
use crate::audio::dsp::{Band, Biquad, Rng};
use crate::audio::scene::Splash;

/// Amplitude at 1 m of a 100 J impact, before the speed factor.
const LOUD_AT_100J: f32 = 0.8;
/// Speed (m/s) at which the speed factor v/(v + v₀) is one half.
const GENTLE_SPEED: f32 = 1.5;
/// Exponent of loudness in energy.
const ENERGY_EXPONENT: f32 = 0.35;
/// Loudest amplitude at 1 m (the limiter catches the sum).
const MAX_LOUD: f32 = 1.5;
/// How long a splash sounds (s).
pub const SPLASH_LENGTH: f32 = 1.2;
/// Delay of the cavity's thump after the contact (s).
const THUMP_DELAY: f32 = 0.03;
/// The cavity's damping: it is torn, not a sphere, and rings two or three cycles (τ ≈ 10-40
/// ms over its 70-500 Hz).
const CAVITY_DAMPING: f32 = 0.3;
/// Spray bubbles per second at the start, per unit of loudness, and their fade (s).
const SPRAY_RATE: f32 = 700.0;
const SPRAY_FADE: f32 = 0.2;
const SPRAY_BUBBLES: Sizes = Sizes {
    min: 0.5e-3,
    max: 3.0e-3,
};
const POOL: usize = 24;

/// A splash sounding.
#[derive(Clone, Debug)]
pub struct SplashVoice {
    rate: f32,
    rng: Rng,
    /// Where it is; `None`: free.
    position: Option<Vec3>,
    /// Samples before its start in the next block.
    wait: usize,
    age: f32,
    loud: f32,
    slap: f32,
    slap_decay: f32,
    slap_tone: Biquad,
    thump_radius: f32,
    thumped: bool,
    bubbles: Bubbles<POOL>,
}

impl SplashVoice {
    /// A free voice for `rate` samples/s.
    pub fn new(rate: f32, seed: u64) -> Self {
        Self {
            rate,
            rng: Rng::new(seed),
            position: None,
            wait: 0,
            age: 0.0,
            loud: 0.0,
            slap: 0.0,
            slap_decay: 0.0,
            slap_tone: Biquad::new(Band::BandPass, 1000.0, 0.8, rate),
            thump_radius: 0.05,
            thumped: false,
            bubbles: Bubbles::default(),
        }
    }

    /// Where it sounds, while it does.
    pub fn position(&self) -> Option<Vec3> {
        self.position
    }

    /// How loud it is now (for replacing the quietest when all are busy).
    pub fn loudness(&self) -> f32 {
        if self.position.is_some() {
            self.loud * (1.0 - self.age / SPLASH_LENGTH).max(0.0)
        } else {
            0.0
        }
    }

    /// Loudness at 1 m for an impact of `energy` J at `speed` m/s.
    pub fn loudness_for(energy: f32, speed: f32) -> f32 {
        let speed = speed.max(0.0);
        let gentle = speed / (speed + GENTLE_SPEED);
        (LOUD_AT_100J * (energy.max(0.0) / 100.0).powf(ENERGY_EXPONENT) * gentle).min(MAX_LOUD)
    }

    /// Starts `splash` `wait` samples into the next block.
    pub fn start(&mut self, splash: &Splash, wait: usize) {
        let r = splash.radius;
        self.position = Some(splash.position);
        self.wait = wait;
        self.age = 0.0;
        self.loud = Self::loudness_for(splash.energy(), splash.speed);
        self.slap = self.loud;
        let tau = 0.012 + 0.04 * r.min(1.0);
        self.slap_decay = (-1.0 / (tau * self.rate)).exp();
        let centre = (1800.0 * (0.1 / r).sqrt()).clamp(400.0, 4000.0);
        self.slap_tone.tune(centre, 0.8, self.rate);
        // The cavity: about a quarter of the body's radius, ringing 70-500 Hz.
        self.thump_radius = (0.25 * r).clamp(MINNAERT / 500.0, MINNAERT / 70.0);
        self.thumped = false;
        self.bubbles = Bubbles::default();
    }

    /// Adds a block (mono, at 1 m) to `out`. Returns whether it sounded.
    pub fn render(&mut self, out: &mut [f32]) -> bool {
        if self.position.is_none() {
            return false;
        }
        let start = self.wait.min(out.len());
        self.wait -= start;
        let out = &mut out[start..];
        let dt = out.len() as f32 / self.rate;
        if !self.thumped && self.age >= THUMP_DELAY {
            self.thumped = true;
            let (r, amp) = (self.thump_radius, 0.5 * self.loud);
            self.bubbles.spawn_damped(r, amp, CAVITY_DAMPING, self.rate);
        }
        let spray = SPRAY_RATE * self.loud * (-self.age / SPRAY_FADE).exp();
        for _ in 0..poisson(&mut self.rng, spray, dt, POOL) {
            let r = SPRAY_BUBBLES.draw(&mut self.rng);
            let amp = 0.15 * self.loud * (r / 2.0e-3).powf(0.7) * (0.5 + self.rng.unit());
            self.bubbles.spawn(r, amp, self.rate);
        }
        for o in out.iter_mut() {
            *o += self.slap * self.slap_tone.next(self.rng.white()) * 3.0;
            self.slap *= self.slap_decay;
        }
        self.bubbles.render(out);
        self.age += dt;
        if self.age >= SPLASH_LENGTH && self.bubbles.live() == 0 {
            self.position = None;
        }
        true
    }
}
