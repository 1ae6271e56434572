//! sin/cos of an angle given in turns, branch-free so the evolution loop vectorizes, and made of
//! plain f32 adds and multiplies so every platform computes the same bits.

/// Adding and subtracting 1.5·2²³ rounds an f32 of magnitude < 2²² to the nearest integer
/// (ties to even) with two plain adds: unlike `f32::round`, which is a libm call on baseline
/// x86-64 (no SSE4.1), this vectorizes everywhere and gives the same bits on every platform.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// Nearest integer of `x` for |x| < 2²² (see `ROUND_MAGIC`).
#[inline(always)]
pub fn round_small(x: f32) -> f32 {
    (x + ROUND_MAGIC) - ROUND_MAGIC
}

/// (sin 2πx, cos 2πx) for `x` in turns with |x| < 2²⁰. Max error ≈ 3e-7.
#[inline(always)]
pub fn sincos_turns(x: f32) -> (f32, f32) {
    // Reduce to r ∈ [−1/8, 1/8] turn and a quadrant q ∈ {0, 1, 2, 3}.
    // x·4 + 1.5·2²³ holds round(4x) in its low mantissa bits (two's complement modulo 2²²), so
    // the quadrant comes from the bits: a float-to-int cast would saturate, which LLVM does not
    // vectorize on x86 (it went scalar, one `cvttss2si` per lane).
    let m = x * 4.0 + ROUND_MAGIC;
    let q4 = m - ROUND_MAGIC;
    let r = x - q4 * 0.25;
    let q = m.to_bits() & 3;
    let t = r * std::f32::consts::TAU;
    let t2 = t * t;
    // Taylor on |t| ≤ π/4: truncation error < 3e-7 (sin), < 3e-8 (cos).
    let s = t * (1.0 + t2 * (-1.0 / 6.0 + t2 * (1.0 / 120.0 + t2 * (-1.0 / 5040.0))));
    let c = 1.0 + t2 * (-0.5 + t2 * (1.0 / 24.0 + t2 * (-1.0 / 720.0 + t2 * (1.0 / 40320.0))));
    // Rotate by q quarter turns: (s, c) → (c, −s) → (−s, −c) → (−c, s).
    let (s1, c1) = if q & 1 == 1 { (c, -s) } else { (s, c) };
    if q & 2 == 2 {
        (-s1, -c1)
    } else {
        (s1, c1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrant_bits_match_the_rounded_integer() {
        for i in -200_000..=200_000 {
            let x = i as f32 * 3.7e-3 + 0.123e-5;
            let m = x * 4.0 + ROUND_MAGIC;
            assert_eq!(
                m.to_bits() & 3,
                (round_small(x * 4.0) as i32 & 3) as u32,
                "{x}"
            );
        }
    }

    #[test]
    fn matches_f64_sin_cos() {
        let mut worst = 0.0f64;
        for i in -40_000..=40_000 {
            let x = i as f32 * 1e-4 + 0.123_456_7e-4;
            let (s, c) = sincos_turns(x);
            let a = x as f64 * std::f64::consts::TAU;
            worst = worst
                .max((s as f64 - a.sin()).abs())
                .max((c as f64 - a.cos()).abs());
        }
        assert!(worst < 4e-7, "max error {worst}");
    }
}
