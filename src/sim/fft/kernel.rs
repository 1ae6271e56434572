//! The FFT pass, written once over a small SIMD trait and instantiated per backend.
//!
//! A pass takes a source and, strip by strip ([`STRIP`] adjacent columns), runs the 1D inverse
//! FFT down the columns and writes the result transposed: strip columns `c0..c0+16` become
//! destination rows `c0..c0+16`. Two passes (field → scratch → field) give the 2D transform in
//! natural order with no separate transpose. Pass 1 reads the natural field and writes the
//! transposed strips as 16×16 tiles; pass 2 reads those tiles (1 KiB runs rather than 64-byte
//! lines a row apart) and writes natural rows.
//!
//! Per strip: the first radix-4 stage reads the source rows and writes a contiguous working
//! buffer of [`CRow`]s (real and imaginary vectors of the 16 columns); the other stages run in
//! place in that buffer (sub-transforms of at most [`L1_ROWS`] rows depth-first, so they stay in
//! L1); the final store gathers the rows in output order (undoing the digit reversal),
//! transposes LANES×LANES blocks in registers and writes whole destination row segments.
//! Lanes always hold adjacent columns, so the butterflies are purely vertical SIMD.

use std::ops::Range;

use super::butterfly::{bfly4, bfly8, cmul, load_row, quarters, store_row, tw4, Simd, C, TILE};
use super::first_stage::{first_stage, Source};
use super::plan::{CRow, Plan, Stage, L1_ROWS, STRIP};

/// One pass's worth of work: some strips of one field. Chunk k of `dst_*` (each chunk
/// `STRIP·N` floats) receives strip `first_strip + k` of the source, transformed and transposed.
///
/// The intermediate (pass 1 → pass 2) is tiled so that pass 2 reads it in 1 KiB runs: pass 1's
/// strip k owns chunk k, made of N/STRIP tiles; tile b holds outputs `STRIP·b ..` as STRIP
/// vectors, one per strip column (that is, already transposed).
pub(super) struct Job<'a> {
    /// Source real plane (the whole N×N field, or the whole tiled intermediate in pass 2).
    pub src_re: &'a [f32],
    /// Source imaginary plane.
    pub src_im: &'a [f32],
    /// Destination real chunks of strips `first_strip ..`, a multiple of `STRIP·N` floats.
    pub dst_re: &'a mut [f32],
    /// Destination imaginary chunks, same extent.
    pub dst_im: &'a mut [f32],
    /// Index of the first strip this job covers.
    pub first_strip: usize,
    /// The source rows that may hold non-zeros: the others are taken as zero, not read (in
    /// pass 2 a source row is a column of the field).
    pub src_rows: Range<usize>,
    /// Pass 1 (natural field → tiled intermediate) or pass 2 (tiled intermediate → natural
    /// field, transposed back).
    pub first_pass: bool,
    /// Columns of the source: the field's side in pass 1, pass 1's transform length in pass 2
    /// (the two differ for a folded transform; `width / STRIP` strips in all).
    pub width: usize,
    /// Pass 1 of a folded transform (see [`super::Fft2d::inverse_batch_support_as`]): the
    /// factors i·ω^r, ω = exp(+2πi/2L), of rows r < L = `plan.n` as (re, im) pairs. Source row
    /// r then becomes (x_r + x_(r+L)) + i·ω^r·(x_r − x_(r+L)): the first radix-2 step of the
    /// length-2L transform, its even and odd outputs packed as real and imaginary parts.
    pub fold: Option<&'a [f32]>,
}

/// Runs one pass over the strips of `job`: reads columns of the source, writes their 1D inverse
/// FFT transposed. `local` is the working buffer, at least N rows.
#[inline(always)]
pub(super) fn pass<S: Simd>(s: S, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    if job.first_pass {
        pass_impl::<S, true>(s, plan, job, local);
    } else {
        pass_impl::<S, false>(s, plan, job, local);
    }
}

/// Offset, within a strip's destination chunk, of outputs `k..` (LANES of them, not crossing
/// a multiple of STRIP) of strip column `c`: tiled in pass 1, natural rows in pass 2.
#[inline(always)]
fn dst_at<const FIRST: bool>(n: usize, c: usize, k: usize) -> usize {
    if FIRST {
        (k / STRIP) * TILE + c * STRIP + k % STRIP
    } else {
        c * n + k
    }
}

#[inline(always)]
fn pass_impl<S: Simd, const FIRST: bool>(s: S, plan: &Plan, job: Job<'_>, local: &mut [CRow]) {
    let n = plan.n;
    let local = &mut local[..n];
    let chunk = STRIP * n;
    for (k, (dre, dim)) in job
        .dst_re
        .chunks_exact_mut(chunk)
        .zip(job.dst_im.chunks_exact_mut(chunk))
        .enumerate()
    {
        let strip = job.first_strip + k;
        let src = Source {
            re: job.src_re,
            im: job.src_im,
            rows: job.src_rows.clone(),
            width: job.width,
            fold: job.fold.unwrap_or(&[]),
        };
        // The whole-field path keeps its loop free of the row test.
        match (job.fold.is_some(), src.rows == (0..n)) {
            (false, true) => first_stage::<S, FIRST, false, false>(s, plan, &src, strip, local),
            (false, false) => first_stage::<S, FIRST, true, false>(s, plan, &src, strip, local),
            // Only pass 1 folds.
            (true, _) if FIRST => {
                if src.rows == (0..2 * n) {
                    first_stage::<S, true, false, true>(s, plan, &src, strip, local)
                } else {
                    first_stage::<S, true, true, true>(s, plan, &src, strip, local)
                }
            }
            (true, _) => unreachable!("pass 2 never folds"),
        }
        later_stages(s, plan, local);
        store_transposed::<S, FIRST>(s, plan, local, dre, dim);
    }
}

/// All stages after the first, in place. Stages on sub-transforms larger than [`L1_ROWS`] run
/// breadth-first over the buffer; the rest depth-first per L1-sized block.
#[inline(always)]
fn later_stages<S: Simd>(s: S, plan: &Plan, local: &mut [CRow]) {
    let stages = &plan.stages[1..];
    let split = stages
        .iter()
        .position(|st| st.len <= L1_ROWS)
        .unwrap_or(stages.len());
    let (big, small) = stages.split_at(split);
    for st in big {
        stage(s, plan, *st, local);
    }
    if let Some(first_small) = small.first() {
        for block in local.chunks_exact_mut(first_small.len) {
            for st in small {
                stage(s, plan, *st, block);
            }
        }
    }
}

/// One in-place stage over every sub-transform of length `st.len` in `rows`.
#[inline(always)]
fn stage<S: Simd>(s: S, plan: &Plan, st: Stage, rows: &mut [CRow]) {
    let tw = &plan.twiddles[st.tw..];
    if st.radix == 4 && st.len == 4 {
        // The last stage for even log2 N: one twiddle-free butterfly per 4 rows.
        for block in rows.chunks_exact_mut(4) {
            for h in 0..STRIP / S::LANES {
                let o = h * S::LANES;
                let x = [
                    load_row(s, &block[0], o),
                    load_row(s, &block[1], o),
                    load_row(s, &block[2], o),
                    load_row(s, &block[3], o),
                ];
                for (row, v) in block.iter_mut().zip(bfly4(s, x)) {
                    store_row(s, row, o, v);
                }
            }
        }
    } else if st.radix == 4 {
        for block in rows.chunks_exact_mut(st.len) {
            let [l0, l1, l2, l3] = quarters(block);
            for (j, (((r0, r1), r2), r3)) in l0
                .iter_mut()
                .zip(l1.iter_mut())
                .zip(l2.iter_mut())
                .zip(l3.iter_mut())
                .enumerate()
            {
                if j == 0 {
                    for h in 0..STRIP / S::LANES {
                        let o = h * S::LANES;
                        let x = [
                            load_row(s, r0, o),
                            load_row(s, r1, o),
                            load_row(s, r2, o),
                            load_row(s, r3, o),
                        ];
                        let [y0, y1, y2, y3] = bfly4(s, x);
                        store_row(s, r0, o, y0);
                        store_row(s, r1, o, y1);
                        store_row(s, r2, o, y2);
                        store_row(s, r3, o, y3);
                    }
                } else {
                    let w = tw4(s, tw, j);
                    for h in 0..STRIP / S::LANES {
                        let o = h * S::LANES;
                        let x = [
                            load_row(s, r0, o),
                            load_row(s, r1, o),
                            load_row(s, r2, o),
                            load_row(s, r3, o),
                        ];
                        let [y0, y1, y2, y3] = bfly4(s, x);
                        store_row(s, r0, o, y0);
                        store_row(s, r1, o, cmul(s, y1, w[0]));
                        store_row(s, r2, o, cmul(s, y2, w[1]));
                        store_row(s, r3, o, cmul(s, y3, w[2]));
                    }
                }
            }
        }
    } else {
        // Radix 8, only ever the last stage (len 8): no twiddles.
        debug_assert!(st.radix == 8 && st.len == 8);
        for block in rows.chunks_exact_mut(8) {
            for h in 0..STRIP / S::LANES {
                let o = h * S::LANES;
                let x: [C<S::V>; 8] = [
                    load_row(s, &block[0], o),
                    load_row(s, &block[1], o),
                    load_row(s, &block[2], o),
                    load_row(s, &block[3], o),
                    load_row(s, &block[4], o),
                    load_row(s, &block[5], o),
                    load_row(s, &block[6], o),
                    load_row(s, &block[7], o),
                ];
                let y = bfly8(s, x);
                for (row, v) in block.iter_mut().zip(y) {
                    store_row(s, row, o, v);
                }
            }
        }
    }
}

/// Writes the strip transposed: output k of strip column c goes to `dst_at(c, k)`, read from
/// working row `perm[k]`.
#[inline(always)]
fn store_transposed<S: Simd, const FIRST: bool>(
    s: S,
    plan: &Plan,
    local: &[CRow],
    dst_re: &mut [f32],
    dst_im: &mut [f32],
) {
    let n = plan.n;
    let w = S::LANES;
    for (kb, p) in plan.perm.chunks_exact(w).enumerate() {
        let k0 = kb * w;
        for h in 0..STRIP / w {
            let o = h * w;
            // One plane at a time keeps the block in registers.
            let mut re = s.zero_block();
            for (t, &row) in p.iter().enumerate() {
                re.as_mut()[t] = s.load(&local[row as usize].re[o..]);
            }
            let re = s.transpose(re);
            for c in 0..w {
                s.store(&mut dst_re[dst_at::<FIRST>(n, o + c, k0)..], re.as_ref()[c]);
            }
            let mut im = s.zero_block();
            for (t, &row) in p.iter().enumerate() {
                im.as_mut()[t] = s.load(&local[row as usize].im[o..]);
            }
            let im = s.transpose(im);
            for c in 0..w {
                s.store(&mut dst_im[dst_at::<FIRST>(n, o + c, k0)..], im.as_ref()[c]);
            }
        }
    }
}
