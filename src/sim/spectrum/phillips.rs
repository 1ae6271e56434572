//! The Phillips spectrum with the thesis's normalization and directional terms (eq. 3-11).

use crate::sim::dispersion::GRAVITY;

/// Smallest cutoff length l_min of eq. 11 (m).
pub const CUTOFF_MIN: f64 = 0.001;

/// Spreading exponent s(α) = 1 + 5α² (eq. 6).
pub fn spreading_exponent(alignment: f32) -> f64 {
    1.0 + 5.0 * (alignment as f64).powi(2)
}

/// Energy kept by waves running against the wind, σ(α) = 0.01 + 0.49(1 − α)² (eq. 8).
pub fn counter_wave_factor(alignment: f32) -> f64 {
    0.01 + 0.49 * (1.0 - alignment as f64).powi(2)
}

/// Cutoff length l = l_min·(0.25·L_patch/l_min)^β (eq. 11).
pub fn cutoff_length(patch: f32, beta: f32) -> f64 {
    CUTOFF_MIN * libm::pow(0.25 * patch as f64 / CUTOFF_MIN, beta as f64)
}

/// Small-wave suppression factor e^(−k²l²) on the power (eq. 10).
pub fn small_wave_factor(k: f64, cutoff: f64) -> f64 {
    libm::exp(-k * k * cutoff * cutoff)
}

/// A = amplitude·A_FFT²·A_spatial² with A_FFT = N^(−1/4), A_spatial = e/L_patch (eq. 4-5).
pub fn normalization(amplitude: f32, n: usize, patch: f32) -> f64 {
    let a_fft2 = 1.0 / libm::sqrt(n as f64);
    let a_spatial = std::f64::consts::E / patch as f64;
    amplitude as f64 * a_fft2 * a_spatial * a_spatial
}

/// Phillips power A·e^(−1/(kL)²)/k⁴·|k̂·ŵ|^(2s) (eq. 3, 7) for wave number `k` > 0 and
/// `cos_theta` = k̂·ŵ; the counter-wave factor is applied by the caller (eq. 9).
pub fn power(a: f64, k: f64, cos_theta: f64, wind_speed: f32, s: f64) -> f64 {
    let l = (wind_speed as f64).powi(2) / GRAVITY as f64;
    let kl = k * l;
    let k2 = k * k;
    a * libm::exp(-1.0 / (kl * kl)) / (k2 * k2) * libm::pow(cos_theta.abs(), 2.0 * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_endpoints() {
        assert_eq!(spreading_exponent(0.0), 1.0);
        assert_eq!(spreading_exponent(1.0), 6.0);
        assert!((counter_wave_factor(1.0) - 0.01).abs() < 1e-12);
        assert!((counter_wave_factor(0.0) - 0.5).abs() < 1e-12);
        assert!((cutoff_length(100.0, 0.0) - CUTOFF_MIN).abs() < 1e-15);
        assert!((cutoff_length(100.0, 1.0) - 25.0).abs() < 1e-9);
    }

    #[test]
    fn peak_near_the_wind_scale() {
        // Energy per log k in 2D is k²·P = A·e^(−1/(kL)²)/k², which peaks at k = 1/L, L = V²/g.
        let v = 10.0f32;
        let l = (v as f64).powi(2) / GRAVITY as f64;
        let f = |k: f64| k * k * power(1.0, k, 1.0, v, 1.0);
        let kp = 1.0 / l;
        assert!(f(kp) > f(kp * 1.1) && f(kp) > f(kp * 0.9));
    }
}
