//! One fixed physics step with 64 floating bodies (the default mix around the deck): the
//! batched height queries of every hull column, the water forces and rapier's step. The sea
//! is the default cascades on a 64² grid (the query cost does not depend on the grid), at the
//! default 10 m/s wind and at 15 m/s; it moves on every third step (a 30 Hz simulation under
//! the 90 Hz physics), outside the timed span. Single thread (rapier without `parallel`).

use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec2;

use vr_ocean::physics::{BodyCount, Floaters, PhysicsConfig, MAX_BODIES, PHYSICS_DT};
use vr_ocean::sim::{OceanConfig, SimCore, Surfaces};

fn step_64(c: &mut Criterion) {
    for wind in [10.0f32, 15.0] {
        let mut cfg = OceanConfig::default_cascades(64).unwrap();
        cfg.waves.wind_speed = wind;
        let mut core = SimCore::new(cfg.clone()).unwrap();
        let mut surfaces = Surfaces::new(&cfg);
        core.step(0.0, &mut surfaces);
        let mut world = Floaters::new(PhysicsConfig::default()).unwrap();
        world
            .spawn_around(BodyCount::new(MAX_BODIES).unwrap(), Vec2::ZERO, &surfaces)
            .unwrap();
        let mut n = 0u64;
        let mut advance = |core: &mut SimCore, s: &mut Surfaces| {
            n += 1;
            if n.is_multiple_of(3) {
                core.step(n as f64 * PHYSICS_DT as f64, s);
            }
        };
        // Ten seconds for the bodies to settle into the sea.
        for _ in 0..900 {
            advance(&mut core, &mut surfaces);
            world.step(&surfaces);
        }
        c.bench_function(&format!("physics_step_64_bodies/wind_{wind}"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    advance(&mut core, &mut surfaces);
                    let t = Instant::now();
                    world.step(&surfaces);
                    total += t.elapsed();
                }
                total
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = step_64
}
criterion_main!(benches);
