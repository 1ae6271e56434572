//! The sound's steady state under a counting global allocator (issue 32): the audio callback
//! (the silent clock's thread running `Player::fill`, the path a device's callback takes), the
//! frame thread's side (reading the sea with `SeaProbe`, publishing frames and splashes), the
//! soundscape rendering a busy sea, and `--audio-out`'s recorder allocate nothing.

use crate::common;

use std::time::Duration;

use glam::Vec2;
use vr_ocean::audio::listen::{DeckOutline, ProbeInput, SeaProbe};
use vr_ocean::audio::measure::{busy_sea, thrown_crate};
use vr_ocean::audio::{AudioOutput, Listener, SoundConfig, Soundscape, Splash, WavRecorder};
use vr_ocean::sim::{OceanConfig, Simulation};

fn the_soundscape_and_recorder_do_not_allocate() {
    let mut engine = Soundscape::new(SoundConfig::default()).unwrap();
    let mut buf = vec![0.0f32; 2 * 480];
    let path = common::scratch_path("audio_no_alloc.wav");
    let mut wav = WavRecorder::create(&path, SoundConfig::default()).unwrap();
    let mut t = 0.0;
    let mut step = |engine: &mut Soundscape, wav: &mut WavRecorder, t: &mut f64, k: u32| {
        *t += 0.01;
        let f = busy_sea(*t);
        engine.set_frame(&f);
        let splashes = [thrown_crate(*t)];
        let hits: &[Splash] = if k.is_multiple_of(20) { &splashes } else { &[] };
        if let Some(s) = hits.first() {
            engine.splash(*s);
        }
        engine.render(&mut buf);
        wav.frame(&f, hits).unwrap();
    };
    for k in 0..200 {
        step(&mut engine, &mut wav, &mut t, k);
    }
    let ((), n) = common::count_allocations(|| {
        for k in 0..500 {
            step(&mut engine, &mut wav, &mut t, k);
        }
    });
    wav.finish().unwrap();
    println!("5 s of a busy sea rendered twice (callback-sized and to WAV): {n} allocations");
    assert_eq!(n, 0, "{n} heap allocations while rendering");
    assert!(engine.stats().splashes >= 25);
    std::fs::remove_file(&path).ok();
}

fn the_callback_and_the_frame_side_do_not_allocate() {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let mut sim = Simulation::new(cfg, 1).unwrap();
    let mut t = 0.0;
    sim.step_blocking(t);
    let mut out = AudioOutput::clock(SoundConfig::default(), 480).unwrap();
    let mut probe = SeaProbe::new();
    let deck = DeckOutline {
        centre: Vec2::ZERO,
        half: Vec2::splat(2.0),
        underside: 0.5,
    };
    let mut frame = |sim: &mut Simulation, out: &mut AudioOutput, t: &mut f64, k: u32| {
        *t += 1.0 / 72.0;
        let surfaces = sim.step_blocking(*t);
        let sound = probe.probe(&ProbeInput {
            time: *t,
            listener: Listener::default(),
            surfaces,
            layer: None,
            wind_speed: 15.0,
            wind_toward_deg: 30.0,
            deck: Some(deck),
        });
        let link = out.sender();
        link.publish(&sound);
        if k.is_multiple_of(10) {
            link.splash(thrown_crate(*t));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    for k in 0..40 {
        frame(&mut sim, &mut out, &mut t, k);
    }
    let (before, _) = out.counters();
    // Counting is process-wide: the clock thread's callbacks are counted with this thread.
    let ((), n) = common::count_allocations(|| {
        for k in 0..150 {
            frame(&mut sim, &mut out, &mut t, k);
        }
    });
    let (after, secs) = out.counters();
    let callbacks = after.callbacks - before.callbacks;
    println!(
        "{callbacks} callbacks and 150 frames (sea probed, frames and splashes published): \
         {n} allocations; {} under-runs in {secs:.1} s",
        after.underruns
    );
    assert!(callbacks >= 50, "the clock ran: {callbacks} callbacks");
    assert_eq!(n, 0, "{n} heap allocations on the audio path");
}

/// Runs this suite (`main.rs` calls it).
pub fn main() {
    crate::run(
        "the_soundscape_and_recorder_do_not_allocate",
        the_soundscape_and_recorder_do_not_allocate,
    );
    crate::run(
        "the_callback_and_the_frame_side_do_not_allocate",
        the_callback_and_the_frame_side_do_not_allocate,
    );
}
