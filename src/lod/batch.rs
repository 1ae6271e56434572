//! Instance data and batching (section 5.6): the visible patches sorted by stitch configuration,
//! one instanced draw per configuration that has instances.

use bytemuck::{Pod, Zeroable};

use super::stitch::StitchFlags;

/// Per-patch instance data, 40 bytes, read by the patch vertex shader (eq. 70: the patch is the
/// unit grid scaled by `size` and moved to `centre`; no rotation).
///
/// The vertex shader computes, for grid vertex (i, j) ∈ {0..V}² (gl_VertexIndex = i + j·(V+1),
/// unit position (u, v) = (i/V − 0.5, j/V − 0.5), eq. 67-68) and h = `size` / V:
///
/// ```text
/// p₀  = centre + size · (u, v)                      // world xz, undisplaced
/// d   = length(vec3(p₀.x, 0, p₀.y) − camera)        // camera: the viewer the LOD used
/// p   = p₀ + chain((i, j), h, level, d, morph, coarse_morph)
/// chain(q, h, l, d, r₀, r₁) = Σ_{n=0..2} 2ⁿh · kₙ · step(qₙ)   // q₀ = q, qₙ₊₁ = (qₙ + step(qₙ)) >> 1
/// kₙ = max(screen(2ⁿh, d, l − n), k(d, r₀) if n = 0, k(d, r₁) if n = 1)
/// k(d, r)    = clamp((d − r.x) / (r.y − r.x), 0, 1), 0 for an empty range
/// step(i, j) = (0, 0)   if i, j even
///              (−1, 0)  if i odd, j even
///              (−1, −1) if i, j odd and (i + j) & 3 == 2
///              (0, −1)  if i even, j odd
///              (−1, +1) if i, j odd and (i + j) & 3 == 0
/// ```
///
/// then samples the ocean displacement at p. Odd vertices slide onto the parent's lattice by
/// the patch's own morph (n = 0); the vertices of an edge stitched to a coarser neighbour (the
/// even ones the index set keeps) follow that neighbour's morph (n = 1; elsewhere in the patch
/// k(d, coarse_morph) is 0); and the collapse by the screen ([`crate::lod::ScreenCollapse`])
/// may take any lattice on toward the next. The grid indices have the parities of the world
/// lattice (the grid origin snaps to S/V), so both patches on either side of every edge move
/// every shared vertex identically and the morph never opens a crack; at k = 1 each triangle
/// collapses onto one of the parent patch's triangles (step follows the parent's fan
/// diagonals), and the quadtree swaps a patch for its parent only where k = 1, so LOD changes
/// do not pop ([`crate::lod::morph`] is the reference implementation the tests run).
///
/// The skirt (its instance has `size` = 1, positions in metres relative to `centre`) moves
/// only its inner-edge vertices (gl_VertexIndex < `SkirtMesh::inner_vertex_count`), by the
/// ring patches' chain from its second lattice: with H = 2·`vertex_spacing` and (i, j) =
/// round(pos.xz / H) (signed: the parities from `& 1` and `& 3`), p = p₀ + chain((i, j), H,
/// level − 1, d, coarse_morph, empty).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchInstance {
    /// Patch centre (world x, z), metres.
    pub centre: [f32; 2],
    /// Patch side s_l = S / 2^l (m).
    pub size: f32,
    /// LOD level l.
    pub level: u32,
    /// Morph range [start, end] (m) of this level.
    pub morph: [f32; 2],
    /// Morph range of level l − 1, applied to vertices on stitched edges.
    pub coarse_morph: [f32; 2],
    /// Stitch flags (eq. 64), the same as the draw's configuration.
    pub stitch: u32,
    /// Cascade fade: the patch's vertex spacing s_l / V (m). The renderer fades out a cascade
    /// whose patch length is under 4 × this (its waves would alias on this mesh).
    pub vertex_spacing: f32,
}

/// One instanced draw: submesh `stitch` of the patch mesh, instances
/// `first_instance .. first_instance + instance_count` of the instance buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawBatch {
    /// The stitch configuration: index set to bind.
    pub stitch: StitchFlags,
    /// First instance in [`Batches::instances`].
    pub first_instance: u32,
    /// Instances in this draw (≥ 1).
    pub instance_count: u32,
}

/// The frame's instance buffer (sorted by stitch configuration) and its ≤ 16 draws, reused
/// across frames.
#[derive(Clone, Debug, Default)]
pub struct Batches {
    instances: Vec<PatchInstance>,
    draws: Vec<DrawBatch>,
}

impl Batches {
    /// Buffers for up to `max_instances` patches.
    pub fn with_capacity(max_instances: usize) -> Self {
        Self {
            instances: Vec::with_capacity(max_instances),
            draws: Vec::with_capacity(16),
        }
    }

    /// Counting sort of `patches` by stitch configuration into the instance buffer, the draws
    /// ordered by their nearest patch to `viewer` (x, z): the GPU then shades the near water
    /// first and its depth test rejects more of what it hides before shading (Adreno's guide
    /// asks for front-to-back order). Instances within a draw keep the traversal's order:
    /// sorting them too made lavapipe's multiview drop the right eye's nearest patches
    /// (`render_images`; a driver fault suspected, not shown). Allocates nothing.
    pub fn build(
        &mut self,
        patches: impl Iterator<Item = PatchInstance> + Clone,
        viewer: [f32; 2],
    ) {
        let mut counts = [0u32; 16];
        for p in patches.clone() {
            counts[p.stitch as usize & 15] += 1;
        }
        let mut offsets = [0u32; 16];
        let mut total = 0;
        self.draws.clear();
        for (k, &n) in counts.iter().enumerate() {
            offsets[k] = total;
            if n > 0 {
                self.draws.push(DrawBatch {
                    stitch: StitchFlags::from_bits(k as u8),
                    first_instance: total,
                    instance_count: n,
                });
            }
            total += n;
        }
        self.instances.clear();
        self.instances
            .resize(total as usize, PatchInstance::zeroed());
        // Each configuration's nearest patch (squared distance), found while placing them.
        let mut nearest = [f32::INFINITY; 16];
        for p in patches {
            let k = p.stitch as usize & 15;
            self.instances[offsets[k] as usize] = p;
            offsets[k] += 1;
            let (dx, dz) = (p.centre[0] - viewer[0], p.centre[1] - viewer[1]);
            nearest[k] = nearest[k].min(dx * dx + dz * dz);
        }
        self.draws.sort_unstable_by(|a, b| {
            nearest[a.stitch.bits() as usize].total_cmp(&nearest[b.stitch.bits() as usize])
        });
    }

    /// The instance buffer, grouped by configuration in the order of [`Self::draws`].
    pub fn instances(&self) -> &[PatchInstance] {
        &self.instances
    }

    /// The instanced draws, at most 16.
    pub fn draws(&self) -> &[DrawBatch] {
        &self.draws
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instance_is_compact_and_pod() {
        assert_eq!(std::mem::size_of::<PatchInstance>(), 40);
        let i = PatchInstance {
            stitch: 5,
            ..Default::default()
        };
        assert_eq!(bytemuck::bytes_of(&i).len(), 40);
    }

    #[test]
    fn batches_group_by_configuration_nearest_draw_first() {
        let mut b = Batches::with_capacity(8);
        let p = |s: u32, x: f32| PatchInstance {
            centre: [x, 0.0],
            stitch: s,
            ..Default::default()
        };
        let patches = [p(3, 0.0), p(0, 1.0), p(3, 2.0), p(15, 3.0)];
        b.build(patches.into_iter(), [0.0, 0.0]);
        assert_eq!(b.draws().len(), 3);
        // Near to far: configuration 3 (nearest at 0 m), then 0 (1 m), then 15 (3 m).
        let order: Vec<u8> = b.draws().iter().map(|d| d.stitch.bits()).collect();
        assert_eq!(order, [3, 0, 15]);
        assert_eq!(b.draws()[0].instance_count, 2);
        let group = &b.instances()[b.draws()[0].first_instance as usize..][..2];
        assert_eq!(group[0].centre[0], 0.0);
        assert_eq!(group[1].centre[0], 2.0);
        // Seen from x = 3 m: configuration 15 first, then 3 (its patch at 2 m), then 0.
        b.build(patches.into_iter(), [3.0, 0.0]);
        let order: Vec<u8> = b.draws().iter().map(|d| d.stitch.bits()).collect();
        assert_eq!(order, [15, 3, 0]);
        // Every instance is in its draw's range.
        for d in b.draws() {
            let range = d.first_instance as usize..(d.first_instance + d.instance_count) as usize;
            assert!(b.instances()[range]
                .iter()
                .all(|i| i.stitch == d.stitch.bits() as u32));
        }
    }
}
