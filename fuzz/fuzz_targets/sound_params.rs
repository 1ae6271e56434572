//! Parameter validation and the sound's input: arbitrary numbers (NaN, infinities, huge) for
//! the waves, the sound's configuration, a frame of the sea and splashes. Validation accepts or
//! refuses without panicking; the soundscape, fed anything, never panics and never emits a
//! sample that is not finite or above its ceiling.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vr_ocean::audio::engine::CEILING;
use vr_ocean::audio::{SoundConfig, SoundFrame, Soundscape, Splash};
use vr_ocean::sim::WaveParams;

/// Reads f32s (and a u32) from the input, zero when it runs out.
struct Numbers<'a>(&'a [u8]);

impl Numbers<'_> {
    fn f32(&mut self) -> f32 {
        let (head, rest) = self.0.split_at(self.0.len().min(4));
        self.0 = rest;
        let mut b = [0u8; 4];
        b[..head.len()].copy_from_slice(head);
        f32::from_le_bytes(b)
    }
}

fuzz_target!(|data: &[u8]| {
    let mut n = Numbers(data);
    let mut waves = WaveParams::default();
    waves.wind_speed = n.f32();
    waves.wind_direction_deg = n.f32();
    waves.choppiness = n.f32();
    waves.alignment = n.f32();
    waves.loop_period = n.f32();
    waves.roughness = n.f32();
    waves.depth = Some(n.f32());
    let _ = waves.validate();

    let config = SoundConfig {
        sample_rate: (n.f32().abs() as u32).saturating_mul(1000),
        volume: n.f32(),
        seed: n.f32().to_bits() as u64,
    };
    let _ = config.validate();
    let Ok(mut engine) = Soundscape::new(SoundConfig::default()) else {
        return;
    };
    let mut frame = SoundFrame {
        wind_speed: n.f32(),
        significant_height: n.f32(),
        ..SoundFrame::default()
    };
    frame.listener.position = [n.f32(), n.f32(), n.f32()].into();
    for w in frame.wash.iter_mut() {
        w.position = [n.f32(), n.f32(), n.f32()].into();
        w.rise = n.f32();
        w.clearance = n.f32();
    }
    for b in frame.breaking.iter_mut() {
        b.position = [n.f32(), n.f32(), n.f32()].into();
        b.production = n.f32();
        b.foam = n.f32();
    }
    engine.set_frame(&frame);
    engine.splash(Splash {
        time: n.f32() as f64,
        position: [n.f32(), n.f32(), n.f32()].into(),
        speed: n.f32(),
        mass: n.f32(),
        radius: n.f32(),
    });
    let mut out = [0.0f32; 2 * 256];
    for _ in 0..4 {
        engine.render(&mut out);
        for &x in &out {
            assert!(x.is_finite() && x.abs() <= CEILING, "sample {x}");
        }
    }
});
