//! The building blocks every voice uses: a seeded noise source, pink and brown noise, the
//! filters (one-pole, RBJ biquads, the head shadow of Brown & Duda) and a smoothed parameter.
//! All are plain state, `Copy`-sized, allocation-free and deterministic for a seed.

use std::f32::consts::PI;

/// A xorshift64* generator: fast, seeded, the same stream on every machine (the WAVs of
/// `--audio-out` are byte-identical for a seed).
#[derive(Clone, Copy, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed` (any value; zero is remapped, xorshift needs a set bit).
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Uniform in [-1, 1): white noise of variance 1/3.
    #[inline]
    pub fn white(&mut self) -> f32 {
        2.0 * self.unit() - 1.0
    }

    /// A standard normal deviate (Box-Muller; one of the pair is dropped: called per block,
    /// not per sample).
    pub fn normal(&mut self) -> f32 {
        let u = self.unit().max(1e-7);
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    }
}

/// Pink (1/f) noise from white: three first-order sections spaced over the audio band (the
/// "economy" fit published by P. Kellet, within ±0.5 dB of -3 dB/octave above 10 Hz).
#[derive(Clone, Copy, Debug, Default)]
pub struct Pink {
    b: [f32; 3],
}

impl Pink {
    /// The next pink sample for white input `w` (unit-ish variance out for `Rng::white`).
    #[inline]
    pub fn next(&mut self, w: f32) -> f32 {
        self.b[0] = 0.99765 * self.b[0] + w * 0.099_046;
        self.b[1] = 0.963 * self.b[1] + w * 0.296_516_4;
        self.b[2] = 0.57 * self.b[2] + w * 1.052_691_3;
        (self.b[0] + self.b[1] + self.b[2] + w * 0.1848) * 0.25
    }
}

/// A one-pole low-pass y += a·(x − y), a = 1 − e^(−2π·fc/fs).
#[derive(Clone, Copy, Debug, Default)]
pub struct OnePole {
    a: f32,
    y: f32,
}

impl OnePole {
    /// A low-pass at `cutoff` Hz for `rate` samples per second.
    pub fn new(cutoff: f32, rate: f32) -> Self {
        let mut f = Self::default();
        f.set_cutoff(cutoff, rate);
        f
    }

    /// Moves the cutoff (keeps the state).
    pub fn set_cutoff(&mut self, cutoff: f32, rate: f32) {
        self.a = 1.0 - (-2.0 * PI * cutoff / rate).exp();
    }

    /// Filters one sample.
    #[inline]
    pub fn next(&mut self, x: f32) -> f32 {
        self.y += self.a * (x - self.y);
        self.y
    }
}

/// What a [`Biquad`] passes (the RBJ audio-EQ cookbook's forms).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Band {
    /// Low-pass, −12 dB/octave above the cutoff.
    LowPass,
    /// High-pass, −12 dB/octave below the cutoff.
    HighPass,
    /// Band-pass with 0 dB at the centre.
    BandPass,
}

/// A second-order section (transposed direct form II) with the RBJ cookbook's coefficients.
#[derive(Clone, Copy, Debug)]
pub struct Biquad {
    band: Band,
    b: [f32; 3],
    a: [f32; 2],
    s: [f32; 2],
}

impl Biquad {
    /// A `band` filter at `freq` Hz with quality `q` for `rate` samples per second.
    pub fn new(band: Band, freq: f32, q: f32, rate: f32) -> Self {
        let mut f = Self {
            band,
            b: [0.0; 3],
            a: [0.0; 2],
            s: [0.0; 2],
        };
        f.tune(freq, q, rate);
        f
    }

    /// New frequency and quality, keeping the state (called once per block).
    pub fn tune(&mut self, freq: f32, q: f32, rate: f32) {
        let w0 = 2.0 * PI * (freq / rate).clamp(1e-5, 0.49);
        let (sin, cos) = w0.sin_cos();
        let alpha = sin / (2.0 * q.max(0.05));
        let a0 = 1.0 + alpha;
        let b = match self.band {
            Band::LowPass => [(1.0 - cos) * 0.5, 1.0 - cos, (1.0 - cos) * 0.5],
            Band::HighPass => [(1.0 + cos) * 0.5, -(1.0 + cos), (1.0 + cos) * 0.5],
            Band::BandPass => [alpha, 0.0, -alpha],
        };
        self.b = [b[0] / a0, b[1] / a0, b[2] / a0];
        self.a = [-2.0 * cos / a0, (1.0 - alpha) / a0];
    }

    /// Filters one sample.
    #[inline]
    pub fn next(&mut self, x: f32) -> f32 {
        let y = self.b[0] * x + self.s[0];
        self.s[0] = self.b[1] * x - self.a[0] * y + self.s[1];
        self.s[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// The head's shadow at one ear (Brown & Duda 1998, "A structural model for binaural sound
/// synthesis"): H(s) = (1 + α·s/(2ω₀)) / (1 + s/(2ω₀)) with ω₀ = c/a, by the bilinear
/// transform. α = 2 facing the source (+6 dB at high frequencies), down to 0.1 behind the
/// head (−20 dB); unity at low frequencies, which bend round the head.
#[derive(Clone, Copy, Debug)]
pub struct HeadShadow {
    beta: f32,
    b: [f32; 2],
    a1: f32,
    x1: f32,
    y1: f32,
}

impl HeadShadow {
    /// The filter for a head of `radius` m, sound at `speed` m/s, `rate` samples/s; α = 1.
    pub fn new(radius: f32, speed: f32, rate: f32) -> Self {
        let omega0 = speed / radius;
        let mut f = Self {
            beta: 2.0 * rate / (2.0 * omega0),
            b: [1.0, 0.0],
            a1: 0.0,
            x1: 0.0,
            y1: 0.0,
        };
        f.set_alpha(1.0);
        f
    }

    /// The zero's weight α (keeps the state).
    pub fn set_alpha(&mut self, alpha: f32) {
        let (ab, b) = (alpha * self.beta, self.beta);
        self.b = [(1.0 + ab) / (1.0 + b), (1.0 - ab) / (1.0 + b)];
        self.a1 = (1.0 - b) / (1.0 + b);
    }

    /// Filters one sample.
    #[inline]
    pub fn next(&mut self, x: f32) -> f32 {
        let y = self.b[0] * x + self.b[1] * self.x1 - self.a1 * self.y1;
        self.x1 = x;
        self.y1 = y;
        y
    }
}

/// A parameter eased toward its target with a time constant, once per block: no zipper noise
/// when a frame moves it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Smooth {
    /// The current value.
    pub value: f32,
}

impl Smooth {
    /// Moves `value` toward `target` over a block of `dt` s with time constant `tau` s.
    #[inline]
    pub fn toward(&mut self, target: f32, dt: f32, tau: f32) -> f32 {
        self.value += (target - self.value) * (1.0 - (-dt / tau).exp());
        self.value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rms(x: &[f32]) -> f32 {
        (x.iter().map(|v| v * v).sum::<f32>() / x.len() as f32).sqrt()
    }

    fn tone_gain(mut f: impl FnMut(f32) -> f32, freq: f32, rate: f32) -> f32 {
        let n = 48_000;
        let out: Vec<f32> = (0..n)
            .map(|i| f((2.0 * PI * freq * i as f32 / rate).sin()))
            .collect();
        rms(&out[n / 2..]) / std::f32::consts::FRAC_1_SQRT_2
    }

    #[test]
    fn noise_is_zero_mean_and_seeded() {
        let mut a = Rng::new(7);
        let mut b = Rng::new(7);
        let xs: Vec<f32> = (0..100_000).map(|_| a.white()).collect();
        let mean = xs.iter().sum::<f32>() / xs.len() as f32;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((rms(&xs) - (1.0f32 / 3.0).sqrt()).abs() < 0.01);
        assert!(xs.iter().all(|&x| x == b.white()));
        assert_ne!(Rng::new(8).white(), xs[0]);
    }

    #[test]
    fn biquads_pass_and_stop_where_their_cookbook_says() {
        let rate = 48_000.0;
        let mut lp = Biquad::new(Band::LowPass, 500.0, 0.707, rate);
        assert!((tone_gain(|x| lp.next(x), 50.0, rate) - 1.0).abs() < 0.02);
        let mut lp = Biquad::new(Band::LowPass, 500.0, 0.707, rate);
        assert!(tone_gain(|x| lp.next(x), 5000.0, rate) < 0.015);
        let mut bp = Biquad::new(Band::BandPass, 1000.0, 2.0, rate);
        assert!((tone_gain(|x| bp.next(x), 1000.0, rate) - 1.0).abs() < 0.02);
        let mut hp = Biquad::new(Band::HighPass, 1000.0, 0.707, rate);
        assert!(tone_gain(|x| hp.next(x), 100.0, rate) < 0.015);
    }

    #[test]
    fn the_head_shadow_is_flat_low_and_shelves_high() {
        let rate = 48_000.0;
        let omega0 = 343.0 / 0.0875;
        for alpha in [2.0f32, 0.1, 1.0] {
            let mut h = HeadShadow::new(0.0875, 343.0, rate);
            h.set_alpha(alpha);
            let low = tone_gain(|x| h.next(x), 60.0, rate);
            assert!((low - 1.0).abs() < 0.02, "α {alpha}: {low}");
            // The bilinear transform's response at f is the analog one at its warped Ω.
            let f = 16_000.0;
            let w = 2.0 * rate * (PI * f / rate).tan() / (2.0 * omega0);
            let analog = (1.0 + (alpha * w).powi(2)).sqrt() / (1.0 + w * w).sqrt();
            let mut h = HeadShadow::new(0.0875, 343.0, rate);
            h.set_alpha(alpha);
            let g = tone_gain(|x| h.next(x), f, rate);
            assert!(
                (g / analog - 1.0).abs() < 0.03,
                "α {alpha}: {g} vs {analog}"
            );
        }
    }
}
