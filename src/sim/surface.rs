//! Stages 5-6 (thesis 4.2.4-4.2.5): from the four transformed fields to the surface a renderer
//! and a buoyancy query use: displacement (eq. 42-44), normals and Jacobian from the spectral
//! derivatives (eq. 47-48), persistent foam, RGBA8/RGBA16F packing and the mip chain (eq. 52-55).

use half::f16;
use rayon::prelude::*;

use crate::sim::grid::{GridSize, SplitField};
use crate::sim::pack;
use crate::sim::params::FoamParams;

/// Everything one cascade publishes per step, in GPU upload formats plus float copies for CPU
/// queries and export. Allocated once; every step overwrites it in place.
pub struct CascadeSurface {
    /// Grid side.
    pub grid: GridSize,
    /// Patch size L (m): texel (c, r) sits at world (c, r)·L/N, repeating every L.
    pub patch: f32,
    /// (Dx, h, Dz, J) per texel in metres (J dimensionless), row-major: the displaced surface
    /// point of texel x is x + (Dx, h, Dz).
    pub displacement: Vec<[f32; 4]>,
    /// The same as RGBA16F for the vertex shader.
    pub displacement_f16: Vec<[f16; 4]>,
    /// RGBA8 normal/foam/smoothness chain (eq. 50-51), mip m at [`pack::mip_offset`].
    pub normal_foam: Vec<u32>,
    /// Float chain behind `normal_foam`: unnormalized, roughness-scaled normal xyz and foam.
    /// Level 0 holds each texel's normal scaled to [`pack::normal_length`].
    pub normal_floats: Vec<[f32; 4]>,
    /// Largest |Dx|, |h|, |Dz| over the patch (m): pads LOD bounding boxes.
    pub max_displacement: [f32; 3],
    /// Simulation time (s) these fields show.
    pub time: f64,
    row_max: Vec<[f32; 3]>,
}

impl CascadeSurface {
    /// Zeroed surface for one cascade.
    pub fn new(grid: GridSize, patch: f32) -> Self {
        let chain = pack::mip_chain_len(grid);
        Self {
            grid,
            patch,
            displacement: vec![[0.0; 4]; grid.texels()],
            displacement_f16: vec![[f16::ZERO; 4]; grid.texels()],
            normal_foam: vec![0; chain],
            normal_floats: vec![[0.0; 4]; chain],
            max_displacement: [0.0; 3],
            time: 0.0,
            row_max: vec![[0.0; 3]; grid.n()],
        }
    }

    /// Unit normal at texel `i` of level 0 (the stored one is roughness-scaled).
    pub fn unit_normal(&self, i: usize) -> [f32; 3] {
        let [x, y, z, _] = self.normal_floats[i];
        let l = (x * x + y * y + z * z).sqrt();
        [x / l, y / l, z / l]
    }

    /// Foam coverage [0, 1] at texel `i` of level 0.
    pub fn foam(&self, i: usize) -> f32 {
        self.normal_floats[i][3]
    }
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
    let lambda = p.choppiness;
    let keep = (-p.foam.decay * p.dt).exp();
    let grow = p.foam.growth * p.dt;
    let len = pack::normal_length(p.roughness);
    let smooth = pack::smoothness(len);
    let planes = [
        (&fields[0].re[..], &fields[0].im[..]),
        (&fields[1].re[..], &fields[1].im[..]),
        (&fields[2].re[..], &fields[2].im[..]),
        (&fields[3].re[..], &fields[3].im[..]),
    ];
    let (level0_floats, _) = out.normal_floats.split_at_mut(n * n);
    let (level0_rgba, _) = out.normal_foam.split_at_mut(n * n);
    out.displacement
        .par_chunks_mut(n)
        .zip(level0_floats.par_chunks_mut(n))
        .zip(level0_rgba.par_chunks_mut(n))
        .zip(foam.par_chunks_mut(n))
        .zip(out.row_max.par_iter_mut())
        .enumerate()
        .for_each(|(row, ((((disp, nf), rgba), foam), rmax))| {
            let base = row * n;
            let mut m = [0.0f32; 3];
            for col in 0..n {
                let i = base + col;
                // (−1)^(x+y) undoes the centred spectrum (eq. 42-43).
                let s = if (row + col) & 1 == 0 { 1.0 } else { -1.0 };
                let h = planes[0].0[i] * s;
                let dx = -lambda * planes[0].1[i] * s;
                let dz = -lambda * planes[1].0[i] * s;
                let hx = planes[1].1[i] * s;
                let hz = planes[2].0[i] * s;
                let dxx = -lambda * planes[2].1[i] * s;
                let dzz = -lambda * planes[3].0[i] * s;
                let dxz = -lambda * planes[3].1[i] * s;
                // Jacobian of the horizontal map x ↦ x + D(x) (eq. 48); ∂Dz/∂x = ∂Dx/∂z.
                let (jxx, jzz) = (1.0 + dxx, 1.0 + dzz);
                let j = jxx * jzz - dxz * dxz;
                // Normal of the displaced surface: ∂P/∂z × ∂P/∂x with P = x + (Dx, h, Dz);
                // for λ = 0 this is eq. 47's (−∂h/∂x, 1, −∂h/∂z). Folded texels (J < 0) flip
                // so the normal keeps facing up.
                let mut nx = hz * dxz - jzz * hx;
                let mut ny = j;
                let mut nz = dxz * hx - jxx * hz;
                if j < 0.0 {
                    (nx, ny, nz) = (-nx, -ny, -nz);
                }
                let l2 = nx * nx + ny * ny + nz * nz;
                let (nx, ny, nz) = if l2 > 1e-20 {
                    let inv = 1.0 / l2.sqrt();
                    (nx * inv, ny * inv, nz * inv)
                } else {
                    (0.0, 1.0, 0.0)
                };
                let f = (foam[col] * keep + grow * (p.foam.threshold - j).max(0.0)).min(1.0);
                foam[col] = f;
                disp[col] = [dx, h, dz, j];
                nf[col] = [nx * len, ny * len, nz * len, f];
                rgba[col] = pack::pack_rgba8(nx, nz, f, smooth);
                m = [m[0].max(dx.abs()), m[1].max(h.abs()), m[2].max(dz.abs())];
            }
            *rmax = m;
        });
    out.max_displacement = out.row_max.iter().fold([0.0f32; 3], |a, r| {
        [a[0].max(r[0]), a[1].max(r[1]), a[2].max(r[2])]
    });
    half::slice::HalfFloatSliceExt::convert_from_f32_slice(
        bytemuck::cast_slice_mut::<[f16; 4], f16>(&mut out.displacement_f16),
        bytemuck::cast_slice::<[f32; 4], f32>(&out.displacement),
    );
    build_mips(out);
    out.time = time;
}

/// Mip levels 1..=log₂N by unnormalized 2×2 box averaging (eq. 52); the averaged normal's
/// length becomes smoothness (eq. 53) and the RGBA8 texel stores it re-normalized.
fn build_mips(out: &mut CascadeSurface) {
    let grid = out.grid;
    for level in 1..grid.mip_levels() {
        let src_off = pack::mip_offset(grid, level - 1);
        let dst_off = pack::mip_offset(grid, level);
        let side = grid.n() >> level;
        let (lo, hi) = out.normal_floats.split_at_mut(dst_off);
        let src = &lo[src_off..];
        let dst = &mut hi[..side * side];
        let rgba = &mut out.normal_foam[dst_off..dst_off + side * side];
        let src_side = side * 2;
        dst.par_chunks_mut(side)
            .zip(rgba.par_chunks_mut(side))
            .enumerate()
            .for_each(|(y, (drow, prow))| {
                let r0 = &src[2 * y * src_side..(2 * y + 1) * src_side];
                let r1 = &src[(2 * y + 1) * src_side..(2 * y + 2) * src_side];
                for x in 0..side {
                    let mut v = [0.0f32; 4];
                    for c in 0..4 {
                        v[c] = 0.25
                            * (r0[2 * x][c] + r0[2 * x + 1][c] + r1[2 * x][c] + r1[2 * x + 1][c]);
                    }
                    drow[x] = v;
                    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    let (nx, nz) = if l > 1e-20 {
                        (v[0] / l, v[2] / l)
                    } else {
                        (0.0, 0.0)
                    };
                    prow[x] = pack::pack_rgba8(nx, nz, v[3], pack::smoothness(l));
                }
            });
    }
}
