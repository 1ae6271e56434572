//! The normal/foam mip chain (eq. 52-55): levels 2..=log₂N by unnormalized 2×2 box averages
//! of the float normals (level 1 is made with level 0, in the row loop); the averaged normal's
//! length becomes smoothness (eq. 53) and the RGBA8 texel stores it re-normalized.

use rayon::prelude::*;

use super::CascadeSurface;
use crate::sim::pack;
use crate::sim::simd::dispatch;
/// The RGBA8 texel of an averaged (unnormalized) normal and foam `v` (eq. 51, 53).
#[inline(always)]
pub(super) fn mip_texel(v: [f32; 4]) -> u32 {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let inv = if l > 1e-20 { 1.0 / l } else { 0.0 };
    pack::pack_rgba8(v[0] * inv, v[2] * inv, v[3], pack::smoothness(l))
}

/// Mip level 1 from level 0 as planes: `src[2q + i]` is component q (normal x, y, z, foam) of
/// source row i; writes one destination row of floats and RGBA8. Outputs are separate
/// arguments so they carry `noalias` (see [`surface_row_kernel`]).
#[inline(always)]
fn mip_planes_kernel(src: [&[f32]; 8], dst: &mut [[f32; 4]], rgba: &mut [u32]) {
    let side = rgba.len();
    // Named, exact-length texel-pair slices: with an array of slices LLVM lost their lengths,
    // kept the bounds checks and ran half the row in a scalar epilogue.
    fn pairs(p: &[f32], side: usize) -> &[[f32; 2]] {
        &p[..2 * side].as_chunks::<2>().0[..side]
    }
    let [x0, x1, y0, y1, z0, z1, w0, w1] = src;
    let (x0, x1) = (pairs(x0, side), pairs(x1, side));
    let (y0, y1) = (pairs(y0, side), pairs(y1, side));
    let (z0, z1) = (pairs(z0, side), pairs(z1, side));
    let (w0, w1) = (pairs(w0, side), pairs(w1, side));
    let dst = &mut dst[..side];
    for x in 0..side {
        let avg = |a: [f32; 2], b: [f32; 2]| 0.25 * (a[0] + a[1] + b[0] + b[1]);
        let v = [
            avg(x0[x], x1[x]),
            avg(y0[x], y1[x]),
            avg(z0[x], z1[x]),
            avg(w0[x], w1[x]),
        ];
        dst[x] = v;
        rgba[x] = mip_texel(v);
    }
}

dispatch!(
    /// [`mip_planes_kernel`] behind runtime ISA dispatch.
    pub(super) fn mip_planes(src: [&[f32]; 8], dst: &mut [[f32; 4]], rgba: &mut [u32]) => mip_planes_kernel
);

/// One destination row of a mip level ≥ 2 from the two texel rows `src0`, `src1` above it.
#[inline(always)]
fn mip_row_kernel(src0: &[[f32; 4]], src1: &[[f32; 4]], dst: &mut [[f32; 4]], rgba: &mut [u32]) {
    let side = rgba.len();
    let (r0, r1) = (&src0[..2 * side], &src1[..2 * side]);
    let (r0, r1) = (
        &r0.as_chunks::<2>().0[..side],
        &r1.as_chunks::<2>().0[..side],
    );
    let dst = &mut dst[..side];
    for x in 0..side {
        let ([a, b], [c, e]) = (r0[x], r1[x]);
        let avg = |k: usize| 0.25 * (a[k] + b[k] + c[k] + e[k]);
        let v = [avg(0), avg(1), avg(2), avg(3)];
        dst[x] = v;
        rgba[x] = mip_texel(v);
    }
}

dispatch!(
    /// [`mip_row_kernel`] behind runtime ISA dispatch.
    fn mip_row(src0: &[[f32; 4]], src1: &[[f32; 4]], dst: &mut [[f32; 4]], rgba: &mut [u32]) => mip_row_kernel
);

/// Mip levels 2..=log₂N (level 1 is made with level 0) by unnormalized 2×2 box averaging
/// (eq. 52); the averaged normal's length becomes smoothness (eq. 53) and the RGBA8 texel
/// stores it re-normalized.
pub(super) fn build_mips(out: &mut CascadeSurface) {
    let grid = out.grid;
    for level in 2..grid.mip_levels() {
        let src_off = out.floats_offset(level - 1);
        let dst_off = out.floats_offset(level);
        let rgba_off = pack::mip_offset(grid, level);
        let side = grid.n() >> level;
        let (lo, hi) = out.normal_floats.split_at_mut(dst_off);
        let src = &lo[src_off..];
        let dst = &mut hi[..side * side];
        let rgba = &mut out.normal_foam[rgba_off..rgba_off + side * side];
        let src_side = side * 2;
        // Small levels are cheaper than a task hand-off: run them on this thread.
        let rows_per_task = (4096 / side).max(1);
        dst.par_chunks_mut(side * rows_per_task)
            .zip(rgba.par_chunks_mut(side * rows_per_task))
            .enumerate()
            .for_each(|(task, (drows, prows))| {
                for (i, (drow, prow)) in drows
                    .chunks_mut(side)
                    .zip(prows.chunks_mut(side))
                    .enumerate()
                {
                    let y = task * rows_per_task + i;
                    mip_row(
                        &src[2 * y * src_side..(2 * y + 1) * src_side],
                        &src[(2 * y + 1) * src_side..(2 * y + 2) * src_side],
                        drow,
                        prow,
                    );
                }
            });
    }
}
