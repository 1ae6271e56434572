//! The quadtree selection: explicit-stack traversal with a squared-distance test (eq. 57-58,
//! measured to the node's square rather than its centre), the finest-level subdivision map,
//! 2:1 balancing and the stitch flags (eq. 62-64).
//!
//! # Restricted quadtree
//! After balancing, edge neighbours differ by at most one level, so each stitched edge (eq. 64:
//! neighbour coarser) meets a neighbour exactly one level coarser and the stitched pattern's
//! vertices are exactly the neighbour's. Balancing only splits. A node splits when the viewer
//! is nearer than R_l = K·s_l to its square; with K > √2 that alone gives a restricted tree, so
//! balancing only acts where the ring rule forced a split.
//!
//! # The ring and the skirt
//! Patches touching the grid edge are split by the same distance test but kept within
//! [boundary level, max ring level] (the latter the one the distance test never splits a ring
//! node at, the former one coarser; below-range ring nodes split, and balancing can refine the
//! whole ring further). The skirt for ring level r has its inner vertices at level r−1's
//! spacing: ring patches at r stitch their outer edge to it, those at r−1 already match it.
//! `tests/lod/watertight.rs` checks the drawn surface is closed (every inner edge used once in
//! each direction, all triangles facing +y) for hundreds of viewers.

use glam::Vec3;

use super::preset::LodSettings;
use super::stitch::StitchFlags;

/// One selected patch: node (x, y) of `level`, covering map cells
/// [x·Δ, (x+1)·Δ) × [y·Δ, (y+1)·Δ) with Δ = 2^(L_max − level) (eq. 62).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leaf {
    /// Node column at its level (x grows with world x).
    pub x: u16,
    /// Node row at its level (y grows with world z).
    pub y: u16,
    /// Level l: the node's size is S / 2^l.
    pub level: u8,
    /// Edges bordering a one-level-coarser neighbour, or the skirt for ring patches (eq. 64).
    pub stitch: StitchFlags,
}

/// A node descriptor on the traversal stack (section 5.2). The thesis carries a `HasRendered`
/// flag down to the finest level so leaf-level nodes can write the map; here a node that stops
/// subdividing writes its whole map block at once, which is what that descent computes, so the
/// flag is implicit: no descendant of an emitted node is ever pushed.
#[derive(Clone, Copy, Debug)]
struct Node {
    x: u16,
    y: u16,
    level: u8,
}

/// The per-frame selection with every buffer owned and reused: the W × W map, the stack and the
/// leaves (capacity W², the most leaves a tree over W² cells can have), so building a frame
/// never allocates.
#[derive(Clone, Debug)]
pub struct Quadtree {
    settings: LodSettings,
    map: Vec<u8>,
    stack: Vec<Node>,
    leaves: Vec<Leaf>,
    ring_level: u8,
}

impl Quadtree {
    /// Buffers for `settings`.
    pub fn new(settings: LodSettings) -> Self {
        let w = settings.map_width() as usize;
        Self {
            settings,
            map: vec![0; w * w],
            stack: Vec::with_capacity(3 * settings.max_level() as usize + 4),
            leaves: Vec::with_capacity(w * w),
            ring_level: settings.boundary_level() as u8,
        }
    }

    /// Selects the patches for a viewer at `viewer_rel`, relative to the grid centre (the grid
    /// spans [−S/2, S/2]² around it; y is the height above the water plane).
    ///
    /// 1. Traversal (eq. 57-58 with the closest point): a node subdivides when
    ///    |q − p|² < R_l², q the point of its square nearest the viewer p and
    ///    R_l = [`LodSettings::split_distance`]. Nodes touching the outer edge (the ring) use
    ///    the same test but always split down to [`LodSettings::boundary_level`] and never
    ///    below [`LodSettings::max_ring_level`].
    /// 2. Balance: any leaf with an edge neighbour more than one level finer splits, until the
    ///    tree is restricted (2:1), so every stitched edge meets a neighbour exactly one level
    ///    coarser, as the patterns of eq. 66 require. With K > √2 the distance test alone
    ///    gives a restricted tree (a node next to a split node of the next finer level is at
    ///    most R_l + √2·s_l < R_(l−1) away), so this only acts where the ring rule forced a
    ///    split. Ring leaves stay within two levels ([`Self::ring_level`] and the next coarser one),
    ///    splitting coarser ones if balancing refined the ring.
    /// 3. Stitch flags from the map (eq. 63-64); the skirt outside the map counts as one level
    ///    coarser than [`Self::ring_level`].
    pub fn build(&mut self, viewer_rel: Vec3) {
        self.traverse(viewer_rel);
        self.balance();
        self.flag_stitches();
    }

    /// The finest level of a patch touching the outer edge in the last [`Self::build`]; every
    /// such patch is at this level or the one above. At most [`LodSettings::max_ring_level`]
    /// unless balancing rippled out to the ring.
    pub fn ring_level(&self) -> u32 {
        self.ring_level as u32
    }

    /// The selected patches of the last [`Self::build`], in traversal order (then splits).
    pub fn leaves(&self) -> &[Leaf] {
        &self.leaves
    }

    /// The level of finest-map cell (gx, gy), or `None` outside the map.
    pub fn level_at(&self, gx: i32, gy: i32) -> Option<u8> {
        let w = self.settings.map_width() as i32;
        ((0..w).contains(&gx) && (0..w).contains(&gy)).then(|| self.map[(gy * w + gx) as usize])
    }

    /// Whether node (x, y) at `level` touches the outer edge of the grid.
    fn on_ring(x: u16, y: u16, level: u8) -> bool {
        let last = (1u32 << level) - 1;
        x == 0 || y == 0 || x as u32 == last || y as u32 == last
    }

    fn traverse(&mut self, p: Vec3) {
        let st = self.settings;
        let size = st.size();
        let (l_max, ring_min, ring_max) = (
            st.max_level() as u8,
            st.boundary_level() as u8,
            st.max_ring_level() as u8,
        );
        self.ring_level = ring_min;
        self.leaves.clear();
        self.stack.clear();
        self.stack.push(Node {
            x: 0,
            y: 0,
            level: 0,
        });
        while let Some(n) = self.stack.pop() {
            let s = st.node_size(n.level as u32);
            let near = || {
                // Eq. 58: the node's square relative to the grid centre; the squared distance
                // from the viewer to its closest point against R_l² (eq. 57).
                let lo_x = -0.5 * size + n.x as f32 * s;
                let lo_z = -0.5 * size + n.y as f32 * s;
                let dx = (lo_x - p.x).max(p.x - (lo_x + s)).max(0.0);
                let dz = (lo_z - p.z).max(p.z - (lo_z + s)).max(0.0);
                let r = st.split_distance(n.level as u32);
                dx * dx + dz * dz + p.y * p.y < r * r
            };
            let subdivide = n.level < l_max
                && if Self::on_ring(n.x, n.y, n.level) {
                    n.level < ring_min || (n.level < ring_max && near())
                } else {
                    near()
                };
            if subdivide {
                let (x, y, level) = (2 * n.x, 2 * n.y, n.level + 1);
                // Reverse order, so the lower-left child is processed first.
                for (dx, dy) in [(1, 1), (0, 1), (1, 0), (0, 0)] {
                    self.stack.push(Node {
                        x: x + dx,
                        y: y + dy,
                        level,
                    });
                }
            } else {
                if Self::on_ring(n.x, n.y, n.level) {
                    self.ring_level = self.ring_level.max(n.level);
                }
                self.emit(n.x, n.y, n.level);
            }
        }
    }

    fn emit(&mut self, x: u16, y: u16, level: u8) {
        self.leaves.push(Leaf {
            x,
            y,
            level,
            stitch: StitchFlags::NONE,
        });
        self.fill(x, y, level);
    }

    /// Writes `level` into the node's block of the map.
    fn fill(&mut self, x: u16, y: u16, level: u8) {
        let w = self.settings.map_width() as usize;
        let b = 1usize << (self.settings.max_level() as u8 - level);
        let (x0, y0) = (x as usize * b, y as usize * b);
        for row in self.map[y0 * w..(y0 + b) * w].chunks_exact_mut(w) {
            row[x0..x0 + b].fill(level);
        }
    }

    /// The finest level among the cells just outside the node's four edges.
    fn finest_edge_neighbour(&self, x: u16, y: u16, level: u8) -> u8 {
        let w = self.settings.map_width() as usize;
        let b = 1usize << (self.settings.max_level() as u8 - level);
        let (x0, y0) = (x as usize * b, y as usize * b);
        let mut m = 0;
        if y0 > 0 {
            m = self.map[(y0 - 1) * w + x0..(y0 - 1) * w + x0 + b]
                .iter()
                .fold(m, |a, &v| a.max(v));
        }
        if y0 + b < w {
            m = self.map[(y0 + b) * w + x0..(y0 + b) * w + x0 + b]
                .iter()
                .fold(m, |a, &v| a.max(v));
        }
        for r in y0..y0 + b {
            if x0 > 0 {
                m = m.max(self.map[r * w + x0 - 1]);
            }
            if x0 + b < w {
                m = m.max(self.map[r * w + x0 + b]);
            }
        }
        m
    }

    /// Splits leaves until no edge neighbour is more than one level finer (restricted quadtree)
    /// and every ring leaf is at the ring level or the one above. Splitting only refines, so
    /// it terminates; a pass that splits nothing ends it.
    fn balance(&mut self) {
        let l_max = self.settings.max_level() as u8;
        loop {
            let mut split = false;
            let mut i = 0;
            while i < self.leaves.len() {
                let Leaf { x, y, level, .. } = self.leaves[i];
                let ring = Self::on_ring(x, y, level);
                if ring && level > self.ring_level {
                    self.ring_level = level;
                    split = true;
                }
                if level < l_max
                    && ((ring && level + 1 < self.ring_level)
                        || self.finest_edge_neighbour(x, y, level) > level + 1)
                {
                    let (cx, cy, cl) = (2 * x, 2 * y, level + 1);
                    self.leaves[i] = Leaf {
                        x: cx,
                        y: cy,
                        level: cl,
                        stitch: StitchFlags::NONE,
                    };
                    for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                        self.leaves.push(Leaf {
                            x: cx + dx,
                            y: cy + dy,
                            level: cl,
                            stitch: StitchFlags::NONE,
                        });
                    }
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        self.fill(cx + dx, cy + dy, cl);
                    }
                    split = true;
                    // Re-examine the first child at index i.
                    continue;
                }
                i += 1;
            }
            if !split {
                break;
            }
        }
    }

    /// Eq. 62-64: neighbour levels read from the map at the stride of the patch's level.
    fn flag_stitches(&mut self) {
        let l_max = self.settings.max_level() as u8;
        for i in 0..self.leaves.len() {
            let Leaf { x, y, level, .. } = self.leaves[i];
            let d = 1i32 << (l_max - level);
            let (gx, gy) = (x as i32 * d, y as i32 * d);
            let mut flags = StitchFlags::NONE;
            for (edge, nx, ny) in [
                (StitchFlags::EAST, gx + d, gy),
                (StitchFlags::NORTH, gx, gy + d),
                (StitchFlags::WEST, gx - 1, gy),
                (StitchFlags::SOUTH, gx, gy - 1),
            ] {
                // Outside the map is the skirt, built one level coarser than the finest ring
                // patches.
                let coarser = self
                    .level_at(nx, ny)
                    .map_or(level == self.ring_level, |l| l < level);
                if coarser {
                    flags = flags.with(edge);
                }
            }
            self.leaves[i].stitch = flags;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::preset::{OceanSize, QualityPreset};

    fn check_balanced(t: &Quadtree, l_max: u8) {
        for leaf in t.leaves() {
            let n = t.finest_edge_neighbour(leaf.x, leaf.y, leaf.level);
            assert!(n <= leaf.level + 1, "{leaf:?} has a neighbour at level {n}");
        }
        // Leaves tile the map exactly once.
        let w = 1usize << l_max;
        let area: usize = t
            .leaves()
            .iter()
            .map(|l| 1usize << (2 * (l_max - l.level)))
            .sum();
        assert_eq!(area, w * w);
    }

    #[test]
    fn trees_are_restricted_and_the_ring_spans_two_levels() {
        for p in QualityPreset::ALL {
            for s in [256.0, 700.0, 8192.0] {
                let st = LodSettings::new(p, OceanSize::new(s).unwrap());
                let mut t = Quadtree::new(st);
                for (i, h) in [0.0, 1.7, 30.0, 400.0, 5000.0].into_iter().enumerate() {
                    let off = st.snap_step() * (i as f32 * 0.23);
                    t.build(Vec3::new(off, h, off * 0.5));
                    check_balanced(&t, st.max_level() as u8);
                    for l in t.leaves() {
                        if Quadtree::on_ring(l.x, l.y, l.level) {
                            let r = t.ring_level();
                            assert!(
                                (r - 1..=r).contains(&(l.level as u32)),
                                "{p:?} S={s}: ring leaf {l:?}, ring level {r}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn balance_splits_a_coarse_leaf_next_to_a_fine_cluster() {
        // Low at S = 8192, viewer on the water: τ = 2 gives deep refinement near the centre;
        // whatever eq. 57 gives, the balanced tree must be 2:1 and the leaf count grows only.
        let st = LodSettings::new(QualityPreset::Low, OceanSize::new(8192.0).unwrap());
        let mut t = Quadtree::new(st);
        t.traverse(Vec3::new(37.0, 0.0, -11.0));
        let before = t.leaves().len();
        t.balance();
        assert!(t.leaves().len() >= before);
        check_balanced(&t, st.max_level() as u8);
    }
}
