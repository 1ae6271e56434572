//! The comfort vignette (issue 45's float mode; Meta's comfort guidance for artificial
//! motion): while the view is moved for the user, a black ring narrows the field of view
//! around each eye's axis. It is drawn last in the pass, blended, untested against depth, from
//! three rings of directions (`shaders/vignette.vert` makes the vertices from their index), so
//! it needs no copy of the frame and covers only the periphery it darkens.

/// Segments around each ring; mirrored in `shaders/vignette.vert`.
pub const VIGNETTE_SEGMENTS: u16 = 48;

/// The rings' triangles: two bands (clear edge to feather, feather to beyond the field of
/// view), each [`VIGNETTE_SEGMENTS`] quads; vertex `ring * SEGMENTS + segment`.
pub fn ring_indices() -> Vec<u16> {
    let n = VIGNETTE_SEGMENTS;
    let mut out = Vec::with_capacity(2 * 6 * n as usize);
    for band in 0..2u16 {
        for s in 0..n {
            let next = (s + 1) % n;
            let (a, b) = (band * n + s, band * n + next);
            let (c, d) = (a + n, b + n);
            out.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rings_close_and_every_quad_spans_two_rings() {
        let idx = ring_indices();
        let n = VIGNETTE_SEGMENTS;
        assert_eq!(idx.len(), 12 * n as usize);
        assert!(idx.iter().all(|&i| i < 3 * n));
        for tri in idx.chunks(3) {
            let rings: Vec<u16> = tri.iter().map(|i| i / n).collect();
            let (lo, hi) = (*rings.iter().min().unwrap(), *rings.iter().max().unwrap());
            assert_eq!(hi - lo, 1, "{tri:?}");
        }
        // The last quad of the first band wraps to segment 0.
        assert!(idx[6 * (n as usize - 1)..6 * n as usize].contains(&0));
    }
}
