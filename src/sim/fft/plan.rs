//! The backend-independent part of a transform: the stage list of the 1D column FFT, its twiddle
//! tables and the output permutation. Built once in [`super::Fft2d::new`], read-only afterwards.

use std::f64::consts::PI;

/// Columns per strip: every pass works on strips of this many adjacent columns. One cache line of
/// f32, so the strided loads of a strip use whole lines, and a multiple of every backend's lane
/// count (4, 8, 16).
pub(super) const STRIP: usize = 16;

/// One row of a strip's working buffer: the real and imaginary parts of [`STRIP`] adjacent columns,
/// each in its own cache line so every vector load/store is aligned.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
pub(super) struct CRow {
    /// Real parts of the strip's columns.
    pub re: [f32; STRIP],
    /// Imaginary parts of the strip's columns.
    pub im: [f32; STRIP],
}

impl CRow {
    /// A row of zeros.
    pub const ZERO: CRow = CRow {
        re: [0.0; STRIP],
        im: [0.0; STRIP],
    };
}

/// One decimation-in-frequency stage of the 1D FFT: butterflies of `radix` points spanning
/// sub-transforms of `len` rows.
#[derive(Clone, Copy, Debug)]
pub(super) struct Stage {
    /// 4, or 8 for the (twiddle-free) last stage when log2 N is odd.
    pub radix: usize,
    /// Length of the sub-transforms this stage splits (N for the first stage).
    pub len: usize,
    /// Offset of this stage's twiddles in [`Plan::twiddles`].
    pub tw: usize,
}

/// Sub-transforms of at most this many rows (32 KiB of [`CRow`]s) are finished depth-first, so
/// their remaining stages run out of L1.
pub(super) const L1_ROWS: usize = 256;

/// Stage list, twiddles and output permutation of the length-N inverse 1D FFT applied along the
/// rows index of every strip (both passes use the same plan because the grid is square).
pub(super) struct Plan {
    /// Transform length N.
    pub n: usize,
    /// Stages in execution order, `len` decreasing from N.
    pub stages: Vec<Stage>,
    /// For radix-4 stages, per butterfly j in 0..len/4: `[w1.re, w1.im, w2.re, w2.im, w3.re, w3.im]`
    /// with `wk = exp(+2πi·k·j/len)`. The radix-8 stage has none.
    pub twiddles: Vec<f32>,
    /// `perm[k]` = the working-buffer row that holds output index k after the last stage
    /// (decimation in frequency leaves the outputs digit-reversed).
    pub perm: Vec<u16>,
}

impl Plan {
    /// Plans the length-`n` inverse FFT (`n` a power of two in 16..=1024): radix-4 stages, the
    /// last one radix 8 when log2(n) is odd.
    pub fn new(n: usize) -> Plan {
        debug_assert!(n.is_power_of_two() && (16..=1024).contains(&n));
        let mut stages = Vec::new();
        let mut twiddles = Vec::new();
        let mut len = n;
        // Radix 4 down to the last stage; when log2(n) is odd the last stage is a twiddle-free
        // radix 8 rather than a radix 4 plus a radix 2 (one fewer sweep over the strip).
        while len >= 4 {
            if len == 8 && n > 8 {
                stages.push(Stage {
                    radix: 8,
                    len,
                    tw: twiddles.len(),
                });
                break;
            }
            stages.push(Stage {
                radix: 4,
                len,
                tw: twiddles.len(),
            });
            for j in 0..len / 4 {
                for k in 1..=3 {
                    let (s, c) = (2.0 * PI * (k * j) as f64 / len as f64).sin_cos();
                    twiddles.push(c as f32);
                    twiddles.push(s as f32);
                }
            }
            len /= 4;
        }
        let mut perm = vec![0u16; n];
        assign_outputs(&stages, 0, n, 0, 1, &mut perm);
        Plan {
            n,
            stages,
            twiddles,
            perm,
        }
    }
}

/// Records which row ends up holding which output. The rows `offset..offset + len` hold the
/// length-`len` sub-transform whose outputs are the global outputs `first + stride·m`; a radix-r
/// stage leaves the outputs with `m ≡ k (mod r)` in its k-th sub-block.
fn assign_outputs(
    stages: &[Stage],
    offset: usize,
    len: usize,
    first: usize,
    stride: usize,
    perm: &mut [u16],
) {
    match stages.split_first() {
        None => {
            debug_assert_eq!(len, 1);
            perm[first] = offset as u16;
        }
        Some((stage, rest)) => {
            let r = stage.radix;
            let sub = len / r;
            for k in 0..r {
                assign_outputs(
                    rest,
                    offset + k * sub,
                    sub,
                    first + stride * k,
                    stride * r,
                    perm,
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perm_is_a_permutation_and_digit_reversal() {
        for log in 4..=10 {
            let n = 1usize << log;
            let plan = Plan::new(n);
            let mut seen = vec![false; n];
            for &p in &plan.perm {
                assert!(!seen[p as usize]);
                seen[p as usize] = true;
            }
            if log % 2 == 0 {
                // Pure radix 4: base-4 digit reversal.
                for k in 0..n {
                    let mut rev = 0;
                    let mut x = k;
                    for _ in 0..log / 2 {
                        rev = rev * 4 + x % 4;
                        x /= 4;
                    }
                    assert_eq!(plan.perm[k] as usize, rev);
                }
            }
        }
    }
}
