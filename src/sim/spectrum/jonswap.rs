//! The JONSWAP fetch-limited frequency spectrum in physical units (Hasselmann et al. 1973).

use crate::sim::params::GRAVITY;

/// Spectral density S(ω) (m²·s) of the JONSWAP spectrum for wind `wind` (m/s at 10 m),
/// fetch `fetch_m` (m) and peak enhancement `gamma`.
pub fn density(omega: f64, wind: f32, fetch_m: f64, gamma: f32) -> f64 {
    if omega <= 0.0 {
        return 0.0;
    }
    let g = GRAVITY as f64;
    let u = wind as f64;
    let alpha = 0.076 * libm::pow(u * u / (fetch_m * g), 0.22);
    let wp = peak_frequency(wind, fetch_m);
    let sigma = if omega <= wp { 0.07 } else { 0.09 };
    let r = libm::exp(-((omega - wp).powi(2)) / (2.0 * sigma * sigma * wp * wp));
    let ratio = wp / omega;
    alpha * g * g / omega.powi(5) * libm::exp(-1.25 * ratio.powi(4)) * libm::pow(gamma as f64, r)
}

/// Peak angular frequency ω_p = 22·(g²/(U·F))^(1/3) (rad/s).
pub fn peak_frequency(wind: f32, fetch_m: f64) -> f64 {
    let g = GRAVITY as f64;
    22.0 * libm::cbrt(g * g / (wind as f64 * fetch_m))
}

/// Normalization of the directional spreading |cos θ|^(2s), with the back half scaled by σ:
/// ∫ over the circle = (1 + σ)·√π·Γ(s + ½)/Γ(s + 1), so that the spread distribution integrates
/// to one and the total variance is that of S(ω).
pub fn spreading_norm(s: f64, counter: f64) -> f64 {
    let half = libm::sqrt(std::f64::consts::PI) * libm::tgamma(s + 0.5) / libm::tgamma(s + 1.0);
    (1.0 + counter) * half
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spreading_integrates_to_one() {
        for (s, sigma) in [(1.0, 0.5), (6.0, 0.01), (3.45, 0.2)] {
            let z = spreading_norm(s, sigma);
            let n = 100_000;
            let mut sum = 0.0;
            for i in 0..n {
                let th =
                    -std::f64::consts::PI + (i as f64 + 0.5) * std::f64::consts::TAU / n as f64;
                let c = th.cos();
                let w = if c < 0.0 { sigma } else { 1.0 };
                sum += w * c.abs().powf(2.0 * s) / z;
            }
            let integral = sum * std::f64::consts::TAU / n as f64;
            assert!((integral - 1.0).abs() < 1e-6, "{s} {sigma}: {integral}");
        }
    }

    fn m0(wind: f32, fetch: f64, gamma: f32) -> f64 {
        let n = 400_000;
        let (w0, w1) = (0.05, 40.0);
        let dw = (w1 - w0) / n as f64;
        (0..n)
            .map(|i| density(w0 + (i as f64 + 0.5) * dw, wind, fetch, gamma) * dw)
            .sum()
    }

    #[test]
    fn without_peak_enhancement_the_variance_is_analytic() {
        // γ = 1 leaves α·g²·ω⁻⁵·e^(−5/4·(ωp/ω)⁴), whose integral is α·g²/(5·ωp⁴).
        let (u, f) = (10.0f32, 100_000.0);
        let g = GRAVITY as f64;
        let alpha = 0.076 * (u as f64 * u as f64 / (f * g)).powf(0.22);
        let wp = peak_frequency(u, f);
        let exact = alpha * g * g / (5.0 * wp.powi(4));
        let got = m0(u, f, 1.0);
        assert!((got / exact - 1.0).abs() < 1e-3, "{got} vs {exact}");
    }

    #[test]
    fn peak_enhancement_and_fetch_behave() {
        let (u, f) = (10.0f32, 100_000.0);
        // γ = 3.3 adds energy around the peak; longer fetch grows the sea and lowers the peak.
        assert!(m0(u, f, 3.3) > 1.2 * m0(u, f, 1.0));
        assert!(m0(u, 4.0 * f, 3.3) > m0(u, f, 3.3));
        assert!(peak_frequency(u, 4.0 * f) < peak_frequency(u, f));
        let tp = std::f64::consts::TAU / peak_frequency(u, f);
        assert!((5.0..7.5).contains(&tp), "Tp {tp}");
    }
}
