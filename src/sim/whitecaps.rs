//! Whitecaps of the whole surface: persistent foam coverage on world-space maps around the
//! viewer, from the Jacobian of the summed cascades (issue 14).
//!
//! Each cascade's own Jacobian (eq. 48) misses where several cascades compress the surface
//! together, which is where real seas break: a short wave folds on the front of a long one. So
//! foam is computed here, once for the whole surface, on square lattices of
//! [`WHITECAP_TEXELS`]² points fixed in the world (rest positions, like every field), spacing
//! [`WHITECAP_SPACING`] per level, following the viewer in whole texels. The Jacobian comes
//! from central differences of the summed horizontal displacement X = Σ Dx, Z = Σ Dz over one
//! lattice step (the thesis's eq. 45-48 in finite form):
//!
//! J = (1 + ∂X/∂x)(1 + ∂Z/∂z) − (∂X/∂z)(∂Z/∂x),
//!
//! i.e. the compression of a lattice cell, which filters out waves shorter than the cell (their
//! sub-metre folds make no visible whitecap) and keeps every cascade's share of the rest.
//! Coverage then grows where J is below [`WHITECAP_THRESHOLD`] and decays everywhere
//! ([`FoamParams::decay`]), so whitecaps linger after the crest has passed:
//!
//! f ← min(1, f·e^(−decay·dt) + G·(U/10 m/s)²·dt·max(0, J_thr − J)).
//!
//! **Why the wind enters twice.** The resolved slopes of a JONSWAP sea hardly grow with the
//! wind (its high-frequency tail is saturated), so the share of strongly compressed surface
//! grows only ~4x from 8 to 20 m/s, while observed whitecap coverage grows ~23x (Monahan &
//! O'Muircheartaigh 1980, W = 3.84·10⁻⁶·U^3.41). The energy that breaking waves turn into foam
//! comes from the wind stress τ = ρ_a·C_d·U², so the production rate G scales with U²: where
//! the surface breaks is the Jacobian's, how much foam the breaking makes is the wind's.
//! `tests/sea_state.rs` measures the resulting coverage against Monahan's law.
//!
//! Storage is toroidal: lattice point (i, j) lives at texel (i mod T, j mod T), so the GPU
//! samples the map with REPEAT addressing at uv = (x/s + ½)/T and a moving viewer only resets
//! the rows and columns that enter the window. Coverage is published as an R8 mip chain so
//! distant water reads the area average instead of aliasing.

use half::f16;
use rayon::prelude::*;

use crate::sim::grid::GridSize;
use crate::sim::params::FoamParams;
use crate::sim::surface::CascadeSurface;

/// Texels per side of each whitecap level.
pub const WHITECAP_TEXELS: usize = 256;

/// Whitecap levels: a fine one near the viewer and a coarse one out to the mid distance.
pub const WHITECAP_LEVELS: usize = 2;

/// Lattice spacing (m) of each level: level 0 covers ±64 m around the viewer at 0.5 m, level 1
/// ±256 m at 2 m. Beyond, the renderer uses level 1's mean coverage.
pub const WHITECAP_SPACING: [f32; WHITECAP_LEVELS] = [0.5, 2.0];

/// Jacobian below which a lattice cell is breaking, per level. The coarser lattice filters
/// more of the short waves' compression, so its threshold sits nearer 1 to give the same
/// coverage of the same sea (measured in `tests/sea_state.rs`).
pub const WHITECAP_THRESHOLD: [f32; WHITECAP_LEVELS] = [0.85, 0.885];

/// Foam produced per second per unit of (J_thr − J) at 10 m/s wind; scales with (U/10)².
/// Calibrated so the default sea's mean coverage follows Monahan's law (see the module doc).
pub const WHITECAP_GROWTH_AT_10: f32 = 6.5;

/// One level's published coverage.
#[derive(Clone, Debug)]
pub struct WhitecapLevel {
    /// Lattice spacing (m).
    pub spacing: f32,
    /// Lattice index of the window's first point along x and z: the window holds points
    /// origin..origin + [`WHITECAP_TEXELS`], at world (i·s, j·s) on the rest surface.
    pub origin: [i32; 2],
    /// Coverage in [0, 1] as R8, toroidal, with its mip chain ([`crate::sim::pack::mip_offset`]
    /// of a [`WHITECAP_TEXELS`] grid).
    pub coverage: Vec<u8>,
    /// Mean coverage over the window.
    pub mean: f32,
}

/// Whitecap coverage of the whole surface, published with each step's surfaces.
#[derive(Clone, Debug)]
pub struct Whitecaps {
    /// Levels, finest first.
    pub levels: [WhitecapLevel; WHITECAP_LEVELS],
}

impl Default for Whitecaps {
    fn default() -> Self {
        let chain = crate::sim::pack::mip_chain_len(grid());
        Self {
            levels: std::array::from_fn(|l| WhitecapLevel {
                spacing: WHITECAP_SPACING[l],
                origin: [0; 2],
                coverage: vec![0; chain],
                mean: 0.0,
            }),
        }
    }
}

impl Whitecaps {
    /// Coverage in [0, 1] at rest position (x, z), nearest lattice point of the finest level
    /// whose window holds it (None outside every window).
    pub fn coverage_at(&self, x: f32, z: f32) -> Option<f32> {
        let t = WHITECAP_TEXELS as i32;
        self.levels.iter().find_map(|l| {
            let (i, j) = (
                (x / l.spacing).round() as i32,
                (z / l.spacing).round() as i32,
            );
            let inside = (l.origin[0]..l.origin[0] + t).contains(&i)
                && (l.origin[1]..l.origin[1] + t).contains(&j);
            inside.then(|| {
                let idx = slot(j) * WHITECAP_TEXELS + slot(i);
                l.coverage[idx] as f32 / 255.0
            })
        })
    }
}

fn grid() -> GridSize {
    GridSize::new(WHITECAP_TEXELS as u32).expect("a power of two")
}

/// Texel of lattice index `i` in the toroidal storage.
#[inline]
fn slot(i: i32) -> usize {
    i.rem_euclid(WHITECAP_TEXELS as i32) as usize
}

/// The persistent state: foam per lattice point of each level, and scratch for the summed
/// horizontal displacement. Owned by the simulation core; allocated once.
pub struct WhitecapState {
    foam: [Vec<f32>; WHITECAP_LEVELS],
    origin: [Option<[i32; 2]>; WHITECAP_LEVELS],
    /// Σ Dx and Σ Dz at the window's lattice points plus a one-point border, row-major
    /// ((T + 2)² each).
    xz: Vec<[f32; 2]>,
}

impl Default for WhitecapState {
    fn default() -> Self {
        let t = WHITECAP_TEXELS;
        Self {
            foam: std::array::from_fn(|_| vec![0.0; t * t]),
            origin: [None; WHITECAP_LEVELS],
            xz: vec![[0.0; 2]; (t + 2) * (t + 2)],
        }
    }
}

/// What one whitecap update needs besides the state.
#[derive(Clone, Copy)]
pub struct WhitecapInput<'a> {
    /// This step's cascades (the Jacobian sums them all).
    pub cascades: &'a [CascadeSurface],
    /// Where the viewer is (world x, z): the windows centre on it.
    pub focus: [f32; 2],
    /// Foam dynamics (its decay; growth and threshold are the whitecaps' own, see the module).
    pub foam: FoamParams,
    /// Wind speed at 10 m (m/s): foam production scales with the wind stress, U².
    pub wind_speed: f32,
    /// Seconds since the previous step (0 on the first).
    pub dt: f32,
}

impl WhitecapState {
    /// Moves the windows to the focus, updates the foam of every level from this step's
    /// Jacobian and publishes the coverage into `out`. Allocates nothing.
    pub fn update(&mut self, input: WhitecapInput<'_>, out: &mut Whitecaps) {
        let t = WHITECAP_TEXELS as i32;
        for (l, level) in out.levels.iter_mut().enumerate() {
            let s = WHITECAP_SPACING[l];
            let origin = [
                (input.focus[0] / s).floor() as i32 - t / 2,
                (input.focus[1] / s).floor() as i32 - t / 2,
            ];
            let foam = &mut self.foam[l];
            match self.origin[l] {
                Some(old) => forget_outside(foam, old, origin),
                None => foam.fill(0.0),
            }
            self.origin[l] = Some(origin);
            sample_displacement(input.cascades, origin, s, &mut self.xz);
            update_foam(&self.xz, origin, s, l, &input, foam, &mut level.coverage);
            level.spacing = s;
            level.origin = origin;
            level.mean = foam.iter().sum::<f32>() / foam.len() as f32;
            crate::sim::pack::build_r8_mips(grid(), &mut level.coverage);
        }
    }
}

/// Zeroes the foam of lattice points in the `new` window that were not in the `old` one.
fn forget_outside(foam: &mut [f32], old: [i32; 2], new: [i32; 2]) {
    let t = WHITECAP_TEXELS as i32;
    let inside = |i: i32, o: i32| (o..o + t).contains(&i);
    for j in new[1]..new[1] + t {
        let row = slot(j) * WHITECAP_TEXELS;
        if !inside(j, old[1]) {
            foam[row..row + WHITECAP_TEXELS].fill(0.0);
            continue;
        }
        for i in new[0]..new[0] + t {
            if !inside(i, old[0]) {
                foam[row + slot(i)] = 0.0;
            }
        }
    }
}

/// Σ Dx and Σ Dz of all cascades at lattice points (origin − 1 .. origin + T + 1)·s.
fn sample_displacement(cascades: &[CascadeSurface], origin: [i32; 2], s: f32, xz: &mut [[f32; 2]]) {
    let side = WHITECAP_TEXELS + 2;
    xz.par_chunks_mut(side).enumerate().for_each(|(r, row)| {
        let z = (origin[1] - 1 + r as i32) as f32 * s;
        row.fill([0.0; 2]);
        for c in cascades {
            add_cascade_row(c, z, (origin[0] - 1) as f32 * s, s, row);
        }
    });
}

/// Adds cascade `c`'s bilinear (Dx, Dz) at (x0 + i·s, z) to `row[i]`.
fn add_cascade_row(c: &CascadeSurface, z: f32, x0: f32, s: f32, row: &mut [[f32; 2]]) {
    let n = c.grid.n();
    let mask = n as i64 - 1;
    let scale = n as f32 / c.patch;
    let v = z * scale;
    let fv = v.floor();
    let tv = v - fv;
    let r0 = fv as i64 & mask;
    let r1 = (r0 + 1) & mask;
    let (b0, b1) = (r0 as usize * n, r1 as usize * n);
    // Full precision when the surface keeps it, else the RGBA16F copy.
    let texel = |i: usize| -> [f32; 2] {
        match c.displacement.get(i) {
            Some(d) => [d[0], d[2]],
            None => {
                let d = &c.displacement_f16[i];
                [f16::to_f32(d[0]), f16::to_f32(d[2])]
            }
        }
    };
    for (i, acc) in row.iter_mut().enumerate() {
        let u = (x0 + i as f32 * s) * scale;
        let fu = u.floor();
        let tu = u - fu;
        let c0 = fu as i64 & mask;
        let c1 = ((c0 + 1) & mask) as usize;
        let c0 = c0 as usize;
        let (a, b, e, f) = (
            texel(b0 + c0),
            texel(b0 + c1),
            texel(b1 + c0),
            texel(b1 + c1),
        );
        for k in 0..2 {
            let top = a[k] + (b[k] - a[k]) * tu;
            let bottom = e[k] + (f[k] - e[k]) * tu;
            acc[k] += top + (bottom - top) * tv;
        }
    }
}

/// The Jacobian of each lattice cell, the foam update, and level 0 of the R8 coverage.
fn update_foam(
    xz: &[[f32; 2]],
    origin: [i32; 2],
    spacing: f32,
    level: usize,
    input: &WhitecapInput<'_>,
    foam: &mut [f32],
    coverage: &mut [u8],
) {
    let t = WHITECAP_TEXELS;
    let side = t + 2;
    let keep = (-input.foam.decay * input.dt).exp();
    let stress = (input.wind_speed / 10.0).powi(2);
    let grow = WHITECAP_GROWTH_AT_10 * stress * input.dt;
    let threshold = WHITECAP_THRESHOLD[level];
    // Central differences over one lattice step on each side.
    let inv = 0.5 / spacing;
    foam.par_chunks_mut(t)
        .zip(coverage[..t * t].par_chunks_mut(t))
        .enumerate()
        .for_each(|(storage_row, (frow, crow))| {
            // The window's lattice row j stored in this row: j ≡ storage_row (mod T).
            let j = origin[1] + (storage_row as i32 - origin[1]).rem_euclid(t as i32);
            let r = (j - origin[1]) as usize + 1;
            let up = &xz[(r - 1) * side..r * side];
            let mid = &xz[r * side..(r + 1) * side];
            let down = &xz[(r + 1) * side..(r + 2) * side];
            for k in 0..t {
                let col = slot(origin[0] + k as i32);
                let x = k + 1;
                let dxx = (mid[x + 1][0] - mid[x - 1][0]) * inv;
                let dzx = (mid[x + 1][1] - mid[x - 1][1]) * inv;
                let dxz = (down[x][0] - up[x][0]) * inv;
                let dzz = (down[x][1] - up[x][1]) * inv;
                let jacobian = (1.0 + dxx) * (1.0 + dzz) - dxz * dzx;
                let f = (frow[col] * keep + grow * (threshold - jacobian).max(0.0)).min(1.0);
                frow[col] = f;
                crow[col] = (f * 255.0 + 0.5) as u8;
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::OceanConfig;
    use crate::sim::surface::FloatCopies;

    fn flat(config: &OceanConfig) -> Vec<CascadeSurface> {
        config
            .patch_sizes
            .iter()
            .map(|&l| CascadeSurface::new(config.grid, l, FloatCopies::Skip))
            .collect()
    }

    #[test]
    fn a_flat_sea_has_no_foam_and_a_compressed_one_foams() {
        let config = OceanConfig::single(16, 10.0).unwrap();
        let mut cascades = flat(&config);
        let mut state = WhitecapState::default();
        let mut out = Whitecaps::default();
        fn input(c: &[CascadeSurface]) -> WhitecapInput<'_> {
            WhitecapInput {
                cascades: c,
                focus: [3.0, -7.0],
                foam: FoamParams::default(),
                wind_speed: 10.0,
                dt: 0.1,
            }
        }
        state.update(input(&cascades), &mut out);
        assert!(out
            .levels
            .iter()
            .all(|l| l.coverage.iter().all(|&c| c == 0)));
        // Dx = −a·sin(kx) compresses the surface where cos(kx) > 1/(a·k)·(1 − threshold).
        let n = config.grid.n();
        let k = std::f32::consts::TAU / 10.0;
        for (i, d) in cascades[0].displacement_f16.iter_mut().enumerate() {
            let x = (i % n) as f32 * 10.0 / n as f32;
            d[0] = f16::from_f32(-1.5 * (k * x).sin());
        }
        for _ in 0..20 {
            state.update(input(&cascades), &mut out);
        }
        let l0 = &out.levels[0];
        assert!(l0.mean > 0.05 && l0.mean < 0.6, "mean coverage {}", l0.mean);
        // Foam where the displacement converges (x ≈ 0 mod 10 m), none where it spreads.
        let at = |x: f32| out.coverage_at(x, -7.0).unwrap();
        assert!(at(10.0) > 0.5 && at(5.0) == 0.0, "{} {}", at(10.0), at(5.0));
        // Mips hold the average.
        let last = *l0.coverage.last().unwrap() as f32 / 255.0;
        assert!((last - l0.mean).abs() < 0.02, "{last} vs {}", l0.mean);
    }

    #[test]
    fn moving_the_viewer_keeps_foam_where_it_was_and_forgets_what_left() {
        let mut foam = vec![0.0; WHITECAP_TEXELS * WHITECAP_TEXELS];
        foam.fill(1.0);
        let old = [0, 0];
        let new = [10, -3];
        forget_outside(&mut foam, old, new);
        let t = WHITECAP_TEXELS as i32;
        for j in new[1]..new[1] + t {
            for i in new[0]..new[0] + t {
                let kept = (0..t).contains(&i) && (0..t).contains(&j);
                let v = foam[slot(j) * WHITECAP_TEXELS + slot(i)];
                assert_eq!(v, if kept { 1.0 } else { 0.0 }, "({i}, {j})");
            }
        }
    }
}
