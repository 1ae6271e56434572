//! The normal/foam mip chain (eq. 52-55): levels 2..=log₂N by unnormalized 2×2 box averages
//! of the float normals (level 1 is made with level 0, in the row loop); the averaged normal's
//! length becomes smoothness (eq. 53) and the RGBA8 texel stores it re-normalized. Every level
//! is four float planes, so one kernel averages level 0 into 1 and each level into the next.

use rayon::prelude::*;

use super::layout::{mip_block, planes_mut, CascadeSurface};
use crate::sim::pack;
use crate::sim::simd::dispatch;

/// The RGBA8 texel of an averaged (unnormalized) normal and foam `v` (eq. 51, 53).
#[inline(always)]
fn mip_texel(v: [f32; 4]) -> u32 {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let inv = if l > 1e-20 { 1.0 / l } else { 0.0 };
    pack::pack_rgba8(v[0] * inv, v[2] * inv, v[3], pack::smoothness(l))
}

/// One destination row of a mip level from the two source rows above it, as planes:
/// `src[2q + i]` is component q (normal x, y, z, foam) of source row i; writes the row's four
/// float planes and RGBA8. Outputs are separate arguments so they carry `noalias` (see
/// `surface_row_kernel`).
#[inline(always)]
fn mip_planes_kernel(
    src: [&[f32]; 8],
    x: &mut [f32],
    y: &mut [f32],
    z: &mut [f32],
    w: &mut [f32],
    rgba: &mut [u32],
) {
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
    let (x, y, z, w) = (
        &mut x[..side],
        &mut y[..side],
        &mut z[..side],
        &mut w[..side],
    );
    for i in 0..side {
        let avg = |a: [f32; 2], b: [f32; 2]| 0.25 * (a[0] + a[1] + b[0] + b[1]);
        (x[i], y[i], z[i], w[i]) = (
            avg(x0[i], x1[i]),
            avg(y0[i], y1[i]),
            avg(z0[i], z1[i]),
            avg(w0[i], w1[i]),
        );
    }
    // The RGBA8 texels in a loop of their own, as the surface row's normalization: their
    // square roots and division are a long chain, and with the averages' shuffles in the same
    // loop too few texels were in flight to hide it.
    let rgba = &mut rgba[..side];
    for i in 0..side {
        rgba[i] = mip_texel([x[i], y[i], z[i], w[i]]);
    }
}

dispatch!(
    /// [`mip_planes_kernel`] behind runtime ISA dispatch.
    pub(super) fn mip_planes(
        src: [&[f32]; 8],
        x: &mut [f32],
        y: &mut [f32],
        z: &mut [f32],
        w: &mut [f32],
        rgba: &mut [u32],
    ) => mip_planes_kernel
);

/// Mip levels 2..=log₂N (level 1 is made with level 0) by unnormalized 2×2 box averaging
/// (eq. 52); the averaged normal's length becomes smoothness (eq. 53) and the RGBA8 texel
/// stores it re-normalized.
pub(super) fn build_mips(out: &mut CascadeSurface) {
    let grid = out.grid;
    for level in 2..grid.mip_levels() {
        let (src_block, src_area) = mip_block(grid, level - 1);
        let (dst_block, area) = mip_block(grid, level);
        let (lo, hi) = out.mip_chain.split_at_mut(dst_block);
        let src = &lo[src_block..src_block + 4 * src_area];
        let [dx, dy, dz, dw] = planes_mut(&mut hi[..4 * area], area);
        let rgba_off = pack::mip_offset(grid, level);
        let rgba = &mut out.normal_foam[rgba_off..rgba_off + area];
        let side = grid.n() >> level;
        let src_side = 2 * side;
        let rows = |y: usize| {
            let r = |q: usize, i: usize| {
                let at = q * src_area + (2 * y + i) * src_side;
                &src[at..at + src_side]
            };
            [
                r(0, 0),
                r(0, 1),
                r(1, 0),
                r(1, 1),
                r(2, 0),
                r(2, 1),
                r(3, 0),
                r(3, 1),
            ]
        };
        // Small levels are cheaper than a task hand-off: run them on this thread.
        let per_task = side * (4096 / side).max(1);
        dx.par_chunks_mut(per_task)
            .zip(dy.par_chunks_mut(per_task))
            .zip(dz.par_chunks_mut(per_task))
            .zip(dw.par_chunks_mut(per_task))
            .zip(rgba.par_chunks_mut(per_task))
            .enumerate()
            .for_each(|(task, ((((x, y), z), w), p))| {
                let rows_out = x
                    .chunks_mut(side)
                    .zip(y.chunks_mut(side))
                    .zip(z.chunks_mut(side))
                    .zip(w.chunks_mut(side))
                    .zip(p.chunks_mut(side));
                for (i, ((((x, y), z), w), p)) in rows_out.enumerate() {
                    mip_planes(rows(task * per_task / side + i), x, y, z, w, p);
                }
            });
    }
}
