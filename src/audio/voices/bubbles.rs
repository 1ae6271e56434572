//! Bubbles: the sound of breaking water is mostly the ringing of freshly made air bubbles
//! (Minnaert 1933): a bubble of radius R rings at f₀ = √(3γp₀/ρ)/(2πR) ≈ 3.26 m/s / R in
//! water at the surface (6.5 kHz at 0.5 mm, 650 Hz at 5 mm), dying out in a few cycles per
//! its damping δ (Devin 1959: ≈ 0.03 for millimetre bubbles, growing with frequency; a time
//! constant τ = 1/(π·f₀·δ)). Each grain here is one bubble: a damped sinusoid rotated by
//! one complex multiply per sample.

use std::f32::consts::PI;

use super::super::dsp::Rng;

/// f₀·R for an air bubble in water at one atmosphere (m/s).
pub const MINNAERT: f32 = 3.26;

/// Grains rendered together: one vector register's worth on AVX (two NEON registers), so the
/// per-sample rotation runs across grains instead of down one grain's dependency chain.
const LANES: usize = 8;

/// A fixed pool of bubble grains (`N` at once, a multiple of 8; a new one beyond is
/// dropped), stored by component so `LANES` grains rotate per instruction.
#[derive(Clone, Debug)]
pub struct Bubbles<const N: usize> {
    re: [f32; N],
    im: [f32; N],
    cos: [f32; N],
    sin: [f32; N],
    left: [u32; N],
    live: usize,
}

impl<const N: usize> Default for Bubbles<N> {
    fn default() -> Self {
        Self {
            re: [0.0; N],
            im: [0.0; N],
            cos: [0.0; N],
            sin: [0.0; N],
            left: [0; N],
            live: 0,
        }
    }
}

/// Radii a breaking crest or a splash makes, in metres: [min, max], drawn with density ∝ R⁻²
/// (more small bubbles than large; measured distributions fall between R⁻¹·⁵ and R⁻³·⁵).
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    /// Smallest radius (m).
    pub min: f32,
    /// Largest radius (m).
    pub max: f32,
}

impl Sizes {
    /// A radius from the R⁻² density (inverse of its CDF).
    pub fn draw(&self, rng: &mut Rng) -> f32 {
        let u = rng.unit();
        1.0 / (1.0 / self.min - u * (1.0 / self.min - 1.0 / self.max))
    }
}

impl<const N: usize> Bubbles<N> {
    /// Bubbles ringing now.
    pub fn live(&self) -> usize {
        self.live
    }

    /// Starts a bubble of radius `r` m at amplitude `amp` for `rate` samples/s, damped as a
    /// free bubble of its size is (Devin's δ).
    pub fn spawn(&mut self, r: f32, amp: f32, rate: f32) {
        let f0 = MINNAERT / r;
        self.spawn_damped(r, amp, 0.03 + 0.01 * f0 / 1000.0, rate);
    }

    /// [`Bubbles::spawn`] with damping `delta` (a torn cavity rings far shorter than a free
    /// bubble).
    pub fn spawn_damped(&mut self, r: f32, amp: f32, delta: f32, rate: f32) {
        let sizes_ok = r.is_finite() && r > 0.0 && delta.is_finite() && delta > 0.0;
        if self.live == N || !sizes_ok || !amp.is_finite() {
            return;
        }
        let f0 = (MINNAERT / r).min(0.45 * rate);
        let tau = 1.0 / (PI * f0 * delta);
        let decay = (-1.0 / (tau * rate)).exp();
        let w = 2.0 * PI * f0 / rate;
        let k = self.live;
        // Starting in sine phase (the output, the imaginary part, at zero): a bubble's ring
        // starts without a click.
        self.re[k] = amp;
        self.im[k] = 0.0;
        self.cos[k] = decay * w.cos();
        self.sin[k] = decay * w.sin();
        // Down by 60 dB: ln(1000)·τ.
        self.left[k] = (6.9 * tau * rate) as u32 + 1;
        self.live += 1;
    }

    /// Adds the live bubbles to `out` (mono) and retires the finished ones (a bubble ending
    /// inside the block rings to its end, 60 dB down).
    pub fn render(&mut self, out: &mut [f32]) {
        let lanes = (self.live.div_ceil(LANES) * LANES).min(N);
        for g in (0..lanes).step_by(LANES) {
            let lane = |a: &[f32; N]| -> [f32; LANES] {
                a[g..g + LANES]
                    .try_into()
                    .expect("N is a multiple of LANES")
            };
            let (mut re, mut im, c, s) = (
                lane(&self.re),
                lane(&self.im),
                lane(&self.cos),
                lane(&self.sin),
            );
            for o in out.iter_mut() {
                let mut sum = 0.0;
                for l in 0..LANES {
                    let r = re[l] * c[l] - im[l] * s[l];
                    im[l] = re[l] * s[l] + im[l] * c[l];
                    re[l] = r;
                    sum += im[l];
                }
                *o += sum;
            }
            self.re[g..g + LANES].copy_from_slice(&re);
            self.im[g..g + LANES].copy_from_slice(&im);
        }
        let n = out.len() as u32;
        let mut k = 0;
        while k < self.live {
            self.left[k] = self.left[k].saturating_sub(n);
            if self.left[k] == 0 {
                self.live -= 1;
                let last = self.live;
                self.re.swap(k, last);
                self.im.swap(k, last);
                self.cos.swap(k, last);
                self.sin.swap(k, last);
                self.left.swap(k, last);
                // A retired lane rings no more (it is rendered beside live ones).
                self.re[last] = 0.0;
                self.im[last] = 0.0;
            } else {
                k += 1;
            }
        }
    }
}

/// How many events a Poisson process of `rate_per_s` makes in `dt` s (drawn by inversion;
/// capped at `cap`).
pub fn poisson(rng: &mut Rng, rate_per_s: f32, dt: f32, cap: usize) -> usize {
    let mean = (rate_per_s * dt).max(0.0);
    if mean <= 0.0 {
        return 0;
    }
    let limit = (-mean).exp();
    let mut p = rng.unit();
    let mut k = 0;
    while p > limit && k < cap {
        p *= rng.unit();
        k += 1;
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bubble_rings_at_minnaerts_frequency_and_dies() {
        let rate = 48_000.0;
        let mut b = Bubbles::<8>::default();
        b.spawn(2.0e-3, 1.0, rate);
        let mut out = vec![0.0f32; 4800];
        for block in out.chunks_mut(64) {
            b.render(block);
        }
        assert_eq!(b.live(), 0, "a 2 mm bubble rings for milliseconds");
        // Zero crossings over the first 5 ms: 2·f₀·t.
        let n = 240;
        let crossings = out[..n]
            .windows(2)
            .filter(|w| w[0].signum() != w[1].signum())
            .count();
        let f = crossings as f32 / 2.0 / (n as f32 / rate);
        assert!((f / (MINNAERT / 2.0e-3) - 1.0).abs() < 0.1, "{f} Hz");
        assert!(out[4000..].iter().all(|x| *x == 0.0));
    }

    #[test]
    fn poisson_counts_have_their_mean() {
        let mut rng = Rng::new(3);
        let total: usize = (0..10_000)
            .map(|_| poisson(&mut rng, 300.0, 0.01, 64))
            .sum();
        let mean = total as f32 / 10_000.0;
        assert!((mean - 3.0).abs() < 0.1, "{mean}");
    }
}
