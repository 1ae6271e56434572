//! Directional spreading of a wind sea that depends on the frequency (issue 29): narrow at the
//! spectral peak, wide above it, as measured by Mitsuyasu et al. (1975) and Hasselmann, Dunckel
//! & Ewing (1980), in the cos²ˢ(θ/2) form:
//!
//! ```text
//! D(θ; ω) = N(s)·cos²ˢ(θ/2),   N(s) = Γ(s + 1) / (2√π·Γ(s + ½))   (∫ D dθ over the circle = 1)
//! s(ω) = 6.97·(ω/ω_p)^4.06                        ω < 1.05·ω_p
//! s(ω) = 9.77·(ω/ω_p)^μ,  μ = −2.33 − 1.45·(U/c_p − 1.17)     ω ≥ 1.05·ω_p
//! ```
//!
//! (θ from the wind direction, c_p = g/ω_p the peak's phase speed, U the 10 m wind.) One
//! exponent for every wavelength (the thesis's eq. 6, |cos θ|²ˢ with s = 4.2) combs the short
//! waves, which carry the slopes, into streaks along the wind: the resolved sea's along/across
//! slope-variance ratio was 9.3 at every scale where Cox & Munk measured about 1.4 at 10 m/s.
//! With s(ω) the short waves are close to isotropic and the ratio lands near Cox & Munk's
//! (`tests/sim/spectrum.rs`). The thesis's spread stays for `--spectrum phillips`.

use crate::sim::dispersion::GRAVITY;

/// The spreading of one wind sea (its wind and peak frequency).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spreading {
    peak: f64,
    mu: f64,
}

impl Spreading {
    /// The spreading of a sea of `wind` (m/s) whose spectrum peaks at `peak` (rad/s).
    pub fn new(wind: f32, peak: f64) -> Self {
        let cp = GRAVITY as f64 / peak;
        Self {
            peak,
            mu: -2.33 - 1.45 * (wind as f64 / cp - 1.17),
        }
    }

    /// The exponent s(ω) of waves of angular frequency `omega` (rad/s).
    pub fn exponent(&self, omega: f64) -> f64 {
        let x = omega / self.peak;
        if x < 1.05 {
            6.97 * libm::pow(x, 4.06)
        } else {
            9.77 * libm::pow(x, self.mu)
        }
    }

    /// D(θ; ω) (1/rad) for waves of frequency `omega` travelling at angle θ to the wind,
    /// given as `cos_theta`.
    pub fn density(&self, omega: f64, cos_theta: f64) -> f64 {
        let s = self.exponent(omega);
        let half = (0.5 * (1.0 + cos_theta)).max(0.0);
        norm(s) * libm::pow(half, s)
    }
}

/// N(s) = Γ(s + 1) / (2√π·Γ(s + ½)), by the log-gamma function (no overflow for large s).
fn norm(s: f64) -> f64 {
    libm::exp(libm::lgamma(s + 1.0) - libm::lgamma(s + 0.5))
        / (2.0 * libm::sqrt(std::f64::consts::PI))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integral(f: impl Fn(f64) -> f64) -> f64 {
        const STEPS: usize = 20_000;
        let h = std::f64::consts::TAU / STEPS as f64;
        (0..STEPS)
            .map(|i| f(-std::f64::consts::PI + (i as f64 + 0.5) * h) * h)
            .sum()
    }

    #[test]
    fn every_frequency_integrates_to_one_and_the_peak_is_narrowest() {
        // A fully developed 10 m/s sea (U/c_p ≈ 0.83).
        let s = Spreading::new(10.0, 0.83 * GRAVITY as f64 / 10.0);
        for x in [0.5, 0.9, 1.0, 1.05, 1.5, 3.0, 10.0, 30.0] {
            let w = x * s.peak;
            let total = integral(|t| s.density(w, t.cos()));
            assert!((total - 1.0).abs() < 1e-6, "ω/ω_p {x}: {total}");
        }
        let at = |x: f64| s.exponent(x * s.peak);
        assert!(at(1.05) > at(0.8) && at(1.05) > at(2.0) && at(2.0) > at(10.0));
        assert!((at(1.05) - 9.77 * 1.05f64.powf(s.mu)).abs() < 1e-9);
        // Short waves are nearly isotropic; younger seas spread more quickly above the peak.
        assert!(at(20.0) < 0.5);
        let young = Spreading::new(10.0, 2.0 * GRAVITY as f64 / 10.0);
        assert!(young.exponent(3.0 * young.peak) < s.exponent(3.0 * s.peak));
    }
}
