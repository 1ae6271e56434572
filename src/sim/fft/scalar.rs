//! Portable backend: the generic kernel over a `[f32; 4]` "vector". No intrinsics and no unsafe;
//! the reference every SIMD backend must agree with, and the fallback on any CPU.

use super::butterfly::Simd;
use super::kernel::{self, Job};
use super::plan::{CRow, Plan};

/// The portable backend's token (always available).
#[derive(Clone, Copy, Debug)]
pub(super) struct Scalar;

impl Simd for Scalar {
    const LANES: usize = 4;
    type V = [f32; 4];

    #[inline(always)]
    fn splat(self, x: f32) -> [f32; 4] {
        [x; 4]
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> [f32; 4] {
        [s[0], s[1], s[2], s[3]]
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: [f32; 4]) {
        s[..4].copy_from_slice(&v);
    }
    #[inline(always)]
    fn add(self, a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
    }
    #[inline(always)]
    fn sub(self, a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
    }
    #[inline(always)]
    fn mul(self, a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
        [a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]]
    }
    #[inline(always)]
    fn mul_add(self, a: [f32; 4], b: [f32; 4], c: [f32; 4]) -> [f32; 4] {
        self.add(self.mul(a, b), c)
    }
    #[inline(always)]
    fn neg_mul_add(self, a: [f32; 4], b: [f32; 4], c: [f32; 4]) -> [f32; 4] {
        self.sub(c, self.mul(a, b))
    }
    type Block = [[f32; 4]; 4];
    #[inline(always)]
    fn zero_block(self) -> [[f32; 4]; 4] {
        [[0.0; 4]; 4]
    }
    #[inline(always)]
    fn transpose(self, m: [[f32; 4]; 4]) -> [[f32; 4]; 4] {
        let mut t = m;
        for (c, col) in t.iter_mut().enumerate() {
            *col = [m[0][c], m[1][c], m[2][c], m[3][c]];
        }
        t
    }
}

/// One pass with the portable backend (see [`kernel::pass`]).
pub(super) fn pass(plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    kernel::pass(Scalar, plan, job, local);
}
