//! x86_64 backends: SSE2 (baseline, 4 lanes), AVX2+FMA (8 lanes) and AVX-512F (16 lanes).
//!
//! Each backend is a zero-sized token whose constructor checks the CPU at runtime; the token's
//! existence is the proof that makes its intrinsics sound to execute. The kernel is instantiated
//! inside a `#[target_feature]` function per backend so the `#[inline(always)]` trait methods
//! compile to the wide instructions.

use core::arch::x86_64::*;

use super::butterfly::Simd;
use super::kernel::{self, Job};
use super::plan::{CRow, Plan};

/// SSE2 token. SSE2 is part of the x86_64 baseline, so it is always available.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sse2(());

impl Sse2 {
    /// Always available on x86_64.
    pub fn new() -> Sse2 {
        Sse2(())
    }
}

// One SAFETY note per backend (inside the impl) covers its intrinsic wrappers: the token
// proves the CPU feature, and every load and store goes through a slice of LANES floats.
#[allow(clippy::undocumented_unsafe_blocks)]
impl Simd for Sse2 {
    const LANES: usize = 4;
    type V = __m128;

    // SAFETY (all methods): SSE and SSE2 are part of the x86_64 baseline, so their intrinsics
    // can always execute; loads and stores go through slices of 4.

    #[inline(always)]
    fn splat(self, x: f32) -> __m128 {
        unsafe { _mm_set1_ps(x) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m128 {
        let s = &s[..4];
        unsafe { _mm_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m128) {
        let s = &mut s[..4];
        unsafe { _mm_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn add(self, a: __m128, b: __m128) -> __m128 {
        unsafe { _mm_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m128, b: __m128) -> __m128 {
        unsafe { _mm_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m128, b: __m128) -> __m128 {
        unsafe { _mm_mul_ps(a, b) }
    }
    #[inline(always)]
    fn mul_add(self, a: __m128, b: __m128, c: __m128) -> __m128 {
        unsafe { _mm_add_ps(_mm_mul_ps(a, b), c) }
    }
    #[inline(always)]
    fn neg_mul_add(self, a: __m128, b: __m128, c: __m128) -> __m128 {
        unsafe { _mm_sub_ps(c, _mm_mul_ps(a, b)) }
    }
    type Block = [__m128; 4];
    #[inline(always)]
    fn zero_block(self) -> [__m128; 4] {
        unsafe { [_mm_setzero_ps(); 4] }
    }
    #[inline(always)]
    fn transpose(self, r: [__m128; 4]) -> [__m128; 4] {
        unsafe {
            let t0 = _mm_unpacklo_ps(r[0], r[1]); // a0 b0 a1 b1
            let t1 = _mm_unpacklo_ps(r[2], r[3]); // c0 d0 c1 d1
            let t2 = _mm_unpackhi_ps(r[0], r[1]); // a2 b2 a3 b3
            let t3 = _mm_unpackhi_ps(r[2], r[3]); // c2 d2 c3 d3
            [
                _mm_movelh_ps(t0, t1),
                _mm_movehl_ps(t1, t0),
                _mm_movelh_ps(t2, t3),
                _mm_movehl_ps(t3, t2),
            ]
        }
    }
}

/// AVX2+FMA token.
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx2(());

impl Avx2 {
    /// The token, if this CPU has AVX2 and FMA.
    pub fn detect() -> Option<Avx2> {
        (is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")).then_some(Avx2(()))
    }
}

// One SAFETY note per backend (inside the impl) covers its intrinsic wrappers: the token
// proves the CPU feature, and every load and store goes through a slice of LANES floats.
#[allow(clippy::undocumented_unsafe_blocks)]
impl Simd for Avx2 {
    const LANES: usize = 8;
    type V = __m256;

    // SAFETY (all methods): an `Avx2` token exists only if `detect` saw AVX2 and FMA, so the
    // AVX/AVX2/FMA intrinsics below can execute; loads and stores go through slices of 8.
    #[inline(always)]
    fn splat(self, x: f32) -> __m256 {
        unsafe { _mm256_set1_ps(x) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m256 {
        let s = &s[..8];
        unsafe { _mm256_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m256) {
        let s = &mut s[..8];
        unsafe { _mm256_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn add(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_mul_ps(a, b) }
    }
    #[inline(always)]
    fn mul_add(self, a: __m256, b: __m256, c: __m256) -> __m256 {
        unsafe { _mm256_fmadd_ps(a, b, c) }
    }
    #[inline(always)]
    fn neg_mul_add(self, a: __m256, b: __m256, c: __m256) -> __m256 {
        unsafe { _mm256_fnmadd_ps(a, b, c) }
    }
    type Block = [__m256; 8];
    #[inline(always)]
    fn zero_block(self) -> [__m256; 8] {
        unsafe { [_mm256_setzero_ps(); 8] }
    }
    #[inline(always)]
    fn transpose(self, r: [__m256; 8]) -> [__m256; 8] {
        unsafe {
            // Within each 128-bit half: 2×2 blocks of pairs, then 4×4 blocks.
            let t0 = _mm256_unpacklo_ps(r[0], r[1]); // a0 b0 a1 b1 | a4 b4 a5 b5
            let t1 = _mm256_unpackhi_ps(r[0], r[1]); // a2 b2 a3 b3 | a6 b6 a7 b7
            let t2 = _mm256_unpacklo_ps(r[2], r[3]);
            let t3 = _mm256_unpackhi_ps(r[2], r[3]);
            let t4 = _mm256_unpacklo_ps(r[4], r[5]);
            let t5 = _mm256_unpackhi_ps(r[4], r[5]);
            let t6 = _mm256_unpacklo_ps(r[6], r[7]);
            let t7 = _mm256_unpackhi_ps(r[6], r[7]);
            let u0 = _mm256_shuffle_ps::<0x44>(t0, t2); // a0 b0 c0 d0 | a4 b4 c4 d4
            let u1 = _mm256_shuffle_ps::<0xEE>(t0, t2); // col 1 | col 5
            let u2 = _mm256_shuffle_ps::<0x44>(t1, t3); // col 2 | col 6
            let u3 = _mm256_shuffle_ps::<0xEE>(t1, t3); // col 3 | col 7
            let u4 = _mm256_shuffle_ps::<0x44>(t4, t6); // rows e..h
            let u5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
            let u6 = _mm256_shuffle_ps::<0x44>(t5, t7);
            let u7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
            [
                _mm256_permute2f128_ps::<0x20>(u0, u4),
                _mm256_permute2f128_ps::<0x20>(u1, u5),
                _mm256_permute2f128_ps::<0x20>(u2, u6),
                _mm256_permute2f128_ps::<0x20>(u3, u7),
                _mm256_permute2f128_ps::<0x31>(u0, u4),
                _mm256_permute2f128_ps::<0x31>(u1, u5),
                _mm256_permute2f128_ps::<0x31>(u2, u6),
                _mm256_permute2f128_ps::<0x31>(u3, u7),
            ]
        }
    }
}

/// AVX-512F token.
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx512(());

impl Avx512 {
    /// The token, if this CPU has AVX-512F.
    pub fn detect() -> Option<Avx512> {
        is_x86_feature_detected!("avx512f").then_some(Avx512(()))
    }
}

// One SAFETY note per backend (inside the impl) covers its intrinsic wrappers: the token
// proves the CPU feature, and every load and store goes through a slice of LANES floats.
#[allow(clippy::undocumented_unsafe_blocks)]
impl Simd for Avx512 {
    const LANES: usize = 16;
    type V = __m512;

    // SAFETY (all methods): an `Avx512` token exists only if `detect` saw AVX-512F, so the
    // AVX-512F intrinsics below can execute; loads and stores go through slices of 16.
    #[inline(always)]
    fn splat(self, x: f32) -> __m512 {
        unsafe { _mm512_set1_ps(x) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> __m512 {
        let s = &s[..16];
        unsafe { _mm512_loadu_ps(s.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: __m512) {
        let s = &mut s[..16];
        unsafe { _mm512_storeu_ps(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn add(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_add_ps(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_sub_ps(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m512, b: __m512) -> __m512 {
        unsafe { _mm512_mul_ps(a, b) }
    }
    #[inline(always)]
    fn mul_add(self, a: __m512, b: __m512, c: __m512) -> __m512 {
        unsafe { _mm512_fmadd_ps(a, b, c) }
    }
    #[inline(always)]
    fn neg_mul_add(self, a: __m512, b: __m512, c: __m512) -> __m512 {
        unsafe { _mm512_fnmadd_ps(a, b, c) }
    }
    type Block = [__m512; 16];
    #[inline(always)]
    fn zero_block(self) -> [__m512; 16] {
        unsafe { [_mm512_setzero_ps(); 16] }
    }
    #[inline(always)]
    fn transpose(self, r: [__m512; 16]) -> [__m512; 16] {
        unsafe {
            // 1. Interleave row pairs: t[2i], t[2i+1] (per 128-bit lane L) hold rows 2i, 2i+1 at
            //    columns 4L, 4L+1 and 4L+2, 4L+3.
            let mut t = [_mm512_setzero_ps(); 16];
            for i in 0..8 {
                t[2 * i] = _mm512_unpacklo_ps(r[2 * i], r[2 * i + 1]);
                t[2 * i + 1] = _mm512_unpackhi_ps(r[2 * i], r[2 * i + 1]);
            }
            // 2. Interleave pairs of pairs: u[4i+m], lane L = rows 4i..4i+3 of column 4L+m.
            let mut u = [_mm512_setzero_ps(); 16];
            for i in 0..4 {
                let (a, b, c, d) = (t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]);
                let pd = _mm512_castps_pd;
                let ps = _mm512_castpd_ps;
                u[4 * i] = ps(_mm512_unpacklo_pd(pd(a), pd(c)));
                u[4 * i + 1] = ps(_mm512_unpackhi_pd(pd(a), pd(c)));
                u[4 * i + 2] = ps(_mm512_unpacklo_pd(pd(b), pd(d)));
                u[4 * i + 3] = ps(_mm512_unpackhi_pd(pd(b), pd(d)));
            }
            // 3./4. Gather 128-bit lanes: column 4L+m = lane L of u[m], u[4+m], u[8+m], u[12+m].
            let mut out = [_mm512_setzero_ps(); 16];
            for m in 0..4 {
                let x0 = _mm512_shuffle_f32x4::<0x88>(u[m], u[4 + m]); // L0 L2 of u[m], u[4+m]
                let x1 = _mm512_shuffle_f32x4::<0xDD>(u[m], u[4 + m]); // L1 L3
                let y0 = _mm512_shuffle_f32x4::<0x88>(u[8 + m], u[12 + m]);
                let y1 = _mm512_shuffle_f32x4::<0xDD>(u[8 + m], u[12 + m]);
                out[m] = _mm512_shuffle_f32x4::<0x88>(x0, y0);
                out[4 + m] = _mm512_shuffle_f32x4::<0x88>(x1, y1);
                out[8 + m] = _mm512_shuffle_f32x4::<0xDD>(x0, y0);
                out[12 + m] = _mm512_shuffle_f32x4::<0xDD>(x1, y1);
            }
            out
        }
    }
}

/// One pass with the SSE2 backend (see [`kernel::pass`]).
pub(super) fn pass_sse2(tok: Sse2, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    kernel::pass(tok, plan, job, local);
}

#[target_feature(enable = "avx2,fma")]
fn pass_avx2_tf(tok: Avx2, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    kernel::pass(tok, plan, job, local);
}

/// One pass with the AVX2 backend (see [`kernel::pass`]).
pub(super) fn pass_avx2(tok: Avx2, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    // SAFETY: `tok` exists only if AVX2 and FMA were detected on this CPU.
    unsafe { pass_avx2_tf(tok, plan, job, local) }
}

#[target_feature(enable = "avx512f")]
fn pass_avx512_tf(tok: Avx512, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    kernel::pass(tok, plan, job, local);
}

/// One pass with the AVX-512 backend (see [`kernel::pass`]).
pub(super) fn pass_avx512(tok: Avx512, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    // SAFETY: `tok` exists only if AVX-512F was detected on this CPU.
    unsafe { pass_avx512_tf(tok, plan, job, local) }
}
