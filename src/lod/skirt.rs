//! The horizon skirt (section 5.7): a ring from the grid edge at S/2 out to 10·S, one draw.

/// The skirt ring, positions relative to the grid centre (metres, y = 0).
///
/// Its inner edge has the vertex spacing of the level below the ring level (the finest ring
/// patches), which is exactly what a ring patch's stitched outer edge has, and what the
/// unstitched outer edge of a ring patch one level coarser has, so the skirt meets the
/// quadtree without T-junctions.
/// The first [`Self::inner_vertex_count`] vertices are the inner edge; the renderer morphs them
/// like a stitched patch edge (`coarse_morph` of the skirt instance) and leaves the four outer
/// corners alone. Each side is a fan from the inner edge to the two outer corners.
#[derive(Clone, Debug)]
pub struct SkirtMesh {
    positions: Vec<[f32; 3]>,
    indices: Vec<u16>,
    inner: u32,
}

impl SkirtMesh {
    /// Builds the ring for grid side `size`, `segments` inner-edge segments per side (even) and
    /// outer half-width `extent`.
    pub fn new(size: f32, segments: u32, extent: f32) -> Self {
        assert!(segments >= 2 && segments.is_multiple_of(2) && 4 * segments + 4 <= 65536);
        let n = segments;
        let half = size / 2.0;
        let step = size / n as f32;
        // Counter-clockwise from above along the square: south edge (+x), east (+z), north (−x),
        // west (−z), starting at the (−S/2, −S/2) corner.
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let dirs = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
        let mut positions = Vec::with_capacity(4 * n as usize + 4);
        for side in 0..4 {
            let (cx, cz) = corners[side];
            let (dx, dz) = dirs[side];
            for k in 0..n {
                let t = k as f32 * step;
                positions.push([cx * half + dx * t, 0.0, cz * half + dz * t]);
            }
        }
        for (cx, cz) in corners {
            positions.push([cx * extent, 0.0, cz * extent]);
        }
        let inner = 4 * n;
        let mut indices = Vec::with_capacity(3 * 4 * (n as usize + 1));
        for side in 0..4 {
            let outer_a = (inner + side) as u16;
            let outer_b = (inner + (side + 1) % 4) as u16;
            for k in 0..n {
                let a = (side * n + k) as u16;
                let b = ((side * n + k + 1) % inner) as u16;
                let o = if k < n / 2 { outer_a } else { outer_b };
                indices.extend_from_slice(&[a, b, o]);
            }
            let mid = (side * n + n / 2) as u16;
            indices.extend_from_slice(&[mid, outer_b, outer_a]);
        }
        Self {
            positions,
            indices,
            inner,
        }
    }

    /// Vertex positions relative to the grid centre.
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }

    /// Triangle list, +y facing.
    pub fn indices(&self) -> &[u16] {
        &self.indices
    }

    /// How many leading vertices form the inner edge.
    pub fn inner_vertex_count(&self) -> u32 {
        self.inner
    }

    /// Triangles in the ring.
    pub fn triangle_count(&self) -> u32 {
        self.indices.len() as u32 / 3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_faces_up_and_covers_the_annulus() {
        let s = SkirtMesh::new(100.0, 8, 1000.0);
        let p = s.positions();
        let mut area = 0.0f64;
        for t in s.indices().chunks(3) {
            let [a, b, c] = [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]];
            let up = (b[2] - a[2]) as f64 * (c[0] - a[0]) as f64
                - (b[0] - a[0]) as f64 * (c[2] - a[2]) as f64;
            assert!(up > 0.0);
            area += up / 2.0;
        }
        assert!((area - (2000.0f64 * 2000.0 - 100.0 * 100.0)).abs() < 1.0);
    }
}
