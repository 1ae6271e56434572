//! Sea states that change smoothly: a new sea state's spectrum is built a slice of rows per
//! step ([`BUILD_STEPS`]), then blended in over [`BLEND_SECONDS`], so no step spikes and
//! nothing pops.
//!
//! The blend mixes the two states' mode powers under the same random draws
//! ([`crate::sim::spectrum::modes`]): the variance is linear in the blend weight, so the
//! significant height moves monotonically from the old state's to the new one's. A coarsest
//! patch that grows with the wind changes by whole octaves, and its draws are keyed on the
//! wave vector: a grown grid holds every wave of the smaller one with its own draw. So the
//! grid switches to the larger patch when the blend starts (the field it shows is the same)
//! and to a smaller one once the blend has ended (the field holds only the smaller grid's
//! waves by then); between those, the renderer's fades follow a patch moving from the old
//! size to the new ([`crate::sim::surface::CascadeSurface::fade_patch`]).
//!
//! All buffers are allocated with the cascade: a change allocates nothing.

use std::ops::Range;

use crate::sim::cascade::CascadeSim;
use crate::sim::grid::{AlignedBuf, GridSize, Support};
use crate::sim::params::WaveParams;
use crate::sim::spectrum::modes::{self, Lattice, Mix, Moments, TAIL_RINGS};
use crate::sim::spectrum::{CascadeSpec, SlopeVariance, SpectrumModel};

/// Steps a new state's spectrum is built over (a slice of rows, and of the tail's rings,
/// per step).
pub const BUILD_STEPS: usize = 64;

/// Seconds of simulation time a blend from one sea state to the next takes.
pub const BLEND_SECONDS: f64 = 5.0;

/// One cascade's buffers for retuning its spectrum.
pub(crate) struct Tuning {
    /// Draws and harmonics of the grid the cascade runs on.
    pub lattice: Lattice,
    /// Mode powers shown at blend weight 0: the current state.
    from: AlignedBuf,
    /// Mode powers of the state being built or blended in, on the same grid.
    to: AlignedBuf,
    from_moments: Moments,
    to_moments: Moments,
    /// Where `from` packs to non-zeros ([`modes::mirror_closed`]).
    from_support: Support,
    /// The non-zeros of `to` built so far; mirror-closed once built.
    to_support: Support,
    /// For a cascade whose patch can change: the draws of the grid it changes to, built in
    /// slices before the switch.
    spare: Option<Lattice>,
    /// The state being built or blended in.
    target: CascadeSpec,
    /// The patch whose waves `from` holds, and `to`'s: the renderer's fades blend them.
    from_patch: f32,
    /// The blend weight the spectrum was last packed at (0 outside a blend).
    weight: f32,
    /// Scratch for [`modes::pack`].
    h0: [AlignedBuf; 2],
    /// What the spectrum packs: `from_support`, or during a blend the union of both.
    support: Support,
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
    fn rebuild(&mut self, spec: &CascadeSpec, waves: &WaveParams) {
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
fn moments(
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

/// Where a retune stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// The spectrum is the current state's.
    Idle,
    /// The new state's powers are being built: the rows and rings done so far.
    Build { rows: usize, rings: usize },
    /// Blending in: simulation seconds since the blend began.
    Blend { elapsed: f64, turn: usize },
    /// Blended; a patch that shrinks builds its smaller grid's draws: rows done.
    Settle { rows: usize },
}

/// The sea-state change in progress, for all cascades ([`crate::sim::SimCore`] owns one).
pub(crate) struct Retune {
    phase: Phase,
    /// The new state's waves and spectrum model (made on the first build step, when
    /// `model_ready` is false: the step that takes the new waves stays light).
    waves: WaveParams,
    model: SpectrumModel,
    model_ready: bool,
    /// The wind shown at weight 0 and at 1 (the renderer's roughness and the whitecaps
    /// follow it).
    winds: [f32; 2],
    /// The unit direction (x, z) the wind blows toward at weight 0 and at 1 (the foam
    /// streaks and the sound follow it with the waves).
    towards: [[f32; 2]; 2],
    /// The blend weight of the last step.
    weight: f64,
}

/// Smoothstep: the blend starts and ends without a kink.
fn ease(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

impl Retune {
    /// Nothing to retune: the spectrum is `waves`'.
    pub fn idle(waves: &WaveParams) -> Self {
        Self {
            phase: Phase::Idle,
            waves: *waves,
            model: SpectrumModel::new(waves),
            model_ready: true,
            winds: [waves.wind_speed; 2],
            towards: [waves.toward(); 2],
            weight: 0.0,
        }
    }

    /// Whether a change to `waves` is still under way.
    pub fn busy(&self) -> bool {
        self.phase != Phase::Idle
    }

    /// The wind the shown spectrum stands for (m/s).
    pub fn shown_wind(&self) -> f32 {
        let [a, b] = self.winds;
        a + (b - a) * self.weight as f32
    }

    /// The unit direction (x, z) the shown spectrum's wind blows toward: turned from the old
    /// to the new by the blend's weight (the shorter way round; straight against the old, the
    /// new one at the blend's half).
    pub fn shown_toward(&self) -> [f32; 2] {
        let [a, b] = self.towards;
        let w = self.weight as f32;
        let (x, z) = (a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w);
        let len = (x * x + z * z).sqrt();
        if len > 1e-4 {
            [x / len, z / len]
        } else if w < 0.5 {
            a
        } else {
            b
        }
    }

    /// Whether the step from `old` to `new` waves can blend: the same draws and dispersion
    /// (seed, depth, loop period), so every wave keeps its phase.
    pub fn can_blend(old: &WaveParams, new: &WaveParams) -> bool {
        old.seed == new.seed && old.depth == new.depth && old.loop_period == new.loop_period
    }

    /// Starts the change to `waves`, whose cascades are `targets`: what is shown now (mid-blend,
    /// the blend as it stands) becomes the state blended from.
    pub fn begin(
        &mut self,
        waves: &WaveParams,
        targets: &[CascadeSpec],
        cascades: &mut [CascadeSim],
    ) {
        let shown = self.shown_wind();
        let shown_toward = self.shown_toward();
        for (c, target) in cascades.iter_mut().zip(targets) {
            let t = &mut c.tuning;
            let weight = t.weight;
            t.weight = 0.0;
            if weight > 0.0 {
                for (f, &to) in t.from.iter_mut().zip(t.to.iter()) {
                    *f += (to - *f) * weight;
                }
                t.from_moments = t.from_moments.lerp(t.to_moments, weight as f64);
                t.from_patch += (t.target.patch - t.from_patch) * weight;
                t.from_support = t.support.clone();
            }
            t.target = *target;
            t.to_moments = Moments::default();
            t.to_support = Support::empty();
        }
        self.waves = *waves;
        self.model_ready = false;
        self.winds = [shown, waves.wind_speed];
        self.towards = [shown_toward, waves.toward()];
        self.weight = 0.0;
        self.phase = Phase::Build { rows: 0, rings: 0 };
    }

    /// Advances the change by one step of `dt` simulation seconds: a slice of the build, a
    /// blend step (the spectra repacked) or a slice of the settling. Allocates nothing.
    pub fn advance(&mut self, dt: f64, cascades: &mut [CascadeSim]) {
        match self.phase {
            Phase::Idle => {}
            Phase::Build { rows, rings } => self.build(rows, rings, cascades),
            Phase::Blend { elapsed, turn } => self.blend(elapsed + dt, turn, cascades),
            Phase::Settle { rows } => self.settle(rows, cascades),
        }
    }

    /// A slice of the build; the step after the last slice switches grids and starts the
    /// blend (each on a step of its own, so neither adds to the other's cost).
    fn build(&mut self, rows: usize, rings: usize, cascades: &mut [CascadeSim]) {
        let n = cascades.first().map_or(0, |c| c.spec.grid.n());
        if !self.model_ready {
            self.model = SpectrumModel::new(&self.waves);
            self.model_ready = true;
            return;
        }
        if rows >= n && rings >= TAIL_RINGS {
            return self.start_blend(cascades);
        }
        let slice = rows..(rows + n.div_ceil(BUILD_STEPS)).min(n);
        let ring_slice = rings..(rings + TAIL_RINGS.div_ceil(BUILD_STEPS)).min(TAIL_RINGS);
        for c in cascades.iter_mut() {
            let run = run_spec(&c.spec, &c.tuning.target);
            let spread = run.octave - c.tuning.target.octave;
            let t = &mut c.tuning;
            if run.octave != c.spec.octave {
                if let Some(spare) = &mut t.spare {
                    spare.fill_rows(&self.waves, &run, slice.clone());
                }
            }
            let nonzero =
                modes::power_rows(&self.model, &t.target, spread, slice.clone(), &mut t.to);
            t.to_support = t.to_support.union(&nonzero);
            let part = moments(&self.model, &run, &t.to, slice.clone(), ring_slice.clone());
            t.to_moments = t.to_moments.plus(part);
        }
        self.phase = Phase::Build {
            rows: slice.end,
            rings: ring_slice.end,
        };
    }

    /// Moves a growing patch to its larger grid (showing what it showed) and readies the
    /// blend, which packs from the next step on.
    fn start_blend(&mut self, cascades: &mut [CascadeSim]) {
        for c in cascades.iter_mut() {
            let run = run_spec(&c.spec, &c.tuning.target);
            if run.octave > c.spec.octave {
                c.switch_grid(run);
                c.show_current();
            }
            let t = &mut c.tuning;
            t.to_support = modes::mirror_closed(&t.to_support, run.grid);
            t.support = t.from_support.union(&t.to_support);
        }
        self.phase = Phase::Blend {
            elapsed: 0.0,
            turn: 0,
        };
    }

    /// A blend step: the weight at `elapsed` seconds, and one cascade (the `turn`th, in
    /// rotation) repacked at it: a third of the packing per step with three cascades, and
    /// each cascade's weight still moves by under 1 % per repack at 72 Hz. Ends once every
    /// cascade shows the new state in full.
    fn blend(&mut self, elapsed: f64, turn: usize, cascades: &mut [CascadeSim]) {
        self.weight = ease(elapsed / BLEND_SECONDS);
        let w = self.weight as f32;
        let count = cascades.len().max(1);
        if let Some(c) = cascades.get_mut(turn % count) {
            c.show_blend(w);
        }
        if cascades.iter().any(|c| c.tuning.weight < 1.0) {
            self.phase = Phase::Blend {
                elapsed,
                turn: turn + 1,
            };
            return;
        }
        for c in cascades.iter_mut() {
            let t = &mut c.tuning;
            std::mem::swap(&mut t.from, &mut t.to);
            t.from_moments = t.to_moments;
            t.from_patch = t.target.patch;
            std::mem::swap(&mut t.from_support, &mut t.to_support);
            t.support = t.from_support.clone();
            t.weight = 0.0;
        }
        self.winds = [self.waves.wind_speed; 2];
        self.towards = [self.waves.toward(); 2];
        self.weight = 0.0;
        let shrinks = cascades
            .iter()
            .any(|c| c.tuning.target.octave < c.spec.octave);
        self.phase = if shrinks {
            Phase::Settle { rows: 0 }
        } else {
            Phase::Idle
        };
    }

    fn settle(&mut self, rows: usize, cascades: &mut [CascadeSim]) {
        let n = cascades.first().map_or(0, |c| c.spec.grid.n());
        let slice = rows..(rows + n.div_ceil(BUILD_STEPS)).min(n);
        for c in cascades.iter_mut() {
            let target = c.tuning.target;
            if target.octave < c.spec.octave {
                if let Some(spare) = &mut c.tuning.spare {
                    spare.fill_rows(&self.waves, &target, slice.clone());
                }
            }
        }
        if slice.end < n {
            self.phase = Phase::Settle { rows: slice.end };
            return;
        }
        for c in cascades.iter_mut() {
            let target = c.tuning.target;
            if target.octave < c.spec.octave {
                c.switch_grid(target);
                c.show_current();
            }
        }
        self.phase = Phase::Idle;
    }
}

/// The grid a cascade runs its change on: the larger of its current patch and the target's
/// (so both states' waves are on it), with the target's band.
fn run_spec(current: &CascadeSpec, target: &CascadeSpec) -> CascadeSpec {
    if current.octave > target.octave {
        CascadeSpec {
            patch: current.patch,
            octave: current.octave,
            ..*target
        }
    } else {
        *target
    }
}

impl CascadeSim {
    /// Changes this cascade to `spec` and `waves` at once (a change that cannot blend): stage 1
    /// in full into the buffers held, the persistent foam kept.
    pub fn retune_at_once(&mut self, spec: CascadeSpec, waves: &WaveParams) {
        self.tuning.rebuild(&spec, waves);
        self.spectrum
            .harmonic
            .copy_from_slice(&self.tuning.lattice.harmonic);
        self.spec = spec;
        self.show_current();
    }

    /// Packs the blend at weight `w` into the spectrum the evolution reads.
    fn show_blend(&mut self, w: f32) {
        let t = &mut self.tuning;
        let mix = Mix {
            from: &t.from,
            to: &t.to,
            weight: w,
        };
        modes::pack(&t.lattice, mix, &t.support, &mut t.h0, &mut self.spectrum.s);
        self.spectrum.support = t.support.clone();
        let m = t.from_moments.lerp(t.to_moments, w as f64);
        self.spectrum.expected_variance = m.variance;
        self.spectrum.slopes = m.slopes;
        self.spectrum.stokes_drift = m.stokes_drift;
        self.fade_patch = t.from_patch + (t.target.patch - t.from_patch) * w;
        t.weight = w;
    }

    /// Packs the current state's powers into the spectrum the evolution reads.
    fn show_current(&mut self) {
        let t = &mut self.tuning;
        let mix = Mix::only(&t.from);
        modes::pack(
            &t.lattice,
            mix,
            &t.from_support,
            &mut t.h0,
            &mut self.spectrum.s,
        );
        self.spectrum.support = t.from_support.clone();
        self.spectrum.expected_variance = t.from_moments.variance;
        self.spectrum.slopes = t.from_moments.slopes;
        self.spectrum.stokes_drift = t.from_moments.stokes_drift;
        self.fade_patch = t.from_patch;
    }

    /// Moves this cascade to the grid of `spec` (its patch whole octaves larger or smaller)
    /// once the spare lattice holds that grid's draws: the shown powers and the persistent
    /// foam are carried over (the powers exactly: every wave they hold is on both grids), the
    /// lattices swap, the harmonics follow.
    fn switch_grid(&mut self, spec: CascadeSpec) {
        let t = &mut self.tuning;
        let Some(spare) = t.spare.as_mut() else {
            return;
        };
        std::mem::swap(&mut t.lattice, spare);
        let grid = spec.grid;
        let shift = spec.octave as i32 - self.spec.octave as i32;
        // The old lattice's ξ planes are free now: scratch for the copies.
        let [scratch_a, scratch_b] = &mut spare.xi;
        scratch_a.copy_from_slice(&t.from);
        let nonzero = regrid_powers(grid, shift, scratch_a, &t.from_support, &mut t.from);
        scratch_b.copy_from_slice(&self.foam);
        regrid_foam(grid, shift, scratch_b, &mut self.foam);
        t.from_support = modes::mirror_closed(&nonzero, grid);
        t.support = t.from_support.clone();
        let keep_tail = t.from_moments.slopes.unresolved;
        let m = Moments::of_rows(&t.from, grid, spec.patch, t.from_support.rows.clone());
        t.from_moments = Moments {
            slopes: SlopeVariance {
                unresolved: keep_tail,
                ..m.slopes
            },
            ..m
        };
        self.spectrum.harmonic.copy_from_slice(&t.lattice.harmonic);
        self.spec = spec;
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

    #[test]
    fn the_blend_eases_in_and_out() {
        assert_eq!(ease(0.0), 0.0);
        assert_eq!(ease(1.0), 1.0);
        assert_eq!(ease(2.0), 1.0);
        assert!((ease(0.5) - 0.5).abs() < 1e-12);
        let mut last = 0.0;
        for i in 1..=100 {
            let e = ease(i as f64 / 100.0);
            assert!(e > last);
            last = e;
        }
    }
}
