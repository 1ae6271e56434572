//! Wind: the roar of moving air round the head and the hiss of spray once the sea starts
//! blowing off its crests. Two decorrelated noise streams, one per ear (wind is diffuse), the
//! ear facing into it the louder.
//!
//! The roar is pink noise through a band-pass whose centre rises with the speed,
//! fc = 150 Hz + 40 Hz·s/m·U (≈ 550 Hz at 10 m/s): faster air makes smaller eddies and higher
//! turbulent noise. Its amplitude grows as U^1.7 (a fit between the dipole noise of wind on
//! a fixed obstacle, pressure ∝ U³ at low speed, and the saturation of recorded wind levels;
//! the constants are ours, chosen by ear-free reasoning and measured in `audio::tests`).
//! Gusts are an Ornstein-Uhlenbeck process on the speed: relative deviation 15 % (the
//! turbulence intensity of marine surface winds is 10-20 %), correlation time 5 s.

use glam::Vec3;

use super::ramp;
use crate::audio::dsp::{Band, Biquad, Pink, Rng, Smooth};

/// Roar amplitude at 10 m/s (linear, full scale 1).
const ROAR_AT_10: f32 = 0.05;
/// Exponent of the roar's growth with speed.
const ROAR_EXPONENT: f32 = 1.7;
/// Spray hiss amplitude per unit of (U − 8 m/s)/12 m/s, to the power 1.5.
const HISS: f32 = 0.05;
/// Wind speed (m/s) above which spray is blown off the crests (Beaufort 5).
const SPRAY_ONSET: f32 = 8.0;
/// Relative gust deviation and correlation time (s).
const GUST_SIGMA: f32 = 0.15;
const GUST_TAU: f32 = 5.0;

/// What the wind voice needs per block.
#[derive(Clone, Copy, Debug)]
pub struct WindInput {
    /// Mean speed (m/s).
    pub speed: f32,
    /// Unit vector in the head's frame pointing where the wind comes from (zero: no side).
    pub from: Vec3,
}

/// The wind voice.
#[derive(Clone, Debug)]
pub struct Wind {
    rate: f32,
    rng: [Rng; 2],
    pink: [Pink; 2],
    roar: [Biquad; 2],
    hiss: [Biquad; 2],
    gust_rng: Rng,
    gust: f32,
    speed: Smooth,
    amp: [[f32; 2]; 2],
}

impl Wind {
    /// A calm wind voice for `rate` samples/s seeded by `seed`.
    pub fn new(rate: f32, seed: u64) -> Self {
        Self {
            rate,
            rng: [Rng::new(seed ^ 0x11), Rng::new(seed ^ 0x12)],
            pink: [Pink::default(); 2],
            roar: [Biquad::new(Band::BandPass, 500.0, 0.6, rate); 2],
            hiss: [Biquad::new(Band::BandPass, 4500.0, 0.8, rate); 2],
            gust_rng: Rng::new(seed ^ 0x13),
            gust: 0.0,
            speed: Smooth::default(),
            amp: [[0.0; 2]; 2],
        }
    }

    /// The speed gusting now (m/s).
    pub fn gusting_speed(&self) -> f32 {
        (self.speed.value * (1.0 + self.gust)).max(0.0)
    }

    /// Adds a block of wind to `out` (interleaved stereo).
    pub fn render(&mut self, input: &WindInput, out: &mut [f32]) {
        let n = out.len() / 2;
        let dt = n as f32 / self.rate;
        let decay = (-dt / GUST_TAU).exp();
        self.gust =
            self.gust * decay + GUST_SIGMA * (1.0 - decay * decay).sqrt() * self.gust_rng.normal();
        self.speed.toward(input.speed.max(0.0), dt, 0.5);
        let u = self.gusting_speed();
        let roar = ROAR_AT_10 * (u / 10.0).powf(ROAR_EXPONENT);
        let spray = ((u - SPRAY_ONSET) / 12.0).max(0.0);
        let hiss = HISS * spray * spray.sqrt();
        for ear in 0..2 {
            self.roar[ear].tune(150.0 + 40.0 * u, 0.6, self.rate);
            let axis = if ear == 0 { Vec3::NEG_X } else { Vec3::X };
            let side = 0.75 + 0.25 * input.from.dot(axis);
            let target = [roar * side, hiss * side];
            let from = self.amp[ear];
            for (i, frame) in out.chunks_exact_mut(2).enumerate() {
                let w = self.rng[ear].white();
                let p = self.pink[ear].next(w);
                let r = self.roar[ear].next(p) * ramp(from[0], target[0], i, n);
                let h = self.hiss[ear].next(w) * ramp(from[1], target[1], i, n);
                frame[ear] += r + h;
            }
            self.amp[ear] = target;
        }
    }
}
