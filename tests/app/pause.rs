//! Issue 44, item 1 (Meta's VRC.Quest.Functional.2): while the user is away (the session not
//! focused: the system menu, the headset off) the world holds still and the sound pauses; back,
//! both go on from where they stopped. Headless frames on lavapipe with the validation layer,
//! a backend that reports frames 30-89 as unfocused, floating bodies, the sound on its device
//! or silent clock.

use crate::common;

use std::time::Instant;

use common::gpu;
use vr_ocean::app::sound::{SoundOptions, SoundSink};
use vr_ocean::app::{self, interaction_for, Capture, DeckPlacement, FloatOptions};
use vr_ocean::lod::QualityPreset;
use vr_ocean::physics::BodyCount;
use vr_ocean::render::StereoMode;
use vr_ocean::xr::desktop::{EyeSize, HeadlessXr};
use vr_ocean::xr::{FrameLoop, FrameState};

const FRAMES: u64 = 120;
/// Frames the backend reports unfocused.
const AWAY: std::ops::Range<u64> = 30..90;

/// The frames' world times and the captured left eyes.
#[derive(Default)]
struct Seen {
    times: Vec<f64>,
    eyes: Vec<(u64, Vec<u8>)>,
}

impl app::RunHooks for Seen {
    fn capture(&mut self, c: &Capture<'_>) -> Result<(), app::AppError> {
        self.eyes.push((c.frame, c.eyes[0].to_vec()));
        Ok(())
    }
    fn frame_done(&mut self, frame: &FrameState) {
        self.times.push(frame.predicted_display_time);
    }
}

#[test]
fn the_world_and_the_sound_hold_still_while_the_user_is_away() {
    let inner = HeadlessXr::new(
        &gpu::validated(),
        EyeSize::new(96, 96).unwrap(),
        // On the deck, looking at the water and the bodies beside it.
        gpu::standing(4.5, 20.0, -22.0),
        FRAMES,
    )
    .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    let log = inner.gpu().validation.clone().expect("validation layer");
    // Unfocused over AWAY; the wall clock's time away measured from its first frame to the
    // first one back.
    let mut began: Option<Instant> = None;
    let mut away_s = 0.0;
    let mut xr = gpu::Edited {
        inner,
        edit: |s: &mut FrameState| {
            s.paused = AWAY.contains(&s.index);
            if s.index == AWAY.start {
                began = Some(Instant::now());
            }
            if s.index == AWAY.end {
                away_s = began.take().unwrap().elapsed().as_secs_f64();
            }
            Ok(())
        },
    };
    // Two frames well inside the absence, the last before it and the first two after it.
    let captures = vec![AWAY.start - 1, AWAY.start + 5, AWAY.end - 5, AWAY.end + 1];
    let mut opts = gpu::small_options(StereoMode::Multiview, captures);
    opts.floating = Some(FloatOptions {
        bodies: BodyCount::new(4).unwrap(),
        deck: DeckPlacement::UnderViewer,
        interaction: Some(interaction_for(QualityPreset::High)),
    });
    opts.audio = SoundOptions {
        sink: SoundSink::Device,
        ..SoundOptions::default()
    };
    let mut seen = Seen::default();
    let report = app::run(&mut xr, &opts, &mut seen).expect("the run");
    drop(xr);
    assert_eq!(report.frames, FRAMES);
    assert_eq!(log.errors(), 0, "validation errors: {:?}", log.messages());

    // The world's clock stands still while away and runs on after it without a jump.
    let t = &seen.times;
    let period = t[1] - t[0];
    assert!(period > 0.0);
    for i in AWAY {
        assert_eq!(t[i as usize], t[AWAY.start as usize], "frame {i}");
    }
    for i in (1..FRAMES as usize).filter(|i| !AWAY.contains(&(*i as u64))) {
        let step = t[i] - t[i - 1];
        assert!(
            step.abs() < 1e-9 || (step - period).abs() < 1e-6,
            "frame {i}: the world moved {step} s"
        );
    }
    assert!(
        (t[FRAMES as usize - 1] - (t[0] + (FRAMES - 1 - 60) as f64 * period)).abs() < 2.0 * period,
        "the world ran {} s in {} frames",
        t[FRAMES as usize - 1] - t[0],
        FRAMES
    );

    // Nothing moves on the screen while away: the sea, the bodies, their splashes.
    let eye = |f: u64| &seen.eyes.iter().find(|(i, _)| *i == f).unwrap().1;
    assert_eq!(
        eye(AWAY.start + 5),
        eye(AWAY.end - 5),
        "the picture changed while the user was away"
    );
    // And it moves again after (the sea's waves at least).
    assert_ne!(eye(AWAY.start - 1), eye(AWAY.end + 1));

    // The sound was paused about as long as the frames were away (the callback's own count
    // of the silence it gave; a 10 ms buffer either side).
    let audio = report.audio.expect("the sound's report");
    println!("{audio}; away {:.2} s by the wall clock", away_s);
    assert!(away_s > 0.1, "away {} s", away_s);
    assert!(
        (audio.paused_s - away_s).abs() < 0.05 + 0.1 * away_s,
        "paused {:.2} s, away {:.2} s",
        audio.paused_s,
        away_s
    );
}
