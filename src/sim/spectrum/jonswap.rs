//! The JONSWAP fetch-limited frequency spectrum in physical units (Hasselmann et al. 1973),
//! and [`JonswapSea`]: the sea a wind makes, its height following the fetch-limited growth law
//! up to the fully developed (Pierson-Moskowitz) limit.
//!
//! JONSWAP's α = 0.076·x^−0.22 and ω_p = 22·(g/U)·x^−1/3 (x = gF/U², the dimensionless fetch)
//! never saturate, and with γ = 3.3 the spectrum holds more variance than the growth law it was
//! fitted with: at 10 m/s and 550 km, 4√m0 is 5.5 m where a fully developed sea has 2.2 m. So the
//! sea takes x_eff = min(x, [`SATURATED_FETCH`]) and scales α so that Hs = 4√m0 follows the
//! law g·Hs/U² = min(1.6e-3·√x, 0.22).

use crate::sim::dispersion::GRAVITY;

/// The dimensionless fetch gF/U² at which a wind sea stops growing (fully developed): where the
/// fetch-limited law 1.6e-3·√x meets the Pierson-Moskowitz limit 0.22.
pub const SATURATED_FETCH: f64 = 1.9e4;

/// Fully developed significant height in units of U²/g (Pierson-Moskowitz).
pub const FULLY_DEVELOPED_HS: f64 = 0.22;

/// Significant wave height (m) of a wind sea of `wind` (m/s at 10 m) over `fetch_m` (m):
/// g·Hs/U² = min(1.6e-3·√(gF/U²), 0.22).
pub fn significant_height(wind: f32, fetch_m: f64) -> f64 {
    let g = GRAVITY as f64;
    let u = wind as f64;
    let x = g * fetch_m / (u * u);
    (1.6e-3 * libm::sqrt(x)).min(FULLY_DEVELOPED_HS) * u * u / g
}

/// The JONSWAP spectrum of a wind sea, normalised to the growth law's Hs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JonswapSea {
    alpha: f64,
    peak: f64,
    gamma: f64,
}

impl JonswapSea {
    /// The sea of `wind` (m/s) over `fetch_m` (m) with peak enhancement `gamma`.
    pub fn new(wind: f32, fetch_m: f64, gamma: f32) -> Self {
        let u = wind as f64;
        let x = dimensionless_fetch(wind, fetch_m);
        let effective_fetch = x * u * u / GRAVITY as f64;
        let raw = Self {
            alpha: 0.076 * libm::pow(x, -0.22),
            peak: peak_frequency(wind, effective_fetch),
            gamma: gamma as f64,
        };
        let target = significant_height(wind, fetch_m) / 4.0;
        Self {
            alpha: raw.alpha * target * target / raw.variance(),
            ..raw
        }
    }

    /// Spectral density S(ω) (m²·s).
    pub fn density(&self, omega: f64) -> f64 {
        shape(omega, self.alpha, self.peak, self.gamma)
    }

    /// Peak angular frequency (rad/s).
    pub fn peak_frequency(&self) -> f64 {
        self.peak
    }

    /// Peak wavelength in deep water, 2πg/ω_p² (m).
    pub fn peak_wavelength(&self) -> f64 {
        std::f64::consts::TAU * GRAVITY as f64 / (self.peak * self.peak)
    }

    /// m0 = ∫S(ω)dω (m²), integrated numerically from a tenth of the peak to 40 peaks.
    pub fn variance(&self) -> f64 {
        const STEPS: usize = 4000;
        let (lo, hi) = (0.1 * self.peak, 40.0 * self.peak);
        // Log-spaced: the peak is narrow and the tail long. Software libm throughout, so the
        // normalisation (and every amplitude) is bit-identical on every platform.
        let ln = libm::log(hi / lo);
        (0..STEPS)
            .map(|i| {
                let w0 = lo * libm::exp(ln * i as f64 / STEPS as f64);
                let w1 = lo * libm::exp(ln * (i + 1) as f64 / STEPS as f64);
                self.density(0.5 * (w0 + w1)) * (w1 - w0)
            })
            .sum()
    }
}

/// The JONSWAP shape α·g²/ω⁵·exp(−5/4·(ω_p/ω)⁴)·γ^r (plain products, no `powi`, whose
/// rounding is the platform's).
fn shape(omega: f64, alpha: f64, wp: f64, gamma: f64) -> f64 {
    if omega <= 0.0 {
        return 0.0;
    }
    let g = GRAVITY as f64;
    let sigma = if omega <= wp { 0.07 } else { 0.09 };
    let d = omega - wp;
    let r = libm::exp(-(d * d) / (2.0 * sigma * sigma * wp * wp));
    let ratio2 = (wp / omega) * (wp / omega);
    let w2 = omega * omega;
    alpha * g * g / (w2 * w2 * omega) * libm::exp(-1.25 * ratio2 * ratio2) * libm::pow(gamma, r)
}

/// The TMA depth factor Φ(ω_h) (Kitaigorodskii), ω_h = ω·√(h/g): the share of a deep-water
/// spectrum a finite depth h keeps.
pub fn depth_factor(omega: f64, depth: f64) -> f64 {
    let wh = omega * libm::sqrt(depth / GRAVITY as f64);
    if wh <= 1.0 {
        0.5 * wh * wh
    } else if wh < 2.0 {
        1.0 - 0.5 * (2.0 - wh) * (2.0 - wh)
    } else {
        1.0
    }
}

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

/// The dimensionless fetch gF/U² of `wind` (m/s) over `fetch_m` (m), at most
/// [`SATURATED_FETCH`] (a fully developed sea grows no further).
fn dimensionless_fetch(wind: f32, fetch_m: f64) -> f64 {
    let u = wind as f64;
    (GRAVITY as f64 * fetch_m / (u * u)).min(SATURATED_FETCH)
}

/// Peak wavelength (m, deep water) of the sea `wind` (m/s) raises over `fetch_m` (m): what
/// [`JonswapSea::peak_wavelength`] gives, without normalizing the spectrum.
pub fn peak_wavelength(wind: f32, fetch_m: f64) -> f64 {
    let u = wind as f64;
    let effective_fetch = dimensionless_fetch(wind, fetch_m) * u * u / GRAVITY as f64;
    let peak = peak_frequency(wind, effective_fetch);
    std::f64::consts::TAU * GRAVITY as f64 / (peak * peak)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sea_follows_the_growth_law_to_the_fully_developed_limit() {
        // Fully developed: Hs ≈ 0.22·U²/g (2.2 m at 10 m/s), whatever the longer fetch.
        for u in [5.0f32, 10.0] {
            let hs = 4.0 * JonswapSea::new(u, 1.0e6, 3.3).variance().sqrt();
            let pm = FULLY_DEVELOPED_HS * (u as f64).powi(2) / GRAVITY as f64;
            assert!((hs / pm - 1.0).abs() < 0.01, "{u} m/s: Hs {hs}, PM {pm}");
        }
        // Fetch-limited: 20 m/s over 300 km is still growing, below its 9 m limit.
        let hs = 4.0 * JonswapSea::new(20.0, 3.0e5, 3.3).variance().sqrt();
        assert!((hs - significant_height(20.0, 3.0e5)).abs() < 0.01 * hs);
        assert!(hs < 0.8 * 8.97 && hs > 4.0, "{hs}");
        // Peak wavelength grows with the wind (fully developed 10 m/s: about 90 m).
        let l10 = JonswapSea::new(10.0, 1.0e6, 3.3).peak_wavelength();
        assert!((70.0..110.0).contains(&l10), "{l10}");
        assert!(JonswapSea::new(20.0, 1.0e6, 3.3).peak_wavelength() > 3.0 * l10);
        // Shallow water keeps less of the long waves.
        assert!(depth_factor(0.5, 5.0) < 0.5 && depth_factor(3.0, 50.0) == 1.0);
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
