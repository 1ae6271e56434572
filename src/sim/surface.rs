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

/// One row of the surface stage.
struct SurfaceRow<'a> {
    fields: [&'a [f32]; 8],
    disp: &'a mut [[f32; 4]],
    floats: &'a mut [[f32; 4]],
    rgba: &'a mut [u32],
    foam: &'a mut [f32],
    row_sign: f32,
    k: SurfaceConsts,
}

#[inline(always)]
fn surface_row_kernel(row: SurfaceRow<'_>) -> [f32; 3] {
    let n = row.disp.len();
    let [f0r, f0i, f1r, f1i, f2r, f2i, f3r, f3i] = row.fields;
    // Exact-length slices let the compiler drop bounds checks and vectorize.
    let (f0r, f0i, f1r, f1i) = (&f0r[..n], &f0i[..n], &f1r[..n], &f1i[..n]);
    let (f2r, f2i, f3r, f3i) = (&f2r[..n], &f2i[..n], &f3r[..n], &f3i[..n]);
    let (floats, rgba, foam) = (&mut row.floats[..n], &mut row.rgba[..n], &mut row.foam[..n]);
    let disp = row.disp;
    let k = row.k;
    // Maxima of |Dx|, |h|, |Dz| as the bits of non-negative floats, whose integer order is
    // their numeric order: an integer max reduction vectorizes, a float one does not.
    let mut m = [0u32; 3];
    for col in 0..n {
        // (−1)^(x+y) undoes the centred spectrum (eq. 42-43).
        let s = if col & 1 == 0 {
            row.row_sign
        } else {
            -row.row_sign
        };
        let h = f0r[col] * s;
        let ls = -k.lambda * s;
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
        disp[col] = [dx, h, dz, j];
        floats[col] = [nx * k.len, ny * k.len, nz * k.len, f];
        rgba[col] = pack::pack_rgba8(nx, nz, f, k.smooth);
        let abs_bits = |v: f32| v.to_bits() & 0x7fff_ffff;
        m = [
            m[0].max(abs_bits(dx)),
            m[1].max(abs_bits(h)),
            m[2].max(abs_bits(dz)),
        ];
    }
    m.map(f32::from_bits)
}

#[inline(always)]
fn surface_row_into(row: SurfaceRow<'_>, max: &mut [f32; 3]) {
    *max = surface_row_kernel(row);
}

dispatch!(
    /// [`surface_row_kernel`] behind runtime ISA dispatch; stores the row's max |Dx|, |h|, |Dz|.
    fn surface_row(row: SurfaceRow<'_>, max: &mut [f32; 3]) => surface_row_into
);

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
    // Level-0 floats and f32 displacement live in a per-pair stack buffer, copied out only when
    // the surface keeps float copies.
    let side1 = n / 2;
    let l1 = out.floats_offset(1);
    let (level0_floats, level1_floats) = out.normal_floats.split_at_mut(l1);
    let level1_floats = &mut level1_floats[..side1 * side1];
    let (level0_rgba, rest) = out.normal_foam.split_at_mut(n * n);
    let level1_rgba = &mut rest[..side1 * side1];
    let process_pair = |pair: usize, p: Pair<'_>, kept: Option<Kept<'_>>, buf: &mut [[f32; 4]]| {
        let (floats, disp) = buf.split_at_mut(2 * n);
        let rows = disp
            .chunks_mut(n)
            .zip(p.disp16.chunks_mut(n))
            .zip(floats.chunks_mut(n))
            .zip(p.rgba.chunks_mut(n))
            .zip(p.foam.chunks_mut(n))
            .zip(p.row_max.iter_mut());
        for (i, (((((disp, disp16), floats), rgba), foam), rmax)) in rows.enumerate() {
            let row = 2 * pair + i;
            let b = row * n;
            let r = |f, im| plane_row(f, im, b, n);
            let surface = SurfaceRow {
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
                disp: &mut *disp,
                floats,
                rgba,
                foam,
                row_sign: if row & 1 == 0 { 1.0 } else { -1.0 },
                k,
            };
            surface_row(surface, rmax);
            // The row is still in L1: convert it to RGBA16F here, not in another pass.
            half::slice::HalfFloatSliceExt::convert_from_f32_slice(
                bytemuck::cast_slice_mut::<[f16; 4], f16>(disp16),
                bytemuck::cast_slice::<[f32; 4], f32>(disp),
            );
        }
        let (src0, src1) = floats.split_at(n);
        mip_row(MipRow {
            src0,
            src1,
            dst: p.floats1,
            rgba: p.rgba1,
        });
        if let Some(kept) = kept {
            kept.floats.copy_from_slice(floats);
            kept.disp.copy_from_slice(disp);
        }
    };
    let pair = |pair: usize, p: Pair<'_>, kept: Option<Kept<'_>>| {
        with_pair_buffer(n, |buf| process_pair(pair, p, kept, buf))
    };
    let pairs = out
        .displacement_f16
        .par_chunks_mut(2 * n)
        .zip(level0_rgba.par_chunks_mut(2 * n))
        .zip(foam.par_chunks_mut(2 * n))
        .zip(out.row_max.par_chunks_mut(2))
        .zip(level1_floats.par_chunks_mut(side1))
        .zip(level1_rgba.par_chunks_mut(side1))
        .map(
            |(((((disp16, rgba), foam), row_max), floats1), rgba1)| Pair {
                disp16,
                rgba,
                foam,
                row_max,
                floats1,
                rgba1,
            },
        )
        .enumerate();
    match out.base {
        FloatCopies::Keep => pairs
            .zip(level0_floats.par_chunks_mut(2 * n))
            .zip(out.displacement.par_chunks_mut(2 * n))
            .for_each(|(((i, p), floats), disp)| pair(i, p, Some(Kept { floats, disp }))),
        FloatCopies::Skip => pairs.for_each(|(i, p)| pair(i, p, None)),
    }
    out.max_displacement = out.row_max.iter().fold([0.0f32; 3], |a, r| {
        [a[0].max(r[0]), a[1].max(r[1]), a[2].max(r[2])]
    });
    build_mips(out);
    out.time = time;
}

/// Runs `f` on a zeroed stack buffer of exactly 4·`n` texels (one row pair's level-0 floats
/// and f32 displacement) for the common sizes, so no step zeroes more than its rows need.
fn with_pair_buffer<R>(n: usize, f: impl FnOnce(&mut [[f32; 4]]) -> R) -> R {
    if n <= 64 {
        f(&mut [[0.0; 4]; 256][..4 * n])
    } else if n <= 256 {
        f(&mut [[0.0; 4]; 1024][..4 * n])
    } else if n <= 512 {
        f(&mut [[0.0; 4]; 2048][..4 * n])
    } else {
        f(&mut [[0.0; 4]; 4 * GridSize::MAX as usize][..4 * n])
    }
}

/// Where a pair's f32 copies go when the surface keeps them.
struct Kept<'a> {
    floats: &'a mut [[f32; 4]],
    disp: &'a mut [[f32; 4]],
}

/// The outputs of one pair of rows in the surface stage.
struct Pair<'a> {
    disp16: &'a mut [[f16; 4]],
    rgba: &'a mut [u32],
    foam: &'a mut [f32],
    row_max: &'a mut [[f32; 3]],
    floats1: &'a mut [[f32; 4]],
    rgba1: &'a mut [u32],
}

/// One destination row of a mip level and the two source rows it averages.
struct MipRow<'a> {
    src0: &'a [[f32; 4]],
    src1: &'a [[f32; 4]],
    dst: &'a mut [[f32; 4]],
    rgba: &'a mut [u32],
}

#[inline(always)]
fn mip_row_kernel(row: MipRow<'_>) {
    let side = row.dst.len();
    let (r0, r1) = (&row.src0[..2 * side], &row.src1[..2 * side]);
    let rgba = &mut row.rgba[..side];
    for (x, d) in row.dst.iter_mut().enumerate() {
        let (a, b, c, e) = (r0[2 * x], r0[2 * x + 1], r1[2 * x], r1[2 * x + 1]);
        let v: [f32; 4] = std::array::from_fn(|k| 0.25 * (a[k] + b[k] + c[k] + e[k]));
        *d = v;
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let inv = if l > 1e-20 { 1.0 / l } else { 0.0 };
        rgba[x] = pack::pack_rgba8(v[0] * inv, v[2] * inv, v[3], pack::smoothness(l));
    }
}

dispatch!(
    /// [`mip_row_kernel`] behind runtime ISA dispatch.
    fn mip_row(row: MipRow<'_>) => mip_row_kernel
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
                    mip_row(MipRow {
                        src0: &src[2 * y * src_side..(2 * y + 1) * src_side],
                        src1: &src[(2 * y + 1) * src_side..(2 * y + 2) * src_side],
                        dst: drow,
                        rgba: prow,
                    });
                }
            });
    }
}
