//! Edge-stitching flags (eq. 62-65) and the 16 triangulation patterns (eq. 66, 68).

/// Which patch edges border a one-level-coarser neighbour (eq. 64): bit 0 East (+x), bit 1
/// North (+z), bit 2 West (−x), bit 3 South (−z). A stitched edge drops its odd vertices so it
/// has exactly the coarser neighbour's vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct StitchFlags(u8);

impl StitchFlags {
    /// No coarser neighbour.
    pub const NONE: Self = Self(0);
    /// East (+x) edge stitched.
    pub const EAST: Self = Self(1);
    /// North (+z) edge stitched.
    pub const NORTH: Self = Self(2);
    /// West (−x) edge stitched.
    pub const WEST: Self = Self(4);
    /// South (−z) edge stitched.
    pub const SOUTH: Self = Self(8);
    /// The four edge flags in bit order E, N, W, S (f(d) of eq. 64).
    pub const EDGES: [Self; 4] = [Self::EAST, Self::NORTH, Self::WEST, Self::SOUTH];

    /// The flags from their 4-bit value (higher bits are ignored).
    pub fn from_bits(bits: u8) -> Self {
        Self(bits & 15)
    }

    /// The 4-bit value, 0..=15: the index of the submesh to draw.
    pub fn bits(self) -> u8 {
        self.0
    }

    /// Whether every flag of `other` is set.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Union.
    pub fn with(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Triangles one patch with these flags has, of V/2 × V/2 cells (eq. 66).
    pub fn triangle_count(self, vertices: u32) -> u32 {
        let half = vertices / 2;
        8 * half * half - self.0.count_ones() * half
    }
}

/// The 3×3 cell ring in counter-clockwise order seen from above (x right, z up on the map):
/// corners and the four edge midpoints, as (vx, vy) offsets inside the cell.
const RING: [(u32, u32); 8] = [
    (0, 0),
    (1, 0),
    (2, 0),
    (2, 1),
    (2, 2),
    (1, 2),
    (0, 2),
    (0, 1),
];

/// The flag whose midpoint each ring entry is (eq. 65), or NONE for corners.
fn midpoint_edge(i: usize) -> StitchFlags {
    match i {
        1 => StitchFlags::SOUTH,
        3 => StitchFlags::EAST,
        5 => StitchFlags::NORTH,
        7 => StitchFlags::WEST,
        _ => StitchFlags::NONE,
    }
}

/// The index set of one submesh: V/2 × V/2 cells of 3×3 vertices, each a fan around its centre
/// (8 triangles), where boundary cells on a stitched edge skip that edge's midpoint (eq. 65-66).
/// Vertex (vx, vy) of cell (cx, cy) is index (2cx + vx) + (2cy + vy)(V + 1) (eq. 68). Triangles
/// face +y (counter-clockwise seen from above).
pub fn index_set(vertices: u32, flags: StitchFlags) -> Vec<u16> {
    let half = vertices / 2;
    let row = vertices + 1;
    let mut out = Vec::with_capacity(3 * flags.triangle_count(vertices) as usize);
    for cy in 0..half {
        for cx in 0..half {
            let mut cell = StitchFlags::NONE;
            if cx == 0 {
                cell = cell.with(StitchFlags::WEST);
            }
            if cx == half - 1 {
                cell = cell.with(StitchFlags::EAST);
            }
            if cy == 0 {
                cell = cell.with(StitchFlags::SOUTH);
            }
            if cy == half - 1 {
                cell = cell.with(StitchFlags::NORTH);
            }
            let cell = StitchFlags(cell.0 & flags.0);
            let idx = |(vx, vy): (u32, u32)| ((2 * cx + vx) + (2 * cy + vy) * row) as u16;
            let centre = idx((1, 1));
            let kept = (0..8).filter(|&i| {
                let e = midpoint_edge(i);
                e == StitchFlags::NONE || !cell.contains(e)
            });
            let mut first = None;
            let mut prev = None;
            for i in kept {
                let v = idx(RING[i]);
                if let Some(p) = prev {
                    out.extend_from_slice(&[centre, v, p]);
                } else {
                    first = Some(v);
                }
                prev = Some(v);
            }
            if let (Some(p), Some(f)) = (prev, first) {
                out.extend_from_slice(&[centre, f, p]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Vertices (i, j) of a patch of grid size `v` whose triangles touch the given edge line.
    fn edge_segments(v: u32, flags: StitchFlags, edge: StitchFlags) -> Vec<(u32, u32)> {
        let idx = index_set(v, flags);
        let row = v + 1;
        let on = |k: u16| {
            let (i, j) = (k as u32 % row, k as u32 / row);
            match edge {
                StitchFlags::EAST => (i == v).then_some(j),
                StitchFlags::WEST => (i == 0).then_some(j),
                StitchFlags::NORTH => (j == v).then_some(i),
                _ => (j == 0).then_some(i),
            }
        };
        let mut segs = Vec::new();
        for t in idx.chunks(3) {
            for e in 0..3 {
                if let (Some(a), Some(b)) = (on(t[e]), on(t[(e + 1) % 3])) {
                    segs.push((a.min(b), a.max(b)));
                }
            }
        }
        segs.sort_unstable();
        segs
    }

    fn opposite(e: StitchFlags) -> StitchFlags {
        StitchFlags(((e.0 << 2) | (e.0 >> 2)) & 15)
    }

    #[test]
    fn each_set_is_a_watertight_upward_cover_of_the_patch() {
        for v in [16, 32, 64] {
            for bits in 0..16 {
                let f = StitchFlags::from_bits(bits);
                let idx = index_set(v, f);
                assert_eq!(idx.len() as u32, 3 * f.triangle_count(v));
                let row = v + 1;
                let p = |k: u16| ((k as u32 % row) as f64, (k as u32 / row) as f64);
                let mut area = 0.0;
                let mut edges: HashMap<(u16, u16), i32> = HashMap::new();
                for t in idx.chunks(3) {
                    let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                    // y of (b − a) × (c − a) with (x, z) = (i, j): must be > 0 (faces +y).
                    let up = (b.1 - a.1) * (c.0 - a.0) - (b.0 - a.0) * (c.1 - a.1);
                    assert!(up > 0.0, "v={v} flags={bits}: triangle {t:?} faces down");
                    area += up / 2.0;
                    for e in 0..3 {
                        *edges.entry((t[e], t[(e + 1) % 3])).or_default() += 1;
                    }
                }
                assert_eq!(area, (v * v) as f64);
                for (&(a, b), &n) in &edges {
                    assert_eq!(n, 1);
                    if !edges.contains_key(&(b, a)) {
                        let (pa, pb) = (p(a), p(b));
                        let border = |q: (f64, f64)| {
                            q.0 == 0.0 || q.1 == 0.0 || q.0 == v as f64 || q.1 == v as f64
                        };
                        assert!(border(pa) && border(pb), "inner edge used once");
                    }
                }
            }
        }
    }

    #[test]
    fn every_set_meets_its_neighbours() {
        let v = 16;
        for bits in 0..16 {
            let f = StitchFlags::from_bits(bits);
            for e in StitchFlags::EDGES {
                let mine = edge_segments(v, f, e);
                for nb in 0..16 {
                    let nf = StitchFlags::from_bits(nb);
                    let theirs = edge_segments(v, nf, opposite(e));
                    if f.contains(e) {
                        // Neighbour one level coarser (twice the size), never stitched toward
                        // us: our edge is one half of theirs, coordinates halved.
                        if nf.contains(opposite(e)) {
                            continue;
                        }
                        for half in 0..2 {
                            let lo = half * v / 2;
                            let coarse: Vec<_> = theirs
                                .iter()
                                .filter(|s| s.0 >= lo && s.1 <= lo + v / 2)
                                .map(|s| (2 * (s.0 - lo), 2 * (s.1 - lo)))
                                .collect();
                            assert_eq!(mine, coarse, "flags {bits} edge {e:?} vs coarse {nb}");
                        }
                    } else if !nf.contains(opposite(e)) {
                        assert_eq!(mine, theirs, "flags {bits} edge {e:?} vs same-level {nb}");
                    }
                }
            }
        }
    }
}
