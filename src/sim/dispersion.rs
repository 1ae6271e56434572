//! Dispersion relations (thesis 3.3) and the loop quantization that makes the animation repeat.

/// Standard gravity (m/s²).
pub const GRAVITY: f32 = 9.81;

/// Beyond this k·d, tanh(k·d) equals 1 in f64, so finite depth is deep water.
const DEEP_KD: f64 = 20.0;

/// Angular frequency ω(k) (rad/s) for wave number `k` (rad/m): deep water ω = √(gk) (eq. 15),
/// or finite depth ω = √(gk·tanh(kd)) when `depth` is given.
pub fn omega(k: f64, depth: Option<f32>) -> f64 {
    let g = GRAVITY as f64;
    match depth {
        Some(d) if k * d as f64 <= DEEP_KD => libm::sqrt(g * k * libm::tanh(k * d as f64)),
        _ => libm::sqrt(g * k),
    }
}

/// Group-velocity factor dω/dk (m/s), used to convert a frequency spectrum S(ω) into a
/// wave-number spectrum: F(k) = S(ω(k))·dω/dk.
pub fn domega_dk(k: f64, depth: Option<f32>) -> f64 {
    let g = GRAVITY as f64;
    let w = omega(k, depth);
    if w == 0.0 {
        return 0.0;
    }
    match depth {
        Some(d) if k * d as f64 <= DEEP_KD => {
            let kd = k * d as f64;
            let th = libm::tanh(kd);
            let sech2 = 1.0 - th * th;
            g * (th + kd * sech2) / (2.0 * w)
        }
        _ => g / (2.0 * w),
    }
}

/// The loop quantization of eq. 16: the harmonic number n = ⌊ω/ω₀⌋ with ω₀ = 2π/T, so the
/// quantized frequency is ω' = n·ω₀ and every mode returns to its phase after T seconds.
pub fn loop_harmonic(omega: f64, period: f32) -> u32 {
    let w0 = std::f64::consts::TAU / period as f64;
    let n = libm::floor(omega / w0);
    // ω ≤ √(g·k_max) with k_max = πN/L is far below 2^24·ω₀ for any valid configuration,
    // so the harmonic is exact in f32 too.
    n.clamp(0.0, (1u32 << 24) as f64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_and_shallow_limits() {
        let k = 0.5;
        let deep = omega(k, None);
        assert!((deep - (GRAVITY as f64 * 0.5).sqrt()).abs() < 1e-12);
        // Very deep water equals the deep relation.
        assert_eq!(omega(k, Some(1000.0)), deep);
        // Shallow water: ω ≈ k·√(gd) when kd ≪ 1.
        let d = 0.5f32;
        let k = 0.01;
        let shallow = omega(k, Some(d));
        assert!((shallow / (k * (GRAVITY as f64 * d as f64).sqrt()) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn group_velocity_matches_finite_difference() {
        for depth in [None, Some(3.0f32), Some(40.0)] {
            for k in [0.01, 0.1, 1.0, 10.0] {
                let h = k * 1e-6;
                let fd = (omega(k + h, depth) - omega(k - h, depth)) / (2.0 * h);
                let an = domega_dk(k, depth);
                assert!((fd / an - 1.0).abs() < 1e-6, "{depth:?} {k}: {fd} vs {an}");
            }
        }
    }

    #[test]
    fn harmonic_floors_to_the_fundamental() {
        let t = 200.0;
        let w0 = std::f64::consts::TAU / 200.0;
        assert_eq!(loop_harmonic(0.0, t), 0);
        assert_eq!(loop_harmonic(w0 * 3.999, t), 3);
        assert_eq!(loop_harmonic(w0 * 4.0 + 1e-12, t), 4);
    }
}
