//! Stages 5-6 (thesis 4.2.4-4.2.5): from the four transformed fields to the surface a renderer
//! and a buoyancy query use: displacement (eq. 42-44), normals and Jacobian from the spectral
//! derivatives (eq. 47-48), persistent foam, RGBA8/RGBA16F packing and the mip chain (eq. 52-55).

use half::f16;
use rayon::prelude::*;

use crate::sim::grid::{GridSize, SplitField};
use crate::sim::pack;
use crate::sim::params::FoamParams;
use crate::sim::simd::dispatch;

/// Everything one cascade publishes per step, in GPU upload formats plus float copies for CPU
/// queries and export. Allocated once; every step overwrites it in place.
pub struct CascadeSurface {
    /// Grid side.
    pub grid: GridSize,
    /// Patch size L (m): texel (c, r) sits at world (c, r)·L/N, repeating every L.
    pub patch: f32,
    /// (Dx, h, Dz, J) per texel in metres (J dimensionless), row-major: the displaced surface
    /// point of texel x is x + (Dx, h, Dz). Full precision with [`FloatCopies::Keep`]; empty
    /// with [`FloatCopies::Skip`], where `displacement_f16` is the only copy.
    pub displacement: Vec<[f32; 4]>,
    /// The same as RGBA16F for the vertex shader (always present).
    pub displacement_f16: Vec<[f16; 4]>,
    /// RGBA8 normal/foam/smoothness chain (eq. 50-51), mip m at [`pack::mip_offset`].
    pub normal_foam: Vec<u32>,
    /// Float chain behind `normal_foam`: unnormalized, roughness-scaled normal xyz and foam,
    /// from level 1 (or level 0 with [`FloatCopies::Keep`]); see [`CascadeSurface::floats_offset`].
    normal_floats: Vec<[f32; 4]>,
    base: FloatCopies,
    /// Largest |Dx|, |h|, |Dz| over the patch (m): pads LOD bounding boxes.
    pub max_displacement: [f32; 3],
    /// Simulation time (s) these fields show.
    pub time: f64,
    row_max: Vec<[f32; 3]>,
}

/// Whether a surface keeps full-precision f32 copies of its level-0 fields: the displacement
/// and the normals and foam. The renderer needs only RGBA16F and RGBA8; each f32 copy costs a
/// 16-byte-per-texel stream every step (2 × 4 MiB at N = 512), so only export and checks keep
/// them. Height queries use the f32 displacement when kept, else the RGBA16F one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloatCopies {
    /// Also store `displacement` and level-0 float normals and foam
    /// ([`CascadeSurface::base_normals`]).
    Keep,
    /// Level 0 exists only in the GPU formats.
    Skip,
}

impl CascadeSurface {
    /// Zeroed surface for one cascade.
    pub fn new(grid: GridSize, patch: f32, base: FloatCopies) -> Self {
        let chain = pack::mip_chain_len(grid);
        let floats = match base {
            FloatCopies::Keep => chain,
            FloatCopies::Skip => chain - grid.texels(),
        };
        Self {
            grid,
            patch,
            displacement: match base {
                FloatCopies::Keep => vec![[0.0; 4]; grid.texels()],
                FloatCopies::Skip => Vec::new(),
            },
            displacement_f16: vec![[f16::ZERO; 4]; grid.texels()],
            normal_foam: vec![0; chain],
            normal_floats: vec![[0.0; 4]; floats],
            base,
            max_displacement: [0.0; 3],
            time: 0.0,
            row_max: vec![[0.0; 3]; grid.n()],
        }
    }

    /// Offset of mip `level` in the float chain (levels below 1 absent with [`FloatCopies::Skip`]).
    fn floats_offset(&self, level: u32) -> usize {
        match self.base {
            FloatCopies::Keep => pack::mip_offset(self.grid, level),
            FloatCopies::Skip => pack::mip_offset(self.grid, level) - self.grid.texels(),
        }
    }

    /// Level-0 roughness-scaled normals (xyz) and foam (w), row-major, when kept.
    pub fn base_normals(&self) -> Option<&[[f32; 4]]> {
        (self.base == FloatCopies::Keep).then(|| &self.normal_floats[..self.grid.texels()])
    }

    /// Unnormalized float mip `level` ≥ 1 (normal xyz, foam w), as averaged (eq. 52).
    pub fn mip_floats(&self, level: u32) -> &[[f32; 4]] {
        let side = self.grid.n() >> level;
        let off = self.floats_offset(level);
        &self.normal_floats[off..off + side * side]
    }
}

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

/// Constants of the surface stage for one step.
#[derive(Clone, Copy)]
struct SurfaceConsts {
    lambda: f32,
    keep: f32,
    grow: f32,
    threshold: f32,
    len: f32,
    smooth: f32,
}

/// What one row of the surface stage reads.
#[derive(Clone, Copy)]
struct RowIn<'a> {
    fields: [&'a [f32]; 8],
    row_sign: f32,
    k: SurfaceConsts,
}

/// What one row of the surface stage writes.
struct RowOut<'a> {
    /// RGBA16F displacement as binary16 bits.
    disp16: &'a mut [[u16; 4]],
    /// Level-0 roughness-scaled normal x, y, z and foam, one plane each (mip level 1 reads them).
    floats: [&'a mut [f32]; 4],
    /// f32 Dx, h, Dz, J planes when the surface keeps float copies; else empty.
    disp: [&'a mut [f32]; 4],
    rgba: &'a mut [u32],
    foam: &'a mut [f32],
    /// Receives the row's max |Dx|, |h|, |Dz|.
    max: &'a mut [f32; 3],
}

/// One texel row of stages 5-6. Every output is a plane or a plain integer array, so the loop
/// vectorizes with no shuffles but the RGBA16F interleave. The outputs are separate arguments:
/// only those carry `noalias` (struct fields do not), and without it LLVM guards the loop with
/// pairwise overlap checks of all eleven outputs, which cost more than a 256-texel row.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn surface_row_kernel<const KEEP: bool>(
    row: RowIn<'_>,
    disp16: &mut [[u16; 4]],
    p0: &mut [f32],
    p1: &mut [f32],
    p2: &mut [f32],
    p3: &mut [f32],
    d0: &mut [f32],
    d1: &mut [f32],
    d2: &mut [f32],
    d3: &mut [f32],
    rgba: &mut [u32],
    foam: &mut [f32],
    max: &mut [f32; 3],
) {
    let n = rgba.len();
    let [f0r, f0i, f1r, f1i, f2r, f2i, f3r, f3i] = row.fields;
    // Exact-length slices let the compiler drop bounds checks and vectorize.
    let (f0r, f0i, f1r, f1i) = (&f0r[..n], &f0i[..n], &f1r[..n], &f1i[..n]);
    let (f2r, f2i, f3r, f3i) = (&f2r[..n], &f2i[..n], &f3r[..n], &f3i[..n]);
    let (foam, disp16) = (&mut foam[..n], &mut disp16[..n]);
    let (p0, p1, p2, p3) = (&mut p0[..n], &mut p1[..n], &mut p2[..n], &mut p3[..n]);
    let m = if KEEP { n } else { 0 };
    let (d0, d1, d2, d3) = (&mut d0[..m], &mut d1[..m], &mut d2[..m], &mut d3[..m]);
    let k = row.k;
    // Maxima of |Dx|, |h|, |Dz| as the bits of non-negative floats, whose integer order is
    // their numeric order: an integer max reduction vectorizes, a float one does not.
    let mut mx = [0u32; 3];
    for col in 0..n {
        // (−1)^(x+y) undoes the centred spectrum (eq. 42-43).
        let s = if col & 1 == 0 {
            row.row_sign
        } else {
            -row.row_sign
        };
        let h = f0r[col] * s;
        // D = +λ·(X, Z) with X = Σ i·u·h̃·e^{ik·x} (see `evolve`): for h = a·cos θ this is
        // Dx = −λ·a·sin θ, the trochoid that gathers points under the crests (Gerstner).
        let ls = k.lambda * s;
        let dx = ls * f0i[col];
        let dz = ls * f1r[col];
        let hx = f1i[col] * s;
        let hz = f2r[col] * s;
        let dxx = ls * f2i[col];
        let dzz = ls * f3r[col];
        let dxz = ls * f3i[col];
        // Jacobian of the horizontal map x ↦ x + D(x) (eq. 48); ∂Dz/∂x = ∂Dx/∂z.
        let (jxx, jzz) = (1.0 + dxx, 1.0 + dzz);
        let j = jxx * jzz - dxz * dxz;
        // Normal of the displaced surface: ∂P/∂z × ∂P/∂x with P = x + (Dx, h, Dz); for λ = 0
        // this is eq. 47's (−∂h/∂x, 1, −∂h/∂z). Folded texels (J < 0) flip so the normal keeps
        // facing up.
        let flip = if j < 0.0 { -1.0 } else { 1.0 };
        let nx = (hz * dxz - jzz * hx) * flip;
        let ny = j * flip;
        let nz = (dxz * hx - jxx * hz) * flip;
        let l2 = nx * nx + ny * ny + nz * nz;
        // A degenerate normal (exact fold edge) becomes straight up.
        let ok = l2 > 1e-20;
        let inv = if ok { 1.0 / l2.sqrt() } else { 0.0 };
        let (nx, ny, nz) = (nx * inv, if ok { ny * inv } else { 1.0 }, nz * inv);
        let f = (foam[col] * k.keep + k.grow * (k.threshold - j).max(0.0)).min(1.0);
        foam[col] = f;
        disp16[col] = [
            pack::f16_bits(dx),
            pack::f16_bits(h),
            pack::f16_bits(dz),
            pack::f16_bits(j),
        ];
        if KEEP {
            (d0[col], d1[col], d2[col], d3[col]) = (dx, h, dz, j);
        }
        (p0[col], p1[col], p2[col], p3[col]) = (nx * k.len, ny * k.len, nz * k.len, f);
        rgba[col] = pack::pack_rgba8(nx, nz, f, k.smooth);
        let abs_bits = |v: f32| v.to_bits() & 0x7fff_ffff;
        mx = [
            mx[0].max(abs_bits(dx)),
            mx[1].max(abs_bits(h)),
            mx[2].max(abs_bits(dz)),
        ];
    }
    *max = mx.map(f32::from_bits);
}

macro_rules! surface_variant {
    ($(#[$m:meta])* $name:ident, $keep:literal) => {
        dispatch!(
            $(#[$m])*
            #[allow(clippy::too_many_arguments)]
            fn $name(
                row: RowIn<'_>,
                disp16: &mut [[u16; 4]],
                p0: &mut [f32],
                p1: &mut [f32],
                p2: &mut [f32],
                p3: &mut [f32],
                d0: &mut [f32],
                d1: &mut [f32],
                d2: &mut [f32],
                d3: &mut [f32],
                rgba: &mut [u32],
                foam: &mut [f32],
                max: &mut [f32; 3],
            ) => surface_row_kernel::<$keep>
        );
    };
}
surface_variant!(
    /// [`surface_row_kernel`] behind runtime ISA dispatch.
    surface_row_skip,
    false
);
surface_variant!(
    /// [`surface_row_kernel`] that also writes the f32 displacement, behind ISA dispatch.
    surface_row_keep,
    true
);

/// Runs one row of the surface stage (writing `out.disp` when it is not empty).
fn surface_row(row: RowIn<'_>, out: RowOut<'_>) {
    let RowOut {
        disp16,
        floats: [p0, p1, p2, p3],
        disp: [d0, d1, d2, d3],
        rgba,
        foam,
        max,
    } = out;
    if d0.is_empty() {
        surface_row_skip(row, disp16, p0, p1, p2, p3, d0, d1, d2, d3, rgba, foam, max)
    } else {
        surface_row_keep(row, disp16, p0, p1, p2, p3, d0, d1, d2, d3, rgba, foam, max)
    }
}

/// Row `b / n` of one plane of `f`.
fn plane_row(f: &SplitField, im: bool, b: usize, n: usize) -> &[f32] {
    if im {
        &f.im[b..b + n]
    } else {
        &f.re[b..b + n]
    }
}

/// Stage 5-6 for one cascade: reads the transformed `fields` (see [`crate::sim::evolve`] for
/// their contents), updates the persistent `foam` state and fills `out` including mips.
pub fn finalize(
    fields: &[SplitField; 4],
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
    };
    // Rows go in pairs so mip level 1 is averaged while both source rows are still in cache.
    // Level-0 floats (and the f32 displacement) live in a per-task stack buffer as planes,
    // copied out only when the surface keeps float copies. Each task runs several pairs with
    // one buffer, cleared once.
    let side1 = n / 2;
    let l1 = out.floats_offset(1);
    let (level0_floats, level1_floats) = out.normal_floats.split_at_mut(l1);
    let level1_floats = &mut level1_floats[..side1 * side1];
    let (level0_rgba, rest) = out.normal_foam.split_at_mut(n * n);
    let level1_rgba = &mut rest[..side1 * side1];
    let keep = out.base == FloatCopies::Keep;
    let process_pair = |pair: usize, p: Pair<'_>, buf: &mut [f32]| {
        // Plane q of row i of the pair at (2q + i)·n: floats, then (kept) displacement.
        let (floats, disp) = buf.split_at_mut(8 * n);
        let mut fl = floats.chunks_exact_mut(n);
        let mut fl: [[&mut [f32]; 2]; 4] = std::array::from_fn(|_| {
            let a = fl.next().expect("8 rows");
            [a, fl.next().expect("8 rows")]
        });
        let mut dl = disp.chunks_exact_mut(n);
        let mut dl: [[&mut [f32]; 2]; 4] = std::array::from_fn(|_| {
            if keep {
                let a = dl.next().expect("8 rows");
                [a, dl.next().expect("8 rows")]
            } else {
                [&mut [][..], &mut [][..]]
            }
        });
        let disp16 = bytemuck::cast_slice_mut::<[f16; 4], [u16; 4]>(p.disp16);
        let rows = disp16
            .chunks_mut(n)
            .zip(p.rgba.chunks_mut(n))
            .zip(p.foam.chunks_mut(n))
            .zip(p.row_max.iter_mut());
        for (i, (((disp16, rgba), foam), rmax)) in rows.enumerate() {
            let row = 2 * pair + i;
            let b = row * n;
            let r = |f, im| plane_row(f, im, b, n);
            let [p0, p1, p2, p3] = &mut fl;
            let [d0, d1, d2, d3] = &mut dl;
            let input = RowIn {
                fields: [
                    r(&fields[0], false),
                    r(&fields[0], true),
                    r(&fields[1], false),
                    r(&fields[1], true),
                    r(&fields[2], false),
                    r(&fields[2], true),
                    r(&fields[3], false),
                    r(&fields[3], true),
                ],
                row_sign: if row & 1 == 0 { 1.0 } else { -1.0 },
                k,
            };
            let out = RowOut {
                disp16,
                floats: [&mut *p0[i], &mut *p1[i], &mut *p2[i], &mut *p3[i]],
                disp: [&mut *d0[i], &mut *d1[i], &mut *d2[i], &mut *d3[i]],
                rgba,
                foam,
                max: rmax,
            };
            surface_row(input, out);
        }
        let [p0, p1, p2, p3] = &fl;
        mip_planes(
            [p0[0], p0[1], p1[0], p1[1], p2[0], p2[1], p3[0], p3[1]],
            p.floats1,
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
        with_pair_buffer(n, keep, |buf| {
            for (i, p) in chunk.split(n, side1).enumerate() {
                process_pair(t * per_task + i, p, buf);
            }
        })
    };
    let rows = 2 * per_task;
    let chunks = out
        .displacement_f16
        .par_chunks_mut(rows * n)
        .zip(level0_rgba.par_chunks_mut(rows * n))
        .zip(foam.par_chunks_mut(rows * n))
        .zip(out.row_max.par_chunks_mut(rows))
        .zip(level1_floats.par_chunks_mut(per_task * side1))
        .zip(level1_rgba.par_chunks_mut(per_task * side1))
        .map(
            |(((((disp16, rgba), foam), row_max), floats1), rgba1)| Pair {
                disp16,
                rgba,
                foam,
                row_max,
                floats1,
                rgba1,
                kept: None,
            },
        )
        .enumerate();
    match out.base {
        FloatCopies::Keep => chunks
            .zip(level0_floats.par_chunks_mut(rows * n))
            .zip(out.displacement.par_chunks_mut(rows * n))
            .for_each(|(((t, p), floats), disp)| {
                task(
                    t,
                    Pair {
                        kept: Some(Kept { floats, disp }),
                        ..p
                    },
                )
            }),
        FloatCopies::Skip => chunks.for_each(|(t, p)| task(t, p)),
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

/// Runs `f` on a zeroed stack buffer for one row pair: 8 planes of `n` floats (level-0
/// normals and foam of both rows), 16 with `keep` (also the f32 displacement). Sized in tiers
/// so small grids don't clear more than they use; called once per task, not per pair.
fn with_pair_buffer<R>(n: usize, keep: bool, f: impl FnOnce(&mut [f32]) -> R) -> R {
    let len = if keep { 16 * n } else { 8 * n };
    if n <= 64 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); 64])[..len])
    } else if n <= 256 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); 256])[..len])
    } else if n <= 512 {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); 512])[..len])
    } else {
        f(&mut bytemuck::cast_slice_mut(&mut [Line([0.0; 16]); GridSize::MAX as usize])[..len])
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
    floats1: &'a mut [[f32; 4]],
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
        self.disp16
            .chunks_mut(2 * n)
            .zip(self.rgba.chunks_mut(2 * n))
            .zip(self.foam.chunks_mut(2 * n))
            .zip(self.row_max.chunks_mut(2))
            .zip(self.floats1.chunks_mut(side1))
            .zip(self.rgba1.chunks_mut(side1))
            .map(
                move |(((((disp16, rgba), foam), row_max), floats1), rgba1)| Pair {
                    disp16,
                    rgba,
                    foam,
                    row_max,
                    floats1,
                    rgba1,
                    kept: kept.next(),
                },
            )
    }
}

/// The RGBA8 texel of an averaged (unnormalized) normal and foam `v` (eq. 51, 53).
#[inline(always)]
fn mip_texel(v: [f32; 4]) -> u32 {
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
    fn mip_planes(src: [&[f32]; 8], dst: &mut [[f32; 4]], rgba: &mut [u32]) => mip_planes_kernel
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
fn build_mips(out: &mut CascadeSurface) {
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
