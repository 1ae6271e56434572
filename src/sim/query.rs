//! Height queries on the displaced surface, for buoyancy and placing things on the water.
//!
//! A texel at rest position p moves to p + D(p) (choppy waves, eq. 44), so the water height at a
//! world point q is h(p*) where p* solves p* + D_xz(p*) = q. The fixed-point iteration
//! p ← q − D_xz(p) converges wherever the surface is not folded (|∂D/∂x| < 1).

use half::f16;

use crate::sim::surface::CascadeSurface;

/// Fixed-point iterations stop when the horizontal residual is below this (m).
const TOLERANCE: f32 = 1e-4;
/// Upper bound on fixed-point iterations (near breaking crests convergence slows down).
const MAX_ITERATIONS: usize = 32;

/// Bilinearly interpolated (Dx, h, Dz) of one cascade at rest position (x, z), wrapping with
/// the patch.
#[inline]
fn sample(c: &CascadeSurface, x: f32, z: f32) -> [f32; 3] {
    let n = c.grid.n();
    let scale = n as f32 / c.patch;
    let (u, v) = (x * scale, z * scale);
    let (fu, fv) = (u.floor(), v.floor());
    let (tu, tv) = (u - fu, v - fv);
    let mask = n as i64 - 1;
    let (c0, r0) = (fu as i64 & mask, fv as i64 & mask);
    let (c1, r1) = ((c0 + 1) & mask, (r0 + 1) & mask);
    // Full precision when the surface keeps it, else the RGBA16F copy (≈ 1 mm steps for
    // waves of a few metres).
    let t = |col: i64, row: i64| -> [f32; 4] {
        let i = row as usize * n + col as usize;
        match c.displacement.get(i) {
            Some(&d) => d,
            None => c.displacement_f16[i].map(f16::to_f32),
        }
    };
    let (a, b, e, f) = (t(c0, r0), t(c1, r0), t(c0, r1), t(c1, r1));
    let mut out = [0.0; 3];
    for k in 0..3 {
        let top = a[k] + (b[k] - a[k]) * tu;
        let bottom = e[k] + (f[k] - e[k]) * tu;
        out[k] = top + (bottom - top) * tv;
    }
    out
}

/// Sum of all cascades' (Dx, h, Dz) at rest position (x, z).
#[inline]
pub fn displacement_at(cascades: &[CascadeSurface], x: f32, z: f32) -> [f32; 3] {
    cascades.iter().fold([0.0; 3], |acc, c| {
        let d = sample(c, x, z);
        [acc[0] + d[0], acc[1] + d[1], acc[2] + d[2]]
    })
}

/// The rest position p* with p* + D_xz(p*) = (x, z): where the water now at (x, z) came from.
pub fn rest_position(cascades: &[CascadeSurface], x: f32, z: f32) -> (f32, f32) {
    let (mut px, mut pz) = (x, z);
    for _ in 0..MAX_ITERATIONS {
        let d = displacement_at(cascades, px, pz);
        let (nx, nz) = (x - d[0], z - d[2]);
        let step = (nx - px).abs().max((nz - pz).abs());
        (px, pz) = (nx, nz);
        if step < TOLERANCE {
            break;
        }
    }
    (px, pz)
}

/// Water surface height (m) at world point (x, z) of the displaced surface.
pub fn height_at(cascades: &[CascadeSurface], x: f32, z: f32) -> f32 {
    let (px, pz) = rest_position(cascades, x, z);
    displacement_at(cascades, px, pz)[1]
}

/// [`height_at`] for many points [x, z], lazily and without allocating.
pub fn heights_at<'a>(
    cascades: &'a [CascadeSurface],
    points: &'a [[f32; 2]],
) -> impl Iterator<Item = f32> + 'a {
    points.iter().map(|p| height_at(cascades, p[0], p[1]))
}
