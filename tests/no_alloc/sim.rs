//! The steady state of the simulation allocates nothing: a counting global allocator watches
//! every thread (caller, worker and Rayon pool) while steps run.

use crate::common;

use std::sync::Mutex;

use vr_ocean::sim::interaction::{InteractionConfig, InteractionLayer, WaveSource};
use vr_ocean::sim::{Derivatives, OceanConfig, SeaState, Simulation, WaveParams};

/// The tests share the counter, so they take turns.
static SERIAL: Mutex<()> = Mutex::new(());

fn steady_state_steps_do_not_allocate() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    for (threads, derivatives) in [
        (1, Derivatives::Spectral),
        (2, Derivatives::Spectral),
        (1, Derivatives::Finite),
        (2, Derivatives::Finite),
    ] {
        let cfg = OceanConfig {
            derivatives,
            ..OceanConfig::default_cascades(64).unwrap()
        };
        let mut sim = Simulation::new(cfg, threads).unwrap();
        let mut t = 0.0;
        // Warm-up: first steps may size lazily created thread-local state.
        for _ in 0..10 {
            t += 1.0 / 72.0;
            sim.step_blocking(t);
        }
        let mut checksum = 0.0f32;
        let ((), n) = common::count_allocations(|| {
            for _ in 0..200 {
                t += 1.0 / 72.0;
                sim.begin_step(t);
                // The caller reads the previous step while the next one runs.
                checksum += sim.surfaces().cascades[0].displacement_f16[5][1].to_f32();
                let s = sim.end_step();
                checksum += s.height_at(1.0, 2.0);
            }
        });
        assert!(checksum.is_finite());
        assert_eq!(
            n, 0,
            "{n} heap allocations in 200 steady-state steps on {threads} thread(s), \
             {derivatives} derivatives"
        );
    }
}

/// A sea-state change (its spectrum built in slices, blended in, the coarsest patch growing an
/// octave and, on the way back, shrinking) allocates nothing after the call that starts it.
fn sea_state_changes_do_not_allocate() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let calm = cfg.waves;
    let gale = WaveParams {
        wind_speed: 19.0,
        ..calm
    };
    let mut sim = Simulation::new(cfg.clone(), 2).unwrap();
    let mut t = 0.0;
    for _ in 0..10 {
        t += 1.0 / 72.0;
        sim.step_blocking(t);
    }
    for waves in [gale, calm] {
        sim.set_waves(SeaState::new(waves).unwrap()).unwrap();
        // The worker takes the new waves with the next step (that call may allocate).
        t += 1.0 / 72.0;
        sim.step_blocking(t);
        let ((), n) = common::count_allocations(|| {
            // The build (64 steps), the blend (5 s) and the settling, at 72 Hz.
            for _ in 0..600 {
                t += 1.0 / 72.0;
                sim.step_blocking(t);
            }
        });
        assert_eq!(
            n, 0,
            "{n} heap allocations while changing to {} m/s",
            waves.wind_speed
        );
    }
    assert_eq!(sim.surfaces().cascades[0].patch, cfg.patch_sizes[0]);
}

/// The interaction layer's step and recentring allocate nothing, on 1 and 2 threads.
fn interaction_steps_do_not_allocate() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let cfg = InteractionConfig::default_with_dt(1.0 / 90.0).unwrap();
            let mut layer = InteractionLayer::new(cfg, 0.0, 0.0);
            let mut x = 0.0;
            let step = |layer: &mut InteractionLayer, x: &mut f32| {
                *x += 0.05;
                layer.recentre(*x, 0.0);
                let mut s = WaveSource::floating_sphere(*x, 0.0, 1.0, 300.0);
                s.impulse = 0.1;
                layer.step(&[s, WaveSource::floating_sphere(-3.0, 2.0, 0.4, 500.0)]);
            };
            for _ in 0..10 {
                step(&mut layer, &mut x);
            }
            let ((), n) = common::count_allocations(|| {
                for _ in 0..100 {
                    step(&mut layer, &mut x);
                }
            });
            assert!(layer.heights().iter().any(|&h| h != 0.0));
            assert_eq!(
                n, 0,
                "{n} heap allocations in 100 layer steps on {threads} thread(s)"
            );
        });
    }
}

/// No libtest harness (`harness = false` in Cargo.toml): the counter is process-wide, and
/// libtest's main thread allocates while it waits for a test thread (its channel registers
/// a waiter), which made the count depend on timing. Here the tests run on the main thread,
/// one after another, and nothing else runs.
/// Runs this suite (`main.rs` calls it).
pub fn main() {
    crate::run(
        "steady_state_steps_do_not_allocate",
        steady_state_steps_do_not_allocate,
    );
    crate::run(
        "sea_state_changes_do_not_allocate",
        sea_state_changes_do_not_allocate,
    );
    crate::run(
        "interaction_steps_do_not_allocate",
        interaction_steps_do_not_allocate,
    );
}
