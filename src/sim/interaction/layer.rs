//! The layer's state and its step (see the [module docs](super)): h and φ as one complex
//! field, the absorbing band, foam, and what is drawn and queried.

use super::modes::{ModeTable, MAX_N};
use super::source::{footprint, WaveSource, FOOTPRINT_AREA};
use super::{InteractionConfig, FOAM_LIFETIME_S, FOAM_SLOPE, SURFACE_TENSION};
use crate::sim::fft::Fft2d;
use crate::sim::grid::{AlignedBuf, SplitField};
use crate::sim::surface::f16_row::interleave_f16;

/// Damping rate at the outer edge of the absorbing band (1/s), rising as the square of the
/// depth into it: over the default band (5 m) a 1-4 m wave is absorbed with < 5 % of its
/// energy sent back (`tests.rs` measures it).
const SPONGE_RATE: f32 = 6.0;

/// Foam added per step and unit of slope above [`FOAM_SLOPE`].
const FOAM_PER_SLOPE: f32 = 0.25;

/// Steepest slope a wave keeps (Stokes's limit, H/λ = 1/7, is a·k = π/7 ≈ 0.45): where the
/// layer is steeper outside the sources' footprints, the wave breaks: h of the cell is scaled
/// down to it (φ kept: the potential energy goes, the kinetic cannot grow) and the energy lost
/// becomes foam. Linear theory alone let a 1 m sphere
/// towed at 1.2 m/s raise a 1.4 m wake; the sea breaks long before.
const BREAK_SLOPE: f32 = 0.44;

/// Foam made per unit of a cell's amplitude lost to breaking.
const FOAM_PER_BREAK: f32 = 2.0;

/// Numbers of the last step, for tests, tools and the performance line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InteractionStats {
    /// Wave energy in the layer before the step's damping (J, sea water's density).
    pub energy_j: f64,
    /// Sources applied (invalid ones skipped).
    pub sources: usize,
}

/// A local, dispersive wave field that follows the viewer. See the [module docs](super).
pub struct InteractionLayer {
    config: InteractionConfig,
    fft: Fft2d,
    modes: ModeTable,
    /// Between steps: h − iφ (re = h, im = −φ).
    field: SplitField,
    scratch: SplitField,
    /// Per row or column: how deep into the absorbing band it is, 0 (inside) to the band's
    /// width (the outermost); a cell's level is the larger of its row's and column's.
    level: Vec<usize>,
    /// Per row level: the row's damping factors for one step, times 1/N² (the transform's
    /// scale), N per level.
    damp: Vec<f32>,
    /// Per row level: the row's fade of what is drawn and queried, 1 inside, 0 at the edge.
    window: Vec<f32>,
    /// Drawn and queried: h·window (m), and foam (0..1).
    height: AlignedBuf,
    foam: AlignedBuf,
    /// 1 in cells a source pressed this step (no breaking there: its hollow is held), else 0.
    forced: Vec<u8>,
    /// RGBA16F (h, ∂h/∂x, ∂h/∂z, foam) of the four planes above, for the renderer.
    texels: Vec<[u16; 4]>,
    /// World position of cell (0, 0) in cells.
    origin: [i64; 2],
    time: f64,
    stats: InteractionStats,
}

impl InteractionLayer {
    /// A calm layer with cell (N/2, N/2) at world (`x`, `z`) rounded to a cell.
    pub fn new(config: InteractionConfig, x: f32, z: f32) -> Self {
        let size = config.cells;
        let n = size.n();
        let fft = Fft2d::new(size);
        fft.prepare_threads();
        let modes = ModeTable::new(
            size,
            config.cell_m,
            config.dt,
            config.gravity,
            SURFACE_TENSION,
        );
        let band = config.sponge_cells();
        let level: Vec<usize> = (0..n)
            .map(|i| band.saturating_sub(i.min(n - 1 - i)))
            .collect();
        let scale = 1.0 / (n * n) as f32;
        // u: depth into the band, 0 inside, 1 at the outermost cell.
        let (per_level_damp, per_level_window): (Vec<f32>, Vec<f32>) = (0..=band)
            .map(|l| {
                let u = l as f32 / band as f32;
                let damp = (-SPONGE_RATE * u * u * config.dt).exp() * scale;
                // Faded over the band's inner two thirds: zero where the damping is strongest.
                let v = (u * 1.5).min(1.0);
                (damp, 1.0 - v * v * (3.0 - 2.0 * v))
            })
            .unzip();
        let rows = |per_level: &[f32]| -> Vec<f32> {
            (0..=band)
                .flat_map(|lr| {
                    let level = &level;
                    (0..n).map(move |c: usize| per_level[lr.max(level[c])])
                })
                .collect()
        };
        let (damp, window) = (rows(&per_level_damp), rows(&per_level_window));
        let mut layer = Self {
            config,
            fft,
            modes,
            field: SplitField::zeros(size),
            scratch: SplitField::zeros(size),
            level,
            damp,
            window,
            height: AlignedBuf::zeros(n * n),
            foam: AlignedBuf::zeros(n * n),
            forced: vec![0; n * n],
            texels: vec![[0; 4]; n * n],
            origin: [0; 2],
            time: 0.0,
            stats: InteractionStats::default(),
        };
        layer.origin = layer.origin_for(x, z);
        layer
    }

    /// The configuration.
    pub fn config(&self) -> &InteractionConfig {
        &self.config
    }

    /// Time stepped so far (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Numbers of the last step.
    pub fn stats(&self) -> InteractionStats {
        self.stats
    }

    /// World (x, z) of cell (0, 0) (m).
    pub fn origin_m(&self) -> [f32; 2] {
        let c = self.config.cell_m as f64;
        [
            (self.origin[0] as f64 * c) as f32,
            (self.origin[1] as f64 * c) as f32,
        ]
    }

    /// The drawn heights h·window (m), row-major, row = z, column = x.
    pub fn heights(&self) -> &[f32] {
        &self.height
    }

    /// RGBA16F texels (h, ∂h/∂x, ∂h/∂z, foam) as binary16 bits, row-major: the renderer's.
    pub fn texels(&self) -> &[[u16; 4]] {
        &self.texels
    }

    /// The cell origin that centres the layer on (x, z).
    fn origin_for(&self, x: f32, z: f32) -> [i64; 2] {
        let half = (self.config.cells.n() / 2) as i64;
        let cell = |v: f32| (v as f64 / self.config.cell_m as f64).round() as i64;
        [cell(x) - half, cell(z) - half]
    }

    /// Moves the layer by whole cells so that (x, z) is near its centre; the waves stay where
    /// they are in the world (cells that come in are calm). A non-finite point is ignored.
    pub fn recentre(&mut self, x: f32, z: f32) {
        if !(x.is_finite() && z.is_finite()) {
            return;
        }
        let to = self.origin_for(x, z);
        let (dx, dz) = (to[0] - self.origin[0], to[1] - self.origin[1]);
        if dx == 0 && dz == 0 {
            return;
        }
        self.origin = to;
        let n = self.config.cells.n();
        for plane in [
            &mut self.field.re,
            &mut self.field.im,
            &mut self.height,
            &mut self.foam,
        ] {
            shift(plane, n, dx, dz);
        }
        self.draw(None);
    }

    /// One step of `dt`: the sources, the exact rotation of every mode, the absorbing band,
    /// foam and the drawn fields. Allocates nothing.
    pub fn step(&mut self, sources: &[WaveSource]) {
        let n = self.config.cells.n();
        let (cell, dt, g) = (self.config.cell_m, self.config.dt, self.config.gravity);
        let mut applied = 0;
        for s in sources.iter().filter(|s| s.is_valid()) {
            applied += 1;
            let reach_m = s.reach(cell);
            let head = s.volume / (FOOTPRINT_AREA * reach_m * reach_m);
            // The field holds −φ: φ −= g·dt·P becomes += ; an impulse pushes water down.
            let (push, kick) = (g * dt * head, s.impulse);
            let cx = s.x / cell - self.origin[0] as f32;
            let cz = s.z / cell - self.origin[1] as f32;
            let reach = reach_m / cell;
            let c0 = (cx - reach).floor().max(0.0) as usize;
            let c1 = ((cx + reach).ceil().max(0.0) as usize).min(n - 1);
            let r0 = (cz - reach).floor().max(0.0) as usize;
            let r1 = ((cz + reach).ceil().max(0.0) as usize).min(n - 1);
            if cx + reach < 0.0 || cz + reach < 0.0 || c0 > c1 || r0 > r1 {
                continue;
            }
            for row in r0..=r1 {
                for col in c0..=c1 {
                    let d = ((col as f32 - cx).powi(2) + (row as f32 - cz).powi(2)).sqrt();
                    let w = footprint(d / reach);
                    if w > 0.0 {
                        let i = row * n + col;
                        self.field.im[i] += (push + kick) * w;
                        self.foam[i] = (self.foam[i] + s.foam * w).min(1.0);
                        self.forced[i] = 1;
                    }
                }
            }
        }
        // Forward transform (of h − iφ: the conjugate), rotate, back.
        self.fft.inverse(&mut self.field, &mut self.scratch);
        let energy = self.modes.rotate(&mut self.field);
        self.fft.inverse(&mut self.field, &mut self.scratch);
        // Scale and damp; keep h − iφ; the drawn height.
        let (level, damp, window) = (&self.level, &self.damp, &self.window);
        self.field
            .re
            .chunks_mut(n)
            .zip(self.field.im.chunks_mut(n))
            .zip(self.height.chunks_mut(n))
            .enumerate()
            .for_each(|(row, ((re, im), out))| {
                let at = level[row] * n..(level[row] + 1) * n;
                let (d, w) = (&damp[at.clone()], &window[at]);
                for c in 0..n {
                    re[c] *= d[c];
                    im[c] *= -d[c];
                    out[c] = re[c] * w[c];
                }
            });
        self.draw(Some((-dt / FOAM_LIFETIME_S).exp()));
        let rho = 1025.0;
        let area = (cell as f64).powi(2);
        self.stats = InteractionStats {
            // Parseval: Σ_x h² = Σ_k |ĥ_k|² / N² for the unnormalized transform.
            energy_j: 0.5 * rho * area * energy / (n * n) as f64,
            sources: applied,
        };
        self.time += dt as f64;
    }

    /// The texels: central-difference slopes of the drawn height, and foam. After a step
    /// (`foam_decay` given) also the foam's life: decay, whitening where the slope passes
    /// [`FOAM_SLOPE`], breaking where it passes [`BREAK_SLOPE`] outside the sources'
    /// footprints.
    fn draw(&mut self, foam_decay: Option<f32>) {
        let n = self.config.cells.n();
        let inv = 0.5 / self.config.cell_m;
        let h = &self.height;
        let (level, window) = (&self.level, &self.window);
        self.texels
            .chunks_mut(n)
            .zip(self.foam.chunks_mut(n))
            .zip(self.forced.chunks_mut(n))
            .zip(self.field.re.chunks_mut(n))
            .enumerate()
            .for_each(|(row, (((out, foam), forced), re))| {
                let up = &h[row.saturating_sub(1) * n..][..n];
                let mid = &h[row * n..][..n];
                let down = &h[(row + 1).min(n - 1) * n..][..n];
                let mut sx = [0.0f32; MAX_N];
                let mut sz = [0.0f32; MAX_N];
                // Branch-free loops over plain slices: they vectorize.
                for ((s, r), l) in sx[1..n - 1].iter_mut().zip(&mid[2..]).zip(&mid[..n - 2]) {
                    *s = (r - l) * inv;
                }
                sx[0] = (mid[1] - mid[0]) * inv;
                sx[n - 1] = (mid[n - 1] - mid[n - 2]) * inv;
                for ((s, d), u) in sz[..n].iter_mut().zip(down).zip(up) {
                    *s = (d - u) * inv;
                }
                if let Some(decay) = foam_decay {
                    for c in 0..n {
                        let s = (sx[c] * sx[c] + sz[c] * sz[c]).sqrt();
                        // 1 where no source holds the cell (a body's own hollow is steep, not
                        // breaking); the share of h kept there.
                        let free = 1.0 - forced[c] as f32;
                        let whiten = free * FOAM_PER_SLOPE * (s - FOAM_SLOPE).max(0.0);
                        let keep = 1.0 - free * (1.0 - BREAK_SLOPE / s.max(BREAK_SLOPE));
                        re[c] *= keep;
                        foam[c] =
                            (foam[c] * decay + whiten + FOAM_PER_BREAK * (1.0 - keep)).min(1.0);
                        forced[c] = 0;
                    }
                }
                // Foam fades across the band as the height does: the texture is clamped, so
                // foam left in its outermost texels would streak out over the sea.
                let mut drawn_foam = [0.0f32; MAX_N];
                let w = &window[level[row] * n..(level[row] + 1) * n];
                for ((d, f), w) in drawn_foam[..n].iter_mut().zip(&foam[..]).zip(w) {
                    *d = f * w;
                }
                interleave_f16([mid, &sx[..n], &sz[..n], &drawn_foam[..n]], out);
            });
    }

    /// The drawn height (m) at world (x, z), bilinear; 0 outside the layer.
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        let n = self.config.cells.n();
        let u = x / self.config.cell_m - self.origin[0] as f32;
        let v = z / self.config.cell_m - self.origin[1] as f32;
        if !(u >= 0.0 && v >= 0.0 && u < (n - 1) as f32 && v < (n - 1) as f32) {
            return 0.0;
        }
        let (c, r) = (u as usize, v as usize);
        let (tu, tv) = (u - c as f32, v - r as f32);
        let h = &self.height;
        let i = r * n + c;
        let top = h[i] + (h[i + 1] - h[i]) * tu;
        let bottom = h[i + n] + (h[i + n + 1] - h[i + n]) * tu;
        top + (bottom - top) * tv
    }

    /// The layer's foam (0..1) at world (x, z), nearest cell; 0 outside.
    pub fn foam_at(&self, x: f32, z: f32) -> f32 {
        let n = self.config.cells.n() as i64;
        let c = (x as f64 / self.config.cell_m as f64).round() as i64 - self.origin[0];
        let r = (z as f64 / self.config.cell_m as f64).round() as i64 - self.origin[1];
        if (0..n).contains(&c) && (0..n).contains(&r) {
            self.foam[(r * n + c) as usize]
        } else {
            0.0
        }
    }
}

/// Moves an N × N plane's content by (−dx, −dz) cells (the origin moved by (dx, dz)): cell
/// (c, r) takes the old (c + dx, r + dz); cells with no old value become 0.
fn shift(plane: &mut [f32], n: usize, dx: i64, dz: i64) {
    let n_i = n as i64;
    if dx.abs() >= n_i || dz.abs() >= n_i {
        plane.fill(0.0);
        return;
    }
    // Rows in the order that never overwrites a row still to be read.
    let row_order = |k: i64| if dz >= 0 { k } else { n_i - 1 - k };
    for k in 0..n_i {
        let r = row_order(k);
        let src = r + dz;
        let dst = (r * n_i) as usize;
        if !(0..n_i).contains(&src) {
            plane[dst..dst + n].fill(0.0);
            continue;
        }
        let s = (src * n_i) as usize;
        // Within the row: copy columns c ← c + dx.
        if dx >= 0 {
            let d = dx as usize;
            plane.copy_within(s + d..s + n, dst);
            plane[dst + n - d..dst + n].fill(0.0);
        } else {
            let d = (-dx) as usize;
            plane.copy_within(s..s + n - d, dst + d);
            plane[dst..dst + d].fill(0.0);
        }
    }
}
