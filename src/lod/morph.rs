//! Geomorphing (CDLOD-style): the reference implementation of the vertex-shader formula
//! documented on [`PatchInstance`], used by the tests to prove the morph keeps the surface
//! watertight.
//!
//! A level-l vertex with an odd world lattice coordinate (in units of its spacing h) slides by
//! h·k toward the even neighbour below it, so at k = 1 a level-l patch has exactly the shape of
//! its level-(l−1) parent and the LOD switch does not pop. k rises with the distance to the
//! viewer over [`LodSettings::morph_range`](super::LodSettings::morph_range). Vertices on a
//! stitched edge are even at level l and follow the coarser neighbour's morph instead, so both
//! sides of every edge move together.

use glam::{Vec2, Vec3};

use super::batch::PatchInstance;
use super::stitch::StitchFlags;

/// k(d, r) = clamp((d − start) / (end − start), 0, 1).
pub fn morph_factor(range: [f32; 2], distance: f32) -> f32 {
    ((distance - range[0]) / (range[1] - range[0])).clamp(0.0, 1.0)
}

/// The offset subtracted from world xz `p` by the morph of a lattice of spacing `h`: h·k on
/// each axis whose lattice coordinate round(p / h) is odd.
pub fn morph_offset(p: Vec2, h: f32, k: f32) -> Vec2 {
    let odd = |c: f32| {
        if ((c / h).round() as i64).rem_euclid(2) == 1 {
            h * k
        } else {
            0.0
        }
    };
    Vec2::new(odd(p.x), odd(p.y))
}

/// The morphed world xz of unit-grid vertex (i, j) (0..=V) of a patch, exactly as the vertex
/// shader computes it (formula on [`PatchInstance`]).
pub fn patch_vertex_xz(inst: &PatchInstance, v: u32, i: u32, j: u32, camera: Vec3) -> Vec2 {
    let unit = Vec2::new(i as f32 / v as f32 - 0.5, j as f32 / v as f32 - 0.5);
    let p0 = Vec2::from(inst.centre) + inst.size * unit;
    let h = inst.size / v as f32;
    let d = Vec3::new(p0.x, 0.0, p0.y).distance(camera);
    let mut p = p0 - morph_offset(p0, h, morph_factor(inst.morph, d));
    let s = StitchFlags::from_bits(inst.stitch as u8);
    let on_stitched = (i == v && s.contains(StitchFlags::EAST))
        || (j == v && s.contains(StitchFlags::NORTH))
        || (i == 0 && s.contains(StitchFlags::WEST))
        || (j == 0 && s.contains(StitchFlags::SOUTH));
    if on_stitched {
        p -= morph_offset(p0, 2.0 * h, morph_factor(inst.coarse_morph, d));
    }
    p
}

/// The morphed world xz of skirt vertex `pos` (relative to the grid centre) with the skirt's
/// instance ([`crate::lod::OceanLod::skirt_instance`]): inner-edge vertices (`inner`) follow
/// the ring patches' stitched outer edges (`coarse_morph` on the doubled ring spacing), outer
/// corners stay put.
pub fn skirt_vertex_xz(inst: &PatchInstance, pos: [f32; 3], inner: bool, camera: Vec3) -> Vec2 {
    let p0 = Vec2::from(inst.centre) + Vec2::new(pos[0], pos[2]);
    if !inner {
        return p0;
    }
    let d = Vec3::new(p0.x, 0.0, p0.y).distance(camera);
    p0 - morph_offset(
        p0,
        2.0 * inst.vertex_spacing,
        morph_factor(inst.coarse_morph, d),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn odd_vertices_reach_even_ones_at_full_morph() {
        assert_eq!(
            morph_offset(Vec2::new(3.0, 4.0), 1.0, 1.0),
            Vec2::new(1.0, 0.0)
        );
        assert_eq!(
            morph_offset(Vec2::new(-3.0, -5.0), 1.0, 0.5),
            Vec2::splat(0.5)
        );
        assert_eq!(morph_factor([10.0, 20.0], 5.0), 0.0);
        assert_eq!(morph_factor([10.0, 20.0], 15.0), 0.5);
        assert_eq!(morph_factor([10.0, 20.0], 25.0), 1.0);
    }
}
