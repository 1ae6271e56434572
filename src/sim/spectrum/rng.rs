//! Per-index deterministic Gaussian draws (thesis eq. 12).
//!
//! Each wave-vector index hashes to its own random numbers, so the spectrum is independent of
//! iteration order, thread count and platform: integer hashing plus `libm` (pure software maths)
//! gives bit-identical results everywhere.

/// SplitMix64 finalizer: a bijective 64-bit mix with full avalanche.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform in (0, 1]: never 0, so ln(u) in Box-Muller is finite.
#[inline]
fn unit_open0(bits: u64) -> f64 {
    ((bits >> 11) as f64 + 1.0) * (1.0 / (1u64 << 53) as f64)
}

/// The complex standard Gaussian ξ (each part N(0,1), so E|ξ|² = 2) for wave-vector `index` of
/// `cascade`, by Box-Muller (eq. 12).
pub fn gaussian_pair(seed: u64, cascade: u32, index: u32) -> (f64, f64) {
    let key = mix(seed ^ mix(((cascade as u64) << 32) | index as u64));
    let u1 = unit_open0(mix(key ^ 0x243F_6A88_85A3_08D3));
    let u2 = unit_open0(mix(key ^ 0x1319_8A2E_0370_7344));
    let r = libm::sqrt(-2.0 * libm::log(u1));
    let (s, c) = libm::sincos(std::f64::consts::TAU * u2);
    (r * s, r * c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_moments() {
        let n = 200_000u32;
        let (mut m, mut v, mut m4) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let (a, b) = gaussian_pair(7, 0, i);
            for x in [a, b] {
                m += x;
                v += x * x;
                m4 += x * x * x * x;
            }
        }
        let cnt = 2.0 * n as f64;
        let (m, v, m4) = (m / cnt, v / cnt, m4 / cnt);
        assert!(m.abs() < 0.01, "mean {m}");
        assert!((v - 1.0).abs() < 0.01, "variance {v}");
        assert!((m4 - 3.0).abs() < 0.05, "kurtosis {m4}");
    }

    #[test]
    fn seeds_and_cascades_differ() {
        assert_ne!(gaussian_pair(1, 0, 5), gaussian_pair(2, 0, 5));
        assert_ne!(gaussian_pair(1, 0, 5), gaussian_pair(1, 1, 5));
        assert_eq!(gaussian_pair(1, 0, 5), gaussian_pair(1, 0, 5));
    }
}
