//! One cascade's buffers for changing its sea state ([`Tuning`]): the shown state's mode
//! powers and the next one's, their supports and moments, the draws of the grid it runs on
//! and of the grid it changes to, and how a blend of the two is packed into the spectrum the
//! evolution reads. [`crate::sim::retune`] drives every cascade's tuning through a change.

use std::ops::Range;

use crate::sim::grid::{AlignedBuf, GridSize, Support};
use crate::sim::params::WaveParams;
use crate::sim::spectrum::modes::{self, Lattice, Mix, Moments, TAIL_RINGS};
use crate::sim::spectrum::{CascadeSpec, PackedSpectrum, SlopeVariance, SpectrumModel};

/// One cascade's buffers for retuning its spectrum.
pub(crate) struct Tuning {
    /// Draws and harmonics of the grid the cascade runs on.
    pub(crate) lattice: Lattice,
    /// Mode powers shown at blend weight 0: the current state.
    pub(crate) from: AlignedBuf,
    /// Mode powers of the state being built or blended in, on the same grid.
    pub(crate) to: AlignedBuf,
    pub(crate) from_moments: Moments,
    pub(crate) to_moments: Moments,
    /// Where `from` packs to non-zeros ([`modes::mirror_closed`]).
    pub(crate) from_support: Support,
    /// The non-zeros of `to` built so far; mirror-closed once built.
    pub(crate) to_support: Support,
    /// For a cascade whose patch can change: the draws of the grid it changes to, built in
    /// slices before the switch.
    pub(crate) spare: Option<Lattice>,
    /// The state being built or blended in.
    pub(crate) target: CascadeSpec,
    /// The patch whose waves `from` holds, and `to`'s: the renderer's fades blend them.
    pub(crate) from_patch: f32,
    /// The blend weight the spectrum was last packed at (0 outside a blend).
    pub(crate) weight: f32,
    /// Scratch for [`modes::pack`].
    pub(crate) h0: [AlignedBuf; 2],
    /// What the spectrum packs: `from_support`, or during a blend the union of both.
    pub(crate) support: Support,
}

impl Tuning {
    /// The tuning of a cascade whose spectrum `spec` is built now (at once): its powers
    /// under `model` in `from`, a spare lattice when `changes_patch`.
    pub fn new(spec: &CascadeSpec, waves: &WaveParams, changes_patch: bool) -> Self {
        let grid = spec.grid;
        let mut tuning = Self {
            lattice: Lattice::zeros(grid),
            from: AlignedBuf::zeros(grid.texels()),
            to: AlignedBuf::zeros(grid.texels()),
            from_moments: Moments::default(),
            to_moments: Moments::default(),
            from_support: Support::empty(),
            to_support: Support::empty(),
            h0: std::array::from_fn(|_| AlignedBuf::zeros(grid.texels())),
            weight: 0.0,
            spare: changes_patch.then(|| Lattice::zeros(grid)),
            target: *spec,
            from_patch: spec.patch,
            support: Support::full(grid),
        };
        tuning.rebuild(spec, waves);
        tuning
    }

    /// Builds `spec`'s draws and `waves`' powers at once (same grid), into the buffers held.
    pub(crate) fn rebuild(&mut self, spec: &CascadeSpec, waves: &WaveParams) {
        let n = spec.grid.n();
        self.lattice.fill_rows(waves, spec, 0..n);
        let model = SpectrumModel::new(waves);
        let nonzero = modes::power_rows(&model, spec, 0, 0..n, &mut self.from);
        self.from_moments = moments(&model, spec, &self.from, 0..n, 0..TAIL_RINGS);
        self.from_support = modes::mirror_closed(&nonzero, spec.grid);
        self.support = self.from_support.clone();
        self.target = *spec;
        self.from_patch = spec.patch;
    }

    /// The powers shown now.
    pub fn powers(&self) -> &[f32] {
        &self.from
    }

    /// Their moments.
    pub fn moments(&self) -> Moments {
        self.from_moments
    }

    /// The support of the shown powers (and during a blend, of both states').
    pub fn support(&self) -> &Support {
        &self.support
    }
}

/// The moments of rows `rows` of `power` (a plane of `spec`'s grid), with the tail rings
/// `rings`.
pub(crate) fn moments(
    model: &SpectrumModel,
    spec: &CascadeSpec,
    power: &[f32],
    rows: Range<usize>,
    rings: Range<usize>,
) -> Moments {
    let m = Moments::of_rows(power, spec.grid, spec.patch, rows);
    Moments {
        slopes: SlopeVariance {
            unresolved: modes::tail_rings(model, spec, rings),
            ..m.slopes
        },
        ..m
    }
}

impl Tuning {
    /// Packs the blend at weight `w` into `spectrum` (the one the evolution reads); returns the
    /// patch whose waves it shows.
    pub(crate) fn show_blend(&mut self, w: f32, spectrum: &mut PackedSpectrum) -> f32 {
        let mix = Mix {
            from: &self.from,
            to: &self.to,
            weight: w,
        };
        modes::pack(
            &self.lattice,
            mix,
            &self.support,
            &mut self.h0,
            &mut spectrum.s,
        );
        spectrum.support = self.support.clone();
        let m = self.from_moments.lerp(self.to_moments, w as f64);
        spectrum.expected_variance = m.variance;
        spectrum.slopes = m.slopes;
        spectrum.stokes_drift = m.stokes_drift;
        self.weight = w;
        self.from_patch + (self.target.patch - self.from_patch) * w
    }

    /// Packs the current state's powers into `spectrum`; returns the patch they show.
    pub(crate) fn show_current(&mut self, spectrum: &mut PackedSpectrum) -> f32 {
        let mix = Mix::only(&self.from);
        modes::pack(
            &self.lattice,
            mix,
            &self.from_support,
            &mut self.h0,
            &mut spectrum.s,
        );
        spectrum.support = self.from_support.clone();
        spectrum.expected_variance = self.from_moments.variance;
        spectrum.slopes = self.from_moments.slopes;
        spectrum.stokes_drift = self.from_moments.stokes_drift;
        self.from_patch
    }

    /// Moves the tuning from the grid of `now` to that of `spec` (its patch whole octaves
    /// larger or smaller) once the spare lattice holds that grid's draws: the shown powers and
    /// the persistent `foam` are carried over (the powers exactly: every wave they hold is on
    /// both grids), the lattices swap, `harmonic` follows. Returns whether it switched.
    pub(crate) fn switch_grid(
        &mut self,
        now: &CascadeSpec,
        spec: &CascadeSpec,
        foam: &mut [f32],
        harmonic: &mut [u32],
    ) -> bool {
        let Some(spare) = self.spare.as_mut() else {
            return false;
        };
        std::mem::swap(&mut self.lattice, spare);
        let grid = spec.grid;
        let shift = spec.octave as i32 - now.octave as i32;
        // The old lattice's ξ planes are free now: scratch for the copies.
        let [scratch_a, scratch_b] = &mut spare.xi;
        scratch_a.copy_from_slice(&self.from);
        let nonzero = regrid_powers(grid, shift, scratch_a, &self.from_support, &mut self.from);
        scratch_b.copy_from_slice(foam);
        regrid_foam(grid, shift, scratch_b, foam);
        self.from_support = modes::mirror_closed(&nonzero, grid);
        self.support = self.from_support.clone();
        let keep_tail = self.from_moments.slopes.unresolved;
        let m = Moments::of_rows(&self.from, grid, spec.patch, self.from_support.rows.clone());
        self.from_moments = Moments {
            slopes: SlopeVariance {
                unresolved: keep_tail,
                ..m.slopes
            },
            ..m
        };
        harmonic.copy_from_slice(&self.lattice.harmonic);
        true
    }
}

/// Copies mode powers `from` (non-zero only within `within`) to `to` for a patch `shift`
/// octaves larger (> 0: wave vector m moves to texel m·2^shift from the centre) or smaller
/// (< 0: to m·2^shift, where it is whole). Waves the new grid does not hold are dropped.
/// Returns the rectangle of the non-zeros written.
fn regrid_powers(
    grid: GridSize,
    shift: i32,
    from: &[f32],
    within: &Support,
    to: &mut [f32],
) -> Support {
    let n = grid.n() as i64;
    let half = n / 2;
    to.fill(0.0);
    let mut written = Support::empty();
    for row in within.rows.clone() {
        for col in within.cols.clone() {
            let p = from[row * n as usize + col];
            if p == 0.0 {
                continue;
            }
            let (mx, mz) = (col as i64 - half, row as i64 - half);
            let dst = if shift >= 0 {
                Some((mx << shift, mz << shift))
            } else {
                let step = 1i64 << -shift;
                (mx % step == 0 && mz % step == 0).then(|| (mx / step, mz / step))
            };
            if let Some((dx, dz)) = dst.filter(|&(x, z)| x.abs() < half && z.abs() < half) {
                let (c, r) = ((dx + half) as usize, (dz + half) as usize);
                to[r * n as usize + c] = p;
                written = written.union(&Support {
                    rows: r..r + 1,
                    cols: c..c + 1,
                });
            }
        }
    }
    written
}

/// Resamples the persistent foam (texel (c, r) at world (c, r)·L/N) for a patch `shift`
/// octaves larger or smaller: each new texel takes the old texel at its world position (the
/// old field repeating every old patch).
fn regrid_foam(grid: GridSize, shift: i32, from: &[f32], to: &mut [f32]) {
    let n = grid.n();
    for (i, f) in to.iter_mut().enumerate() {
        let (col, row) = (i % n, i / n);
        let (sc, sr) = if shift >= 0 {
            ((col << shift) % n, (row << shift) % n)
        } else {
            (col >> -shift, row >> -shift)
        };
        *f = from[sr * n + sc];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_regrid_both_ways_without_loss() {
        let grid = GridSize::new(16).unwrap();
        let n = 16;
        let mut small = vec![0.0f32; n * n];
        // Modes within a quarter of the grid's reach from the centre.
        for row in 5..12 {
            for col in 5..12 {
                small[row * n + col] = (row * n + col) as f32;
            }
        }
        let mut grown = vec![0.0f32; n * n];
        let all = Support::full(grid);
        let written = regrid_powers(grid, 1, &small, &all, &mut grown);
        assert_eq!(written.rows, 2..15);
        let sum = |p: &[f32]| p.iter().sum::<f32>();
        assert_eq!(sum(&small), sum(&grown));
        // Wave vector (+2, −1) of the small grid is (+4, −2) on the grown one.
        assert_eq!(grown[6 * n + 12], small[7 * n + 10]);
        let mut back = vec![0.0f32; n * n];
        let _ = regrid_powers(grid, -1, &grown, &written, &mut back);
        assert_eq!(back, small);
    }

    #[test]
    fn foam_keeps_its_world_positions() {
        let grid = GridSize::new(16).unwrap();
        let n = 16;
        let old: Vec<f32> = (0..n * n).map(|i| i as f32).collect();
        let mut grown = vec![0.0; n * n];
        regrid_foam(grid, 1, &old, &mut grown);
        // New texel (1, 0) sits at world 2·L/16 of the old patch: old texel (2, 0).
        assert_eq!(grown[1], old[2]);
        // New texel (9, 3): world (18, 6)·L/16, the old field repeating: old texel (2, 6).
        assert_eq!(grown[3 * n + 9], old[6 * n + 2]);
        let mut small = vec![0.0; n * n];
        regrid_foam(grid, -1, &old, &mut small);
        // New texel (3, 3) at world (1.5, 1.5)·L/16: old texel (1, 1).
        assert_eq!(small[n * 3 + 3], old[n + 1]);
    }
}
