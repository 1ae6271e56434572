//! aarch64 backend: NEON (AdvSIMD), 4 lanes with fused multiply-add. NEON is part of the aarch64
//! baseline, so the token is always available there.

use core::arch::aarch64::*;

use super::butterfly::Simd;
use super::kernel::{self, Job};
use super::plan::{CRow, Plan};

/// NEON token (always available on aarch64).
#[derive(Clone, Copy, Debug)]
pub(super) struct Neon(());

impl Neon {
    /// The token, if this CPU has NEON (every aarch64 CPU does; checked anyway).
    pub fn detect() -> Option<Neon> {
        std::arch::is_aarch64_feature_detected!("neon").then_some(Neon(()))
    }
}

// One SAFETY note per backend (inside the impl) covers its intrinsic wrappers: the token
// proves the CPU feature, and every load and store goes through a slice of LANES floats.
#[allow(clippy::undocumented_unsafe_blocks)]
impl Simd for Neon {
    const LANES: usize = 4;
    type V = float32x4_t;

    // SAFETY (all methods): NEON is part of the aarch64 baseline (enabled for the whole target),
    // so its intrinsics can always execute; loads and stores go through slices of 4.

    #[inline(always)]
    fn splat(self, x: f32) -> float32x4_t {
        unsafe { vdupq_n_f32(x) }
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> float32x4_t {
        let s = &s[..4];
        unsafe { vld1q_f32(s.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: float32x4_t) {
        let s = &mut s[..4];
        unsafe { vst1q_f32(s.as_mut_ptr(), v) }
    }
    #[inline(always)]
    fn add(self, a: float32x4_t, b: float32x4_t) -> float32x4_t {
        unsafe { vaddq_f32(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: float32x4_t, b: float32x4_t) -> float32x4_t {
        unsafe { vsubq_f32(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: float32x4_t, b: float32x4_t) -> float32x4_t {
        unsafe { vmulq_f32(a, b) }
    }
    #[inline(always)]
    fn mul_add(self, a: float32x4_t, b: float32x4_t, c: float32x4_t) -> float32x4_t {
        unsafe { vfmaq_f32(c, a, b) }
    }
    #[inline(always)]
    fn neg_mul_add(self, a: float32x4_t, b: float32x4_t, c: float32x4_t) -> float32x4_t {
        // c - a*b, fused: one `fmls`.
        unsafe { vfmsq_f32(c, a, b) }
    }
    type Block = [float32x4_t; 4];
    #[inline(always)]
    fn zero_block(self) -> [float32x4_t; 4] {
        unsafe { [vdupq_n_f32(0.0); 4] }
    }
    #[inline(always)]
    fn transpose(self, r: [float32x4_t; 4]) -> [float32x4_t; 4] {
        unsafe {
            let t0 = vreinterpretq_f64_f32(vtrn1q_f32(r[0], r[1])); // a0 b0 a2 b2
            let t1 = vreinterpretq_f64_f32(vtrn2q_f32(r[0], r[1])); // a1 b1 a3 b3
            let t2 = vreinterpretq_f64_f32(vtrn1q_f32(r[2], r[3])); // c0 d0 c2 d2
            let t3 = vreinterpretq_f64_f32(vtrn2q_f32(r[2], r[3])); // c1 d1 c3 d3
            [
                vreinterpretq_f32_f64(vtrn1q_f64(t0, t2)),
                vreinterpretq_f32_f64(vtrn1q_f64(t1, t3)),
                vreinterpretq_f32_f64(vtrn2q_f64(t0, t2)),
                vreinterpretq_f32_f64(vtrn2q_f64(t1, t3)),
            ]
        }
    }
}

/// One pass with the NEON backend (see [`kernel::pass`]).
pub(super) fn pass_neon(tok: Neon, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    kernel::pass(tok, plan, job, local);
}
