//! rustfft as a 2D baseline: rows, transpose, rows, transpose, in its interleaved format.

use std::sync::Arc;

use rustfft::num_complex::Complex32;
use rustfft::{Fft, FftPlanner};

/// `count` inverse 2D transforms of side `n` with rustfft.
pub struct RustFft2d {
    fft: Arc<dyn Fft<f32>>,
    n: usize,
    data: Vec<Vec<Complex32>>,
    transposed: Vec<Complex32>,
    scratch: Vec<Complex32>,
}

impl RustFft2d {
    /// Plans once and fills `count` fields with finite values.
    pub fn new(n: usize, count: usize) -> Self {
        let fft = FftPlanner::new().plan_fft_inverse(n);
        let scratch = vec![Complex32::default(); fft.get_inplace_scratch_len()];
        let data = vec![vec![Complex32::default(); n * n]; count];
        let mut s = Self {
            fft,
            n,
            data,
            transposed: vec![Complex32::default(); n * n],
            scratch,
        };
        s.refill();
        s
    }

    /// Restores the inputs (in-place transforms would otherwise grow without bound).
    pub fn refill(&mut self) {
        for (k, field) in self.data.iter_mut().enumerate() {
            for (i, v) in field.iter_mut().enumerate() {
                *v = Complex32::new(((i + k) % 17) as f32 * 0.1, (i % 5) as f32 * 0.2);
            }
        }
    }

    /// All transforms once.
    pub fn inverse_all(&mut self) {
        let n = self.n;
        for field in &mut self.data {
            self.fft.process_with_scratch(field, &mut self.scratch);
            transpose(field, &mut self.transposed, n);
            self.fft
                .process_with_scratch(&mut self.transposed, &mut self.scratch);
            transpose(&self.transposed, field, n);
        }
    }
}

fn transpose(src: &[Complex32], dst: &mut [Complex32], n: usize) {
    const B: usize = 16;
    for rb in (0..n).step_by(B) {
        for cb in (0..n).step_by(B) {
            for r in rb..(rb + B).min(n) {
                for c in cb..(cb + B).min(n) {
                    dst[c * n + r] = src[r * n + c];
                }
            }
        }
    }
}
