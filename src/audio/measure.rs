//! Measures of rendered sound for the tests and the benchmark: power, spectral centroid,
//! onsets. Plain and slow (a direct DFT on a few windows); never on the audio path.

use std::f64::consts::TAU;

use glam::Vec3;

use super::scene::{SoundFrame, Splash};

/// Mean square over every sample of `x` (any channel layout).
pub fn power(x: &[f32]) -> f64 {
    x.iter().map(|&v| v as f64 * v as f64).sum::<f64>() / x.len().max(1) as f64
}

/// Channel `ch` of interleaved stereo `x`.
pub fn channel(x: &[f32], ch: usize) -> Vec<f32> {
    x.iter().skip(ch).step_by(2).copied().collect()
}

/// Decibels of `b`'s power over `a`'s.
pub fn db_over(b: &[f32], a: &[f32]) -> f64 {
    10.0 * (power(b) / power(a)).log10()
}

/// Spectral centroid (Hz) of mono `x` at `rate`: Σ f·|X(f)|² / Σ |X(f)|² over up to eight
/// Hann-windowed 4096-sample windows (every fourth bin: ample for a broadband centroid).
pub fn centroid(x: &[f32], rate: f32) -> f64 {
    let n = 4096;
    let (mut num, mut den) = (0.0, 0.0);
    for chunk in x.chunks_exact(n).take(8) {
        let w: Vec<f64> = chunk
            .iter()
            .enumerate()
            .map(|(i, &v)| v as f64 * (0.5 - 0.5 * (TAU * i as f64 / n as f64).cos()))
            .collect();
        for k in (1..n / 2).step_by(4) {
            let step = TAU * k as f64 / n as f64;
            let (mut re, mut im) = (0.0, 0.0);
            for (i, v) in w.iter().enumerate() {
                let (s, c) = (step * i as f64).sin_cos();
                re += v * c;
                im -= v * s;
            }
            let mag = re * re + im * im;
            num += mag * k as f64 * rate as f64 / n as f64;
            den += mag;
        }
    }
    num / den.max(1e-30)
}

/// First sample of mono `x` above `fraction` of its peak.
pub fn onset(x: &[f32], fraction: f32) -> Option<usize> {
    let peak = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    x.iter()
        .position(|v| v.abs() > fraction * peak && peak > 0.0)
}

/// Start of the first window of `window` samples of mono `x`, from `from` on, whose rms is
/// over `factor` times the median window rms of the `window`s before `from`: a sound
/// rising out of a steady bed.
pub fn rise(x: &[f32], from: usize, window: usize, factor: f32) -> Option<usize> {
    let rms = |w: &[f32]| (w.iter().map(|v| v * v).sum::<f32>() / w.len() as f32).sqrt();
    let mut bed: Vec<f32> = x[..from.min(x.len())]
        .chunks_exact(window)
        .map(rms)
        .collect();
    if bed.is_empty() {
        return None;
    }
    bed.sort_by(f32::total_cmp);
    let level = bed[bed.len() / 2];
    x[from..]
        .chunks_exact(window)
        .position(|w| rms(w) > factor * level)
        .map(|k| from + k * window)
}

/// A sea with every voice busy at `time` (s): a gale, a high sea, water at the deck's
/// underside, whitecaps all round. The worst case for cost and level (tests, benchmark).
pub fn busy_sea(time: f64) -> SoundFrame {
    let mut f = SoundFrame {
        time,
        wind_speed: 22.0,
        significant_height: 6.0,
        ..SoundFrame::default()
    };
    let t = time as f32;
    for (k, w) in f.wash.iter_mut().enumerate() {
        w.position = Vec3::new(2.0 * (k as f32 - 1.5), 0.0, -1.0);
        w.rise = (t * 3.0 + k as f32).sin();
        w.clearance = 0.2 * (t * 2.0).cos();
    }
    for (k, b) in f.breaking.iter_mut().enumerate() {
        let a = k as f32 * 0.785;
        b.position = Vec3::new(8.0 * a.cos(), 0.0, 8.0 * a.sin());
        b.production = 0.15;
        b.foam = 0.15;
    }
    f
}

/// A 25 kg body hitting the water at 6 m/s at `time`, 3.6 m to the front left.
pub fn thrown_crate(time: f64) -> Splash {
    Splash {
        time,
        position: Vec3::new(-3.0, 0.0, -2.0),
        speed: 6.0,
        mass: 25.0,
        radius: 0.3,
    }
}
