//! GPU upload encodings (thesis 3.8.3-3.9.2, 4.4): normal length from roughness, smoothness from
//! normal length, RGBA8 packing and the offsets of the contiguous mip chain.

use crate::sim::grid::GridSize;

/// Expected normal length for material roughness r ∈ [0, 1] (eq. 49).
#[inline]
pub fn normal_length(roughness: f32) -> f32 {
    let r = roughness;
    1.0 - r * (0.306 + r * (0.113 + r * 0.081))
}

/// Smoothness from an averaged (unnormalized) normal's length (eq. 53): [2/3, 1] ↦ [0, 1].
#[inline(always)]
pub fn smoothness(normal_length: f32) -> f32 {
    // (|n| − 2/3)/(1/3) written as 3|n| − 2, exact at |n| = 1.
    let t = (3.0 * normal_length - 2.0).clamp(0.0, 1.0);
    let r = 1.0 - t * (0.85 + 0.15 * t);
    1.0 - r.max(0.0).sqrt()
}

/// The Toksvig slope variance (1 − |n|)/|n| of the averaged normal that smoothness s encodes
/// (eq. 53 inverted), fitted as u²·(c₀ + c₁u + c₂u² + c₃u³ + c₄u⁴), u = 1 − s: within 0.6 % of
/// the exact form. The water shader evaluates it per texel (`toksvig_variance` in
/// `shaders/ocean.frag`, these coefficients) instead of a square root and a division (issue 28).
pub const TOKSVIG_FIT: [f32; 5] = [0.29176, -0.03476, 0.30023, -0.36776, 0.30845];

/// 1.5·2²³: adding it to x ∈ [0, 2²²) leaves round(x) in the low mantissa bits.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// Quantizes a [0, 1] value to 8 bits, rounding to nearest (eq. 50's ⌊v·255 + 0.5⌋ except
/// that exact ties go to even, as GPUs convert UNORM). Done with a float add and a bit mask
/// instead of a saturating float-to-int cast, so the surface loop vectorizes.
#[inline(always)]
fn unorm8(v: f32) -> u32 {
    (v.clamp(0.0, 1.0) * 255.0 + ROUND_MAGIC).to_bits() & 0xff
}

/// RGBA8 texel (eq. 50-51): R, G = unit normal x, z mapped from [−1, 1]; B = foam coverage
/// (the persistent foam replaces eq. 50's raw Jacobian, which is kept in the displacement
/// texture's alpha); A = smoothness. R is the lowest byte.
#[inline(always)]
pub fn pack_rgba8(nx: f32, nz: f32, foam: f32, smoothness: f32) -> u32 {
    unorm8(nx * 0.5 + 0.5)
        | (unorm8(nz * 0.5 + 0.5) << 8)
        | (unorm8(foam) << 16)
        | (unorm8(smoothness) << 24)
}

/// IEEE binary16 bits of `x`, rounded to nearest even: what F16C, NEON's `fcvtn` and `half`
/// compute for every non-NaN input (NaN becomes the quiet NaN 0x7e00, sign kept). Written
/// branch-free in integer and f32 arithmetic so that it vectorizes at every SIMD tier: the
/// surface stage's fallback where the CPU has no conversion instruction (SSE2).
#[inline(always)]
pub fn f16_bits(x: f32) -> u16 {
    let bits = x.to_bits();
    let sign = (bits >> 16) & 0x8000;
    let a = bits & 0x7fff_ffff;
    // Normal results: rebias the exponent (127 → 15) and round the 13 dropped mantissa bits to
    // nearest even; a carry out of the mantissa correctly bumps the exponent (up to infinity).
    let normal = a
        .wrapping_sub((127 - 15) << 23)
        .wrapping_add(0xfff + ((a >> 13) & 1))
        >> 13;
    // Subnormal results (|x| < 2⁻¹⁴): in x + 0.5 one ulp is 2⁻²⁴, the f16 subnormal step, so the
    // f32 add rounds to nearest even and leaves the f16 mantissa in the low bits.
    let subnormal = (f32::from_bits(a) + 0.5)
        .to_bits()
        .wrapping_sub(0.5f32.to_bits());
    let r = if a >= (127 + 16) << 23 {
        // |x| ≥ 2¹⁶ (or Inf, NaN): infinity or NaN.
        if a > 0x7f80_0000 {
            0x7e00
        } else {
            0x7c00
        }
    } else if a < (127 - 14) << 23 {
        subnormal
    } else {
        normal
    };
    (r | sign) as u16
}

/// Texel offset of mip `level` in the contiguous chain (eq. 55):
/// (4N² − 1)/3 − (4^(log₂N + 1 − m) − 1)/3.
#[inline]
pub fn mip_offset(grid: GridSize, level: u32) -> usize {
    let total = mip_chain_len(grid);
    let rest = ((1usize << (2 * (grid.log2() + 1 - level))) - 1) / 3;
    total - rest
}

/// Texels in the whole chain N² + (N/2)² + … + 1 = (4N² − 1)/3.
#[inline]
pub fn mip_chain_len(grid: GridSize) -> usize {
    (4 * grid.texels() - 1) / 3
}

/// Box-filtered mips of an R8 chain (the eq. 55 layout of `grid`) from its level 0. Tiling
/// and toroidal maps average correctly: the side is a power of two, so a 2×2 block never
/// straddles the wrap.
pub fn build_r8_mips(grid: GridSize, chain: &mut [u8]) {
    for level in 1..grid.mip_levels() {
        let (src_side, dst_side) = (grid.n() >> (level - 1), grid.n() >> level);
        let (head, tail) = chain.split_at_mut(mip_offset(grid, level));
        let src = &head[mip_offset(grid, level - 1)..];
        for r in 0..dst_side {
            for c in 0..dst_side {
                let at = |rr: usize, cc: usize| src[(2 * r + rr) * src_side + 2 * c + cc] as u32;
                let sum = at(0, 0) + at(0, 1) + at(1, 0) + at(1, 1);
                tail[r * dst_side + c] = ((sum + 2) / 4) as u8;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Length of the averaged normal that smoothness `s` encodes: eq. 53 inverted.
    fn normal_length_of(smoothness: f32) -> f32 {
        let r = (1.0 - smoothness) * (1.0 - smoothness);
        let t = (-0.85 + (0.7225 + 0.6 * (1.0 - r)).sqrt()) / 0.3;
        (t.clamp(0.0, 1.0) + 2.0) / 3.0
    }

    /// [`TOKSVIG_FIT`] at smoothness `s`, as the shader evaluates it.
    fn toksvig_variance_fit(s: f32) -> f32 {
        let u = 1.0 - s;
        let c = TOKSVIG_FIT;
        u * u * (c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * c[4]))))
    }

    #[test]
    fn the_shaders_toksvig_fit_follows_eq_53() {
        for k in 0..=1000 {
            let s = k as f32 / 1000.0;
            let len = normal_length_of(s);
            assert!(
                (smoothness(len) - s).abs() < 2e-3,
                "eq. 53 round trip at {s}"
            );
            let exact = 1.0 / len - 1.0;
            let fit = toksvig_variance_fit(s);
            assert!(
                (fit - exact).abs() <= 0.006 * exact + 1e-6,
                "s {s}: fit {fit}, exact {exact}"
            );
        }
        let shader = include_str!("../../shaders/ocean.frag");
        for c in TOKSVIG_FIT {
            assert!(shader.contains(&format!("{c}")), "ocean.frag lacks {c}");
        }
    }

    #[test]
    fn thesis_endpoints() {
        assert_eq!(normal_length(0.0), 1.0);
        assert!((normal_length(1.0) - 0.5).abs() < 1e-6);
        assert_eq!(smoothness(1.0), 1.0);
        assert_eq!(smoothness(2.0 / 3.0), 0.0);
        assert_eq!(smoothness(0.1), 0.0);
        assert!(smoothness(0.9) > smoothness(0.8));
    }

    #[test]
    fn packing_layout() {
        let p = pack_rgba8(1.0, -1.0, 0.5, 1.0);
        assert_eq!(p & 0xff, 255);
        assert_eq!((p >> 8) & 0xff, 0);
        assert_eq!((p >> 16) & 0xff, 128);
        assert_eq!(p >> 24, 255);
    }

    #[test]
    fn f16_bits_match_half_for_every_non_nan_input_tried() {
        let check = |bits: u32| {
            let x = f32::from_bits(bits);
            if !x.is_nan() {
                assert_eq!(
                    f16_bits(x),
                    half::f16::from_f32(x).to_bits(),
                    "{x:e} ({bits:#x})"
                );
            }
        };
        // Every f32 around the subnormal/normal boundary and the overflow edge, both signs.
        for exp in (100..=114).chain(140..=143) {
            for m in 0..1u32 << 23 {
                check((exp << 23) | m);
                check(0x8000_0000 | (exp << 23) | m);
            }
        }
        // A sweep over all bit patterns.
        for bits in (0..=u32::MAX).step_by(61) {
            check(bits);
        }
        assert_eq!(f16_bits(f32::NAN), 0x7e00);
        assert_eq!(f16_bits(f32::INFINITY), 0x7c00);
        assert_eq!(f16_bits(-0.0), 0x8000);
    }

    #[test]
    fn mip_offsets_follow_the_geometric_series() {
        for n in [16, 64, 1024] {
            let g = GridSize::new(n).unwrap();
            let mut expect = 0;
            for m in 0..g.mip_levels() {
                assert_eq!(mip_offset(g, m), expect, "n {n} level {m}");
                expect += (g.n() >> m) * (g.n() >> m);
            }
            assert_eq!(expect, mip_chain_len(g));
        }
    }
}
