//! The simulation pipeline (thesis 4, Table 1): stage 1 on demand, stages 2-6 every step, and
//! the double buffer that lets step t + dt run on the Rayon pool while the caller reads step t.

use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use crate::base::ParamError;
use crate::sim::cascade::{CascadeSim, StageTimes, StepAt};
use crate::sim::config::{OceanConfig, PatchFit};
use crate::sim::evolve::LoopPhase;
use crate::sim::fft::Fft2d;
use crate::sim::grid::{GridSize, SplitField};
use crate::sim::params::{SeaState, WaveParams};
use crate::sim::retune::Retune;
use crate::sim::spectrum::PackedSpectrum;
use crate::sim::surface::SurfaceParams;
use crate::sim::whitecaps::{WhitecapInput, WhitecapState};

pub use crate::sim::output::Surfaces;

/// FFT scratch fields on the current Rayon pool: two up to N = 256 with two or more threads, so
/// the four transforms go in two groups of two and a step has four fork-joins in its FFT
/// instead of eight (fields and scratch, 3 MB, still fit the shared cache); one from N = 512,
/// where a second field's working set evicts the first's, and one on a single thread, where a
/// group buys no parallelism and a second scratch only crowds the cache (N = 128 FFT stage
/// ~15 % faster).
fn scratch_fields(grid: GridSize) -> usize {
    if grid.n() <= 256 && rayon::current_num_threads() > 1 {
        2
    } else {
        1
    }
}

/// The synchronous pipeline: owns every buffer, so [`SimCore::step`] allocates nothing.
/// Runs its stages on the current Rayon pool.
pub struct SimCore {
    config: OceanConfig,
    fft: Fft2d,
    cascades: Vec<CascadeSim>,
    /// FFT scratch shared by all cascades ([`scratch_fields`]): the transforms of a step run in
    /// groups through cache-resident scratch, their strips split among the threads. (One
    /// scratch per thread made 2 threads only 1.47× faster than 1 at N = 512; one shared
    /// scratch, 1.79×.)
    scratch: Vec<SplitField>,
    whitecaps: WhitecapState,
    /// The sea-state change under way, if any.
    retune: Retune,
    focus: [f32; 2],
    last_time: Option<f64>,
    timings: StageTimes,
}

impl SimCore {
    /// Validates `config` and runs stage 1 for every cascade. Call it on the Rayon pool that
    /// will run its steps: the FFT scratch is sized for that pool's thread count (any pool
    /// gives the same results, only slower) and each of its threads gets its FFT working
    /// buffer here.
    pub fn new(config: OceanConfig) -> Result<Self, ParamError> {
        config.validate()?;
        for (i, ratio) in config.aligned_cascades() {
            log::warn!(
                "cascades {i} and {} have a near-integer patch ratio {ratio:.3}: their tiling \
                 repeats line up; prefer ratios like 3.7",
                i + 1
            );
        }
        let grid = config.grid;
        let grows = matches!(config.patch_fit, PatchFit::GrowWithWind { .. });
        let cascades = config
            .cascade_specs()
            .into_iter()
            .enumerate()
            .map(|(i, spec)| {
                CascadeSim::new(spec, &config.waves, config.derivatives, grows && i == 0)
            })
            .collect();
        let fft = Fft2d::new(grid);
        // Every worker's FFT buffer now, not in the first steps that happen to reach it.
        fft.prepare_threads();
        Ok(Self {
            fft,
            retune: Retune::idle(&config.waves),
            config,
            cascades,
            scratch: (0..scratch_fields(grid))
                .map(|_| SplitField::zeros(grid))
                .collect(),
            whitecaps: WhitecapState::new(grid),
            focus: [0.0; 2],
            last_time: None,
            timings: StageTimes::default(),
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &OceanConfig {
        &self.config
    }

    /// The FFT plan (its backend tells which SIMD path runs).
    pub fn fft(&self) -> &Fft2d {
        &self.fft
    }

    /// Expected height variance Σ E|h̃|² of each cascade (m²), for Parseval checks.
    pub fn expected_variances(&self) -> impl Iterator<Item = f64> + '_ {
        self.cascades.iter().map(|c| c.spectrum.expected_variance)
    }

    /// Changes the waves. A new sea state (anything that shapes the spectrum) is reached
    /// smoothly: its spectrum built over [`crate::sim::retune::BUILD_STEPS`] steps, then
    /// blended in over [`crate::sim::retune::BLEND_SECONDS`] of simulation time; a new seed,
    /// depth or loop period changes the draws or the phases and applies at once. Choppiness,
    /// roughness and foam take effect at the next step for free. With
    /// [`crate::sim::PatchFit::GrowWithWind`] the coarsest patch follows the new wind (the
    /// surfaces carry it to the renderer and the height queries).
    ///
    /// Fails only when the refitted patches are out of range; the waves were checked when
    /// `sea` was made.
    pub fn set_waves(&mut self, sea: SeaState) -> Result<(), ParamError> {
        let (config, refit) = self.config.with_sea(sea)?;
        self.change(config, refit, Change::Smooth);
        Ok(())
    }

    /// [`SimCore::set_waves`] at once: the next step shows the new sea state in full.
    pub fn set_waves_at_once(&mut self, sea: SeaState) -> Result<(), ParamError> {
        let (config, refit) = self.config.with_sea(sea)?;
        self.change(config, refit, Change::AtOnce);
        Ok(())
    }

    /// Whether a sea-state change is still being built or blended.
    pub fn retuning(&self) -> bool {
        self.retune.busy()
    }

    /// Moves to `config` (checked: [`OceanConfig::with_sea`]; `refit`: its coarsest patch
    /// changed) by `change`.
    fn change(&mut self, config: OceanConfig, refit: bool, change: Change) {
        let waves = config.waves;
        let old = self.config.waves;
        self.config = config;
        let reshaped = WaveParams {
            choppiness: old.choppiness,
            roughness: old.roughness,
            foam: old.foam,
            ..waves
        } != old;
        if !(reshaped || refit) && change == Change::Smooth {
            return;
        }
        let targets = self.config.cascade_specs();
        if change == Change::Smooth && Retune::can_blend(&old, &waves) {
            self.retune.begin(&waves, &targets, &mut self.cascades);
        } else {
            for (c, spec) in self.cascades.iter_mut().zip(targets) {
                c.retune_at_once(spec, &waves);
            }
            self.retune = Retune::idle(&waves);
        }
    }

    /// Stages 2-6 for time `t` (s) into `out`: evolution, four inverse FFTs per cascade,
    /// displacement, normals, Jacobian, foam, packing and mips. Foam integrates over the time
    /// since the previous step. The pool's other threads stay awake until it returns
    /// ([`crate::sim::awake`]).
    pub fn step(&mut self, t: f64, out: &mut Surfaces) {
        crate::sim::awake::with_pool_awake(|| self.step_awake(t, out));
    }

    /// [`SimCore::step`] with the pool's threads kept awake.
    fn step_awake(&mut self, t: f64, out: &mut Surfaces) {
        let waves = &self.config.waves;
        let dt = match self.last_time {
            Some(prev) if t > prev => (t - prev) as f32,
            _ => 0.0,
        };
        self.last_time = Some(t);
        self.retune
            .advance(dt as f64, &self.config.waves, &mut self.cascades);
        let params = SurfaceParams {
            choppiness: waves.choppiness,
            roughness: waves.roughness,
            foam: waves.foam,
            dt,
        };
        let phase = LoopPhase::new(t, waves.loop_period);
        // During a sea-state change, the wind the shown spectrum stands for.
        let wind = self.retune.shown_wind();
        out.unresolved_slope_variance = crate::sim::spectrum::unresolved_slope_variance(
            wind,
            self.cascades
                .iter()
                .map(|c| c.spectrum.slopes.shown(self.config.derivatives)),
        ) as f32;
        out.base_normal_length = crate::sim::pack::normal_length(waves.roughness);
        let variance: f64 = self
            .cascades
            .iter()
            .map(|c| c.spectrum.expected_variance)
            .sum();
        out.significant_height = 4.0 * variance.sqrt() as f32;
        out.wind = (wind, self.retune.shown_toward());
        let mut times = StageTimes::default();
        for (c, surface) in self.cascades.iter_mut().zip(&mut out.cascades) {
            let at = StepAt { t, phase, params };
            c.step(&self.fft, &mut self.scratch, at, surface, &mut times);
        }
        let t4 = Instant::now();
        // The shown spectrum's Stokes drift and the wind's current carry the foam.
        let stokes = self.cascades.iter().map(|c| c.spectrum.stokes_drift);
        let input = WhitecapInput {
            cascades: &out.cascades,
            focus: self.focus,
            foam: waves.foam,
            wind_speed: wind,
            drift: crate::sim::drift::surface_drift(stokes, wind, waves.toward()),
            dt,
        };
        if self.config.whitecaps {
            self.whitecaps.update(input, &mut out.whitecaps);
        }
        times.whitecaps = t4.elapsed();
        self.timings = times;
    }

    /// Centres the whitecap maps on the viewer at world (x, z) from the next step on.
    pub fn set_focus(&mut self, x: f32, z: f32) {
        if x.is_finite() && z.is_finite() {
            self.focus = [x, z];
        }
    }

    /// Stage times of the last [`SimCore::step`].
    pub fn timings(&self) -> StageTimes {
        self.timings
    }

    /// Re-runs stage 1 (spectrum generation) for every cascade and returns its wall time; the
    /// spectrum is unchanged (same seed), so this only measures.
    pub fn regenerate_spectrum(&mut self) -> Duration {
        let t0 = Instant::now();
        for c in &mut self.cascades {
            c.spectrum = PackedSpectrum::generate(&self.config.waves, &c.spec);
        }
        t0.elapsed()
    }
}

/// How [`SimCore`] takes new waves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Change {
    /// Built in slices and blended in.
    Smooth,
    /// In full before the next step.
    AtOnce,
}

/// What passes between the caller and the worker.
#[derive(Default)]
struct Slot {
    /// A step to run: time and the buffer to fill.
    request: Option<(f64, Surfaces)>,
    /// A finished step.
    done: Option<Surfaces>,
    /// New waves to apply before the next step.
    /// A sea-state change for the worker: the configuration [`Simulation::set_waves`]
    /// checked, and whether its coarsest patch changed.
    change: Option<(OceanConfig, bool)>,
    /// Where the viewer is (world x, z), for the whitecap maps.
    focus: [f32; 2],
    /// Wall time of the last finished step on the worker.
    last_step: Duration,
    shutdown: bool,
    exited: bool,
}

struct Shared {
    slot: Mutex<Slot>,
    wake: Condvar,
}

impl Shared {
    fn lock(&self) -> std::sync::MutexGuard<'_, Slot> {
        // A poisoned lock means the worker panicked; the slot data is still consistent.
        self.slot.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Waits until the worker has handed a buffer back, takes it and keeps the lock.
    fn take_done(&self) -> (std::sync::MutexGuard<'_, Slot>, Surfaces) {
        let mut slot = self.lock();
        loop {
            match slot.done.take() {
                Some(s) => return (slot, s),
                None => slot = self.wake.wait(slot).unwrap_or_else(|e| e.into_inner()),
            }
        }
    }
}

/// Why the simulation could not start.
#[derive(Debug)]
pub enum SimError {
    /// A parameter is out of range.
    Param(ParamError),
    /// The thread pool could not be built (e.g. threads = 0 or the OS refused a thread).
    Threads(String),
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Param(e) => e.fmt(f),
            SimError::Threads(e) => write!(f, "cannot start simulation threads: {e}"),
        }
    }
}

impl std::error::Error for SimError {}

impl From<ParamError> for SimError {
    fn from(e: ParamError) -> Self {
        SimError::Param(e)
    }
}

/// The double-buffered simulation: [`Simulation::begin_step`] starts step t on a dedicated
/// Rayon pool and returns at once; the caller keeps reading [`Simulation::surfaces`] (the
/// previous step) until [`Simulation::end_step`] swaps the new one in. The worker runs as one
/// long-lived job inside the pool, so steps inject nothing into Rayon's queues and the steady
/// state allocates nothing.
pub struct Simulation {
    front: Surfaces,
    shared: Arc<Shared>,
    in_flight: bool,
    threads: usize,
    config: OceanConfig,
    pool: Option<rayon::ThreadPool>,
    /// The pool's threads, by kernel id (for the runtime's thread settings).
    workers: super::workers::WorkerThreads,
}

impl Simulation {
    /// Starts a simulation of `config` on `threads` worker threads (≥ 1).
    pub fn new(config: OceanConfig, threads: usize) -> Result<Self, SimError> {
        if threads == 0 {
            return Err(SimError::Param(ParamError::new(
                "threads",
                0.0,
                "at least 1 thread",
            )));
        }
        let workers = super::workers::WorkerThreads::default();
        let registry = workers.clone();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("ocean-sim-{i}"))
            .start_handler(move |i| {
                registry.register_this_thread();
                // On Android (the Quest) above normal (the OpenXR backend raises the render
                // thread alike, or hands both to the runtime's thread settings). Desktops keep
                // the default: there the GPU driver may be CPU threads (lavapipe) that must not
                // be starved.
                let raised = cfg!(target_os = "android")
                    && super::workers::raise_thread_priority(super::workers::WORKER_NICE);
                if i == 0 {
                    log::debug!(
                        "simulation workers at nice {}: {}",
                        super::workers::WORKER_NICE,
                        if raised { "yes" } else { "not permitted" }
                    );
                }
            })
            .build()
            .map_err(|e| SimError::Threads(e.to_string()))?;
        let mut core = pool.install(|| SimCore::new(config.clone()))?;
        let front = Surfaces::new(&config);
        let back = Surfaces::new(&config);
        let shared = Arc::new(Shared {
            slot: Mutex::new(Slot {
                done: Some(back),
                ..Slot::default()
            }),
            wake: Condvar::new(),
        });
        let worker = shared.clone();
        pool.spawn(move || worker_loop(&mut core, &worker));
        Ok(Self {
            front,
            shared,
            in_flight: false,
            threads,
            config,
            pool: Some(pool),
            workers,
        })
    }

    /// The pool's worker threads (their kernel ids, as they start).
    pub fn workers(&self) -> &super::workers::WorkerThreads {
        &self.workers
    }

    /// The configuration (waves as last set).
    pub fn config(&self) -> &OceanConfig {
        &self.config
    }

    /// Worker threads in the pool.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// The newest finished step.
    pub fn surfaces(&self) -> &Surfaces {
        &self.front
    }

    /// Queues the sea state `sea`; it applies from the next step (see [`SimCore::set_waves`]).
    /// Fails only when the refitted patches are out of range.
    pub fn set_waves(&mut self, sea: SeaState) -> Result<(), ParamError> {
        let (config, refit) = self.config.with_sea(sea)?;
        self.config = config.clone();
        self.shared.lock().change = Some((config, refit));
        Ok(())
    }

    /// Centres the whitecap maps on the viewer at world (x, z) from the next step on
    /// (non-finite positions are ignored).
    pub fn set_focus(&mut self, x: f32, z: f32) {
        self.shared.lock().focus = [x, z];
    }

    /// Starts computing time `t` (s) in the background. If a step is already running, waits
    /// for it first (and publishes it).
    pub fn begin_step(&mut self, t: f64) {
        if self.in_flight {
            self.end_step();
        }
        let (mut slot, back) = self.shared.take_done();
        slot.request = Some((t, back));
        self.in_flight = true;
        drop(slot);
        self.shared.wake.notify_all();
    }

    /// Waits for the step started by [`Self::begin_step`] and makes it current. Without a step
    /// in flight this returns the current surfaces at once.
    pub fn end_step(&mut self) -> &Surfaces {
        if self.in_flight {
            let (mut slot, new) = self.shared.take_done();
            let old = std::mem::replace(&mut self.front, new);
            slot.done = Some(old);
            self.in_flight = false;
        }
        &self.front
    }

    /// Wall time the worker spent on the last finished step (stages 2-6, or 1-6 after a
    /// wave change).
    pub fn last_step_time(&self) -> Duration {
        self.shared.lock().last_step
    }

    /// Computes time `t` and returns it: `begin_step` + `end_step`.
    pub fn step_blocking(&mut self, t: f64) -> &Surfaces {
        self.begin_step(t);
        self.end_step()
    }
}

impl Drop for Simulation {
    fn drop(&mut self) {
        let mut slot = self.shared.lock();
        slot.shutdown = true;
        self.shared.wake.notify_all();
        while !slot.exited {
            slot = self
                .shared
                .wake
                .wait(slot)
                .unwrap_or_else(|e| e.into_inner());
        }
        drop(slot);
        drop(self.pool.take());
    }
}

/// The worker: waits for a request, runs it with the pool's threads, hands the buffer back.
fn worker_loop(core: &mut SimCore, shared: &Shared) {
    let mut slot = shared.lock();
    loop {
        if slot.shutdown {
            slot.exited = true;
            shared.wake.notify_all();
            return;
        }
        let Some((t, mut out)) = slot.request.take() else {
            slot = shared.wake.wait(slot).unwrap_or_else(|e| e.into_inner());
            continue;
        };
        let change = slot.change.take();
        let focus = slot.focus;
        drop(slot);
        core.set_focus(focus[0], focus[1]);
        // The step's time includes taking new waves (a sea-state change starts there).
        let start = std::time::Instant::now();
        if let Some((config, refit)) = change {
            core.change(config, refit, Change::Smooth);
        }
        core.step(t, &mut out);
        let took = start.elapsed();
        slot = shared.lock();
        slot.last_step = took;
        slot.done = Some(out);
        shared.wake.notify_all();
    }
}
