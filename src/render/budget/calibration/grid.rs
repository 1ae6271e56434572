//! The geometry of the calibration's grids of small triangles (`render::calibration`'s grid
//! kernels): square cells of a whole number of pixels from the viewport's corner, each split
//! along its rising diagonal, drawn under 4x MSAA with Vulkan's standard sample positions.

/// Vulkan's standard sample positions of 4x MSAA, within a pixel.
const SAMPLES: [(f64, f64); 4] = [
    (0.375, 0.125),
    (0.875, 0.375),
    (0.125, 0.625),
    (0.625, 0.875),
];

/// Fragments per pixel of a grid of `cell`-pixel cells under 4× MSAA with Vulkan's standard
/// sample positions: a pixel is shaded once for each triangle that covers any of its samples.
/// The cell's diagonal splits the samples of the `cell` pixels along it between both
/// triangles, and no sample lies on an edge: 1 + 1 / cell.
pub fn fragments_per_pixel(cell: u32) -> f64 {
    1.0 + 1.0 / f64::from(cell.max(1))
}

/// Lanes per fragment of a grid of `cell`-pixel cells (as [`fragments_per_pixel`] makes its
/// fragments) on a device that shades each triangle in the `block`-pixel squares (aligned to
/// the pixel grid's origin, as the grid is) that hold any of its covered samples: counted over
/// one period of both grids.
pub fn grid_lanes_per_fragment(cell: u32, block: u32) -> f64 {
    let (cell, block) = (cell.max(1), block.max(1));
    let period = lcm(cell, block);
    let (mut lanes, mut fragments) = (0u64, 0u64);
    for cy in (0..period).step_by(cell as usize) {
        for cx in (0..period).step_by(cell as usize) {
            // The cell's two triangles: below and above its diagonal x + y = cell.
            for upper in [false, true] {
                let mut blocks = std::collections::HashSet::new();
                for j in 0..cell {
                    for i in 0..cell {
                        let covered = SAMPLES.iter().any(|&(sx, sy)| {
                            let sum = f64::from(i) + sx + f64::from(j) + sy;
                            (sum > f64::from(cell)) == upper
                        });
                        if covered {
                            fragments += 1;
                            blocks.insert(((cx + i) / block, (cy + j) / block));
                        }
                    }
                }
                lanes += blocks.len() as u64 * u64::from(block * block);
            }
        }
    }
    lanes as f64 / fragments as f64
}

fn lcm(a: u32, b: u32) -> u32 {
    let gcd = |mut x: u32, mut y: u32| {
        while y != 0 {
            (x, y) = (y, x % y);
        }
        x
    };
    a / gcd(a, b) * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_lanes_follow_the_blocks_a_triangle_touches() {
        // One lane per fragment where the device wastes none.
        assert!((grid_lanes_per_fragment(4, 1) - 1.0).abs() < 1e-12);
        // 1-pixel cells in 4x4 blocks: 16 triangles' single fragments share no block.
        assert!((grid_lanes_per_fragment(1, 4) - 16.0).abs() < 1e-12);
        // 2-pixel cells in 2x2 quads: each triangle takes its cell's one quad, 3 fragments.
        assert!((grid_lanes_per_fragment(2, 2) - 4.0 / 3.0).abs() < 1e-12);
        // Large cells waste little.
        assert!(grid_lanes_per_fragment(32, 2) < 1.1);
    }

    /// The closed form against counting: each pixel of a cell, each of Vulkan's standard 4×
    /// sample positions, on which side of the diagonal x + y = cell it falls.
    #[test]
    fn fragments_per_pixel_counts_the_pixels_the_diagonal_splits() {
        for cell in 1..=8u32 {
            let s = f64::from(cell);
            let mut fragments = 0;
            for i in 0..cell {
                for j in 0..cell {
                    let sums = SAMPLES.map(|(x, y)| f64::from(i) + x + f64::from(j) + y);
                    fragments += usize::from(sums.iter().any(|&v| v < s));
                    fragments += usize::from(sums.iter().any(|&v| v > s));
                    assert!(sums.iter().all(|&v| v != s), "a sample on the diagonal");
                }
            }
            let per_pixel = fragments as f64 / (s * s);
            assert!(
                (per_pixel - fragments_per_pixel(cell)).abs() < 1e-12,
                "cell {cell}"
            );
        }
        // A 1-pixel cell's diagonal splits every pixel's samples; a 2-pixel cell's, half.
        assert_eq!(fragments_per_pixel(1), 2.0);
        assert_eq!(fragments_per_pixel(2), 1.5);
    }
}
