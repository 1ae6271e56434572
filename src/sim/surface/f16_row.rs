//! RGBA16F texels from four f32 planes: the displacement's GPU format, converted by the CPU's
//! own instruction where it has one (F16C `vcvtps2ph` on x86-64 at the AVX2 tier and above,
//! NEON `fcvtn` on aarch64), else by [`pack::f16_bits`] in plain Rust. Every path rounds to
//! nearest even, so all give the same bits for every non-NaN value.
//!
//! A pass of its own rather than a part of the surface row loop: in software the conversion
//! is ~15 vector instructions per plane, a third of that loop, and its registers made the
//! loop spill; the instruction does eight texels of one plane at once. Not `half`'s slice
//! conversion: it converts one contiguous slice, and feeding it texels in (Dx, h, Dz, J) order
//! would put a 4-plane transpose back into the row loop; here the interleave is two unpacks per
//! pair of planes (F16C) or the `st4` store itself (NEON).

use crate::sim::pack;

/// Writes `out[i] = [p0[i], p1[i], p2[i], p3[i]]` as binary16 bits (round to nearest even).
/// Every plane must hold at least `out.len()` values.
pub(crate) fn interleave_f16(planes: [&[f32]; 4], out: &mut [[u16; 4]]) {
    let n = out.len();
    let planes = planes.map(|p| &p[..n]);
    #[cfg(target_arch = "x86_64")]
    {
        use crate::sim::simd::{active_tier, Tier};
        if active_tier() >= Tier::Avx2 && has_f16c() {
            // SAFETY: the CPU has F16C and AVX, checked just above.
            let done = unsafe { f16c(planes, out) };
            software(planes, &mut out[done..], done);
        } else {
            software(planes, out, 0);
        }
    }
    #[cfg(target_arch = "aarch64")]
    {
        let done = neon(planes, out);
        software(planes, &mut out[done..], done);
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    software(planes, out, 0);
}

/// True when this x86-64 CPU has F16C and AVX (cached by std after the first call).
#[cfg(target_arch = "x86_64")]
fn has_f16c() -> bool {
    std::is_x86_feature_detected!("avx") && std::is_x86_feature_detected!("f16c")
}

/// The texels from `from` on, by [`pack::f16_bits`] (`out[i]` is texel `from + i`).
fn software(planes: [&[f32]; 4], out: &mut [[u16; 4]], from: usize) {
    let n = out.len();
    // Named exact-length slices and an explicit loop: the vectorizer then converts four texels
    // per plane at once (an array `map` per texel stayed scalar).
    let [a, b, c, d] = planes.map(|p| &p[from..from + n]);
    for i in 0..n {
        out[i] = [
            pack::f16_bits(a[i]),
            pack::f16_bits(b[i]),
            pack::f16_bits(c[i]),
            pack::f16_bits(d[i]),
        ];
    }
}

/// Whole groups of eight texels by F16C; returns how many texels it wrote.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,f16c")]
unsafe fn f16c(planes: [&[f32]; 4], out: &mut [[u16; 4]]) -> usize {
    use std::arch::x86_64::*;
    let whole = out.len() / 8 * 8;
    for (i, texels) in out[..whole].chunks_exact_mut(8).enumerate() {
        let half = |p: &[f32]| {
            let p = &p[8 * i..8 * i + 8];
            // SAFETY: `p` holds the eight floats an unaligned 256-bit load reads.
            let v = unsafe { _mm256_loadu_ps(p.as_ptr()) };
            _mm256_cvtps_ph::<_MM_FROUND_TO_NEAREST_INT>(v)
        };
        let [a, b, c, d] = planes.map(half);
        // (a0 b0 a1 b1 a2 b2 a3 b3), then whole texels (a b c d) two per 128-bit store.
        let (ab_lo, ab_hi) = (_mm_unpacklo_epi16(a, b), _mm_unpackhi_epi16(a, b));
        let (cd_lo, cd_hi) = (_mm_unpacklo_epi16(c, d), _mm_unpackhi_epi16(c, d));
        let pairs = [
            _mm_unpacklo_epi32(ab_lo, cd_lo),
            _mm_unpackhi_epi32(ab_lo, cd_lo),
            _mm_unpacklo_epi32(ab_hi, cd_hi),
            _mm_unpackhi_epi32(ab_hi, cd_hi),
        ];
        for (two, v) in texels.chunks_exact_mut(2).zip(pairs) {
            // SAFETY: `two` is two texels, 16 bytes, what an unaligned 128-bit store writes.
            unsafe { _mm_storeu_si128(two.as_mut_ptr().cast(), v) };
        }
    }
    whole
}

/// Whole groups of four texels by NEON `fcvtn` and an interleaving store; returns how many
/// texels it wrote.
#[cfg(target_arch = "aarch64")]
fn neon(planes: [&[f32]; 4], out: &mut [[u16; 4]]) -> usize {
    use std::arch::aarch64::*;
    use std::arch::asm;
    let whole = out.len() / 4 * 4;
    for (i, texels) in out[..whole].chunks_exact_mut(4).enumerate() {
        let half = |p: &[f32]| {
            let p = &p[4 * i..4 * i + 4];
            // SAFETY: `p` holds the four floats a 128-bit load reads.
            let v = unsafe { vld1q_f32(p.as_ptr()) };
            let h: uint16x4_t;
            // SAFETY: `fcvtn` (base ARMv8 Advanced SIMD) converts four floats to binary16 in
            // registers, rounding per FPCR (round to nearest even unless a program changed it);
            // it touches no memory or stack.
            unsafe {
                asm!("fcvtn {h:v}.4h, {v:v}.4s", h = out(vreg) h, v = in(vreg) v,
                     options(pure, nomem, nostack));
            }
            h
        };
        let [a, b, c, d] = planes.map(half);
        // SAFETY: `texels` is four texels, the 32 bytes `vst4_u16` writes interleaved.
        unsafe { vst4_u16(texels.as_mut_ptr().cast(), uint16x4x4_t(a, b, c, d)) };
    }
    whole
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values across binary16's range: normals, subnormals, overflow, both signs, ties.
    fn values(n: usize, seed: u32) -> Vec<f32> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                // Exponents 100..=145 cover f16 subnormals (< 2^-14), normals and overflow.
                let exp = 100 + (s >> 8) % 46;
                let bits = (s & 0x8000_0000) | (exp << 23) | (s.rotate_left(11) & 0x7f_ffff);
                // Every eighth value a round-to-even tie (the 13 dropped bits 1000…0).
                let bits = if s.is_multiple_of(8) {
                    (bits & !0x1fff) | 0x1000
                } else {
                    bits
                };
                f32::from_bits(bits)
            })
            .collect()
    }

    #[test]
    fn the_instruction_gives_the_software_bits() {
        for n in [1, 3, 4, 7, 8, 9, 16, 61, 256] {
            let p: Vec<Vec<f32>> = (0..4).map(|q| values(n, 7 + q)).collect();
            let planes = [&p[0][..], &p[1][..], &p[2][..], &p[3][..]];
            let expect: Vec<[u16; 4]> = (0..n)
                .map(|i| planes.map(|q| pack::f16_bits(q[i])))
                .collect();
            let mut out = vec![[0u16; 4]; n];
            software(planes, &mut out, 0);
            assert_eq!(out, expect, "software, n {n}");
            // The dispatched path: F16C or NEON where the CPU has them.
            let mut out = vec![[0u16; 4]; n];
            interleave_f16(planes, &mut out);
            assert_eq!(out, expect, "dispatched, n {n}");
            #[cfg(target_arch = "x86_64")]
            if has_f16c() {
                let mut out = vec![[0u16; 4]; n];
                // SAFETY: the CPU has F16C and AVX (checked).
                let done = unsafe { f16c(planes, &mut out) };
                assert_eq!(done, n / 8 * 8);
                assert_eq!(out[..done], expect[..done], "F16C, n {n}");
            }
            #[cfg(target_arch = "aarch64")]
            {
                let mut out = vec![[0u16; 4]; n];
                let done = neon(planes, &mut out);
                assert_eq!(done, n / 4 * 4);
                assert_eq!(out[..done], expect[..done], "NEON, n {n}");
            }
        }
    }
}
