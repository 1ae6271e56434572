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
//! sub-metre folds make no visible whitecap) and keeps every cascade's share of the rest. Each
//! cascade is sampled from the mip of its displacement whose texels match the lattice spacing
//! (`whitecaps/sampling.rs`), so the waves a lattice cannot hold are averaged out rather than
//! aliased into compressions the sea does not have. Coverage then grows where J is below
//! [`WHITECAP_THRESHOLD`] and decays everywhere ([`FoamParams::decay`]), so whitecaps linger
//! after the crest has passed:
//!
//! f ← min(1, f·e^(−decay·dt) + G·(U/10 m/s)²·dt·max(0, J_thr − J)).
//!
//! **Why the wind enters twice.** The resolved slopes of a JONSWAP sea hardly grow with the
//! wind (its high-frequency tail is saturated), so the share of strongly compressed surface
//! grows only ~4x from 8 to 20 m/s, while observed whitecap coverage grows ~23x (Monahan &
//! O'Muircheartaigh 1980, W = 3.84·10⁻⁶·U^3.41). The energy that breaking waves turn into foam
//! comes from the wind stress τ = ρ_a·C_d·U², so the production rate G scales with U²: where
//! the surface breaks is the Jacobian's, how much foam the breaking makes is the wind's.
//! `tests/app/sea_state.rs` measures the resulting coverage against Monahan's law.
//!
//! **Drift.** Foam floats: it rides the waves' orbital motion (the lattice is a rest-position
//! field, displaced with the surface like every other) and drifts with the surface's mean
//! current (the Stokes drift plus the wind-driven current, [`crate::sim::drift`]), which no
//! linear displacement holds. So the lattices are fixed in the drifting water, not in the world:
//! lattice point (i, j) sits at rest position (i·s, j·s) + [`Whitecaps::drift`], the distance the
//! drift has carried the surface since the start. The Jacobian is sampled there, so foam made
//! at a crest stays with the water that broke and moves downwind with it (without the numerical
//! diffusion that resampling a world-fixed map every step would add).
//!
//! Storage is toroidal: lattice point (i, j) lives at texel (i mod T, j mod T), so the GPU
//! samples the map with REPEAT addressing at uv = (x/s + ½)/T and a moving viewer only resets
//! the rows and columns that enter the window. Coverage is published as an R8 mip chain so
//! distant water reads the area average instead of aliasing.

mod sampling;

use rayon::prelude::*;

use sampling::{add_cascade, mip_for, DisplacementMips, Lattice};
pub use sampling::{WHITECAP_LEVELS, WHITECAP_SPACING, WHITECAP_TEXELS};

use crate::sim::grid::GridSize;
use crate::sim::params::FoamParams;
use crate::sim::surface::CascadeSurface;

/// Jacobian below which a lattice cell is breaking, per level. The coarser lattice filters
/// more of the short waves' compression, so its threshold sits nearer 1 to give the same
/// coverage of the same sea (measured in `tests/app/sea_state.rs`; set with the cascades sampled
/// from their mips, `whitecaps/sampling.rs`).
pub const WHITECAP_THRESHOLD: [f32; WHITECAP_LEVELS] = [0.855, 0.90];

/// Foam produced per second per unit of (J_thr − J) at 10 m/s wind; scales with (U/10)².
/// Calibrated so the default sea's mean coverage follows Monahan's law (see the module doc).
pub const WHITECAP_GROWTH_AT_10: f32 = 6.5;

/// One level's published coverage.
#[derive(Clone, Debug)]
pub struct WhitecapLevel {
    /// Lattice spacing (m).
    pub spacing: f32,
    /// Lattice index of the window's first point along x and z: the window holds points
    /// origin..origin + [`WHITECAP_TEXELS`], at rest positions (i·s, j·s) + [`Whitecaps::drift`].
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
    /// How far (x, z) (m) the surface's mean drift has carried the lattices since the start:
    /// the rest position of lattice point (0, 0) of every level.
    pub drift: [f32; 2],
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
            drift: [0.0; 2],
        }
    }
}

impl Whitecaps {
    /// Coverage in [0, 1] at rest position (x, z), nearest lattice point of the finest level
    /// whose window holds it (None outside every window).
    pub fn coverage_at(&self, x: f32, z: f32) -> Option<f32> {
        let t = WHITECAP_TEXELS as i32;
        let (x, z) = (x - self.drift[0], z - self.drift[1]);
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
    /// Per level, Σ Dx and Σ Dz at the window's lattice points plus a one-point border,
    /// row-major ((T + 2)² each).
    xz: [Vec<[f32; 2]>; WHITECAP_LEVELS],
    /// [`Whitecaps::drift`], accumulated in f64.
    drift: [f64; 2],
    /// One cascade's (Dx, Dz) as f32 and the mips the levels sample (see `sampling`).
    mips: DisplacementMips,
}

impl WhitecapState {
    /// Zeroed state for cascades of side `grid`.
    pub fn new(grid: GridSize) -> Self {
        let t = WHITECAP_TEXELS;
        Self {
            foam: std::array::from_fn(|_| vec![0.0; t * t]),
            origin: [None; WHITECAP_LEVELS],
            xz: std::array::from_fn(|_| vec![[0.0; 2]; (t + 2) * (t + 2)]),
            drift: [0.0; 2],
            mips: DisplacementMips::new(grid),
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
    /// The surface's mean drift (x, z) (m/s, [`crate::sim::drift::surface_drift`]): carries the
    /// foam downwind.
    pub drift: [f32; 2],
    /// Seconds since the previous step (0 on the first).
    pub dt: f32,
}

impl WhitecapState {
    /// Moves the windows to the focus, updates the foam of every level from this step's
    /// Jacobian and publishes the coverage into `out`. Allocates nothing (unless the cascades
    /// are larger than the grid the state was made for, which sizes it once).
    pub fn update(&mut self, input: WhitecapInput<'_>, out: &mut Whitecaps) {
        let t = WHITECAP_TEXELS as i32;
        for (d, v) in self.drift.iter_mut().zip(input.drift) {
            *d += v as f64 * input.dt as f64;
        }
        let drift = self.drift.map(|d| d as f32);
        out.drift = drift;
        // The focus in the drifting lattices' frame.
        let focus = [input.focus[0] - drift[0], input.focus[1] - drift[1]];
        let origins: [[i32; 2]; WHITECAP_LEVELS] = std::array::from_fn(|l| {
            let s = WHITECAP_SPACING[l];
            [
                (focus[0] / s).floor() as i32 - t / 2,
                (focus[1] / s).floor() as i32 - t / 2,
            ]
        });
        for xz in &mut self.xz {
            xz.fill([0.0; 2]);
        }
        for c in input.cascades {
            // Each level samples the mip whose texels match its spacing.
            let mips = WHITECAP_SPACING.map(|s| mip_for(c.grid.n(), c.patch, s));
            self.mips.load(c, mips.into_iter().max().unwrap_or(0));
            for (l, xz) in self.xz.iter_mut().enumerate() {
                let level = self.mips.level(mips[l], c.patch);
                let lattice = Lattice {
                    origin: origins[l],
                    spacing: WHITECAP_SPACING[l],
                    drift,
                };
                add_cascade(level, lattice, xz);
            }
        }
        for (l, level) in out.levels.iter_mut().enumerate() {
            let (s, origin) = (WHITECAP_SPACING[l], origins[l]);
            let foam = &mut self.foam[l];
            match self.origin[l] {
                Some(old) => forget_outside(foam, old, origin),
                None => foam.fill(0.0),
            }
            self.origin[l] = Some(origin);
            let coverage = &mut level.coverage;
            let total = update_foam(&self.xz[l], origin, s, l, &input, foam, coverage);
            level.spacing = s;
            level.origin = origin;
            level.mean = total / foam.len() as f32;
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

/// The Jacobian of each lattice cell, the foam update, and level 0 of the R8 coverage; returns
/// the sum of the foam (for the mean).
fn update_foam(
    xz: &[[f32; 2]],
    origin: [i32; 2],
    spacing: f32,
    level: usize,
    input: &WhitecapInput<'_>,
    foam: &mut [f32],
    coverage: &mut [u8],
) -> f32 {
    let t = WHITECAP_TEXELS;
    let side = t + 2;
    let keep = (-input.foam.decay * input.dt).exp();
    let stress = (input.wind_speed / 10.0).powi(2);
    let grow = WHITECAP_GROWTH_AT_10 * stress * input.dt;
    let threshold = WHITECAP_THRESHOLD[level];
    // Central differences over one lattice step on each side.
    let inv = 0.5 / spacing;
    let k = FoamConsts {
        inv,
        keep,
        grow,
        threshold,
    };
    // The window's column k is stored at slot(origin + k): two contiguous runs per row, the
    // second wrapping to the storage's start, so each run is a plain loop that vectorizes.
    let wrap = t - slot(origin[0]);
    let mut row_sums = [0.0f32; WHITECAP_TEXELS];
    foam.par_chunks_mut(t)
        .zip(coverage[..t * t].par_chunks_mut(t))
        .zip(row_sums.par_iter_mut())
        .enumerate()
        .for_each(|(storage_row, ((frow, crow), sum))| {
            // The window's lattice row j stored in this row: j ≡ storage_row (mod T).
            let j = origin[1] + (storage_row as i32 - origin[1]).rem_euclid(t as i32);
            let r = (j - origin[1]) as usize + 1;
            let rows = [
                &xz[(r - 1) * side..r * side],
                &xz[r * side..(r + 1) * side],
                &xz[(r + 1) * side..(r + 2) * side],
            ];
            let (f_end, f_start) = frow.split_at_mut(t - wrap);
            let (c_end, c_start) = crow.split_at_mut(t - wrap);
            // Window columns 0..wrap sit at slots T − wrap..T, the rest at 0..T − wrap.
            foam_run(rows.map(|v| &v[..wrap + 2]), f_start, c_start, k);
            foam_run(rows.map(|v| &v[wrap..]), f_end, c_end, k);
            *sum = lane_sum(frow);
        });
    lane_sum(&row_sums)
}

/// The sum of `v` in eight interleaved partial sums (a serial f32 sum is one add latency per
/// element; this vectorizes).
fn lane_sum(v: &[f32]) -> f32 {
    let mut lanes = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let tail: f32 = chunks.remainder().iter().sum();
    for c in chunks {
        for (l, x) in lanes.iter_mut().zip(c) {
            *l += x;
        }
    }
    lanes.iter().sum::<f32>() + tail
}

/// The per-step constants of the foam update.
#[derive(Clone, Copy)]
struct FoamConsts {
    /// 1 / (2·spacing): central differences over one lattice step on each side.
    inv: f32,
    keep: f32,
    grow: f32,
    threshold: f32,
}

/// The Jacobian and foam update of a run of `foam.len()` consecutive window columns, whose
/// summed displacement (with a one-point border) is `rows` = [up, mid, down].
#[inline]
fn foam_run(rows: [&[[f32; 2]]; 3], foam: &mut [f32], coverage: &mut [u8], k: FoamConsts) {
    let len = foam.len();
    let [up, mid, down] = rows.map(|r| &r[..len + 2]);
    let coverage = &mut coverage[..len];
    for i in 0..len {
        let x = i + 1;
        let dxx = (mid[x + 1][0] - mid[x - 1][0]) * k.inv;
        let dzx = (mid[x + 1][1] - mid[x - 1][1]) * k.inv;
        let dxz = (down[x][0] - up[x][0]) * k.inv;
        let dzz = (down[x][1] - up[x][1]) * k.inv;
        let jacobian = (1.0 + dxx) * (1.0 + dzz) - dxz * dzx;
        let f = (foam[i] * k.keep + k.grow * (k.threshold - jacobian).max(0.0)).min(1.0);
        foam[i] = f;
        coverage[i] = (f * 255.0 + 0.5) as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::config::OceanConfig;
    use crate::sim::surface::FloatCopies;
    use half::f16;

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
        let mut state = WhitecapState::new(config.grid);
        let mut out = Whitecaps::default();
        fn input(c: &[CascadeSurface]) -> WhitecapInput<'_> {
            WhitecapInput {
                cascades: c,
                focus: [3.0, -7.0],
                foam: FoamParams::default(),
                wind_speed: 10.0,
                drift: [0.0; 2],
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
    fn foam_drifts_with_the_surface() {
        let config = OceanConfig::single(16, 10.0).unwrap();
        let mut cascades = flat(&config);
        let mut state = WhitecapState::new(config.grid);
        let mut out = Whitecaps::default();
        fn input(c: &[CascadeSurface], drift: [f32; 2]) -> WhitecapInput<'_> {
            WhitecapInput {
                cascades: c,
                focus: [3.0, -7.0],
                foam: FoamParams::default(),
                wind_speed: 10.0,
                drift,
                dt: 0.1,
            }
        }
        // Foam in bands across x (as in the test above), made while the surface stands still.
        let n = config.grid.n();
        let k = std::f32::consts::TAU / 10.0;
        let mut compressed = flat(&config);
        for (i, d) in compressed[0].displacement_f16.iter_mut().enumerate() {
            let x = (i % n) as f32 * 10.0 / n as f32;
            d[0] = f16::from_f32(-1.5 * (k * x).sin());
        }
        for _ in 0..20 {
            state.update(input(&compressed, [0.0; 2]), &mut out);
        }
        let xs: Vec<f32> = (0..40).map(|i| i as f32 * 0.5).collect();
        let before: Vec<f32> = xs
            .iter()
            .map(|&x| out.coverage_at(x, -7.0).unwrap())
            .collect();
        // Then a calm sea (no new foam) drifting 1.5 m/s along x for 2 s: the bands are 3 m
        // downstream, faded by the decay, and not where they were.
        for c in &mut cascades {
            c.displacement_f16.fill([f16::ZERO; 4]);
        }
        for _ in 0..20 {
            state.update(input(&cascades, [1.5, 0.0]), &mut out);
        }
        assert!((out.drift[0] - 3.0).abs() < 1e-4 && out.drift[1] == 0.0);
        let keep = (-FoamParams::default().decay * 2.0).exp();
        let (mut moved, mut stayed) = (0.0f32, 0.0f32);
        for (&x, &b) in xs.iter().zip(&before) {
            let after = out.coverage_at(x + 3.0, -7.0).unwrap();
            moved = moved.max((after - b * keep).abs());
            stayed = stayed.max((out.coverage_at(x, -7.0).unwrap() - b * keep).abs());
        }
        assert!(before.iter().any(|&b| b * keep > 0.2), "{before:?}");
        assert!(moved < 2.0 / 255.0, "{moved}");
        assert!(stayed > 0.2, "{stayed}");
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
