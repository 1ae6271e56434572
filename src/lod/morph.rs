//! Geomorphing (CDLOD-style): the reference implementation of the vertex-shader formula
//! documented on [`PatchInstance`], used by the tests to prove the morph keeps the surface
//! watertight and free of pops.
//!
//! Each odd vertex of a level-l patch (odd grid index, spacing h) slides by h·k onto a vertex
//! of the level-(l−1) lattice ([`morph_step`]), k rising with the vertex's distance to the
//! viewer over [`LodSettings::morph_range`](super::LodSettings::morph_range). At k = 1 the
//! patch's triangles collapse exactly onto its parent's triangles (the fan diagonals included),
//! each vertex carrying a parent vertex's position, so the surface, displacement sampled at the
//! morphed positions, is the parent's; and k is 1 wherever the quadtree may swap a patch for
//! its parent, 0 wherever it may swap a parent for its children, so the swap does not pop.
//! Vertices on a stitched edge follow the coarser neighbour's own morph as well, so both sides
//! of every edge move together. Beyond both, the collapse by the screen
//! ([`ScreenCollapse`]) may walk a vertex on up the coarser lattices ([`chain_offset`]): each
//! step is a function of the lattice point and its distance alone, so it too keeps every
//! shared vertex shared.
//!
//! The morph range of level l is [R_l + √2·s_l + 5h_l, R_(l−1) − 5h_l]: k = 1 on every vertex of
//! a patch whenever it can be swapped for its parent, k = 0 on every vertex of a parent whenever
//! it can be swapped for its children, also when a snap moves the node lattice under a fixed
//! point. `tests/lod/geomorph.rs` walks viewers across split boundaries and snaps in 1-5 cm
//! steps and bounds the rendered height change at fixed points by the morph's own motion. Not
//! covered: the last two cells next to the grid's outer edge (which moves with the snap and
//! changes its skirt stitching with the ring level), and heights where the ring rule forces
//! splits the distance test did not ask for (viewers a sizeable fraction of S above the water).

use glam::{IVec2, Vec2, Vec3};

use super::batch::PatchInstance;
use super::collapse::ScreenCollapse;

/// k(d, r) = clamp((d − start) / (end − start), 0, 1).
pub fn morph_factor(range: [f32; 2], distance: f32) -> f32 {
    ((distance - range[0]) / (range[1] - range[0])).clamp(0.0, 1.0)
}

/// Where lattice vertex (i, j) goes at full morph, in units of the spacing: (0, 0) when both
/// are even (it is a coarse vertex); −1 along an odd axis when the other is even (onto the
/// lower end of the coarse edge it halves); and when both are odd (the centre of a coarse
/// square), along that square's diagonal in the coarse fan triangulation of eq. 65-66:
/// (−1, −1) when (i + j) mod 4 = 2, (−1, +1) when (i + j) mod 4 = 0.
///
/// (i, j) count from the grid corner (or centre: same parities), which is how the patch grid
/// indices count; negative values (the skirt) use Euclidean parity, as `& 1`, `& 3` do.
pub fn morph_step(i: i32, j: i32) -> IVec2 {
    match (i & 1, j & 1) {
        (0, 0) => IVec2::ZERO,
        (1, 0) => IVec2::new(-1, 0),
        (0, _) => IVec2::new(0, -1),
        _ if (i + j) & 3 == 2 => IVec2::new(-1, -1),
        _ => IVec2::new(-1, 1),
    }
}

/// The morph chain's offset (m) of vertex `idx` of the level-`level` lattice of spacing
/// `spacing` at `distance` (`morph_chain` in `shaders/ocean.vert`, the formula on
/// [`PatchInstance`]): the vertex slides toward the next coarser lattice's vertex by k₀, the
/// larger of the CDLOD factor of range `first` and the screen's collapse, that vertex toward
/// the next by k₁ (`second` or the screen's), and on by the screen's alone, for at most
/// [`ScreenCollapse::CHAIN_STEPS`] lattices.
pub fn chain_offset(
    idx: IVec2,
    spacing: f32,
    level: u32,
    distance: f32,
    cdlod: [[f32; 2]; 2],
    collapse: &ScreenCollapse,
) -> Vec2 {
    let factor = |r: [f32; 2]| {
        if r[1] > r[0] {
            morph_factor(r, distance)
        } else {
            0.0
        }
    };
    let (mut idx, mut hh, mut offset) = (idx, spacing, Vec2::ZERO);
    for n in 0..ScreenCollapse::CHAIN_STEPS {
        let screen = level
            .checked_sub(n)
            .map_or(0.0, |l| collapse.factor(hh, distance, l));
        let own = cdlod.get(n as usize).map_or(0.0, |&r| factor(r));
        let step = morph_step(idx.x, idx.y);
        offset += hh * screen.max(own) * step.as_vec2();
        idx = (idx + step) >> 1;
        hh *= 2.0;
    }
    offset
}

/// The morphed world xz of unit-grid vertex (i, j) (0..=V) of a patch, exactly as the vertex
/// shader computes it (formula on [`PatchInstance`]), for a viewer at `camera` and the frame's
/// `collapse`.
pub fn patch_vertex_xz(
    inst: &PatchInstance,
    v: u32,
    (i, j): (u32, u32),
    camera: Vec3,
    collapse: &ScreenCollapse,
) -> Vec2 {
    let unit = Vec2::new(i as f32 / v as f32 - 0.5, j as f32 / v as f32 - 0.5);
    let p0 = Vec2::from(inst.centre) + inst.size * unit;
    let h = inst.size / v as f32;
    let d = Vec3::new(p0.x, 0.0, p0.y).distance(camera);
    let idx = IVec2::new(i as i32, j as i32);
    p0 + chain_offset(
        idx,
        h,
        inst.level,
        d,
        [inst.morph, inst.coarse_morph],
        collapse,
    )
}

/// The morphed world xz of skirt vertex `pos` (relative to the grid centre) with the skirt's
/// instance ([`crate::lod::OceanLod::skirt_instance`]): inner-edge vertices (`inner`) follow
/// the ring patches' outer edges (their chain from its second lattice: spacing H = 2 ×
/// `vertex_spacing`, lattice index round(pos.xz / H), `coarse_morph`), outer corners stay put.
pub fn skirt_vertex_xz(
    inst: &PatchInstance,
    pos: [f32; 3],
    inner: bool,
    camera: Vec3,
    collapse: &ScreenCollapse,
) -> Vec2 {
    let p0 = Vec2::from(inst.centre) + Vec2::new(pos[0], pos[2]);
    if !inner {
        return p0;
    }
    let d = Vec3::new(p0.x, 0.0, p0.y).distance(camera);
    let hh = 2.0 * inst.vertex_spacing;
    let idx = IVec2::new((pos[0] / hh).round() as i32, (pos[2] / hh).round() as i32);
    let level = inst.level.saturating_sub(1);
    p0 + chain_offset(idx, hh, level, d, [inst.coarse_morph, [0.0; 2]], collapse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::stitch::{index_set, StitchFlags};

    #[test]
    fn steps_and_factors() {
        assert_eq!(morph_step(4, 6), IVec2::ZERO);
        assert_eq!(morph_step(3, 4), IVec2::new(-1, 0));
        assert_eq!(morph_step(-2, -5), IVec2::new(0, -1));
        assert_eq!(morph_step(1, 1), IVec2::new(-1, -1));
        assert_eq!(morph_step(3, 1), IVec2::new(-1, 1));
        assert_eq!(morph_step(-1, -1), IVec2::new(-1, -1));
        assert_eq!(morph_step(-1, 1), IVec2::new(-1, 1));
        assert_eq!(morph_factor([10.0, 20.0], 5.0), 0.0);
        assert_eq!(morph_factor([10.0, 20.0], 15.0), 0.5);
        assert_eq!(morph_factor([10.0, 20.0], 25.0), 1.0);
    }

    /// Every triangle of every index set, at full morph, is either degenerate or one of the
    /// triangles of the parent's mesh (2× spacing, `index_set(V, NONE)` over a 2×2 block of
    /// children), and together they cover the same area once: the collapsed patch is the
    /// parent's mesh.
    #[test]
    fn full_morph_collapses_onto_the_parent_triangles() {
        let v = 16u32;
        let row = v + 1;
        // The parent's triangles, in child lattice units.
        let mut parent: Vec<[(i32, i32); 3]> = index_set(v, StitchFlags::NONE)
            .chunks(3)
            .map(|t| {
                let q = |k: u16| (2 * (k as u32 % row) as i32, 2 * (k as u32 / row) as i32);
                let mut t = [q(t[0]), q(t[1]), q(t[2])];
                let m = t.iter().enumerate().min_by_key(|(_, p)| **p).unwrap().0;
                t.rotate_left(m);
                t
            })
            .collect();
        parent.sort_unstable();
        let children = [(0, 0), (v as i32, 0), (0, v as i32), (v as i32, v as i32)];
        for ((ox, oy), bits) in children
            .into_iter()
            .flat_map(|c| (0..16).map(move |b| (c, b)))
        {
            let mut area = 0i64;
            for t in index_set(v, StitchFlags::from_bits(bits)).chunks(3) {
                let q = |k: u16| {
                    let (i, j) = ((k as u32 % row) as i32 + ox, (k as u32 / row) as i32 + oy);
                    let s = morph_step(i, j);
                    (i + s.x, j + s.y)
                };
                let mut c = [q(t[0]), q(t[1]), q(t[2])];
                // y of (b − a) × (c − a), > 0 for the +y facing triangles of eq. 66.
                let a = (c[1].1 - c[0].1) as i64 * (c[2].0 - c[0].0) as i64
                    - (c[1].0 - c[0].0) as i64 * (c[2].1 - c[0].1) as i64;
                assert!(a >= 0, "flags {bits}: collapsed triangle {c:?} flipped");
                if a == 0 {
                    continue;
                }
                area += a;
                let m = c.iter().enumerate().min_by_key(|(_, p)| **p).unwrap().0;
                c.rotate_left(m);
                assert!(
                    parent.binary_search(&c).is_ok(),
                    "flags {bits}: collapsed triangle {c:?} is not a parent triangle"
                );
            }
            assert_eq!(area, 2 * (v * v) as i64, "flags {bits}");
        }
    }
}
