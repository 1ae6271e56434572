//! The sound of whole runs (issue 32), rendered with `headless --audio-out` on lavapipe: the
//! same path and seed write the same bytes; a thrown crate's splash starts on its impact;
//! the sea is louder and brighter in a gale; nothing clips; bad options are refused.

use crate::common;

use std::path::Path;

use common::{assert_rejected, scratch_path, vr_ocean};
use vr_ocean::audio::measure::{centroid, channel, db_over, rise};

const RATE: f32 = 48_000.0;

/// Runs a small headless render writing `wav`; returns stderr (the splash log lines).
fn render(wav: &Path, extra: &[&str]) -> String {
    let out_dir = wav.with_extension("frames");
    let mut args = vec![
        "headless",
        "--size",
        "32x32",
        "--bodies",
        "0",
        "--out",
        out_dir.to_str().unwrap(),
        "--audio-out",
        wav.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let out = vr_ocean(&args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {err}");
    let _ = std::fs::remove_dir_all(&out_dir);
    err
}

fn samples(wav: &Path) -> Vec<f32> {
    let mut r = hound::WavReader::open(wav).unwrap();
    let spec = r.spec();
    assert_eq!(
        (spec.channels, spec.sample_rate, spec.bits_per_sample),
        (2, 48_000, 16)
    );
    let x: Vec<f32> = r
        .samples::<i16>()
        .map(|s| s.unwrap() as f32 / i16::MAX as f32)
        .collect();
    assert!(x.iter().all(|v| v.is_finite()));
    let peak = x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(peak < 0.9, "no clipping: peak {peak}");
    x
}

/// The time (s) of the first `splash at T s` line.
fn logged_splash(stderr: &str) -> f64 {
    stderr
        .lines()
        .find_map(|l| {
            l.split("splash at ")
                .nth(1)?
                .split(" s:")
                .next()?
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no splash logged: {stderr}"))
}

#[test]
fn a_thrown_crate_splashes_on_its_impact_and_the_file_repeats() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/throw.path");
    let (a, b) = (scratch_path("throw-a.wav"), scratch_path("throw-b.wav"));
    let args = ["--frames", "180", "--wind", "4", "--path", path];
    let err = render(&a, &args);
    render(&b, &args);
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        "the same path and seed write the same file"
    );
    let impact = logged_splash(&err);
    let x = samples(&a);
    // From the first drawn frame's time to the last's: 179 periods of 1/72 s.
    assert_eq!(x.len(), 2 * (179.0 / 72.0 * RATE as f64).round() as usize);
    // The file starts at the first drawn frame, path time 0: its samples are on that clock.
    let left = channel(&x, 0);
    let from = (0.6 * RATE) as usize;
    let onset = rise(&left, from, 48, 6.0).expect("a splash rises out of the sea") as f64;
    let heard = onset / RATE as f64;
    eprintln!("impact at {impact:.3} s, splash heard from {heard:.3} s");
    assert!(
        impact > 1.0 && impact < 2.0,
        "the crate flies about a second: {impact}"
    );
    assert!((heard - impact).abs() <= 0.020, "{heard} vs {impact}");
    for p in [a, b] {
        std::fs::remove_file(p).ok();
    }
}

#[test]
fn a_gale_is_louder_and_brighter_than_a_breeze() {
    // Two sea realizations each: over two seconds at one place, a big wave washing round the
    // deck (low and loud) can darken one realization's gale; the wind's and the whitecaps'
    // brightness is what holds across them.
    let common = ["--frames", "144", "--settle", "4"];
    let (mut db, mut c5, mut c20) = (0.0, 0.0, 0.0);
    let seeds = ["1", "2"];
    for seed in seeds {
        let (a, b) = (
            scratch_path(&format!("wind5-{seed}.wav")),
            scratch_path(&format!("wind20-{seed}.wav")),
        );
        render(
            &a,
            &[&common[..], &["--wind", "5", "--seed", seed]].concat(),
        );
        render(
            &b,
            &[&common[..], &["--wind", "20", "--seed", seed]].concat(),
        );
        let (x5, x20) = (samples(&a), samples(&b));
        let n = seeds.len() as f64;
        db += db_over(&x20, &x5) / n;
        c5 += centroid(&channel(&x5, 0), RATE) / n;
        c20 += centroid(&channel(&x20, 0), RATE) / n;
        for p in [a, b] {
            std::fs::remove_file(p).ok();
        }
    }
    eprintln!(
        "5 → 20 m/s (mean of {} seas): {db:+.1} dB, centroid {c5:.0} → {c20:.0} Hz",
        seeds.len()
    );
    assert!(db >= 10.0, "{db} dB");
    assert!(c20 > c5, "{c5} → {c20} Hz");
}

#[test]
fn bad_sound_options_are_refused() {
    let out = scratch_path("bad-audio");
    let out = out.to_str().unwrap();
    assert_rejected(
        &["headless", "--volume", "2", "--out", out],
        &["volume", "0 (silent) to 1"],
    );
    assert_rejected(&["headless", "--volume=-0.5", "--out", out], &["volume"]);
    let wav = scratch_path("both.wav");
    assert_rejected(
        &[
            "headless",
            "--audio",
            "on",
            "--audio-out",
            wav.to_str().unwrap(),
            "--out",
            out,
        ],
        &["--audio-out", "choose one"],
    );
    assert_rejected(
        &[
            "headless",
            "--audio-out",
            "/proc/vr-ocean.wav",
            "--frames",
            "1",
            "--out",
            out,
        ],
        &["cannot write /proc"],
    );
}
