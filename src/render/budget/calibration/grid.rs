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

/// The block sides the counting pass estimates lanes for (`PathCounts::BLOCK_SIDES`) and how
/// much less than a block a triangle grows by before it covers a sample of the next block
/// (fitted to sampled triangles: `triangle_lanes_follow_sampled_triangles`).
pub const BLOCK_SHRINK: [(u32, f64); 3] = [(2, 0.75), (4, 1.0), (8, 2.0)];

/// The lanes a triangle of `area` pixels whose bounding box is `widths` (its width plus its
/// height) pixels is shaded on, at a random place, on a device that shades in `block`-pixel
/// squares, and the fragments it makes under 4x MSAA: the blocks holding a covered sample are
/// about those the triangle grown by `block - shrink` meets (its area, widths × growth,
/// growth²; at least one), the fragments about `area + 0.35 widths` (at least one). The
/// counting pass (`shaders/ocean.frag`, `count_size`) computes the same per fragment.
pub fn triangle_lanes(area: f64, widths: f64, block: u32) -> (f64, f64) {
    let b = f64::from(block);
    let shrink = BLOCK_SHRINK
        .iter()
        .find(|(side, _)| *side == block)
        .map_or(b / 4.0, |&(_, s)| s);
    let g = b - shrink;
    let lanes = (area + g * widths + g * g).max(b * b);
    let fragments = (area + 0.35 * widths).max(1.0);
    (lanes, fragments)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mesh-like triangles (a cell's half under random scale, stretch, turn, shear and place),
    /// their samples and blocks counted exactly, against [`triangle_lanes`] per size class:
    /// within 25 % for 2×2 quads and 4×4 blocks (the least, a quarter-pixel triangle's share of
    /// one quad, is the worst).
    #[test]
    fn triangle_lanes_follow_sampled_triangles() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rand = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let inside = |p: (f64, f64), t: [(f64, f64); 3]| {
            let cross = |o: (f64, f64), u: (f64, f64), v: (f64, f64)| {
                (u.0 - o.0) * (v.1 - o.1) - (u.1 - o.1) * (v.0 - o.0)
            };
            let d = [
                cross(t[0], t[1], p),
                cross(t[1], t[2], p),
                cross(t[2], t[0], p),
            ];
            !(d.iter().any(|&x| x < 0.0) && d.iter().any(|&x| x > 0.0))
        };
        for block in [2u32, 4] {
            // Per size class (log2 area): exact lanes, exact fragments, estimated lanes per
            // fragment weighted by the exact fragments.
            let mut classes = std::collections::BTreeMap::<i32, [f64; 3]>::new();
            for _ in 0..1500 {
                let scale = 2f64.powf(-1.0 + 5.0 * rand());
                let stretch = 2f64.powf(-3.0 + 6.0 * rand()).sqrt();
                let (turn, shear) = (std::f64::consts::PI * rand(), rand() - 0.5);
                let (c, s) = (turn.cos(), turn.sin());
                let u = (scale * stretch * c, scale * stretch * s);
                let v = (
                    scale / stretch * (shear * c - s),
                    scale / stretch * (shear * s + c),
                );
                let o = (8.0 * rand(), 8.0 * rand());
                let t = [o, (o.0 + u.0, o.1 + u.1), (o.0 + v.0, o.1 + v.1)];
                let (xs, ys) = (t.map(|p| p.0), t.map(|p| p.1));
                let (x0, x1) = (
                    xs.iter().cloned().fold(f64::MAX, f64::min),
                    xs.iter().cloned().fold(f64::MIN, f64::max),
                );
                let (y0, y1) = (
                    ys.iter().cloned().fold(f64::MAX, f64::min),
                    ys.iter().cloned().fold(f64::MIN, f64::max),
                );
                let mut fragments = 0.0;
                let mut blocks = std::collections::HashSet::new();
                for px in (x0.floor() as i64 - 1)..=(x1.ceil() as i64) {
                    for py in (y0.floor() as i64 - 1)..=(y1.ceil() as i64) {
                        if SAMPLES
                            .iter()
                            .any(|&(sx, sy)| inside((px as f64 + sx, py as f64 + sy), t))
                        {
                            fragments += 1.0;
                            blocks.insert((
                                px.div_euclid(i64::from(block)),
                                py.div_euclid(i64::from(block)),
                            ));
                        }
                    }
                }
                if fragments == 0.0 {
                    continue;
                }
                let area = 0.5 * (u.0 * v.1 - u.1 * v.0).abs();
                let (lanes, estimated) = triangle_lanes(area, (x1 - x0) + (y1 - y0), block);
                let class = area.log2().floor() as i32;
                let e = classes.entry(class).or_default();
                e[0] += blocks.len() as f64 * f64::from(block * block);
                e[1] += fragments;
                e[2] += lanes / estimated * fragments;
            }
            for (class, [lanes, fragments, estimated]) in classes {
                let (exact, est) = (lanes / fragments, estimated / fragments);
                assert!(
                    (est / exact - 1.0).abs() < 0.25,
                    "{block}-pixel blocks, triangles of 2^{class} pixels: {est:.2} lanes a \
                     fragment estimated, {exact:.2} counted"
                );
            }
        }
    }

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
