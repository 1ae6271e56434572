//! The soundscape's cost (issue 32's goal: under 2 % of one core): one second of sound at
//! 48 kHz rendered in 10 ms buffers (the device callback's size), for a busy sea (a gale,
//! whitecaps in every sector, water at the deck, a splash every half second) and a calm one.
//! Criterion's time per iteration is the time per second of sound: 10 ms is 1 % of a core.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};

use vr_ocean::audio::measure::{busy_sea, thrown_crate};
use vr_ocean::audio::{SoundConfig, SoundFrame, Soundscape};

fn second_of_sound(c: &mut Criterion) {
    for (name, busy) in [("busy_sea", true), ("calm_sea", false)] {
        let mut engine = Soundscape::new(SoundConfig::default()).unwrap();
        let mut buffer = vec![0.0f32; 2 * 480];
        let mut t = 0.0f64;
        let mut second = move |engine: &mut Soundscape| {
            for k in 0..100u32 {
                t += 0.01;
                let frame = if busy {
                    busy_sea(t)
                } else {
                    SoundFrame {
                        time: t,
                        wind_speed: 5.0,
                        significant_height: 0.6,
                        ..SoundFrame::default()
                    }
                };
                engine.set_frame(&frame);
                if busy && k.is_multiple_of(50) {
                    engine.splash(thrown_crate(t));
                }
                engine.render(&mut buffer);
            }
        };
        second(&mut engine);
        c.bench_function(&format!("soundscape/{name}/1_s_in_10_ms_buffers"), |b| {
            b.iter(|| second(&mut engine))
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    targets = second_of_sound
}
criterion_main!(benches);
