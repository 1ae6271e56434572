//! Whitecaps breaking: the crackle of the bubbles a crest entrains as it spills, and the fizz
//! of the foam it leaves. One voice per sector round the listener.
//!
//! Grains arrive as a Poisson process at a rate proportional to the foam being made (the air
//! a breaker entrains grows with the energy it loses, and foam production is this
//! simulation's measure of it) plus a trickle per unit of standing foam (bursting bubbles);
//! the fizz is high-passed noise over 3 kHz following the same two terms.

use super::bubbles::{poisson, Bubbles, Sizes};
use super::ramp;
use crate::audio::dsp::{Band, Biquad, Rng};

/// Bubble grains per second per unit of (area/r²-weighted) foam production.
const GRAINS_PER_PRODUCTION: f32 = 600.0;
/// Grains per second per unit of (area/r²-weighted) standing foam.
const GRAINS_PER_FOAM: f32 = 30.0;
/// A grain's amplitude at 1 m for a 2 mm bubble.
const GRAIN_AMP: f32 = 0.2;
/// Fizz amplitude per √(weighted foam).
const FIZZ: f32 = 0.02;
/// Bubble sizes of a spilling crest.
const CREST_BUBBLES: Sizes = Sizes {
    min: 0.4e-3,
    max: 5.0e-3,
};
/// Grains ringing at once per sector.
const POOL: usize = 24;

/// One sector's breaking.
#[derive(Clone, Debug)]
pub struct Crackle {
    rate: f32,
    rng: Rng,
    bubbles: Bubbles<POOL>,
    fizz: Biquad,
    fizz_amp: f32,
}

impl Crackle {
    /// A quiet sector for `rate` samples/s.
    pub fn new(rate: f32, seed: u64) -> Self {
        Self {
            rate,
            rng: Rng::new(seed),
            bubbles: Bubbles::default(),
            fizz: Biquad::new(Band::HighPass, 3000.0, 0.707, rate),
            fizz_amp: 0.0,
        }
    }

    /// Adds a block (mono, at 1 m: the sector's distance is the spatializer's) for foam made
    /// at `production` and lying at `foam` (both weighted as [`crate::audio::BreakingSector`]
    /// says) whose centre is `distance` m away. Returns whether it sounded.
    pub fn render(&mut self, production: f32, foam: f32, distance: f32, out: &mut [f32]) -> bool {
        let n = out.len();
        let (production, foam) = (production.max(0.0), foam.max(0.0));
        // The inputs are weighted by area/r² (what reaches the listener); the spatializer
        // applies 1/d to the amplitude again, so its d² comes back out of the rate (power).
        let d2 = distance.max(1.0).powi(2);
        let rate = (GRAINS_PER_PRODUCTION * production + GRAINS_PER_FOAM * foam) * d2;
        let count = poisson(&mut self.rng, rate, n as f32 / self.rate, POOL);
        for _ in 0..count {
            let r = CREST_BUBBLES.draw(&mut self.rng);
            let amp = GRAIN_AMP * (r / 2.0e-3).powf(0.7) * (0.5 + self.rng.unit());
            self.bubbles.spawn(r, amp, self.rate);
        }
        let target = FIZZ * (d2 * (foam + 3.0 * production)).sqrt();
        let silent = self.bubbles.live() == 0 && target <= 0.0 && self.fizz_amp <= 0.0;
        if silent {
            return false;
        }
        self.bubbles.render(out);
        let from = self.fizz_amp;
        for (i, o) in out.iter_mut().enumerate() {
            *o += self.fizz.next(self.rng.white()) * ramp(from, target, i, n);
        }
        self.fizz_amp = target;
        true
    }
}
