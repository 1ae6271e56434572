//! One texel row of stages 5-6: displacement (eq. 42-44), the Jacobian (eq. 48), normals of
//! the displaced surface (eq. 47), persistent foam and the RGBA8 encoding, in two vectorized
//! loops per row (the second normalizes the normals) behind runtime ISA dispatch (the RGBA16F
//! displacement is converted from its planes afterwards, see [`super::f16_row`]).

use crate::sim::grid::{GridSize, SplitField};
use crate::sim::pack;
use crate::sim::simd::dispatch;

/// (−1)^col for every column of the largest grid: the centred spectrum's sign (eq. 42-43) as
/// a load, so the row loop keeps no vector of 64-bit column indices to derive it from.
static ALTERNATING: [f32; GridSize::MAX as usize] = {
    let mut s = [1.0; GridSize::MAX as usize];
    let mut i = 1;
    while i < s.len() {
        s[i] = -1.0;
        i += 2;
    }
    s
};

/// Constants of the surface stage for one step.
#[derive(Clone, Copy)]
pub(super) struct SurfaceConsts {
    pub lambda: f32,
    pub keep: f32,
    pub grow: f32,
    pub threshold: f32,
    pub len: f32,
    pub smooth: f32,
    /// 1 / (2Δ) with Δ = L/N the texel spacing (m): central differences' divisor.
    pub inv_2dx: f32,
}

/// What a texel's surface needs, sign-corrected and scaled (m, or dimensionless for slopes):
/// height, displacement and the nine derivatives of eq. 47-48, however they were taken.
#[derive(Clone, Copy)]
pub(super) struct Texel {
    h: f32,
    dx: f32,
    dz: f32,
    /// ∂h/∂x, ∂h/∂z.
    hx: f32,
    hz: f32,
    /// ∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z, ∂Dz/∂x (the last two equal in the spectral mode).
    dxx: f32,
    dzz: f32,
    dxz: f32,
    dzx: f32,
}

/// Where one row's [`Texel`]s come from: the derivative mode's fields.
pub(super) trait Source: Copy {
    /// The same source with every slice cut to what a row of `n` texels reads (exact lengths
    /// let LLVM drop bounds checks).
    fn fit(self, n: usize) -> Self;
    /// Texel `col` with sign `s` = (−1)^(row+col) (eq. 42-43).
    fn at(&self, col: usize, s: f32, k: &SurfaceConsts) -> Texel;
}

/// Spectral derivatives: the eight real fields of the four packed transforms (see
/// [`crate::sim::evolve`]), this row of each plane.
#[derive(Clone, Copy)]
pub(super) struct Spectral<'a> {
    pub fields: [&'a [f32]; 8],
}

impl Source for Spectral<'_> {
    #[inline(always)]
    fn fit(self, n: usize) -> Self {
        Self {
            fields: self.fields.map(|p| &p[..n]),
        }
    }
    #[inline(always)]
    fn at(&self, col: usize, s: f32, k: &SurfaceConsts) -> Texel {
        let [f0r, f0i, f1r, f1i, f2r, f2i, f3r, f3i] = self.fields;
        // D = +λ·(X, Z) with X = Σ i·u·h̃·e^{ik·x} (see `evolve`): for h = a·cos θ this is
        // Dx = −λ·a·sin θ, the trochoid that gathers points under the crests (Gerstner).
        let ls = k.lambda * s;
        let dxz = ls * f3i[col];
        Texel {
            h: f0r[col] * s,
            dx: ls * f0i[col],
            dz: ls * f1r[col],
            hx: f1i[col] * s,
            hz: f2r[col] * s,
            dxx: ls * f2i[col],
            dzz: ls * f3r[col],
            dxz,
            // ∂Dz/∂x = ∂Dx/∂z for the spectral fields.
            dzx: dxz,
        }
    }
}

/// Central differences (eq. 45-46): h, X and Z of this row and of the rows above (z + Δ) and
/// below (z − Δ), wrapping around the patch.
#[derive(Clone, Copy)]
pub(super) struct Finite<'a> {
    /// [h, X, Z] of this row, raw (before the sign correction) and padded ([`pad_row`]):
    /// column c at c + 1, its neighbours at c and c + 2 for every c, the row's ends included.
    pub mid: [&'a [f32]; 3],
    /// [h, X, Z] of row r + 1.
    pub up: [&'a [f32]; 3],
    /// [h, X, Z] of row r − 1.
    pub down: [&'a [f32]; 3],
}

/// Copies row `src` into `dst` (`src.len() + 2` floats) with one column of wrap-around on each
/// side: `dst[0]` is the last column, `dst[n + 1]` the first. With it the row loop reads both
/// neighbours of every column, the ends too, and runs as whole vectors with no scalar edges
/// or remainder.
pub(super) fn pad_row(src: &[f32], dst: &mut [f32]) {
    let n = src.len();
    dst[1..n + 1].copy_from_slice(src);
    (dst[0], dst[n + 1]) = (src[n - 1], src[0]);
}

impl Finite<'_> {
    /// The texel at `col`: padded column `col + 1`, its neighbours `col` and `col + 2`.
    #[inline(always)]
    fn around(&self, col: usize, s: f32, k: &SurfaceConsts) -> Texel {
        let (l, r) = (col, col + 2);
        let [h, x, z] = self.mid.map(|p| &p[1..]);
        let [hl, xl, zl] = self.mid;
        let [hu, xu, zu] = self.up;
        let [hd, xd, zd] = self.down;
        let ls = k.lambda * s;
        // Neighbours carry the opposite sign, (−1)^(c±1) = −(−1)^c, so
        // f(c+1) − f(c−1) = −s·(raw(c+1) − raw(c−1)).
        let d = -s * k.inv_2dx;
        let ld = k.lambda * d;
        Texel {
            h: h[col] * s,
            dx: ls * x[col],
            dz: ls * z[col],
            hx: d * (hl[r] - hl[l]),
            hz: d * (hu[col] - hd[col]),
            dxx: ld * (xl[r] - xl[l]),
            dzz: ld * (zu[col] - zd[col]),
            dxz: ld * (xu[col] - xd[col]),
            dzx: ld * (zl[r] - zl[l]),
        }
    }
}

impl<'a> Source for Finite<'a> {
    #[inline(always)]
    fn fit(self, n: usize) -> Self {
        let cut = |p: [&'a [f32]; 3], len: usize| p.map(|q| &q[..len]);
        Self {
            mid: cut(self.mid, n + 2),
            up: cut(self.up, n),
            down: cut(self.down, n),
        }
    }
    #[inline(always)]
    fn at(&self, col: usize, s: f32, k: &SurfaceConsts) -> Texel {
        self.around(col, s, k)
    }
}

/// What one row of the surface stage reads.
#[derive(Clone, Copy)]
pub(super) struct RowIn<S> {
    pub src: S,
    pub row_sign: f32,
    pub k: SurfaceConsts,
}

/// What one row of the surface stage writes.
pub(super) struct RowOut<'a> {
    /// Level-0 roughness-scaled normal x, y, z and foam, one plane each (mip level 1 reads them).
    pub floats: [&'a mut [f32]; 4],
    /// Dx, h, Dz, J, one plane each (converted to RGBA16F, and kept when the surface keeps
    /// float copies).
    pub disp: [&'a mut [f32]; 4],
    pub rgba: &'a mut [u32],
    pub foam: &'a mut [f32],
    /// Receives the row's max |Dx|, |h|, |Dz|.
    pub max: &'a mut [f32; 3],
}

/// One texel row of stages 5-6. Every output is a plane or a plain integer array, so the loop
/// vectorizes with no shuffles. The outputs are separate arguments:
/// only those carry `noalias` (struct fields do not), and without it LLVM guards the loop with
/// pairwise overlap checks of all eleven outputs, which cost more than a 256-texel row.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn surface_row_kernel<S: Source>(
    row: RowIn<S>,
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
    // Exact-length slices let the compiler drop bounds checks and vectorize.
    let src = row.src.fit(n);
    let foam = &mut foam[..n];
    let (p0, p1, p2, p3) = (&mut p0[..n], &mut p1[..n], &mut p2[..n], &mut p3[..n]);
    let (d0, d1, d2, d3) = (&mut d0[..n], &mut d1[..n], &mut d2[..n], &mut d3[..n]);
    let k = row.k;
    // (−1)^(x+y) undoes the centred spectrum (eq. 42-43); ±1 times the row's sign is exact.
    let alternating = &ALTERNATING[..n];
    let sign = |col: usize| row.row_sign * alternating[col];
    // Maxima of |Dx|, |h|, |Dz| as the bits of non-negative floats, whose integer order is
    // their numeric order: an integer max reduction vectorizes, a float one does not.
    let mut mx = [0u32; 3];
    // A macro, not a closure: the closure was compiled apart, without the caller's target
    // features, and called per texel (9x slower).
    macro_rules! texel {
        ($col:expr, $t:expr) => {{
        let (col, t): (usize, Texel) = ($col, $t);
        let Texel {
            h,
            dx,
            dz,
            hx,
            hz,
            dxx,
            dzz,
            dxz,
            dzx,
        } = t;
        // Jacobian of the horizontal map x ↦ x + D(x) (eq. 48).
        let (jxx, jzz) = (1.0 + dxx, 1.0 + dzz);
        let j = jxx * jzz - dxz * dzx;
        // Normal of the displaced surface: ∂P/∂z × ∂P/∂x with P = x + (Dx, h, Dz); for λ = 0
        // this is eq. 47's (−∂h/∂x, 1, −∂h/∂z). Folded texels (J < 0) flip so the normal keeps
        // facing up.
        let flip = if j < 0.0 { -1.0 } else { 1.0 };
        // The normal, not yet unit: normalized by the second loop below.
        let nx = (hz * dzx - jzz * hx) * flip;
        let ny = j * flip;
        let nz = (dxz * hx - jxx * hz) * flip;
        let f = (foam[col] * k.keep + k.grow * (k.threshold - j).max(0.0)).min(1.0);
        foam[col] = f;
        (d0[col], d1[col], d2[col], d3[col]) = (dx, h, dz, j);
        (p0[col], p1[col], p2[col], p3[col]) = (nx, ny, nz, f);
        let abs_bits = |v: f32| v.to_bits() & 0x7fff_ffff;
        mx = [
            mx[0].max(abs_bits(dx)),
            mx[1].max(abs_bits(h)),
            mx[2].max(abs_bits(dz)),
        ];
        }};
    }
    for col in 0..n {
        texel!(col, src.at(col, sign(col), &k));
    }
    *max = mx.map(f32::from_bits);
    // The normalization in a loop of its own: its square root and division end a texel's
    // longest dependency chain, and in one loop with the rest the core's reorder window held
    // too few texels to hide it (the loop ran latency-bound; split, the surface stage is
    // 10-35 % faster at N = 128-256, see docs/notes/fft-128bit.md).
    normalize(p0, p1, p2, p3, rgba, &k);
}

/// Makes the row's normals `(nx, ny, nz)` unit, scales them by the roughness length and
/// packs them with the foam `f` into RGBA8. A degenerate normal (an exact fold edge) becomes
/// straight up.
#[inline(always)]
fn normalize(
    nx: &mut [f32],
    ny: &mut [f32],
    nz: &mut [f32],
    f: &[f32],
    rgba: &mut [u32],
    k: &SurfaceConsts,
) {
    let n = rgba.len();
    let (nx, ny, nz, f) = (&mut nx[..n], &mut ny[..n], &mut nz[..n], &f[..n]);
    for i in 0..n {
        let (x, y, z) = (nx[i], ny[i], nz[i]);
        let l2 = x * x + y * y + z * z;
        let ok = l2 > 1e-20;
        let inv = if ok { 1.0 / l2.sqrt() } else { 0.0 };
        let (x, y, z) = (x * inv, if ok { y * inv } else { 1.0 }, z * inv);
        (nx[i], ny[i], nz[i]) = (x * k.len, y * k.len, z * k.len);
        rgba[i] = pack::pack_rgba8(x, z, f[i], k.smooth);
    }
}

macro_rules! surface_variant {
    ($(#[$m:meta])* $name:ident, $src:ident) => {
        dispatch!(
            $(#[$m])*
            #[allow(clippy::too_many_arguments)]
            fn $name(
                row: RowIn<$src<'_>>,
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
            ) => surface_row_kernel::<$src<'_>>
        );
    };
}
surface_variant!(
    /// [`surface_row_kernel`] from spectral derivatives, behind runtime ISA dispatch.
    surface_row_spectral,
    Spectral
);
surface_variant!(
    /// [`surface_row_kernel`] by central differences, behind runtime ISA dispatch.
    surface_row_finite,
    Finite
);

/// One row's source in either derivative mode.
#[derive(Clone, Copy)]
pub(super) enum RowSource<'a> {
    Spectral(Spectral<'a>),
    Finite(Finite<'a>),
}

/// Runs one row of the surface stage.
pub(super) fn surface_row(row: RowIn<RowSource<'_>>, out: RowOut<'_>) {
    let RowOut {
        floats: [p0, p1, p2, p3],
        disp: [d0, d1, d2, d3],
        rgba,
        foam,
        max,
    } = out;
    let (row_sign, k) = (row.row_sign, row.k);
    macro_rules! run {
        ($kernel:ident, $src:expr) => {
            $kernel(
                RowIn {
                    src: $src,
                    row_sign,
                    k,
                },
                p0,
                p1,
                p2,
                p3,
                d0,
                d1,
                d2,
                d3,
                rgba,
                foam,
                max,
            )
        };
    }
    match row.src {
        RowSource::Spectral(src) => run!(surface_row_spectral, src),
        RowSource::Finite(src) => run!(surface_row_finite, src),
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
