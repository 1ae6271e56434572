//! Stage 1 (thesis 4.2.1) in parts that a sea-state change can spread over many steps and
//! blend ([`crate::sim::retune`]):
//! - [`Lattice`]: a grid's random draws ξ (eq. 12) and loop harmonics (eq. 16);
//! - [`power_rows`]: each mode's expected power P = E|h₀(k)|² (eq. 13), row by row, on the
//!   spectrum's own grid or on one whose patch is whole octaves larger (a grown patch holds
//!   every wave vector of the smaller one);
//! - [`pack`]: h₀ = ξ·√(P/2) (eq. 13) of a blend of two power planes, packed as eq. 22;
//! - [`Moments`]: the variance and the slope variances of a power plane.
//!
//! Blending powers, not amplitudes, under the same ξ makes the sea's variance exactly linear
//! in the blend weight: the significant height moves monotonically to the new state's.

use std::ops::Range;

use rayon::prelude::*;

use crate::sim::dispersion;
use crate::sim::grid::{AlignedBuf, GridSize, Support};
use crate::sim::params::WaveParams;
use crate::sim::spectrum::{
    mode_power, power_at, rng, wave_vector, CascadeSpec, SlopeVariance, SpectrumModel, CAPILLARY_K,
};

/// One grid's random draws ξ (real and imaginary planes) and the loop harmonic of each
/// texel's wave vector (eq. 16); what stays when only the spectrum's shape changes.
pub struct Lattice {
    /// The grid's side.
    pub grid: GridSize,
    /// ξ's real and imaginary parts per texel, row-major.
    pub xi: [AlignedBuf; 2],
    /// Harmonic n of ω' = n·2π/T per texel (eq. 16).
    pub harmonic: Vec<u32>,
}

impl Lattice {
    /// An unfilled lattice for `grid`.
    pub fn zeros(grid: GridSize) -> Self {
        Self {
            grid,
            xi: std::array::from_fn(|_| AlignedBuf::zeros(grid.texels())),
            harmonic: vec![0; grid.texels()],
        }
    }

    /// Fills rows `rows` for cascade `spec` with `waves`' seed, depth and loop period, in
    /// parallel on the current Rayon pool (bit-identical whatever the thread count).
    pub fn fill_rows(&mut self, waves: &WaveParams, spec: &CascadeSpec, rows: Range<usize>) {
        let n = spec.grid.n();
        let span = rows.start * n..rows.end * n;
        let [re, im] = &mut self.xi;
        re[span.clone()]
            .par_chunks_mut(n)
            .zip(im[span.clone()].par_chunks_mut(n))
            .zip(self.harmonic[span].par_chunks_mut(n))
            .enumerate()
            .for_each(|(r, ((re, im), harm))| {
                let row = rows.start + r;
                for col in 0..n {
                    let (a, b) =
                        rng::gaussian_pair(waves.seed, spec.index, spec.draw_index(col, row));
                    re[col] = a as f32;
                    im[col] = b as f32;
                    let (kx, kz) = wave_vector(col, row, spec.grid, spec.patch);
                    let k = (kx * kx + kz * kz).sqrt();
                    harm[col] = dispersion::loop_harmonic(
                        dispersion::omega(k, waves.depth),
                        waves.loop_period,
                    );
                }
            });
    }
}

/// Fills rows `rows` of `out` (a plane of a grid whose patch is 2^`spread` times `target`'s,
/// same N) with the mode powers of `target` under `model`: a texel holds the target's mode
/// when its wave vector is one of the target grid's, else nothing. With `spread` 0 this is
/// [`mode_power`] on the target's own grid. Returns the rectangle of the non-zeros written.
pub fn power_rows(
    model: &SpectrumModel,
    target: &CascadeSpec,
    spread: u32,
    rows: Range<usize>,
    out: &mut [f32],
) -> Support {
    let n = target.grid.n();
    let half = (n / 2) as i32;
    let step = 1i32 << spread;
    out[rows.start * n..rows.end * n]
        .par_chunks_mut(n)
        .enumerate()
        .map(|(r, out)| {
            let row = rows.start + r;
            let mz = row as i32 - half;
            let mut cols = n..0;
            for (col, p) in out.iter_mut().enumerate() {
                let mx = col as i32 - half;
                // The Nyquist row and column have no Hermitian partner on this grid.
                *p = if col == 0 || row == 0 || mx % step != 0 || mz % step != 0 {
                    0.0
                } else {
                    let tc = (mx / step + half) as usize;
                    let tr = (mz / step + half) as usize;
                    mode_power(model, target, tc, tr) as f32
                };
                if *p != 0.0 {
                    cols = cols.start.min(col)..cols.end.max(col + 1);
                }
            }
            if cols.is_empty() {
                Support::empty()
            } else {
                Support {
                    rows: row..row + 1,
                    cols,
                }
            }
        })
        .reduce(Support::empty, |a, b| a.union(&b))
}

/// `s` and its mirror image k ↦ −k: where [`pack`] writes non-zeros for powers within `s`
/// (h₀(k) and h₀*(−k) share a texel).
pub fn mirror_closed(s: &Support, grid: GridSize) -> Support {
    if s.is_empty() {
        return Support::empty();
    }
    let n = grid.n();
    // Texel i mirrors to (n − i) mod n: a range [a, b) within 1..n to [n − b + 1, n − a + 1);
    // texel 0 is its own mirror.
    let flip = |r: &Range<usize>| {
        if r.start == 0 {
            0..n
        } else {
            n - r.end + 1..n - r.start + 1
        }
    };
    s.union(&Support {
        rows: flip(&s.rows),
        cols: flip(&s.cols),
    })
}

/// A blend of two power planes: P = (1 − `weight`)·`from` + `weight`·`to`.
#[derive(Clone, Copy)]
pub struct Mix<'a> {
    /// The powers at weight 0.
    pub from: &'a [f32],
    /// The powers at weight 1.
    pub to: &'a [f32],
    /// The blend weight in [0, 1].
    pub weight: f32,
}

impl<'a> Mix<'a> {
    /// One plane alone.
    pub fn only(p: &'a [f32]) -> Self {
        Self {
            from: p,
            to: p,
            weight: 0.0,
        }
    }
}

/// Packs h₀ = ξ·√(P/2) of the blended powers `mix` (eq. 13) into the planes
/// S' = (a+c, b+d, b−d, c−a) of eq. 22, (a, b) = h₀(k), (c, d) = h₀*(−k): the texels of
/// `support` (which must be [`mirror_closed`]) computed, every other texel zeroed. `h0` is
/// scratch (h₀'s real and imaginary planes). In parallel on the current Rayon pool; allocates
/// nothing.
pub fn pack(
    lattice: &Lattice,
    mix: Mix,
    support: &Support,
    h0: &mut [AlignedBuf; 2],
    out: &mut [AlignedBuf; 4],
) {
    let n = lattice.grid.n();
    let [xr, xi] = &lattice.xi;
    let Mix { from, to, weight } = mix;
    let cols = support.cols.clone();
    let [hr, hi] = h0;
    // h₀ inside the support: contiguous streams, one square root per texel.
    hr.par_chunks_mut(n)
        .zip(hi.par_chunks_mut(n))
        .enumerate()
        .filter(|(row, _)| support.rows.contains(row))
        .for_each(|(row, (hr, hi))| {
            let base = row * n;
            for col in cols.clone() {
                let i = base + col;
                let amp = (0.5 * (from[i] + weight * (to[i] - from[i]))).sqrt();
                hr[col] = xr[i] * amp;
                hi[col] = xi[i] * amp;
            }
        });
    let (hr, hi) = (&*hr, &*hi);
    let [s0, s1, s2, s3] = out;
    s0.par_chunks_mut(n)
        .zip(s1.par_chunks_mut(n))
        .zip(s2.par_chunks_mut(n))
        .zip(s3.par_chunks_mut(n))
        .enumerate()
        .for_each(|(row, (((x, y), z), w))| {
            if !support.rows.contains(&row) {
                for plane in [x, y, z, w] {
                    plane.fill(0.0);
                }
                return;
            }
            for plane in [&mut *x, &mut *y, &mut *z, &mut *w] {
                plane[..cols.start].fill(0.0);
                plane[cols.end..].fill(0.0);
            }
            let (base, mirror) = (row * n, ((n - row) & (n - 1)) * n);
            for col in cols.clone() {
                let (i, m) = (base + col, mirror + ((n - col) & (n - 1)));
                x[col] = hr[i] + hr[m];
                y[col] = hi[i] - hi[m];
                z[col] = hi[i] + hi[m];
                w[col] = hr[m] - hr[i];
            }
        });
}

/// What a spectrum's power plane holds: the height variance Σ E|h̃(k)|² (m²), the slope
/// variances and the surface's Stokes drift. Additive over rows, and linear in a blend of two
/// planes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    /// Σ_k E|h̃(k, t)|² = 2·Σ P (k ↦ −k permutes the grid).
    pub variance: f64,
    /// Slope variances ([`SlopeVariance`]).
    pub slopes: SlopeVariance,
    /// The Stokes drift at the surface (x, z) (m/s), deep water: a wave of amplitude a
    /// travelling along k carries the surface forward at a²·ω·|k| (Stokes 1847; Kenyon 1969
    /// for a spectrum). The wave along +k is h₀(k)'s (the crate's convention), of amplitude
    /// a² = 4·E|h₀(k)|² = 4·P, so u_s = Σ_k 4·P·ω(k)·k.
    pub stokes_drift: [f64; 2],
}

impl Moments {
    /// The moments of rows `rows` of power plane `p` on a grid of side `grid` and patch
    /// `patch` (m); the unresolved tail is [`tail_rings`]'s.
    pub fn of_rows(p: &[f32], grid: GridSize, patch: f32, rows: Range<usize>) -> Self {
        let n = grid.n();
        let dx = patch as f64 / n as f64;
        let g = crate::sim::dispersion::GRAVITY as f64;
        let (variance, resolved, resolved_finite, stokes_x, stokes_z) = rows
            .into_par_iter()
            .map(|row| {
                let mut sums = (0.0, 0.0, 0.0, 0.0, 0.0);
                for col in 0..n {
                    let power = p[row * n + col];
                    if power == 0.0 {
                        continue;
                    }
                    // Both h̃(k) and h̃(−k) carry E|h₀|²: 2·P per mode, times k² (or what
                    // central differences respond with, sin(kΔ)/Δ per axis).
                    let p2 = 2.0 * power as f64;
                    let (kx, kz) = wave_vector(col, row, grid, patch);
                    let fd = ((kx * dx).sin().powi(2) + (kz * dx).sin().powi(2)) / (dx * dx);
                    let k2 = kx * kx + kz * kz;
                    // 4·P·ω·k with deep water's ω = √(g|k|).
                    let drift = 2.0 * p2 * (g * k2.sqrt()).sqrt();
                    sums.0 += p2;
                    sums.1 += p2 * k2;
                    sums.2 += p2 * fd;
                    sums.3 += drift * kx;
                    sums.4 += drift * kz;
                }
                sums
            })
            .reduce(
                || (0.0, 0.0, 0.0, 0.0, 0.0),
                |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2, a.3 + b.3, a.4 + b.4),
            );
        Self {
            variance,
            stokes_drift: [stokes_x, stokes_z],
            slopes: SlopeVariance {
                resolved,
                resolved_finite,
                unresolved: 0.0,
            },
        }
    }

    /// The sum of two parts.
    pub fn plus(self, o: Self) -> Self {
        Self {
            variance: self.variance + o.variance,
            stokes_drift: [
                self.stokes_drift[0] + o.stokes_drift[0],
                self.stokes_drift[1] + o.stokes_drift[1],
            ],
            slopes: SlopeVariance {
                resolved: self.slopes.resolved + o.slopes.resolved,
                resolved_finite: self.slopes.resolved_finite + o.slopes.resolved_finite,
                unresolved: self.slopes.unresolved + o.slopes.unresolved,
            },
        }
    }

    /// The moments of the blend (1 − `w`)·self + `w`·`to` of two power planes.
    pub fn lerp(self, to: Self, w: f64) -> Self {
        let l = |a: f64, b: f64| a + (b - a) * w;
        Self {
            variance: l(self.variance, to.variance),
            stokes_drift: [
                l(self.stokes_drift[0], to.stokes_drift[0]),
                l(self.stokes_drift[1], to.stokes_drift[1]),
            ],
            slopes: SlopeVariance {
                resolved: l(self.slopes.resolved, to.slopes.resolved),
                resolved_finite: l(self.slopes.resolved_finite, to.slopes.resolved_finite),
                unresolved: l(self.slopes.unresolved, to.slopes.unresolved),
            },
        }
    }
}

/// Rings of the polar grid (log-spaced in |k|) on which [`tail_rings`] integrates.
pub const TAIL_RINGS: usize = 160;
/// Spokes of that polar grid.
const TAIL_SPOKES: usize = 180;

/// The unresolved slope variance ([`SlopeVariance::unresolved`]) of cascade `c` from rings
/// `rings` of [`TAIL_RINGS`]: waves beyond its grid's Nyquist wave number up to
/// [`CAPILLARY_K`]. Zero for every cascade but the finest, whose band ends inside its grid.
pub fn tail_rings(model: &SpectrumModel, c: &CascadeSpec, rings: Range<usize>) -> f64 {
    let n = c.grid.n();
    let nyquist = std::f64::consts::PI * n as f64 / c.patch as f64;
    if !c.band.hi.is_infinite() || nyquist >= CAPILLARY_K {
        return 0.0;
    }
    let dk_grid = std::f64::consts::TAU / c.patch as f64;
    let ln_span = (CAPILLARY_K / nyquist).ln();
    let dtheta = std::f64::consts::TAU / TAIL_SPOKES as f64;
    let mut sum = 0.0;
    for i in rings {
        let u0 = i as f64 / TAIL_RINGS as f64;
        let u1 = (i + 1) as f64 / TAIL_RINGS as f64;
        let (k0, k1) = (
            nyquist * (u0 * ln_span).exp(),
            nyquist * (u1 * ln_span).exp(),
        );
        let k = 0.5 * (k0 + k1);
        for j in 0..TAIL_SPOKES {
            let th = (j as f64 + 0.5) * dtheta;
            let (kx, kz) = (k * th.cos(), k * th.sin());
            // A polar cell of area k·Δk·Δθ holds that many grid modes of spacing 2π/L.
            let modes = k * (k1 - k0) * dtheta / (dk_grid * dk_grid);
            sum += 2.0 * power_at(model, c, kx, kz, k) * k * k * modes;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::config::OceanConfig;

    #[test]
    fn a_grown_grid_holds_the_smaller_grids_modes_with_their_draws() {
        let mut cfg = OceanConfig::default_cascades(64).unwrap();
        cfg.waves.wind_speed = 5.0;
        cfg.fit_patches();
        let small = cfg.cascade_specs()[0];
        assert_eq!(small.octave, 0);
        let grown = CascadeSpec {
            patch: small.patch * 2.0,
            octave: 1,
            ..small
        };
        let model = SpectrumModel::new(&cfg.waves);
        let n = 64;
        let mut own = vec![0.0f32; n * n];
        let mut spread = vec![0.0f32; n * n];
        let _ = power_rows(&model, &small, 0, 0..n, &mut own);
        let _ = power_rows(&model, &small, 1, 0..n, &mut spread);
        let (mut a, mut b) = (Lattice::zeros(small.grid), Lattice::zeros(small.grid));
        a.fill_rows(&cfg.waves, &small, 0..n);
        b.fill_rows(&cfg.waves, &grown, 0..n);
        let mut held = 0;
        for row in 1..n {
            for col in 1..n {
                let p = own[row * n + col];
                if p == 0.0 {
                    continue;
                }
                // Texel m of the small grid is texel 2m of the grown one (m from the centre).
                let grown_at = |c: usize| (2 * c as i64 - n as i64 / 2) as usize;
                let (gc, gr) = (grown_at(col), grown_at(row));
                assert!(
                    gc < n && gr < n,
                    "mode ({col}, {row}) beyond the grown grid"
                );
                let (i, j) = (row * n + col, gr * n + gc);
                assert_eq!(spread[j], p);
                assert_eq!(a.xi[0][i], b.xi[0][j]);
                assert_eq!(a.xi[1][i], b.xi[1][j]);
                assert_eq!(a.harmonic[i], b.harmonic[j]);
                held += 1;
            }
        }
        assert!(held > 50, "{held} modes");
        // Nothing else: the same energy.
        let sum = |p: &[f32]| p.iter().map(|&x| x as f64).sum::<f64>();
        assert_eq!(sum(&own), sum(&spread));
    }

    #[test]
    fn one_wave_drifts_the_surface_at_stokes_speed() {
        // One mode of a 64 m patch, wave vector 2π/64·(3, −4): a²·ω·|k| along k.
        let grid = GridSize::new(16).unwrap();
        let (n, patch) = (grid.n(), 64.0f32);
        let (col, row) = (n / 2 + 3, n / 2 - 4);
        let mut p = vec![0.0f32; n * n];
        let power = 0.01f32;
        p[row * n + col] = power;
        let m = Moments::of_rows(&p, grid, patch, 0..n);
        let (kx, kz) = wave_vector(col, row, grid, patch);
        let k = kx.hypot(kz);
        let a2 = 4.0 * power as f64;
        let speed = a2 * (crate::sim::dispersion::GRAVITY as f64 * k).sqrt() * k;
        let [ux, uz] = m.stokes_drift;
        assert!(
            (ux.hypot(uz) / speed - 1.0).abs() < 1e-6,
            "{ux} {uz} vs {speed}"
        );
        assert!((ux * kz - uz * kx).abs() < 1e-9 * speed && ux * kx > 0.0);
        // The variance is a²/2.
        assert!((m.variance / (a2 / 2.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn blended_variance_is_linear_in_the_weight() {
        let mut cfg = OceanConfig::default_cascades(32).unwrap();
        let spec = cfg.cascade_specs()[1];
        let model = SpectrumModel::new(&cfg.waves);
        let n = 32;
        let mut from = vec![0.0f32; n * n];
        let a = power_rows(&model, &spec, 0, 0..n, &mut from);
        cfg.waves.wind_speed = 17.0;
        let mut to = vec![0.0f32; n * n];
        let b = power_rows(&SpectrumModel::new(&cfg.waves), &spec, 0, 0..n, &mut to);
        let mut lattice = Lattice::zeros(spec.grid);
        lattice.fill_rows(&cfg.waves, &spec, 0..n);
        let support = mirror_closed(&a.union(&b), spec.grid);
        // Every non-zero of either plane or its mirror is inside.
        for (i, (&f, &t)) in from.iter().zip(&to).enumerate() {
            let (row, col) = (i / n, i % n);
            let (mr, mc) = ((n - row) % n, (n - col) % n);
            if f != 0.0 || t != 0.0 {
                assert!(support.rows.contains(&row) && support.cols.contains(&col));
                assert!(support.rows.contains(&mr) && support.cols.contains(&mc));
            }
        }
        let mut s: [AlignedBuf; 4] = std::array::from_fn(|_| AlignedBuf::zeros(n * n));
        let m0 = Moments::of_rows(&from, spec.grid, spec.patch, 0..n);
        let m1 = Moments::of_rows(&to, spec.grid, spec.patch, 0..n);
        for w in [0.0f32, 0.25, 0.5, 1.0] {
            let mixed: Vec<f32> = from
                .iter()
                .zip(&to)
                .map(|(a, b)| (1.0 - w) * a + w * b)
                .collect();
            let m = Moments::of_rows(&mixed, spec.grid, spec.patch, 0..n);
            let l = m0.lerp(m1, w as f64);
            assert!((m.variance / l.variance - 1.0).abs() < 1e-5, "{w}");
            assert!(
                (m.stokes_drift[0] / l.stokes_drift[0] - 1.0).abs() < 1e-5,
                "{w}"
            );
            let mix = Mix {
                from: &from,
                to: &to,
                weight: w,
            };
            let mut h0: [AlignedBuf; 2] = std::array::from_fn(|_| AlignedBuf::zeros(n * n));
            pack(&lattice, mix, &support, &mut h0, &mut s);
            // |h₀(k)|² summed over the grid: Σ |ξ|²·P/2, whose mean is Σ P.
            let energy: f64 = (0..n * n)
                .map(|i| {
                    // a = (S'x − S'w)/2, b = (S'y + S'z)/2.
                    let (a, b) = ((s[0][i] - s[3][i]) / 2.0, (s[1][i] + s[2][i]) / 2.0);
                    (a * a + b * b) as f64
                })
                .sum();
            let expect: f64 = (0..n * n)
                .map(|i| {
                    let (x, y) = (lattice.xi[0][i] as f64, lattice.xi[1][i] as f64);
                    (x * x + y * y) * 0.5 * mixed[i] as f64
                })
                .sum();
            assert!((energy / expect.max(1e-30) - 1.0).abs() < 1e-4, "{w}");
        }
    }
}
