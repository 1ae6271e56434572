//! Quality presets (thesis Table 2) and the ocean size S with its derived quadtree constants
//! (eq. 56, 62, 69).

use crate::base::ParamError;

/// A quality preset of thesis Table 2: patch resolution V, LOD distance scale τ and cull scale β.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum QualityPreset {
    /// V = 16, τ = 2.0, β = 1.2.
    Low,
    /// V = 32, τ = 1.5, β = 1.5.
    Medium,
    /// V = 64, τ = 1.2, β = 1.8.
    High,
    /// V = 64, τ = 1.0, β = 2.0.
    Ultra,
}

impl QualityPreset {
    /// Every preset, coarsest first.
    pub const ALL: [Self; 4] = [Self::Low, Self::Medium, Self::High, Self::Ultra];

    /// Cells per patch side V (Table 2); a patch mesh has (V + 1)² vertices (eq. 67).
    pub fn vertices(self) -> u32 {
        match self {
            Self::Low => 16,
            Self::Medium => 32,
            Self::High | Self::Ultra => 64,
        }
    }

    /// LOD distance scale τ of the subdivision test (eq. 57).
    pub fn lod_scale(self) -> f32 {
        match self {
            Self::Low => 2.0,
            Self::Medium => 1.5,
            Self::High => 1.2,
            Self::Ultra => 1.0,
        }
    }

    /// Split scale K = max(τ, √2 + 10/V + 0.1): a node splits when the viewer is nearer than
    /// K·s to its square ([`LodSettings::split_distance`]). Eq. 57 compares the centre
    /// distance with τ·s; CDLOD morphing needs the closest point and a LOD band wider than a
    /// patch diagonal plus the snap margins (K > √2 + 10/V, see
    /// [`LodSettings::morph_range`]), so τ is raised to that bound where it is smaller. Every
    /// ring of levels costs ∝ K² patches; a larger K (τ + 1 was tried) drew 2-4× the triangles
    /// and made a 8192 m ocean cost 1.7-1.8× a 1024 m one on lavapipe, against ≤ 1.25×.
    pub fn split_scale(self) -> f32 {
        let v = self.vertices() as f32;
        self.lod_scale()
            .max(std::f32::consts::SQRT_2 + 10.0 / v + 0.1)
    }

    /// Cull scale β (eq. 61): here the safety factor on the displacement padding of each
    /// patch's culling box (see [`crate::lod::frustum::patch_box`]).
    pub fn cull_scale(self) -> f32 {
        match self {
            Self::Low => 1.2,
            Self::Medium => 1.5,
            Self::High => 1.8,
            Self::Ultra => 2.0,
        }
    }

    /// The next preset up, the finest wrapping round to the coarsest (the controller's preset
    /// button cycles them).
    pub fn next(self) -> Self {
        match self {
            Self::Low => Self::Medium,
            Self::Medium => Self::High,
            Self::High => Self::Ultra,
            Self::Ultra => Self::Low,
        }
    }

    /// Lower-case name, as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Low => "low",
            Self::Medium => "medium",
            Self::High => "high",
            Self::Ultra => "ultra",
        }
    }
}

/// The side S of the square the quadtree covers, in metres, validated to [256, 8192].
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct OceanSize(f32);

impl OceanSize {
    /// Smallest accepted S (m).
    pub const MIN: f32 = 256.0;
    /// Largest accepted S (m).
    pub const MAX: f32 = 8192.0;

    /// Validates S: finite and in [[`Self::MIN`], [`Self::MAX`]] metres.
    pub fn new(metres: f32) -> Result<Self, ParamError> {
        if metres.is_finite() && (Self::MIN..=Self::MAX).contains(&metres) {
            Ok(Self(metres))
        } else {
            Err(ParamError::new(
                "size",
                metres as f64,
                "an ocean size in [256, 8192] (m)",
            ))
        }
    }

    /// S in metres.
    pub fn metres(self) -> f32 {
        self.0
    }

    /// L_max = clamp(⌊log2(S / 64) + 0.5⌋, 2, 8) (eq. 56).
    pub fn max_level(self) -> u32 {
        ((self.0 / 64.0).log2() + 0.5).floor().clamp(2.0, 8.0) as u32
    }
}

/// Everything the LOD derives from a preset and a size; immutable after construction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodSettings {
    preset: QualityPreset,
    size: f32,
    max_level: u32,
    max_ring_level: u32,
}

impl LodSettings {
    /// Derives L_max (eq. 56) and the ring levels (see [`Self::max_ring_level`]).
    pub fn new(preset: QualityPreset, size: OceanSize) -> Self {
        let max_level = size.max_level();
        let v = preset.vertices() as f32;
        let k = preset.split_scale();
        // Smallest level at which no node touching the outer edge passes the split test for a
        // viewer in the snap cell: such a node's box is at least S/2 − s − δ away (δ = S/V),
        // so 2^b·(1/2 − 1/V) − 1 ≥ K in units of s_b.
        let mut ring = 2;
        while ((1u32 << ring) as f32) * (0.5 - 1.0 / v) - 1.0 < k {
            ring += 1;
        }
        Self {
            preset,
            size: size.metres(),
            max_level,
            max_ring_level: ring.min(max_level),
        }
    }

    /// The preset.
    pub fn preset(&self) -> QualityPreset {
        self.preset
    }

    /// S in metres.
    pub fn size(&self) -> f32 {
        self.size
    }

    /// V: cells per patch side.
    pub fn vertices(&self) -> u32 {
        self.preset.vertices()
    }

    /// L_max (eq. 56); the subdivision map is W = 2^L_max cells wide.
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// Width W = 2^L_max of the finest-level subdivision map.
    pub fn map_width(&self) -> u32 {
        1 << self.max_level
    }

    /// The finest level a patch touching the outer edge of the grid (the "ring") is split
    /// to: the smallest level at which the split test ([`Self::split_distance`]) never splits a
    /// ring node for a viewer in the snap cell, so capping the ring here removes no detail the
    /// distance asked for.
    ///
    /// Ring patches stay within two levels, [`Self::boundary_level`] ..= this, so that one
    /// prebuilt horizon skirt, whose inner edge has the vertex spacing of the level below the
    /// finest ring patch, meets all of them without T-junctions: the finer ring patches stitch
    /// their outer edge toward it, the coarser ones already have its spacing.
    pub fn max_ring_level(&self) -> u32 {
        self.max_ring_level
    }

    /// The coarsest level of a patch touching the outer edge of the grid: one above
    /// [`Self::max_ring_level`], and at least 2 (the grid snap keeps the morph lattices of
    /// levels ≥ 2 fixed in the world; see [`Self::snap_step`]). Ring nodes coarser than this
    /// split whatever their distance; the ring level of a frame
    /// ([`crate::lod::Quadtree::ring_level`]) is in `boundary_level..=max_level`.
    pub fn boundary_level(&self) -> u32 {
        (self.max_ring_level.saturating_sub(1))
            .max(2)
            .min(self.max_level)
    }

    /// Node size s_l = S / 2^l.
    pub fn node_size(&self, level: u32) -> f32 {
        self.size / (1u32 << level) as f32
    }

    /// Vertex spacing of a level-l patch, s_l / V.
    pub fn vertex_spacing(&self, level: u32) -> f32 {
        self.node_size(level) / self.vertices() as f32
    }

    /// Grid snap step δ = S / V (eq. 69 uses S / 2V).
    ///
    /// Twice the thesis's step, so a snap moves every lattice the geomorph reads by a multiple
    /// of 4 of its spacing from level 2 on (δ = 2^l · s_l / V): which vertices are odd, and
    /// which diagonal each coarse cell has, stay fixed in the world, so a snap alone never
    /// changes the drawn surface (see [`crate::lod::morph`]). Node lattices stay fixed too
    /// (δ is a multiple or a divisor of every s_l).
    pub fn snap_step(&self) -> f32 {
        self.size / self.vertices() as f32
    }

    /// Split distance R_l = K·s_l (m): a level-l node is subdivided when the viewer is nearer
    /// than R_l to the closest point of its square (replaces eq. 57's centre distance; see
    /// [`QualityPreset::split_scale`]).
    pub fn split_distance(&self, level: u32) -> f32 {
        self.preset.split_scale() * self.node_size(level)
    }

    /// Geomorph distance range [start, end] (m) of level l: a level-l vertex's morph factor
    /// rises from 0 at `start` to 1 at `end` ([`crate::lod::morph::morph_factor`]); h_l is the
    /// level's vertex spacing.
    ///
    /// `end` = R_(l−1) − 5·h_l: a level-l patch is replaced by its parent exactly when the
    /// viewer is R_(l−1) from the parent's square, which holds all the patch's vertices, so
    /// they are all fully morphed onto the parent's lattice then. `start` = R_l + √2·s_l + 5·h_l:
    /// a level-l patch appears (its children merge) when the viewer is R_l from its square, so
    /// no vertex of it is farther than R_l + √2·s_l and none is morphed yet. The 5·h_l margins
    /// cover a grid snap, which shifts the node lattice: a point then changes patch without
    /// any split, and the vertices of the triangles drawn over it lie within 4.5·h_l of it
    /// (one cell, or two along a stitched edge). Needs K > √2 + 10/V. Level 0 never morphs
    /// (infinite range).
    pub fn morph_range(&self, level: u32) -> [f32; 2] {
        if level == 0 {
            return [f32::MAX, f32::MAX];
        }
        let (s, h) = (self.node_size(level), 5.0 * self.vertex_spacing(level));
        [
            self.split_distance(level) + std::f32::consts::SQRT_2 * s + h,
            self.split_distance(level - 1) - h,
        ]
    }

    /// Distance from the grid centre to the outer edge of the horizon skirt (section 5.7: 10·S).
    pub fn skirt_extent(&self) -> f32 {
        10.0 * self.size
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_cycles_through_every_preset_coarsest_to_finest() {
        let mut p = QualityPreset::Low;
        let mut seen = Vec::new();
        for _ in 0..4 {
            seen.push(p);
            p = p.next();
        }
        assert_eq!(seen, QualityPreset::ALL);
        assert_eq!(p, QualityPreset::Low);
    }

    #[test]
    fn max_level_follows_eq_56() {
        let l = |s: f32| OceanSize::new(s).unwrap().max_level();
        assert_eq!(l(256.0), 2);
        assert_eq!(l(512.0), 3);
        assert_eq!(l(1000.0), 4);
        assert_eq!(l(4096.0), 6);
        assert_eq!(l(8192.0), 7);
    }

    #[test]
    fn sizes_outside_range_are_rejected() {
        for s in [0.0, 255.0, 8193.0, f32::NAN, f32::INFINITY, -300.0] {
            let e = OceanSize::new(s).unwrap_err();
            assert_eq!(e.parameter, "size");
            assert!(e.valid.contains("[256, 8192]"));
        }
    }

    #[test]
    fn boundary_level_is_within_the_tree() {
        for p in QualityPreset::ALL {
            for s in [256.0, 300.0, 1024.0, 8192.0] {
                let st = LodSettings::new(p, OceanSize::new(s).unwrap());
                assert!((2..=st.max_level()).contains(&st.boundary_level()));
                assert!((st.boundary_level()..=st.max_level()).contains(&st.max_ring_level()));
                assert!(st.max_ring_level() - st.boundary_level() <= 1);
            }
        }
    }
}
