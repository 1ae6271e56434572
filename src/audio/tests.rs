//! The soundscape's behaviour, from made-up scenes: loudness with the wind, a splash placed
//! on the left, splashes on their sample, no clipping, the same seed the same sound.

use glam::{Quat, Vec3};

use super::engine::{SoundConfig, Soundscape, CEILING};
use super::measure::{self, centroid, power};
use super::scene::{Listener, SoundFrame, Splash};
use super::spatial::{woodworth_itd, HEAD_RADIUS, SPEED_OF_SOUND};

const RATE: f32 = 48_000.0;

fn render(engine: &mut Soundscape, seconds: f32) -> Vec<f32> {
    let mut out = vec![0.0f32; 2 * (seconds * RATE) as usize];
    engine.render(&mut out);
    out
}

fn engine(frame: &SoundFrame) -> Soundscape {
    let mut e = Soundscape::new(SoundConfig::default()).unwrap();
    e.set_frame(frame);
    e
}

fn windy(speed: f32) -> SoundFrame {
    SoundFrame {
        wind_speed: speed,
        significant_height: 0.0,
        ..SoundFrame::default()
    }
}

#[test]
fn the_wind_grows_louder_and_brighter() {
    let mut calm = engine(&windy(5.0));
    let mut gale = engine(&windy(20.0));
    // Past the parameters' easing.
    render(&mut calm, 2.0);
    render(&mut gale, 2.0);
    let (a, b) = (render(&mut calm, 4.0), render(&mut gale, 4.0));
    let db = 10.0 * (power(&b) / power(&a)).log10();
    let (ca, cb) = (
        centroid(&measure::channel(&a, 0), RATE),
        centroid(&measure::channel(&b, 0), RATE),
    );
    eprintln!("wind 5 → 20 m/s: {db:+.1} dB, centroid {ca:.0} → {cb:.0} Hz");
    assert!(db >= 10.0, "{db} dB");
    assert!(cb > 1.3 * ca, "{ca} → {cb} Hz");
}

fn splash_at(position: Vec3, time: f64) -> Splash {
    Splash {
        time,
        position,
        speed: 5.0,
        mass: 20.0,
        radius: 0.25,
    }
}

/// First frame in `ch` whose sample exceeds 5 % of that channel's peak.
fn onset(x: &[f32], ch: usize) -> usize {
    measure::onset(&measure::channel(x, ch), 0.05).expect("a splash was rendered")
}

#[test]
fn a_splash_on_the_left_is_louder_and_earlier_on_the_left() {
    let head = Listener::default();
    for turn in [0.0f32, 0.7] {
        let listener = Listener {
            orientation: Quat::from_rotation_y(turn),
            ..head
        };
        let mut e = engine(&SoundFrame {
            listener,
            ..SoundFrame::default()
        });
        // 3 m to the head's left.
        let left = listener.orientation * Vec3::new(-3.0, 0.0, 0.0);
        e.splash(splash_at(listener.position + left, 0.01));
        let out = render(&mut e, 1.5);
        let l: Vec<f32> = out.iter().step_by(2).copied().collect();
        let r: Vec<f32> = out.iter().skip(1).step_by(2).copied().collect();
        let db = 10.0 * (power(&l) / power(&r)).log10();
        let itd = (onset(&out, 1) as f32 - onset(&out, 0) as f32) / RATE;
        let model = woodworth_itd(std::f32::consts::FRAC_PI_2);
        eprintln!(
            "turn {turn}: left {db:+.1} dB over right, arrives {:.3} ms first (model {:.3})",
            itd * 1e3,
            model * 1e3
        );
        assert!(db > 3.0, "{db} dB");
        assert!((itd - model).abs() < 1.0e-4, "{itd} s vs {model} s");
    }
    assert!(
        (woodworth_itd(std::f32::consts::FRAC_PI_2) - HEAD_RADIUS / SPEED_OF_SOUND * 2.5708).abs()
            < 1e-6
    );
}

#[test]
fn a_splash_starts_on_its_sample() {
    // Straight ahead: both ears the same; the common delay is under 20 samples.
    let listener = Listener::default();
    for at in [0.2, 0.5137, 0.9] {
        let mut e = engine(&SoundFrame::default());
        e.splash(splash_at(
            listener.position + Vec3::new(0.0, -1.5, -3.0),
            at,
        ));
        let out = render(&mut e, 1.2);
        let start = onset(&out, 0) as f64 / RATE as f64;
        assert!((start - at).abs() < 1.0e-3, "{start} vs {at}");
    }
}

#[test]
fn a_storm_of_splashes_never_clips_or_goes_nan() {
    let mut frame = windy(25.0);
    frame.significant_height = 8.0;
    for (k, w) in frame.wash.iter_mut().enumerate() {
        w.position = Vec3::new(k as f32 - 1.5, 0.0, 1.0);
        w.rise = 3.0;
        w.clearance = 0.0;
    }
    for (k, b) in frame.breaking.iter_mut().enumerate() {
        b.position = Vec3::new(5.0 * (k as f32).cos(), 0.0, 5.0 * (k as f32).sin());
        b.production = 5.0;
        b.foam = 5.0;
    }
    let mut e = engine(&frame);
    for k in 0..12 {
        let mut s = splash_at(Vec3::new(0.0, 0.0, -0.5), 0.05 * k as f64);
        s.mass = 500.0;
        s.speed = 15.0;
        e.splash(s);
    }
    let out = render(&mut e, 3.0);
    assert!(out.iter().all(|v| v.is_finite()));
    let peak = out.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(peak <= CEILING, "{peak}");
    assert!(
        e.stats().peak > CEILING,
        "the limiter was exercised: {}",
        e.stats().peak
    );
    // Bad input is dropped, not rendered.
    let mut bad = splash_at(Vec3::new(f32::NAN, 0.0, 0.0), 3.1);
    e.splash(bad);
    bad.position = Vec3::ZERO;
    bad.mass = -1.0;
    e.splash(bad);
    assert_eq!(e.stats().dropped, 2);
}

#[test]
fn the_same_seed_makes_the_same_sound() {
    let frame = windy(12.0);
    let mut a = engine(&frame);
    let mut b = engine(&frame);
    a.splash(splash_at(Vec3::new(2.0, 0.0, -2.0), 0.3));
    b.splash(splash_at(Vec3::new(2.0, 0.0, -2.0), 0.3));
    assert_eq!(render(&mut a, 1.0), render(&mut b, 1.0));
    let mut c = Soundscape::new(SoundConfig {
        seed: 2,
        ..SoundConfig::default()
    })
    .unwrap();
    c.set_frame(&frame);
    assert_ne!(render(&mut a, 0.5), render(&mut c, 0.5));
}

#[test]
fn bad_settings_are_refused_with_their_range() {
    let e = Soundscape::new(SoundConfig {
        volume: 1.5,
        ..SoundConfig::default()
    });
    assert!(e.err().unwrap().to_string().contains("0 (silent) to 1"));
    let e = Soundscape::new(SoundConfig {
        sample_rate: 1000,
        ..SoundConfig::default()
    });
    assert!(e.is_err());
}

#[test]
fn a_broken_frame_is_silenced_not_rendered_as_nan() {
    let mut frame = windy(f32::NAN);
    frame.significant_height = f32::INFINITY;
    frame.listener.position = Vec3::new(3.0e38, -3.0e38, 0.0);
    frame.listener.orientation = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    frame.wash[0].rise = f32::NAN;
    frame.wash[1].clearance = f32::NAN;
    frame.wash[2].position = Vec3::new(-3.0e38, 0.0, 3.0e38);
    frame.breaking[0].production = f32::INFINITY;
    frame.breaking[1].position = Vec3::splat(f32::NAN);
    let mut e = engine(&frame);
    let out = render(&mut e, 1.0);
    assert!(out.iter().all(|v| v.is_finite() && v.abs() <= CEILING));
    // A splash too big or too fast to be real is dropped.
    let mut s = splash_at(Vec3::ZERO, 0.0);
    s.speed = f32::MAX;
    e.splash(s);
    assert_eq!(e.stats().dropped, 1);
}

/// The first difference of one channel: its power is the sound's above a few kilohertz (a
/// high-pass rising 6 dB an octave).
fn highs(x: &[f32], ch: usize) -> Vec<f32> {
    let c = measure::channel(x, ch);
    c.windows(2).map(|w| w[1] - w[0]).collect()
}

#[test]
fn under_the_water_the_air_goes_quiet_and_the_sea_low_and_close() {
    let mut air = engine(&measure::busy_sea(0.0));
    let mut water = engine(&SoundFrame {
        submersion: 1.0,
        ..measure::busy_sea(0.0)
    });
    render(&mut air, 1.0);
    render(&mut water, 1.0);
    let (a, w) = (render(&mut air, 3.0), render(&mut water, 3.0));
    let (ca, cw) = (
        centroid(&measure::channel(&a, 0), RATE),
        centroid(&measure::channel(&w, 0), RATE),
    );
    let highs_db = 10.0 * (power(&highs(&w, 0)) / power(&highs(&a, 0))).log10();
    let all_db = 10.0 * (power(&w) / power(&a)).log10();
    eprintln!("under: centroid {ca:.0} → {cw:.0} Hz, highs {highs_db:+.1} dB, all {all_db:+.1} dB");
    assert!(
        cw < 0.4 * ca,
        "the sea under the water is not low: {ca:.0} → {cw:.0} Hz"
    );
    assert!(highs_db < -20.0, "the highs fell only {highs_db:.1} dB");
    // Muffled, not silenced: the water's own sound stays near its level.
    assert!(all_db > -12.0, "the whole sea fell {all_db:.1} dB");
    // The wind alone: the surface turns it away.
    let mut wind_air = engine(&windy(15.0));
    let mut wind_water = engine(&SoundFrame {
        submersion: 0.5,
        ..windy(15.0)
    });
    render(&mut wind_air, 1.0);
    render(&mut wind_water, 1.0);
    let wind_db = measure::db_over(&render(&mut wind_water, 2.0), &render(&mut wind_air, 2.0));
    eprintln!("the wind under the water: {wind_db:+.1} dB");
    assert!(wind_db < -20.0, "the wind fell only {wind_db:.1} dB");
}

#[test]
fn crossing_the_surface_does_not_click() {
    // Down and up again in a high swell with no wind, no breaking near and the deck clear of
    // the water (the swell's rumble alone: a low sound, against which a step would stand
    // out).
    let calm = |t: f64, submersion: f32| SoundFrame {
        time: t,
        significant_height: 6.0,
        submersion,
        ..SoundFrame::default()
    };
    // A click is a step: one sample's change far beyond its neighbours'. The largest change
    // between samples while crossing, against the largest in a second of each side's steady
    // sound.
    let sharpest = |x: &[f32]| highs(x, 0).iter().fold(0.0f32, |m, d| m.max(d.abs()));
    let mut e = engine(&calm(0.0, -0.3));
    render(&mut e, 1.0);
    let above = sharpest(&render(&mut e, 1.0));
    e.set_frame(&calm(2.0, 0.3));
    render(&mut e, 1.0);
    let below = sharpest(&render(&mut e, 1.0));
    let steady = above.max(below);
    let mut worst: f32 = 0.0;
    for (depth, t) in [(-0.3, 4.0), (0.3, 5.0), (-0.3, 6.0), (0.3, 7.0)] {
        e.set_frame(&calm(t, depth));
        worst = worst.max(sharpest(&render(&mut e, 0.25)));
        render(&mut e, 0.75);
    }
    eprintln!("largest change between samples: above {above:.3e}, below {below:.3e}, crossing {worst:.3e}");
    assert!(
        worst <= steady * 1.05,
        "a crossing clicks: {worst:.3e} vs {steady:.3e}"
    );
}
