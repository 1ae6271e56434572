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

use crate::sim::cascade::CascadeSim;
use crate::sim::grid::Support;
use crate::sim::params::WaveParams;
use crate::sim::spectrum::modes::{self, Moments, TAIL_RINGS};
use crate::sim::spectrum::{CascadeSpec, SpectrumModel};
use crate::sim::tuning::moments;

/// Steps a new state's spectrum is built over (a slice of rows, and of the tail's rings,
/// per step).
pub const BUILD_STEPS: usize = 64;

/// Seconds of simulation time a blend from one sea state to the next takes.
pub const BLEND_SECONDS: f64 = 5.0;

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
    /// The new state's spectrum model (made on the first build step, when `model_ready` is
    /// false: the step that takes the new waves stays light). The waves themselves are the
    /// simulation's ([`crate::sim::SimCore`] holds them; each call is handed them).
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
        self.model_ready = false;
        self.winds = [shown, waves.wind_speed];
        self.towards = [shown_toward, waves.toward()];
        self.weight = 0.0;
        self.phase = Phase::Build { rows: 0, rings: 0 };
    }

    /// Advances the change to `waves` (the ones [`Retune::begin`] was given) by one step of
    /// `dt` simulation seconds: a slice of the build, a blend step (the spectra repacked) or a
    /// slice of the settling. Allocates nothing.
    pub fn advance(&mut self, dt: f64, waves: &WaveParams, cascades: &mut [CascadeSim]) {
        match self.phase {
            Phase::Idle => {}
            Phase::Build { rows, rings } => self.build(rows, rings, waves, cascades),
            Phase::Blend { elapsed, turn } => self.blend(elapsed + dt, turn, waves, cascades),
            Phase::Settle { rows } => self.settle(rows, waves, cascades),
        }
    }

    /// A slice of the build; the step after the last slice switches grids and starts the
    /// blend (each on a step of its own, so neither adds to the other's cost).
    fn build(
        &mut self,
        rows: usize,
        rings: usize,
        waves: &WaveParams,
        cascades: &mut [CascadeSim],
    ) {
        let n = cascades.first().map_or(0, |c| c.spec.grid.n());
        if !self.model_ready {
            self.model = SpectrumModel::new(waves);
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
                    spare.fill_rows(waves, &run, slice.clone());
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
    fn blend(
        &mut self,
        elapsed: f64,
        turn: usize,
        waves: &WaveParams,
        cascades: &mut [CascadeSim],
    ) {
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
        self.winds = [waves.wind_speed; 2];
        self.towards = [waves.toward(); 2];
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

    fn settle(&mut self, rows: usize, waves: &WaveParams, cascades: &mut [CascadeSim]) {
        let n = cascades.first().map_or(0, |c| c.spec.grid.n());
        let slice = rows..(rows + n.div_ceil(BUILD_STEPS)).min(n);
        for c in cascades.iter_mut() {
            let target = c.tuning.target;
            if target.octave < c.spec.octave {
                if let Some(spare) = &mut c.tuning.spare {
                    spare.fill_rows(waves, &target, slice.clone());
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

#[cfg(test)]
mod tests {
    use super::*;

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
