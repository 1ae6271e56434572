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

/// The mean height over a disc of `radius` (m) about (x, z): the centre and six points on
/// its rim, each weighted by the area nearest it (a quarter, and an eighth each). A floating
/// body's buoyancy averages the water over its footprint the same way: waves shorter than it
/// hardly move it.
pub fn footprint_height(cascades: &[CascadeSurface], x: f32, z: f32, radius: f32) -> f32 {
    let mut sum = 0.25 * height_at(cascades, x, z);
    for k in 0..6 {
        let a = k as f32 * std::f32::consts::FRAC_PI_3;
        sum += 0.125 * height_at(cascades, x + radius * a.cos(), z + radius * a.sin());
    }
    sum
}

/// [`height_at`] for many points [x, z], lazily and without allocating.
pub fn heights_at<'a>(
    cascades: &'a [CascadeSurface],
    points: &'a [[f32; 2]],
) -> impl Iterator<Item = f32> + 'a {
    points.iter().map(|p| height_at(cascades, p[0], p[1]))
}

/// Which side of the displaced surface a point is on (issue 45: the renderer draws each pixel
/// from the side its point on the near plane is on; the float mode and the sound change with
/// the head's side).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// In the air.
    Above,
    /// In the water.
    Below,
}

/// How far (m) point `p` = [x, y, z] is below the displaced surface (negative above it).
pub fn depth_at(cascades: &[CascadeSurface], p: [f32; 3]) -> f32 {
    height_at(cascades, p[0], p[2]) - p[1]
}

/// The side of the surface every one of `points` is on by more than `margin` (m), or `None`
/// when they straddle it or come within `margin` of it: the near plane's corners and centre
/// of an eye, for the renderer, which decides per pixel only when the surface may cross the
/// near plane (what the cascades do not hold, the interaction layer's rings and the mesh's
/// interpolation, is what `margin` covers).
pub fn side_of_all(cascades: &[CascadeSurface], points: &[[f32; 3]], margin: f32) -> Option<Side> {
    let mut side = None;
    for &p in points {
        let depth = depth_at(cascades, p);
        let this = if depth > margin {
            Side::Below
        } else if depth < -margin {
            Side::Above
        } else {
            return None;
        };
        if side.is_some_and(|s| s != this) {
            return None;
        }
        side = Some(this);
    }
    side
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::grid::GridSize;
    use crate::sim::surface::FloatCopies;

    /// One 16-texel cascade of patch 16 m whose height rises along x: h = 0.1·(x mod 16) − 0.5
    /// at the texels (a ramp, so the answer depends on where the point is).
    fn ramp() -> Vec<CascadeSurface> {
        let grid = GridSize::new(16).unwrap();
        let mut c = CascadeSurface::new(grid, 16.0, FloatCopies::Keep);
        for (i, d) in c.displacement.iter_mut().enumerate() {
            d[1] = 0.1 * (i % 16) as f32 - 0.5;
        }
        vec![c]
    }

    #[test]
    fn the_footprint_averages_the_ramp_and_sees_a_level_sea_as_is() {
        let c = ramp();
        // On the ramp (linear between texels) the rim's points average to the centre's height.
        let centre = height_at(&c, 5.0, 2.0);
        assert!((footprint_height(&c, 5.0, 2.0, 0.5) - centre).abs() < 1e-5);
        let flat = vec![CascadeSurface::new(
            GridSize::new(16).unwrap(),
            16.0,
            FloatCopies::Keep,
        )];
        assert_eq!(footprint_height(&flat, 3.0, -7.0, 0.5), 0.0);
    }

    #[test]
    fn depth_is_measured_from_the_displaced_height() {
        let c = ramp();
        // At x = 5 the surface is at 0.0: 0.3 m under it is 0.3 deep, 0.2 m over it -0.2.
        assert!((depth_at(&c, [5.0, -0.3, 2.0]) - 0.3).abs() < 1e-5);
        assert!((depth_at(&c, [5.0, 0.2, 2.0]) + 0.2).abs() < 1e-5);
    }

    #[test]
    fn points_on_one_side_beyond_the_margin_agree_and_others_straddle() {
        let c = ramp();
        let under = [[2.0, -0.5, 0.0], [3.0, -0.5, 0.0]];
        assert_eq!(side_of_all(&c, &under, 0.1), Some(Side::Below));
        let over = [[2.0, 0.5, 0.0], [3.0, 0.5, 0.0]];
        assert_eq!(side_of_all(&c, &over, 0.1), Some(Side::Above));
        // The same height y = 0 is above the water at x = 2 (h = -0.3), below at x = 8 (0.3).
        let across = [[2.0, 0.0, 0.0], [8.0, 0.0, 0.0]];
        assert_eq!(side_of_all(&c, &across, 0.1), None);
        // Within the margin of the surface counts as straddling.
        assert_eq!(side_of_all(&c, &[[5.0, 0.05, 0.0]], 0.1), None);
    }
}
