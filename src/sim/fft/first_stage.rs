//! The first radix-4 stage of a pass: reads the strip's source rows (only the live ones of a
//! sparse field; two folded into one for [`super::Output::RealRowPairs`]) and writes the
//! working buffer, with the stage's twiddles applied.

use std::ops::Range;

use super::butterfly::{bfly4, cmul, quarters, store_row, tw4, Simd, Tw, C, TILE};
use super::plan::{CRow, Plan, STRIP};

/// Offset of the STRIP source values of row `r` of strip `strip`: natural row-major in pass 1,
/// tiled in pass 2.
#[inline(always)]
fn src_at<const FIRST: bool>(width: usize, strip: usize, r: usize) -> usize {
    if FIRST {
        r * width + strip * STRIP
    } else {
        ((r / STRIP) * (width / STRIP) + strip) * TILE + (r % STRIP) * STRIP
    }
}

/// A pass's source planes and the rows of them that may hold non-zeros.
pub(super) struct Source<'a> {
    /// The source's real plane (the whole field, or pass 1's tiled intermediate).
    pub re: &'a [f32],
    /// Its imaginary plane.
    pub im: &'a [f32],
    /// The rows that may hold non-zeros (see [`super::kernel::Job::src_rows`]).
    pub rows: Range<usize>,
    /// See [`super::kernel::Job::width`].
    pub width: usize,
    /// See [`super::kernel::Job::fold`] (empty when not folding).
    pub fold: &'a [f32],
}

/// Zeros standing in for a source row outside [`Source::rows`].
const ZERO_ROW: [f32; STRIP] = [0.0; STRIP];

/// The first radix-4 stage: source rows in, working buffer out. With `SPARSE`, rows outside
/// [`Source::rows`] are zeros, not read. With `FOLD`, each input row is first folded from two
/// source rows (see [`super::kernel::Job::fold`]).
#[inline(always)]
pub(super) fn first_stage<S: Simd, const FIRST: bool, const SPARSE: bool, const FOLD: bool>(
    s: S,
    plan: &Plan,
    src: &Source<'_>,
    strip: usize,
    local: &mut [CRow],
) {
    let n = plan.n;
    let st = plan.stages[0];
    debug_assert!(st.radix == 4 && st.len == n);
    let tw = &plan.twiddles[st.tw..];
    let q = n / 4;
    let [l0, l1, l2, l3] = quarters(local);
    for j in 0..q {
        let w = tw4(s, tw, j);
        // The source row j + p·q of both planes, or zeros outside the live rows.
        let fetch = |r: usize| -> (&[f32; STRIP], &[f32; STRIP]) {
            if !SPARSE || src.rows.contains(&r) {
                let at = src_at::<FIRST>(src.width, strip, r);
                (src_row(src.re, at), src_row(src.im, at))
            } else {
                (&ZERO_ROW, &ZERO_ROW)
            }
        };
        let (r0, r1, r2, r3) = (fetch(j), fetch(j + q), fetch(j + 2 * q), fetch(j + 3 * q));
        let re = [r0.0, r1.0, r2.0, r3.0];
        let im = [r0.1, r1.1, r2.1, r3.1];
        // The fold's partner rows r + n and factors (unused without `FOLD`).
        let partner = |p: usize| {
            if FOLD {
                fetch(j + p * q + n)
            } else {
                (&ZERO_ROW, &ZERO_ROW)
            }
        };
        let (f0, f1, f2, f3) = (partner(0), partner(1), partner(2), partner(3));
        let (re2, im2) = ([f0.0, f1.0, f2.0, f3.0], [f0.1, f1.1, f2.1, f3.1]);
        // No closure may take or return a vector here: one compiled apart from this function
        // lacks its target features and is called per use (the AVX2 fold ran 2.5x slower).
        let fw: [&[f32]; 4] = if FOLD {
            std::array::from_fn(|p| &src.fold[2 * (j + p * q)..][..2])
        } else {
            [&[0.0; 2]; 4]
        };
        for h in 0..STRIP / S::LANES {
            let o = h * S::LANES;
            let x = [
                input::<S, FOLD>(s, (re[0], im[0]), (re2[0], im2[0]), fw[0], o),
                input::<S, FOLD>(s, (re[1], im[1]), (re2[1], im2[1]), fw[1], o),
                input::<S, FOLD>(s, (re[2], im[2]), (re2[2], im2[2]), fw[2], o),
                input::<S, FOLD>(s, (re[3], im[3]), (re2[3], im2[3]), fw[3], o),
            ];
            let [y0, y1, y2, y3] = bfly4(s, x);
            store_row(s, &mut l0[j], o, y0);
            store_row(s, &mut l1[j], o, cmul(s, y1, w[0]));
            store_row(s, &mut l2[j], o, cmul(s, y2, w[1]));
            store_row(s, &mut l3[j], o, cmul(s, y3, w[2]));
        }
    }
}

/// Input `o..` of a first-stage row: the source row `a` (re, im), or with `FOLD` the fold of
/// `a` and its partner `b` with factor `w` = i·ω^r (see [`super::kernel::Job::fold`]).
#[inline(always)]
fn input<S: Simd, const FOLD: bool>(
    s: S,
    a: (&[f32; STRIP], &[f32; STRIP]),
    b: (&[f32; STRIP], &[f32; STRIP]),
    w: &[f32],
    o: usize,
) -> C<S::V> {
    let a = C {
        re: s.load(&a.0[o..]),
        im: s.load(&a.1[o..]),
    };
    if !FOLD {
        return a;
    }
    let b = C {
        re: s.load(&b.0[o..]),
        im: s.load(&b.1[o..]),
    };
    let d = C {
        re: s.sub(a.re, b.re),
        im: s.sub(a.im, b.im),
    };
    let w = Tw {
        re: s.splat(w[0]),
        im: s.splat(w[1]),
    };
    let od = cmul(s, d, w);
    C {
        re: s.add(s.add(a.re, b.re), od.re),
        im: s.add(s.add(a.im, b.im), od.im),
    }
}

/// The [`STRIP`] source values at `at`.
#[inline(always)]
fn src_row(plane: &[f32], at: usize) -> &[f32; STRIP] {
    plane[at..at + STRIP]
        .try_into()
        .expect("strip inside the field")
}
