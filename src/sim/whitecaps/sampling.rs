//! Sampling the cascades at the whitecap lattices: each cascade's (Dx, Dz) as f32, box-filtered
//! down to the mip whose texels match a lattice's spacing, then bilinear at the lattice points.
//!
//! Point samples of a cascade whose texels are much finer than the lattice alias: the 16 m
//! cascade's decimetre waves, sampled every 2 m, fold into a compression pattern of metres that
//! the sea does not have. The Jacobian of a lattice cell is meant to see only the waves the
//! cell resolves (see the module above), so each cascade is sampled from the mip whose texel
//! size L/N·2^m is nearest the spacing on a log scale: its 2^m × 2^m box average removes what
//! the lattice cannot hold. (It saves no time: the bilinear at every lattice point is
//! compute-bound, and building the mips costs ~0.03 ms per step for three cascades.)

use half::slice::HalfFloatSliceExt;
use rayon::prelude::*;

use crate::sim::grid::GridSize;
use crate::sim::surface::CascadeSurface;

/// Whitecap levels: a fine one near the viewer and a coarse one out to the mid distance.
pub const WHITECAP_LEVELS: usize = 2;

/// Lattice spacing (m) of each level: level 0 covers ±64 m around the viewer at 0.5 m, level 1
/// ±256 m at 2 m. Beyond, the renderer uses level 1's mean coverage.
pub const WHITECAP_SPACING: [f32; WHITECAP_LEVELS] = [0.5, 2.0];

/// Texels per side of each whitecap level.
pub const WHITECAP_TEXELS: usize = 256;

/// One cascade's (Dx, Dz) as f32: level 0 and the box-filtered mips the lattices sample, each
/// level row-major right after the previous one. Converted once per cascade and step (converting
/// the 8 halves of each bilinear sample cost ~4 ms per cascade and step at N = 256 on Zen 3).
pub(super) struct DisplacementMips {
    texels: Vec<[f32; 2]>,
    /// Level-0 side of the cascade last loaded.
    n: usize,
}

impl DisplacementMips {
    /// Room for every mip [`mip_for`] can pick on `grid`.
    pub fn new(grid: GridSize) -> Self {
        let n = grid.n();
        Self {
            texels: vec![[0.0; 2]; level_offset(n, deepest(n) + 1)],
            n,
        }
    }

    /// Loads cascade `c`'s (Dx, Dz) and builds its mips 1..=`top`. Allocates only for a grid
    /// larger than the one the pyramid was made for.
    pub fn load(&mut self, c: &CascadeSurface, top: u32) {
        let n = c.grid.n();
        let len = level_offset(n, top + 1);
        if self.texels.len() < len {
            self.texels.resize(len, [0.0; 2]);
        }
        self.n = n;
        load_dxz(c, &mut self.texels[..n * n]);
        for m in 1..=top {
            let (from, src_side) = (level_offset(n, m - 1), n >> (m - 1));
            let (to, side) = (level_offset(n, m), n >> m);
            let (lo, hi) = self.texels.split_at_mut(to);
            box_average(
                &lo[from..from + src_side * src_side],
                &mut hi[..side * side],
                side,
            );
        }
    }

    /// Mip `m` (built by the last [`DisplacementMips::load`]) of a cascade of patch `patch` m.
    pub fn level(&self, m: u32, patch: f32) -> MipView<'_> {
        let side = self.n >> m;
        let at = level_offset(self.n, m);
        let cell = (1u32 << m) as f32;
        MipView {
            texels: &self.texels[at..at + side * side],
            side,
            scale: side as f32 / patch,
            offset: (cell - 1.0) / (2.0 * cell),
        }
    }
}

/// One mip of a cascade's (Dx, Dz), for [`add_cascade`]: texel coordinate u = x·scale − offset
/// at world x. A mip-m texel averages level-0 texels i·2^m .. (i + 1)·2^m − 1, whose centre lies
/// (2^m − 1)/2 level-0 texels past the first (level-0 texel c sits at world c·L/N).
#[derive(Clone, Copy)]
pub(super) struct MipView<'a> {
    pub texels: &'a [[f32; 2]],
    /// Texels per side.
    pub side: usize,
    /// Texels per metre.
    pub scale: f32,
    /// (2^m − 1)/2^(m+1) texels: 0 at level 0.
    pub offset: f32,
}

/// The mip of a cascade of `n` texels over `patch` m whose texel size is nearest `spacing` (m)
/// on a log scale: round(log2(spacing·N/L)), at least level 0, at most the 2×2 level.
pub(super) fn mip_for(n: usize, patch: f32, spacing: f32) -> u32 {
    let m = (spacing * n as f32 / patch).log2().round();
    (m.max(0.0) as u32).min(deepest(n))
}

/// The deepest mip [`mip_for`] picks on an n-grid: 2×2 texels.
fn deepest(n: usize) -> u32 {
    n.trailing_zeros() - 1
}

/// Offset of mip `m` in a pyramid of level-0 side `n`.
fn level_offset(n: usize, m: u32) -> usize {
    (0..m).map(|l| (n >> l) * (n >> l)).sum()
}

/// Each texel of `dst` (`side` × `side`) the mean of its 2×2 block of `src` (twice the side).
fn box_average(src: &[[f32; 2]], dst: &mut [[f32; 2]], side: usize) {
    let src_side = 2 * side;
    for (y, row) in dst.chunks_exact_mut(side).enumerate() {
        let a = &src[2 * y * src_side..(2 * y + 1) * src_side];
        let b = &src[(2 * y + 1) * src_side..(2 * y + 2) * src_side];
        for (x, o) in row.iter_mut().enumerate() {
            for k in 0..2 {
                o[k] = (a[2 * x][k] + a[2 * x + 1][k] + b[2 * x][k] + b[2 * x + 1][k]) * 0.25;
            }
        }
    }
}

/// Cascade `c`'s (Dx, Dz) into `dxz` as f32: from its f32 copy when kept, else converted
/// from RGBA16F a row at a time (F16C or NEON where the CPU has it, through `half`).
fn load_dxz(c: &CascadeSurface, dxz: &mut [[f32; 2]]) {
    let n = c.grid.n();
    if c.displacement.len() == dxz.len() {
        dxz.par_chunks_mut(n)
            .zip(c.displacement.par_chunks(n))
            .for_each(|(out, row)| {
                for (o, d) in out.iter_mut().zip(row) {
                    *o = [d[0], d[2]];
                }
            });
        return;
    }
    // One row buffer per rayon job, not per row (it is 16 KiB to clear).
    let buffer = || [[0.0f32; 4]; GridSize::MAX as usize];
    dxz.par_chunks_mut(n)
        .zip(c.displacement_f16.par_chunks(n))
        .for_each_init(buffer, |floats, (out, row)| {
            let floats = &mut floats[..n];
            row.as_flattened()
                .convert_to_f32_slice(floats.as_flattened_mut());
            for (o, d) in out.iter_mut().zip(floats.iter()) {
                *o = [d[0], d[2]];
            }
        });
}

/// floor(u) as a texel index wrapped by `mask`, and u − floor(u): the bits of `f32::floor`
/// (exact: |u| < 2²³ truncates exactly, larger f32 are whole) without libm's `floorf` call,
/// which x86-64's baseline (no SSE4.1 rounding) made for every sample.
#[inline]
fn split(u: f32, mask: i64) -> (usize, f32) {
    let t = u as i64;
    let floor = t - i64::from(u < t as f32);
    ((floor & mask) as usize, u - floor as f32)
}

/// Where a level's window of lattice points lies: points origin .. origin + T (and a one-point
/// border) at rest positions (i·s, j·s) + drift.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lattice {
    /// Lattice index of the window's first point (x, z).
    pub origin: [i32; 2],
    /// Spacing s (m).
    pub spacing: f32,
    /// Rest position of lattice point (0, 0) (m): how far the surface has drifted.
    pub drift: [f32; 2],
}

impl Lattice {
    /// Rest position along axis `a` of the window's border point `k` (index origin − 1 + k).
    #[inline]
    fn at(&self, a: usize, k: usize) -> f32 {
        (self.origin[a] - 1 + k as i32) as f32 * self.spacing + self.drift[a]
    }
}

/// Adds the bilinear (Dx, Dz) of one cascade's mip `view` at the points of `lattice` (with
/// their border) to `xz`, separably: the lattice columns' texel columns and weights are the
/// same in every row (computed once), so each texel row is sampled along x once
/// ([`HeldRows`]) and a lattice row blends two of them. The same operations in the same order
/// as a bilinear per point, so the same bits.
pub(super) fn add_cascade(view: MipView<'_>, lattice: Lattice, xz: &mut [[f32; 2]]) {
    const SIDE: usize = WHITECAP_TEXELS + 2;
    let n = view.side;
    let mask = n as i64 - 1;
    let (scale, offset, dxz) = (view.scale, view.offset, view.texels);
    let mut cols = [(0usize, 0usize, 0.0f32); SIDE];
    for (i, col) in cols.iter_mut().enumerate() {
        let (c0, tu) = split(lattice.at(0, i) * scale - offset, mask);
        *col = (c0, (c0 + 1) & (n - 1), tu);
    }
    // Texel row `r` sampled at the lattice's columns, linear in x.
    let sample = |r: usize, out: &mut SampledRow| {
        let src = &dxz[r * n..(r + 1) * n];
        for (o, &(c0, c1, tu)) in out.iter_mut().zip(&cols) {
            let (a, b) = (src[c0], src[c1]);
            for k in 0..2 {
                o[k] = a[k] + (b[k] - a[k]) * tu;
            }
        }
    };
    xz.par_chunks_mut(SIDE * ROWS_PER_TASK)
        .enumerate()
        .for_each(|(task, rows)| {
            let mut held = HeldRows {
                rows: [[[0.0; 2]; SIDE]; 2],
                texel_row: [None; 2],
            };
            for (i, row) in rows.chunks_exact_mut(SIDE).enumerate() {
                let r = task * ROWS_PER_TASK + i;
                let (r0, tv) = split(lattice.at(1, r) * scale - offset, mask);
                let r1 = (r0 + 1) & (n - 1);
                let (top, bottom) = held.pair(r0, r1, &sample);
                for ((acc, t), b) in row.iter_mut().zip(top).zip(bottom) {
                    for k in 0..2 {
                        acc[k] += t[k] + (b[k] - t[k]) * tv;
                    }
                }
            }
        });
}

/// Lattice rows per task of [`add_cascade`] (each task starts with no texel row held).
const ROWS_PER_TASK: usize = 32;

/// One texel row sampled along x at the lattice's columns (border included).
type SampledRow = [[f32; 2]; WHITECAP_TEXELS + 2];

/// The two texel rows (sampled along x) that [`add_cascade`]'s last lattice row blended, and
/// which texel row each is. The mip's texels are about the lattice's spacing, so the next
/// lattice row needs at most one new one.
struct HeldRows {
    rows: [SampledRow; 2],
    texel_row: [Option<usize>; 2],
}

impl HeldRows {
    /// Texel rows `r0` and `r1` (different), sampled by `sample` unless already held.
    fn pair(
        &mut self,
        r0: usize,
        r1: usize,
        sample: &impl Fn(usize, &mut SampledRow),
    ) -> (&SampledRow, &SampledRow) {
        debug_assert_ne!(r0, r1);
        let holds = |slot: usize, r: usize| self.texel_row[slot] == Some(r);
        // Keep the slot that holds r0, else the one that holds r1; resample the other.
        let top = usize::from(!(holds(0, r0) || (!holds(1, r0) && holds(1, r1))));
        let bottom = 1 - top;
        for (slot, r) in [(top, r0), (bottom, r1)] {
            if self.texel_row[slot] != Some(r) {
                sample(r, &mut self.rows[slot]);
                self.texel_row[slot] = Some(r);
            }
        }
        (&self.rows[top], &self.rows[bottom])
    }
}

/// [`add_cascade`] one point at a time: the reference its separable bits are tested against.
#[cfg(test)]
fn add_cascade_per_point(view: MipView<'_>, lattice: Lattice, xz: &mut [[f32; 2]]) {
    let side = WHITECAP_TEXELS + 2;
    let n = view.side;
    let mask = n as i64 - 1;
    for (r, row) in xz.chunks_mut(side).enumerate() {
        let (r0, tv) = split(lattice.at(1, r) * view.scale - view.offset, mask);
        let r1 = (r0 + 1) & (n - 1);
        for (i, acc) in row.iter_mut().enumerate() {
            let (c0, tu) = split(lattice.at(0, i) * view.scale - view.offset, mask);
            let c1 = (c0 + 1) & (n - 1);
            let at = |r: usize, c: usize| view.texels[r * n + c];
            let (a, b, e, f) = (at(r0, c0), at(r0, c1), at(r1, c0), at(r1, c1));
            for k in 0..2 {
                let top = a[k] + (b[k] - a[k]) * tu;
                let bottom = e[k] + (f[k] - e[k]) * tu;
                acc[k] += top + (bottom - top) * tv;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::surface::FloatCopies;
    use half::f16;

    /// The bit patterns of `v`, for exact comparisons.
    fn bits(v: &[[f32; 2]]) -> Vec<[u32; 2]> {
        v.iter().map(|p| p.map(f32::to_bits)).collect()
    }

    /// Level 0 holds each texel's (Dx, Dz) exactly as the surface has it (the f32 copy when
    /// kept, else the halves), and sampling it gives the bits of a bilinear per point, for
    /// every default cascade and both spacings, anywhere in the world.
    #[test]
    fn level_zero_is_the_surface_and_samples_like_the_bilinear_per_point() {
        let grid = GridSize::new(64).unwrap();
        let mut seed = 0x9e37_79b9u32;
        let mut noise = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 4.0 - 2.0
        };
        for keep in [FloatCopies::Skip, FloatCopies::Keep] {
            let mut cascades: Vec<CascadeSurface> = [257.0, 69.5, 16.1]
                .map(|l| CascadeSurface::new(grid, l, keep))
                .into();
            for c in &mut cascades {
                for i in 0..grid.texels() {
                    let d = [noise(), noise(), noise(), noise()];
                    c.displacement_f16[i] = d.map(f16::from_f32);
                    if let Some(f) = c.displacement.get_mut(i) {
                        *f = d;
                    }
                }
            }
            let mut mips = DisplacementMips::new(grid);
            let side = WHITECAP_TEXELS + 2;
            for c in &cascades {
                mips.load(c, 0);
                let level = mips.level(0, c.patch);
                for (i, got) in level.texels.iter().enumerate() {
                    let want = match c.displacement.get(i) {
                        Some(d) => [d[0], d[2]],
                        None => {
                            [c.displacement_f16[i][0], c.displacement_f16[i][2]].map(f16::to_f32)
                        }
                    };
                    assert!(bits(&[*got]) == bits(&[want]), "{keep:?} texel {i}");
                }
                for focus in [[0.0, 0.0], [-1234.56, 98765.4], [3.3e5, -7.1e4]] {
                    for (l, &s) in WHITECAP_SPACING.iter().enumerate() {
                        let t = WHITECAP_TEXELS as i32;
                        let origin = [
                            (focus[0] / s).floor() as i32 - t / 2,
                            (focus[1] / s).floor() as i32 - t / 2,
                        ];
                        let (mut got, mut want) = (
                            vec![[0.25f32; 2]; side * side],
                            vec![[0.25; 2]; side * side],
                        );
                        let lattice = Lattice {
                            origin,
                            spacing: s,
                            drift: [0.0; 2],
                        };
                        add_cascade(level, lattice, &mut got);
                        add_cascade_per_point(level, lattice, &mut want);
                        assert!(
                            bits(&got) == bits(&want),
                            "{keep:?} patch {} {focus:?} level {l}",
                            c.patch
                        );
                    }
                }
            }
        }
    }

    /// The separable sampling gives the bits of a bilinear per point on every mip, at both
    /// spacings, anywhere in the world (texel rows shared by lattice rows or not).
    #[test]
    fn separable_sampling_gives_the_bits_of_the_bilinear_per_point() {
        let grid = GridSize::new(64).unwrap();
        let mut c = CascadeSurface::new(grid, 16.1, FloatCopies::Keep);
        for (i, d) in c.displacement.iter_mut().enumerate() {
            let x = i as f32 * 0.37;
            *d = [x.sin(), 0.0, (1.3 * x).cos(), 0.0];
        }
        let mut mips = DisplacementMips::new(grid);
        mips.load(&c, deepest(64));
        let side = WHITECAP_TEXELS + 2;
        for m in 0..=deepest(64) {
            for &s in &WHITECAP_SPACING {
                for (origin, drift) in [
                    ([-128, -128], [0.0, 0.0]),
                    ([1000, -37], [0.123, -7.9]),
                    ([-90_000, 41_000], [-1234.5, 17.25]),
                ] {
                    let view = mips.level(m, c.patch);
                    let (mut got, mut want) =
                        (vec![[0.5f32; 2]; side * side], vec![[0.5; 2]; side * side]);
                    let lattice = Lattice {
                        origin,
                        spacing: s,
                        drift,
                    };
                    add_cascade(view, lattice, &mut got);
                    add_cascade_per_point(view, lattice, &mut want);
                    assert!(
                        bits(&got) == bits(&want),
                        "mip {m}, spacing {s}, origin {origin:?}, drift {drift:?}"
                    );
                }
            }
        }
    }

    /// A mip texel is the mean of its block of level-0 texels.
    #[test]
    fn mips_are_box_averages() {
        let grid = GridSize::new(32).unwrap();
        let mut c = CascadeSurface::new(grid, 8.0, FloatCopies::Keep);
        for (i, d) in c.displacement.iter_mut().enumerate() {
            *d = [(i % 7) as f32 - 3.0, 0.0, (i % 11) as f32 * 0.5, 0.0];
        }
        let mut mips = DisplacementMips::new(grid);
        mips.load(&c, 3);
        for m in 1..=3u32 {
            let v = mips.level(m, c.patch);
            let cell = 1usize << m;
            assert_eq!(v.side, 32 / cell);
            for (t, got) in v.texels.iter().enumerate() {
                let (x, y) = (t % v.side, t / v.side);
                let mut want = [0.0f64; 2];
                for j in y * cell..(y + 1) * cell {
                    for i in x * cell..(x + 1) * cell {
                        let d = c.displacement[j * 32 + i];
                        want[0] += d[0] as f64;
                        want[1] += d[2] as f64;
                    }
                }
                for k in 0..2 {
                    let want = want[k] / (cell * cell) as f64;
                    assert!((got[k] as f64 - want).abs() < 1e-5, "mip {m} texel {t}");
                }
            }
        }
    }

    /// Waves shorter than twice the coarse lattice's spacing hardly reach it (point samples
    /// alias them at full amplitude); waves a lattice resolves do. Near a lattice's Nyquist
    /// the bilinear between mip texels attenuates too (a 1.6 m wave at 0.5 m: the box keeps
    /// 0.85, the interpolation between texels 0.44 apart ~0.57), as a GPU's mip sampling would.
    #[test]
    fn the_lattices_see_only_the_waves_they_resolve() {
        let grid = GridSize::new(256).unwrap();
        // A 16 m patch (6.25 cm texels) holding one wave along x of wavelength `lambda`.
        let amplitude_at = |lambda: f32, level: usize| -> f32 {
            let mut c = CascadeSurface::new(grid, 16.0, FloatCopies::Skip);
            let k = std::f32::consts::TAU / lambda;
            for (i, d) in c.displacement_f16.iter_mut().enumerate() {
                let x = (i % 256) as f32 * 16.0 / 256.0;
                d[0] = f16::from_f32((k * x).sin());
            }
            let s = WHITECAP_SPACING[level];
            let m = mip_for(256, c.patch, s);
            let mut mips = DisplacementMips::new(grid);
            mips.load(&c, m);
            let mut xz = vec![[0.0f32; 2]; (WHITECAP_TEXELS + 2).pow(2)];
            let lattice = Lattice {
                origin: [-128, -128],
                spacing: s,
                drift: [0.0; 2],
            };
            add_cascade(mips.level(m, c.patch), lattice, &mut xz);
            xz.iter().map(|p| p[0].abs()).fold(0.0, f32::max)
        };
        // 1.6 m: beyond the 2 m lattice's Nyquist (4 m), within the 0.5 m one's (1 m).
        let (coarse, fine) = (amplitude_at(1.6, 1), amplitude_at(1.6, 0));
        assert!(
            coarse < 0.25,
            "a 1.6 m wave at the 2 m lattice: amplitude {coarse}"
        );
        assert!(
            fine > 0.4,
            "a 1.6 m wave at the 0.5 m lattice: amplitude {fine}"
        );
        // Well resolved: 4 m at the fine lattice, 16 m at the coarse one.
        let (four, sixteen) = (amplitude_at(4.0, 0), amplitude_at(16.0, 1));
        assert!(
            four > 0.85,
            "a 4 m wave at the 0.5 m lattice: amplitude {four}"
        );
        assert!(
            sixteen > 0.85,
            "a 16 m wave at the 2 m lattice: amplitude {sixteen}"
        );
    }
}
