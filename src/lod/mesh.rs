//! The shared patch mesh: (V + 1)² vertices in unit space (eq. 67) and the 16 index sets, one
//! per stitch configuration, generated once.

use super::stitch::{index_set, StitchFlags};

/// The patch grid every quadtree patch instances: vertex (i, j) at (i/V − 0.5, 0, j/V − 0.5)
/// (eq. 67), index set `k` for stitch flags `k` (eq. 64-68).
#[derive(Clone, Debug)]
pub struct PatchMesh {
    vertices_per_side: u32,
    positions: Vec<[f32; 3]>,
    index_sets: [Vec<u16>; 16],
}

impl PatchMesh {
    /// Builds the grid for V cells per side (V even, (V + 1)² ≤ 65536 so indices fit u16).
    pub fn new(vertices_per_side: u32) -> Self {
        assert!(vertices_per_side.is_multiple_of(2) && vertices_per_side <= 254);
        let v = vertices_per_side;
        let positions = (0..=v)
            .flat_map(|j| {
                (0..=v).map(move |i| [i as f32 / v as f32 - 0.5, 0.0, j as f32 / v as f32 - 0.5])
            })
            .collect();
        let index_sets = std::array::from_fn(|k| index_set(v, StitchFlags::from_bits(k as u8)));
        Self {
            vertices_per_side: v,
            positions,
            index_sets,
        }
    }

    /// V.
    pub fn vertices_per_side(&self) -> u32 {
        self.vertices_per_side
    }

    /// Vertex positions in unit space, row-major in j (z) then i (x) (eq. 67-68).
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }

    /// The triangle list (u16 indices, +y facing) of stitch configuration `flags`.
    pub fn indices(&self, flags: StitchFlags) -> &[u16] {
        &self.index_sets[flags.bits() as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_has_v_plus_one_squared_vertices_in_unit_square() {
        let m = PatchMesh::new(16);
        assert_eq!(m.positions().len(), 17 * 17);
        assert_eq!(m.positions()[0], [-0.5, 0.0, -0.5]);
        assert_eq!(m.positions()[17 * 17 - 1], [0.5, 0.0, 0.5]);
        assert_eq!(
            m.positions()[1 + 17],
            [1.0 / 16.0 - 0.5, 0.0, 1.0 / 16.0 - 0.5]
        );
        assert_eq!(m.indices(StitchFlags::NONE).len(), 3 * 8 * 64);
        assert_eq!(
            m.indices(StitchFlags::from_bits(15)).len(),
            3 * (8 * 64 - 4 * 8)
        );
    }
}
