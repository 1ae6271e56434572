//! Quadtree level of detail for the ocean surface (thesis section 5): which patches to draw,
//! at which resolution, with which stitching, as instanced draws. Pure CPU geometry: no Vulkan,
//! no XR; the renderer uploads [`OceanLod::instances`] and issues [`OceanLod::draws`] plus the
//! skirt.
//!
//! Per frame ([`OceanLod::update`]): snap the grid centre (eq. 69), select and balance the
//! quadtree ([`quadtree`], eq. 56-58, 62-64), cull each patch's displacement-padded box against
//! both eyes ([`frustum`], eq. 59-61), and batch the survivors by stitch configuration
//! ([`batch`], eq. 70). The patch mesh and its 16 index sets ([`mesh`], [`stitch`], eq. 65-68)
//! and the skirt ([`skirt`], section 5.7) are built once.
//!
//! # Snapping
//! The grid centre snaps to δ = S/V (eq. 69 uses S/2V). Every vertex lattice of level ≥ 2, with
//! its parities mod 4 (which vertices are odd, which diagonal each coarse cell has), is fixed in
//! world space as the head moves; node lattices of coarse levels do move by δ.
//!
//! # No allocation per frame
//! Map, stack, leaves, visibility and instances are sized once for the worst case (W² leaves);
//! `tests/no_alloc/lod.rs` counts allocations.

pub mod batch;
pub mod collapse;
pub mod frustum;
pub mod mesh;
pub mod morph;
pub mod preset;
pub mod quadtree;
pub mod skirt;
pub mod stitch;
pub mod svg;

use glam::{Vec2, Vec3};

use crate::base::ParamError;

pub use batch::{Batches, DrawBatch, PatchInstance};
pub use collapse::ScreenCollapse;
pub use frustum::{Frustum, MaxDisplacement, StereoFrustum};
pub use mesh::PatchMesh;
pub use preset::{LodSettings, OceanSize, QualityPreset};
pub use quadtree::{Leaf, Quadtree};
pub use skirt::SkirtMesh;
pub use stitch::StitchFlags;

/// What one frame's LOD needs.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    /// The viewer the LOD distances are measured from (usually [`StereoFrustum::centre`]).
    pub viewer: Vec3,
    /// Both eyes' frusta; `None` keeps every patch (tests, overview captures).
    pub culling: Option<&'a StereoFrustum>,
    /// Box padding: the simulation's real maximum displacement.
    pub max_displacement: MaxDisplacement,
}

/// Counts of the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Patches in the balanced quadtree.
    pub patches: u32,
    /// Patches that passed culling (= instances).
    pub visible: u32,
    /// Patch draws (≤ 16); the skirt adds one.
    pub draws: u32,
    /// Triangles drawn, patches and skirt.
    pub triangles: u32,
}

/// The LOD system: built once per preset and size, updated once per frame without allocating.
#[derive(Clone, Debug)]
pub struct OceanLod {
    settings: LodSettings,
    mesh: PatchMesh,
    skirts: Vec<SkirtMesh>,
    tree: Quadtree,
    batches: Batches,
    visible: Vec<bool>,
    grid_centre: Vec2,
    stats: FrameStats,
}

impl OceanLod {
    /// Builds the meshes (16 index sets, skirt) and the per-frame buffers for `settings`.
    pub fn new(settings: LodSettings) -> Self {
        let w = settings.map_width() as usize;
        let v = settings.vertices();
        // One skirt per possible ring level, its inner edge at the ring's stitched spacing.
        let skirts = (settings.boundary_level()..=settings.max_level())
            .map(|ring| {
                let segments = (1u32 << ring) * v / 2;
                SkirtMesh::new(settings.size(), segments, settings.skirt_extent())
            })
            .collect();
        Self {
            mesh: PatchMesh::new(v),
            skirts,
            tree: Quadtree::new(settings),
            batches: Batches::with_capacity(w * w),
            visible: Vec::with_capacity(w * w),
            grid_centre: Vec2::ZERO,
            stats: FrameStats::default(),
            settings,
        }
    }

    /// Runs one frame: snap, select, balance, stitch, cull, batch. Rejects a non-finite or
    /// out-of-range viewer with a [`ParamError`]; the previous frame's output is then cleared.
    pub fn update(&mut self, input: &FrameInput<'_>) -> Result<FrameStats, ParamError> {
        if let Err(e) = frustum::validate_viewer(input.viewer) {
            self.tree = Quadtree::new(self.settings);
            self.batches.build(std::iter::empty(), [0.0, 0.0]);
            self.stats = FrameStats::default();
            return Err(e);
        }
        let st = self.settings;
        let delta = st.snap_step();
        // Eq. 69 (with δ = S/V, see LodSettings::snap_step).
        self.grid_centre = Vec2::new(
            (input.viewer.x / delta).floor() * delta,
            (input.viewer.z / delta).floor() * delta,
        );
        let rel = input.viewer - Vec3::new(self.grid_centre.x, 0.0, self.grid_centre.y);
        self.tree.build(rel);

        let beta = st.preset().cull_scale();
        self.visible.clear();
        for leaf in self.tree.leaves() {
            let inst = patch_instance(&st, self.grid_centre, leaf);
            let keep = input.culling.is_none_or(|f| {
                let (c, e) =
                    frustum::patch_box(inst.centre, inst.size, beta, input.max_displacement);
                f.intersects_aabb(c, e)
            });
            self.visible.push(keep);
        }
        let centre = self.grid_centre;
        let patches = self
            .tree
            .leaves()
            .iter()
            .zip(self.visible.iter())
            .filter(|(_, &v)| v)
            .map(|(l, _)| patch_instance(&st, centre, l));
        self.batches
            .build(patches, [input.viewer.x, input.viewer.z]);

        let v = st.vertices();
        let triangles = self
            .batches
            .draws()
            .iter()
            .map(|d| d.instance_count * d.stitch.triangle_count(v))
            .sum::<u32>()
            + self.skirt().triangle_count();
        self.stats = FrameStats {
            patches: self.tree.leaves().len() as u32,
            visible: self.batches.instances().len() as u32,
            draws: self.batches.draws().len() as u32,
            triangles,
        };
        Ok(self.stats)
    }

    /// The instance data of a selected patch of the last frame.
    pub fn instance_of(&self, leaf: &Leaf) -> PatchInstance {
        patch_instance(&self.settings, self.grid_centre, leaf)
    }

    /// The skirt's instance: `centre` = grid centre, `size` = 1 (its positions are in metres),
    /// `level` = the ring level, all edges "stitched" with `coarse_morph` of the level below, so
    /// its inner vertices morph exactly like the ring patches' outer edges (the stitched ones
    /// at the ring level, the unstitched ones of the level below with their own morph).
    pub fn skirt_instance(&self) -> PatchInstance {
        let st = &self.settings;
        let level = self.tree.ring_level();
        PatchInstance {
            centre: self.grid_centre.to_array(),
            size: 1.0,
            level,
            morph: st.morph_range(level),
            coarse_morph: st.morph_range(level - 1),
            stitch: 15,
            vertex_spacing: st.vertex_spacing(level),
        }
    }

    /// The settings.
    pub fn settings(&self) -> &LodSettings {
        &self.settings
    }

    /// The shared patch mesh and its 16 index sets.
    pub fn mesh(&self) -> &PatchMesh {
        &self.mesh
    }

    /// The skirt mesh to draw this frame, the one matching the ring level (positions relative
    /// to [`Self::grid_centre`]). All skirts are built in [`Self::new`].
    pub fn skirt(&self) -> &SkirtMesh {
        &self.skirts[(self.tree.ring_level() - self.settings.boundary_level()) as usize]
    }

    /// The skirt for ring level `ring` (`boundary_level..=max_level`): the renderer uploads
    /// them all once and draws the one [`Self::skirt`] returns.
    ///
    /// # Panics
    /// If `ring` is outside that range.
    pub fn skirt_for_ring(&self, ring: u32) -> &SkirtMesh {
        &self.skirts[(ring - self.settings.boundary_level()) as usize]
    }

    /// The snapped grid centre (world x, z) of the last frame (eq. 69).
    pub fn grid_centre(&self) -> Vec2 {
        self.grid_centre
    }

    /// Every patch of the last frame's balanced tree, culled or not.
    pub fn leaves(&self) -> &[Leaf] {
        self.tree.leaves()
    }

    /// Whether each of [`Self::leaves`] passed culling.
    pub fn visible(&self) -> &[bool] {
        &self.visible
    }

    /// The last frame's quadtree (map queries).
    pub fn tree(&self) -> &Quadtree {
        &self.tree
    }

    /// The instance buffer to upload, grouped as [`Self::draws`] expects.
    pub fn instances(&self) -> &[PatchInstance] {
        self.batches.instances()
    }

    /// The instanced patch draws (≤ 16); draw the skirt once more.
    pub fn draws(&self) -> &[DrawBatch] {
        self.batches.draws()
    }

    /// Counts of the last frame.
    pub fn stats(&self) -> FrameStats {
        self.stats
    }
}

/// Eq. 70: a patch's centre (eq. 58 around the snapped grid centre), size and shader data.
fn patch_instance(st: &LodSettings, grid_centre: Vec2, leaf: &Leaf) -> PatchInstance {
    let level = leaf.level as u32;
    let s = st.node_size(level);
    let half = 0.5 * st.size();
    PatchInstance {
        centre: [
            grid_centre.x - half + (leaf.x as f32 + 0.5) * s,
            grid_centre.y - half + (leaf.y as f32 + 0.5) * s,
        ],
        size: s,
        level,
        morph: st.morph_range(level),
        coarse_morph: st.morph_range(level.saturating_sub(1)),
        stitch: leaf.stitch.bits() as u32,
        vertex_spacing: st.vertex_spacing(level),
    }
}
