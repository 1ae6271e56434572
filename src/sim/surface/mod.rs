//! Stages 5-6 (thesis 4.2.4-4.2.5): from the transformed fields to the surface a renderer
//! and a buoyancy query use: displacement (eq. 42-44), normals and Jacobian (eq. 47-48) from
//! the spectral derivatives or from central differences of the displacement (eq. 45-46, see
//! [`crate::sim::Derivatives`]), persistent foam, RGBA8/RGBA16F packing and the mip chain
//! (eq. 52-55).
//!
//! # Formats
//! [`CascadeSurface::displacement_f16`] is RGBA16F (Dx, h, Dz, J); `normal_foam` is RGBA8
//! (n.x, n.z, foam, smoothness) with mips at the offsets of eq. 55. Foam replaces eq. 50's raw
//! Jacobian in B (J stays in the displacement's alpha). RGBA16F is converted from the row's f32
//! planes by F16C or NEON where present, else `pack::f16_bits`: round to nearest even, the
//! same bits on every path (`f16_row.rs`).
//!
//! # Float copies on request
//! `Surfaces::new` (the renderer's) keeps only the GPU formats plus float mips from level 1;
//! `Surfaces::with_float_copies` (export, checks) also keeps the f32 displacement and level-0
//! normals and foam. Level-0 floats and the displacement are made as planes in a stack buffer
//! per task, one row pair at a time (mip 1 is averaged there, RGBA16F converted from there);
//! the f32 copies are interleaved from it only when kept.
//! Height queries read the f32 copy when present, else the RGBA16F (within 1 cm, tested).
//!
//! # Kernel outputs are arguments
//! The row kernel takes every `&mut` output as its own argument: only arguments carry
//! `noalias`; outputs inside a struct made LLVM guard the loop with pairwise overlap checks.

use half::f16;
use rayon::prelude::*;

use crate::sim::grid::{GridSize, SplitField};
use crate::sim::pack;
use crate::sim::params::FoamParams;

pub(crate) mod f16_row;
mod layout;
mod mips;
mod row;

use self::f16_row::interleave_f16;
use self::layout::{mip_block, planes_mut};
pub use self::layout::{CascadeSurface, FloatCopies};
use self::mips::{build_mips, mip_planes};
use self::row::{
    pad_row, plane_row, surface_row, Finite, RowIn, RowOut, RowSource, Spectral, SurfaceConsts,
};

/// The unit normal of a roughness-scaled normal.
pub fn unit(n: [f32; 4]) -> [f32; 3] {
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    [n[0] / l, n[1] / l, n[2] / l]
}

/// Per-step inputs of the surface stage.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceParams {
    /// Choppiness λ (eq. 44).
    pub choppiness: f32,
    /// Material roughness (eq. 49).
    pub roughness: f32,
    /// Foam dynamics.
    pub foam: FoamParams,
    /// Seconds since the previous step (0 on the first), for foam growth and decay.
    pub dt: f32,
}

/// One cascade's transformed fields, as its derivative mode made them.
#[derive(Clone, Copy)]
pub enum Transformed<'a> {
    /// The four packed fields of [`crate::sim::evolve::evolve`] (spectral derivatives).
    Spectral(&'a [SplitField; 4]),
    /// The two of [`crate::sim::evolve::evolve_finite`] (central differences): h + i·X, and Z
    /// as row pairs ([`crate::sim::fft::Output::RealRowPairs`]: rows 2p and 2p + 1 in the real
    /// and imaginary plane of row p).
    Finite(&'a [SplitField; 2]),
}

impl<'a> Transformed<'a> {
    /// Row `row`'s source for the row kernel (grid side `n`); the finite mode's middle rows
    /// are padded into `pad` (3·(n + 2) floats, see [`row::pad_row`]).
    fn row<'b>(self, row: usize, n: usize, pad: &'b mut [f32]) -> RowSource<'b>
    where
        'a: 'b,
    {
        let r = |f, im, row: usize| plane_row(f, im, row * n, n);
        match self {
            Transformed::Spectral(f) => RowSource::Spectral(Spectral {
                fields: [
                    r(&f[0], false, row),
                    r(&f[0], true, row),
                    r(&f[1], false, row),
                    r(&f[1], true, row),
                    r(&f[2], false, row),
                    r(&f[2], true, row),
                    r(&f[3], false, row),
                    r(&f[3], true, row),
                ],
            }),
            Transformed::Finite(f) => {
                let hxz = |row: usize| {
                    [
                        r(&f[0], false, row),
                        r(&f[0], true, row),
                        r(&f[1], row & 1 == 1, row / 2),
                    ]
                };
                let mut padded = pad.chunks_exact_mut(n + 2);
                for src in hxz(row) {
                    pad_row(src, padded.next().expect("3 padded rows"));
                }
                let mut padded = pad.chunks_exact(n + 2);
                RowSource::Finite(Finite {
                    mid: std::array::from_fn(|_| padded.next().expect("3 padded rows")),
                    up: hxz((row + 1) % n),
                    down: hxz((row + n - 1) % n),
                })
            }
        }
    }
}

/// Stage 5-6 for one cascade: reads the transformed `fields` (see [`crate::sim::evolve`] for
/// their contents), updates the persistent `foam` state and fills `out` including mips.
pub fn finalize(
    fields: Transformed<'_>,
    foam: &mut [f32],
    p: SurfaceParams,
    time: f64,
    out: &mut CascadeSurface,
) {
    let n = out.grid.n();
    let len = pack::normal_length(p.roughness);
    let k = SurfaceConsts {
        lambda: p.choppiness,
        keep: (-p.foam.decay * p.dt).exp(),
        grow: p.foam.growth * p.dt,
        threshold: p.foam.threshold,
        len,
        smooth: pack::smoothness(len),
        inv_2dx: n as f32 / (2.0 * out.patch),
    };
    // Rows go in pairs so mip level 1 is averaged while both source rows are still in cache.
    // Level-0 floats and the f32 displacement live in a per-task stack buffer as planes: the
    // displacement's RGBA16F is converted from there, and both are copied out only when the
    // surface keeps float copies. Each task runs several pairs with one buffer, cleared once.
    let side1 = n / 2;
    let keep = out.keeps_floats();
    let (block1, area1) = mip_block(out.grid, 1);
    let [f1x, f1y, f1z, f1w] = planes_mut(&mut out.mip_chain[block1..block1 + 4 * area1], area1);
    let (level0_rgba, rest) = out.normal_foam.split_at_mut(n * n);
    let level1_rgba = &mut rest[..side1 * side1];
    let process_pair = |pair: usize, p: Pair<'_>, buf: &mut [f32]| {
        // Plane q of row i of the pair at (2q + i)·n: the floats, then the displacement, then
        // the finite mode's padded rows.
        let (floats, rest) = buf.split_at_mut(8 * n);
        let (disp, pad) = rest.split_at_mut(8 * n);
        let mut fl = floats.chunks_exact_mut(n);
        let mut fl: [[&mut [f32]; 2]; 4] = std::array::from_fn(|_| {
            let a = fl.next().expect("8 rows");
            [a, fl.next().expect("8 rows")]
        });
        let mut dl = disp.chunks_exact_mut(n);
        let mut dl: [[&mut [f32]; 2]; 4] = std::array::from_fn(|_| {
            let a = dl.next().expect("8 rows");
            [a, dl.next().expect("8 rows")]
        });
        let disp16 = bytemuck::cast_slice_mut::<[f16; 4], [u16; 4]>(p.disp16);
        let rows = disp16
            .chunks_mut(n)
            .zip(p.rgba.chunks_mut(n))
            .zip(p.foam.chunks_mut(n))
            .zip(p.row_max.iter_mut());
        for (i, (((disp16, rgba), foam), rmax)) in rows.enumerate() {
            let row = 2 * pair + i;
            let [p0, p1, p2, p3] = &mut fl;
            let [d0, d1, d2, d3] = &mut dl;
            let input = RowIn {
                src: fields.row(row, n, pad),
                row_sign: if row & 1 == 0 { 1.0 } else { -1.0 },
                k,
            };
            let out = RowOut {
                floats: [&mut *p0[i], &mut *p1[i], &mut *p2[i], &mut *p3[i]],
                disp: [&mut *d0[i], &mut *d1[i], &mut *d2[i], &mut *d3[i]],
                rgba,
                foam,
                max: rmax,
            };
            surface_row(input, out);
            interleave_f16([&*d0[i], &*d1[i], &*d2[i], &*d3[i]], disp16);
        }
        let [p0, p1, p2, p3] = &fl;
        let [f1x, f1y, f1z, f1w] = p.floats1;
        mip_planes(
            [p0[0], p0[1], p1[0], p1[1], p2[0], p2[1], p3[0], p3[1]],
            f1x,
            f1y,
            f1z,
            f1w,
            p.rgba1,
        );
        if let Some(kept) = p.kept {
            let interleave = |dst: &mut [[f32; 4]], planes: &[[&mut [f32]; 2]; 4]| {
                for (i, row) in dst.chunks_mut(n).enumerate() {
                    for (x, v) in row.iter_mut().enumerate() {
                        *v = std::array::from_fn(|q| planes[q][i][x]);
                    }
                }
            };
            interleave(kept.floats, &fl);
            interleave(kept.disp, &dl);
        }
    };
    let pairs = n / 2;
    // A few tasks per thread balance the load; fewer would leave a thread idle at the end.
    let tasks = (4 * rayon::current_num_threads()).min(pairs);
    let per_task = pairs.div_ceil(tasks);
    let task = |t: usize, chunk: Pair<'_>| {
        with_pair_buffer(n, |buf| {
            for (i, p) in chunk.split(n, side1).enumerate() {
                process_pair(t * per_task + i, p, buf);
            }
        })
    };
    let rows = 2 * per_task;
    let level1 = per_task * side1;
    let chunks = out
        .displacement_f16
        .par_chunks_mut(rows * n)
        .zip(level0_rgba.par_chunks_mut(rows * n))
        .zip(foam.par_chunks_mut(rows * n))
        .zip(out.row_max.par_chunks_mut(rows))
        .zip(f1x.par_chunks_mut(level1))
        .zip(f1y.par_chunks_mut(level1))
        .zip(f1z.par_chunks_mut(level1))
        .zip(f1w.par_chunks_mut(level1))
        .zip(level1_rgba.par_chunks_mut(level1))
        .map(
            |((((((((disp16, rgba), foam), row_max), x), y), z), w), rgba1)| Pair {
                disp16,
                rgba,
                foam,
                row_max,
                floats1: [x, y, z, w],
                rgba1,
                kept: None,
            },
        )
        .enumerate();
    if keep {
        chunks
            .zip(out.base_floats.par_chunks_mut(rows * n))
            .zip(out.displacement.par_chunks_mut(rows * n))
            .for_each(|(((t, p), floats), disp)| {
                task(
                    t,
                    Pair {
                        kept: Some(Kept { floats, disp }),
                        ..p
                    },
                )
            });
    } else {
        chunks.for_each(|(t, p)| task(t, p));
    }
    out.max_displacement = out.row_max.iter().fold([0.0f32; 3], |a, r| {
        [a[0].max(r[0]), a[1].max(r[1]), a[2].max(r[2])]
    });
    build_mips(out);
    out.time = time;
}

/// A cache line of f32: the element of the pair buffer, so its planes are 64-byte aligned.
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct Line([f32; 16]);

/// Runs `f` on a zeroed stack buffer for one row pair: 16 planes of `n` floats (level-0
/// normals and foam, then the displacement, of both rows), then room for three padded rows
/// of `n + 2` (all of it within 20 planes: n ≥ 16). Sized in tiers so small grids don't clear
/// more than they use; called once per task, not per pair.
fn with_pair_buffer<R>(n: usize, f: impl FnOnce(&mut [f32]) -> R) -> R {
    let len = 20 * n;
    // 20 planes of the tier's side, in lines of 16 floats.
    const fn lines(side: u32) -> usize {
        20 * side as usize / 16
    }
    if n <= 64 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); lines(64)])[..len])
    } else if n <= 256 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); lines(256)])[..len])
    } else if n <= 512 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); lines(512)])[..len])
    } else {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); lines(GridSize::MAX)])[..len])
    }
}

/// Where a pair's f32 copies go when the surface keeps them.
struct Kept<'a> {
    floats: &'a mut [[f32; 4]],
    disp: &'a mut [[f32; 4]],
}

/// The outputs of one or more consecutive row pairs in the surface stage.
struct Pair<'a> {
    disp16: &'a mut [[f16; 4]],
    rgba: &'a mut [u32],
    foam: &'a mut [f32],
    row_max: &'a mut [[f32; 3]],
    /// Level-1 float planes (normal x, y, z, foam).
    floats1: [&'a mut [f32]; 4],
    rgba1: &'a mut [u32],
    kept: Option<Kept<'a>>,
}

impl<'a> Pair<'a> {
    /// The single row pairs of a task's chunk (grid side `n`, level-1 side `side1`).
    fn split(self, n: usize, side1: usize) -> impl Iterator<Item = Pair<'a>> {
        let kept = self.kept.map(|k| {
            k.floats
                .chunks_mut(2 * n)
                .zip(k.disp.chunks_mut(2 * n))
                .map(|(floats, disp)| Kept { floats, disp })
        });
        let mut kept = kept.into_iter().flatten();
        let [x, y, z, w] = self.floats1;
        self.disp16
            .chunks_mut(2 * n)
            .zip(self.rgba.chunks_mut(2 * n))
            .zip(self.foam.chunks_mut(2 * n))
            .zip(self.row_max.chunks_mut(2))
            .zip(x.chunks_mut(side1))
            .zip(y.chunks_mut(side1))
            .zip(z.chunks_mut(side1))
            .zip(w.chunks_mut(side1))
            .zip(self.rgba1.chunks_mut(side1))
            .map(
                move |((((((((disp16, rgba), foam), row_max), x), y), z), w), rgba1)| Pair {
                    disp16,
                    rgba,
                    foam,
                    row_max,
                    floats1: [x, y, z, w],
                    rgba1,
                    kept: kept.next(),
                },
            )
    }
}
