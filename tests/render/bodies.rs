//! The floating bodies and the deck drawn in the ocean's pass (issue 15), on lavapipe with the
//! validation layer required: they show (buoys red on the water, the deck's planks under the
//! viewer), cost at most three draws more, and both stereo paths draw the same.

use crate::common;

use common::gpu::{self, Frame};
use vr_ocean::app::{interaction_for, DeckPlacement, FloatOptions, RunReport};
use vr_ocean::lod::QualityPreset;
use vr_ocean::physics::BodyCount;
use vr_ocean::render::StereoMode;

/// Frames to render: 2 s at 72 Hz, long enough for the bodies to settle on the waves.
const FRAMES: u64 = 145;
const W: u32 = 200;
const H: u32 = 160;

fn render(stereo: StereoMode, bodies: Option<usize>) -> (RunReport, Frame) {
    let mut opts = gpu::small_options(stereo, vec![FRAMES - 1]);
    opts.floating = bodies.map(|n| FloatOptions {
        bodies: BodyCount::new(n).unwrap(),
        deck: DeckPlacement::UnderViewer,
        interaction: Some(interaction_for(QualityPreset::High)),
    });
    // On the deck (eyes 1.7 m above its top at 2.8 m), looking down at the water beside it.
    let path = gpu::standing(4.5, 20.0, -22.0);
    let (report, mut frames) = gpu::render(&opts, path, FRAMES, W, H);
    (report, frames.pop().expect("one capture"))
}

/// Pixels of `eye` that read as a buoy: strongly red.
fn red_pixels(f: &Frame, eye: usize) -> usize {
    let mut n = 0;
    for y in 0..f.height {
        for x in 0..f.width {
            let [r, g, b, _] = f.pixel(eye, x, y);
            let (r, g, b) = (r as u32, g as u32, b as u32);
            if r > 60 && r > 2 * g && r > 2 * b {
                n += 1;
            }
        }
    }
    n
}

/// Share of the bottom eighth of `eye` where `a` and `b` differ by more than 24 codes in some
/// channel: what the deck covers.
fn bottom_changed(a: &Frame, b: &Frame, eye: usize) -> f64 {
    let (mut changed, mut all) = (0, 0);
    for y in a.height * 7 / 8..a.height {
        for x in 0..a.width {
            let (p, q) = (a.pixel(eye, x, y), b.pixel(eye, x, y));
            all += 1;
            if (0..3).any(|c| (p[c] as i32 - q[c] as i32).abs() > 24) {
                changed += 1;
            }
        }
    }
    changed as f64 / all as f64
}

#[test]
fn bodies_and_the_deck_are_drawn_in_the_ocean_pass() {
    let (bare_report, bare) = render(StereoMode::Multiview, None);
    let (report, with) = render(StereoMode::Multiview, Some(24));
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        println!("saved {}", with.save("bodies").display());
        println!("saved {}", bare.save("no-bodies").display());
    }
    let extra = report.max_draws as i64 - bare_report.max_draws as i64;
    println!(
        "draws: {} without bodies, {} with (+{extra})",
        bare_report.max_draws, report.max_draws
    );
    assert!(
        (1..=3).contains(&extra),
        "the bodies and the deck take {extra} more draws (at most 3: one per mesh)"
    );
    for eye in 0..2 {
        let (red, none) = (red_pixels(&with, eye), red_pixels(&bare, eye));
        let deck = bottom_changed(&with, &bare, eye);
        println!("eye {eye}: buoy pixels {red} (without bodies {none}), deck covers {:.0} % of the bottom", 100.0 * deck);
        assert_eq!(none, 0, "eye {eye}: red pixels without any buoy");
        assert!(
            red >= 15,
            "eye {eye}: only {red} buoy pixels: are the bodies drawn?"
        );
        assert!(
            deck > 0.5,
            "eye {eye}: the deck covers {:.0} % of the image's bottom",
            100.0 * deck
        );
    }
}

#[test]
fn both_stereo_paths_draw_the_bodies_alike() {
    let (_, mv) = render(StereoMode::Multiview, Some(24));
    let (_, tp) = render(StereoMode::TwoPass, Some(24));
    for eye in 0..2 {
        let (a, b) = (red_pixels(&mv, eye), red_pixels(&tp, eye));
        println!("eye {eye}: buoy pixels multiview {a}, two-pass {b}");
        assert!(a >= 15, "eye {eye}: {a} buoy pixels");
        // The same deterministic run: the same bodies in the same places.
        assert!(
            a.abs_diff(b) <= a / 20 + 2,
            "eye {eye}: multiview {a} vs two-pass {b}"
        );
    }
}
