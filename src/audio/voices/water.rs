//! The water round the listener: the swell's low rumble and the wash against the deck.
//!
//! **Rumble**: noise under 100 Hz (a second-order low-pass, normalized to unit variance by its
//! equivalent noise bandwidth, ≈ 1.11·fc for a Butterworth section), the same at both ears
//! (a wavelength of 3-10 m bends round any head). Its level follows the sea's energy, as
//! Hs^0.8, and the water's heave round the deck: the rms of the wash points' rise speeds.
//!
//! **Wash**: water rising and falling against the hull sounds as a broadband rush centred
//! near 600 Hz with a froth above 2.5 kHz; rising water (running up the hull) is louder than
//! falling. Where the deck's underside is near the water the rush grows, and water reaching
//! it slaps: a short burst of noise whose level follows the rise speed.

use super::ramp;
use crate::audio::dsp::{Band, Biquad, OnePole, Rng, Smooth};

/// Rumble amplitude at Hs = 2 m and moderate heave.
const RUMBLE_AT_2M: f32 = 0.02;
/// Rumble cut-off (Hz).
const RUMBLE_CUTOFF: f32 = 100.0;
/// Rise speed (m/s) of the wash points at which the heave term is 1.
const HEAVE_REF: f32 = 0.5;
/// Wash amplitude per m/s of rise.
const WASH_PER_SPEED: f32 = 0.06;
/// Clearance (m) over which the deck's nearness brings the wash up.
const NEAR_DECK: f32 = 0.4;
/// A slap's amplitude per m/s of rise, and its decay time (s).
const SLAP_PER_SPEED: f32 = 0.25;
const SLAP_TAU: f32 = 0.03;

/// The swell's rumble.
#[derive(Clone, Debug)]
pub struct Rumble {
    rate: f32,
    rng: Rng,
    low: Biquad,
    norm: f32,
    amp: f32,
    heave: Smooth,
}

impl Rumble {
    /// A quiet rumble for `rate` samples/s.
    pub fn new(rate: f32, seed: u64) -> Self {
        Self {
            rate,
            rng: Rng::new(seed ^ 0x21),
            low: Biquad::new(Band::LowPass, RUMBLE_CUTOFF, 0.707, rate),
            // White of variance 1/3 into a band of ≈1.11·fc out of rate/2.
            norm: (3.0 * 0.5 * rate / (1.11 * RUMBLE_CUTOFF)).sqrt(),
            amp: 0.0,
            heave: Smooth::default(),
        }
    }

    /// Adds a block to `out` (mono) for significant height `hs` (m) and the rms rise speed
    /// `heave` (m/s) of the water round the deck.
    pub fn render(&mut self, hs: f32, heave: f32, out: &mut [f32]) {
        let n = out.len();
        let heave = self.heave.toward(heave.max(0.0), n as f32 / self.rate, 0.3);
        let target = RUMBLE_AT_2M
            * (hs.max(0.0) / 2.0).powf(0.8)
            * (0.5 + 0.5 * (heave / HEAVE_REF).min(2.0));
        let from = self.amp;
        for (i, o) in out.iter_mut().enumerate() {
            *o += self.norm * self.low.next(self.rng.white()) * ramp(from, target, i, n);
        }
        self.amp = target;
    }
}

/// The wash at one point against the deck.
#[derive(Clone, Debug)]
pub struct Wash {
    rate: f32,
    rng: Rng,
    body: Biquad,
    froth: Biquad,
    slap_tone: OnePole,
    amp: f32,
    slap: f32,
    clearance: f32,
}

impl Wash {
    /// A still wash point for `rate` samples/s.
    pub fn new(rate: f32, seed: u64) -> Self {
        Self {
            rate,
            rng: Rng::new(seed),
            body: Biquad::new(Band::BandPass, 600.0, 0.6, rate),
            froth: Biquad::new(Band::HighPass, 2500.0, 0.707, rate),
            slap_tone: OnePole::new(1500.0, rate),
            amp: 0.0,
            slap: 0.0,
            clearance: f32::INFINITY,
        }
    }

    /// Adds a block to `out` (mono) for water rising at `rise` m/s with `clearance` m below
    /// the deck's underside. Returns whether it made any sound.
    pub fn render(&mut self, rise: f32, clearance: f32, out: &mut [f32]) -> bool {
        let n = out.len();
        let near = if clearance.is_finite() {
            1.0 + 2.0 * (-clearance.max(0.0) / NEAR_DECK).exp()
        } else {
            1.0
        };
        let rise = if rise.is_finite() { rise } else { 0.0 };
        let target = WASH_PER_SPEED * (0.3 * rise.abs() + rise.max(0.0)) * near;
        // The water reaches the deck's underside: a slap.
        if self.clearance > 0.0 && clearance <= 0.0 && rise > 0.0 {
            self.slap = (self.slap + SLAP_PER_SPEED * rise.min(3.0)).min(1.0);
        }
        self.clearance = clearance;
        if target <= 0.0 && self.amp <= 0.0 && self.slap < 1e-4 {
            return false;
        }
        let from = self.amp;
        let slap_decay = (-1.0 / (SLAP_TAU * self.rate)).exp();
        for (i, o) in out.iter_mut().enumerate() {
            let w = self.rng.white();
            let a = ramp(from, target, i, n);
            let rush = self.body.next(w) + 0.4 * self.froth.next(w);
            *o += a * rush + self.slap * self.slap_tone.next(w) * 3.0;
            self.slap *= slap_decay;
        }
        self.amp = target;
        true
    }
}
