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

use super::first_stage::{first_stage, Source};
use super::plan::{CRow, Plan, Stage, L1_ROWS, STRIP};

/// The vector operations the kernel needs. Implemented by zero-sized "proof" tokens: a value of
/// an implementing type exists only if the CPU supports the instructions its methods use, which is
/// what makes the methods safe to call. All methods are `#[inline(always)]` so they compile into
/// the `#[target_feature]` entry point that instantiates the kernel.
pub(super) trait Simd: Copy {
    /// f32 lanes per vector.
    const LANES: usize;
    /// The vector type.
    type V: Copy;
    /// All lanes `x`.
    fn splat(self, x: f32) -> Self::V;
    /// Loads `s[..LANES]` (panics if `s` is shorter; callers pass slices the compiler can size).
    fn load(self, s: &[f32]) -> Self::V;
    /// Stores into `s[..LANES]` (panics if `s` is shorter).
    fn store(self, s: &mut [f32], v: Self::V);
    /// `a + b`.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a - b`.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b`.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b + c` (fused where the backend has FMA).
    fn mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// `c - a * b` (fused where the backend has FMA). NEON has this one as a single
    /// instruction (`fmls`) but not `a * b - c`, which cost it a negation per complex product.
    fn neg_mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// LANES vectors: a LANES×LANES block of f32, one row per vector.
    type Block: Copy + AsRef<[Self::V]> + AsMut<[Self::V]>;
    /// A block of zeros.
    fn zero_block(self) -> Self::Block;
    /// The transposed block: lane t of output vector c is lane c of input vector t.
    fn transpose(self, b: Self::Block) -> Self::Block;
}

/// A split complex vector: LANES adjacent columns.
#[derive(Clone, Copy)]
pub(super) struct C<V> {
    pub re: V,
    pub im: V,
}

/// A complex twiddle factor, broadcast to all lanes.
#[derive(Clone, Copy)]
pub(super) struct Tw<V> {
    pub re: V,
    pub im: V,
}

#[inline(always)]
pub(super) fn cmul<S: Simd>(s: S, a: C<S::V>, w: Tw<S::V>) -> C<S::V> {
    C {
        re: s.neg_mul_add(a.im, w.im, s.mul(a.re, w.re)),
        im: s.mul_add(a.re, w.im, s.mul(a.im, w.re)),
    }
}

/// Radix-4 inverse butterfly (no twiddles): `y_k = Σ_p x_p·i^(pk)`.
#[inline(always)]
pub(super) fn bfly4<S: Simd>(s: S, x: [C<S::V>; 4]) -> [C<S::V>; 4] {
    let [a, b, c, d] = x;
    let t0 = C {
        re: s.add(a.re, c.re),
        im: s.add(a.im, c.im),
    };
    let t1 = C {
        re: s.sub(a.re, c.re),
        im: s.sub(a.im, c.im),
    };
    let t2 = C {
        re: s.add(b.re, d.re),
        im: s.add(b.im, d.im),
    };
    let t3 = C {
        re: s.sub(b.re, d.re),
        im: s.sub(b.im, d.im),
    };
    [
        C {
            re: s.add(t0.re, t2.re),
            im: s.add(t0.im, t2.im),
        },
        // t1 + i·t3
        C {
            re: s.sub(t1.re, t3.im),
            im: s.add(t1.im, t3.re),
        },
        C {
            re: s.sub(t0.re, t2.re),
            im: s.sub(t0.im, t2.im),
        },
        // t1 - i·t3
        C {
            re: s.add(t1.re, t3.im),
            im: s.sub(t1.im, t3.re),
        },
    ]
}

/// Twiddles of radix-4 butterfly `j` of a stage, broadcast.
#[inline(always)]
pub(super) fn tw4<S: Simd>(s: S, tw: &[f32], j: usize) -> [Tw<S::V>; 3] {
    let w = &tw[6 * j..6 * j + 6];
    [
        Tw {
            re: s.splat(w[0]),
            im: s.splat(w[1]),
        },
        Tw {
            re: s.splat(w[2]),
            im: s.splat(w[3]),
        },
        Tw {
            re: s.splat(w[4]),
            im: s.splat(w[5]),
        },
    ]
}

#[inline(always)]
fn load_row<S: Simd>(s: S, row: &CRow, o: usize) -> C<S::V> {
    C {
        re: s.load(&row.re[o..]),
        im: s.load(&row.im[o..]),
    }
}

#[inline(always)]
pub(super) fn store_row<S: Simd>(s: S, row: &mut CRow, o: usize, v: C<S::V>) {
    s.store(&mut row.re[o..], v.re);
    s.store(&mut row.im[o..], v.im);
}

/// Splits `rows` into four equal quarters.
#[inline(always)]
pub(super) fn quarters(rows: &mut [CRow]) -> [&mut [CRow]; 4] {
    let q = rows.len() / 4;
    let (a, rest) = rows.split_at_mut(q);
    let (b, rest) = rest.split_at_mut(q);
    let (c, d) = rest.split_at_mut(q);
    [a, b, c, &mut d[..q]]
}

/// Floats in one STRIP×STRIP tile of the intermediate layout.
pub(super) const TILE: usize = STRIP * STRIP;

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

/// Radix-8 inverse butterfly (no twiddles): `y_k = Σ_p x_p·ω^(pk)`, `ω = exp(+2πi/8)`, as a
/// radix-2 split (`a_p = x_p + x_(p+4)`, `b_p = (x_p − x_(p+4))·ω^p`) followed by two radix-4
/// butterflies giving the even and the odd outputs.
#[inline(always)]
fn bfly8<S: Simd>(s: S, x: [C<S::V>; 8]) -> [C<S::V>; 8] {
    let add = |a: C<S::V>, b: C<S::V>| C {
        re: s.add(a.re, b.re),
        im: s.add(a.im, b.im),
    };
    let sub = |a: C<S::V>, b: C<S::V>| C {
        re: s.sub(a.re, b.re),
        im: s.sub(a.im, b.im),
    };
    let a = [
        add(x[0], x[4]),
        add(x[1], x[5]),
        add(x[2], x[6]),
        add(x[3], x[7]),
    ];
    let [d0, d1, d2, d3] = [
        sub(x[0], x[4]),
        sub(x[1], x[5]),
        sub(x[2], x[6]),
        sub(x[3], x[7]),
    ];
    let [e0, e1, e2, e3] = bfly4(s, a);
    // Odd outputs: radix 4 over b = [d0, d1·ω, i·d2, d3·ω³] with ω = (1+i)/√2, ω³ = (−1+i)/√2.
    let h = s.splat(std::f32::consts::FRAC_1_SQRT_2);
    let u = s.sub(d1.re, d1.im); // √2·Re(d1·ω)
    let v = s.add(d1.re, d1.im); // √2·Im(d1·ω)
    let w = s.add(d3.re, d3.im); // −√2·Re(d3·ω³)
    let z = s.sub(d3.re, d3.im); // √2·Im(d3·ω³)
                                 // b0 ± b2 with b2 = i·d2.
    let t0 = C {
        re: s.sub(d0.re, d2.im),
        im: s.add(d0.im, d2.re),
    };
    let t1 = C {
        re: s.add(d0.re, d2.im),
        im: s.sub(d0.im, d2.re),
    };
    // b1 ± b3.
    let t2 = C {
        re: s.mul(s.sub(u, w), h),
        im: s.mul(s.add(v, z), h),
    };
    let t3 = C {
        re: s.mul(s.add(u, w), h),
        im: s.mul(s.sub(v, z), h),
    };
    let o1 = add(t0, t2);
    let o5 = sub(t0, t2);
    // t1 ± i·t3
    let o3 = C {
        re: s.sub(t1.re, t3.im),
        im: s.add(t1.im, t3.re),
    };
    let o7 = C {
        re: s.add(t1.re, t3.im),
        im: s.sub(t1.im, t3.re),
    };
    [e0, o1, e1, o3, e2, o5, e3, o7]
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
