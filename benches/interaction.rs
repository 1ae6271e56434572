//! One step of the interaction layer at its default size (256² cells of 0.16 m) on one
//! thread: a towed 1 m float (its pressure and the layer following it) and a second body at
//! rest, after 5 s of wake. The gate: ≤ 0.5 ms on one core.

use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};

use vr_ocean::sim::interaction::{InteractionConfig, InteractionLayer, WaveSource};

fn step_default(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let dt = 1.0 / 90.0;
    let cfg = InteractionConfig::default_with_dt(dt).unwrap();
    let mut layer = InteractionLayer::new(cfg, 0.0, 0.0);
    let mut x = 0.0f32;
    let mut step = move |layer: &mut InteractionLayer| {
        x += 1.2 * dt;
        layer.recentre(x, 0.0);
        layer.step(&[
            WaveSource::floating_sphere(x, 0.0, 1.0, 100.0),
            WaveSource::floating_sphere(-3.0, 4.0, 0.6, 500.0),
        ]);
    };
    pool.install(|| {
        for _ in 0..450 {
            step(&mut layer);
        }
    });
    // Timed on the pool's one thread (the criterion handle stays on this one).
    c.bench_function("interaction_step/256_cells/1_thread", |b| {
        b.iter_custom(|iters| {
            pool.install(|| {
                let t = Instant::now();
                for _ in 0..iters {
                    step(&mut layer);
                }
                t.elapsed()
            })
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = step_default
}
criterion_main!(benches);
