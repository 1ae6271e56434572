//! One texel row of stages 5-6: displacement (eq. 42-44), the Jacobian (eq. 48), normals of
//! the displaced surface (eq. 47), persistent foam, and the RGBA16F/RGBA8 encodings, in one
//! vectorized loop per row behind runtime ISA dispatch.

use crate::sim::grid::SplitField;
use crate::sim::pack;
use crate::sim::simd::dispatch;

/// Constants of the surface stage for one step.
#[derive(Clone, Copy)]
pub(super) struct SurfaceConsts {
    pub lambda: f32,
    pub keep: f32,
    pub grow: f32,
    pub threshold: f32,
    pub len: f32,
    pub smooth: f32,
}

/// What one row of the surface stage reads.
#[derive(Clone, Copy)]
pub(super) struct RowIn<'a> {
    pub fields: [&'a [f32]; 8],
    pub row_sign: f32,
    pub k: SurfaceConsts,
}

/// What one row of the surface stage writes.
pub(super) struct RowOut<'a> {
    /// RGBA16F displacement as binary16 bits.
    pub disp16: &'a mut [[u16; 4]],
    /// Level-0 roughness-scaled normal x, y, z and foam, one plane each (mip level 1 reads them).
    pub floats: [&'a mut [f32]; 4],
    /// f32 Dx, h, Dz, J planes when the surface keeps float copies; else empty.
    pub disp: [&'a mut [f32]; 4],
    pub rgba: &'a mut [u32],
    pub foam: &'a mut [f32],
    /// Receives the row's max |Dx|, |h|, |Dz|.
    pub max: &'a mut [f32; 3],
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
pub(super) fn surface_row(row: RowIn<'_>, out: RowOut<'_>) {
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
pub(super) fn plane_row(f: &SplitField, im: bool, b: usize, n: usize) -> &[f32] {
    if im {
        &f.im[b..b + n]
    } else {
        &f.re[b..b + n]
    }
}
