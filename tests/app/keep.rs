//! Issue 44, item 2: what the user chose is kept whenever it may be the last chance: once a
//! change has settled ([`app::KEEP_AFTER`]), at once when the app pauses (before STOPPING and
//! `onStop`), and at the end of a run that ended in an error (a lost runtime), not only after
//! a clean end. Headless frames on lavapipe with the validation
//! layer; the backend injects a wind change, then fails.

use crate::common;

use std::time::{Duration, Instant};

use common::gpu;
use vr_ocean::app::chosen::Chosen;
use vr_ocean::app::keep::SettingsKeeper;
use vr_ocean::app::{self, RunHooks};
use vr_ocean::render::StereoMode;
use vr_ocean::ui::SettingsFile;
use vr_ocean::xr::desktop::{EyeSize, HeadlessXr};
use vr_ocean::xr::{FrameLoop, FrameState, Tweak, XrError};

/// Keeps every call's wind.
#[derive(Default)]
struct Kept(Vec<f32>);

impl RunHooks for Kept {
    fn keep(&mut self, chosen: &Chosen) {
        self.0.push(chosen.waves.wind_speed);
    }
}

fn lost_after(fail_after: Duration, hooks: &mut dyn RunHooks) -> (f32, String) {
    lost_after_pausing(fail_after, None, hooks)
}

/// As [`lost_after`], the app paused (the focus lost) from frame `pause_from` on.
fn lost_after_pausing(
    fail_after: Duration,
    pause_from: Option<u64>,
    hooks: &mut dyn RunHooks,
) -> (f32, String) {
    let inner = HeadlessXr::new(
        &gpu::validated(),
        EyeSize::new(32, 32).unwrap(),
        gpu::standing(1.7, 0.0, -8.0),
        5000,
    )
    .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    let log = inner.gpu().validation.clone().expect("validation layer");
    // The wind raised by 3 m/s at frame 2; the runtime "lost" once the change has stood for
    // `fail_after` (or at frame 2000).
    let mut changed_at: Option<Instant> = None;
    let mut xr = gpu::Edited {
        inner,
        edit: |s: &mut FrameState| {
            if s.index == 2 {
                s.tweaks[0] = Some(Tweak::WindSpeed(3.0));
                changed_at = Some(Instant::now());
            }
            s.paused |= pause_from.is_some_and(|f| s.index >= f);
            let waited = changed_at.is_some_and(|t| t.elapsed() >= fail_after);
            if waited || s.index >= 2000 {
                return Err(XrError::Backend("the runtime was lost (test)".into()));
            }
            Ok(())
        },
    };
    let opts = gpu::small_options(StereoMode::Multiview, Vec::new());
    let start_wind = opts.ocean.waves.wind_speed;
    let err = app::run(&mut xr, &opts, hooks).expect_err("the runtime was lost");
    drop(xr);
    assert_eq!(log.errors(), 0, "validation errors: {:?}", log.messages());
    (start_wind, err.to_string())
}

#[test]
fn a_settled_change_is_kept_and_a_lost_runtime_keeps_the_last_word() {
    // Lost before the change settled: the start's word, then the new wind once, at the end.
    let mut quick = Kept::default();
    let (wind, err) = lost_after(Duration::from_millis(100), &mut quick);
    assert!(err.contains("runtime was lost"), "{err}");
    assert_eq!(quick.0, vec![wind, wind + 3.0], "kept {:?}", quick.0);

    // Lost well after it settled: kept when it settled, and again at the end.
    let mut late = Kept::default();
    lost_after(app::KEEP_AFTER * 3, &mut late);
    assert_eq!(
        late.0,
        vec![wind, wind + 3.0, wind + 3.0],
        "kept {:?}",
        late.0
    );
}

#[test]
fn a_change_is_kept_at_once_when_the_app_pauses() {
    // Paused two frames after the change, lost 100 ms later: kept at the pause (before the
    // change settled) and at the end. Without the pause's save only the end would keep it.
    let mut paused = Kept::default();
    let (wind, _) = lost_after_pausing(Duration::from_millis(100), Some(4), &mut paused);
    assert_eq!(
        paused.0,
        vec![wind, wind + 3.0, wind + 3.0],
        "kept {:?}",
        paused.0
    );
}

#[test]
fn the_settings_keeper_saves_what_a_lost_run_chose() {
    let dir = std::env::temp_dir().join(format!("vr-ocean-keep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let file = SettingsFile::at(dir.join("settings.json"));
    let mut keeper = SettingsKeeper::new(Some(&file), 0.5, true);
    let (wind, _) = lost_after(Duration::from_millis(100), &mut keeper);
    // The start's word (no file yet) and the end's; the file then holds the last.
    assert_eq!(keeper.saves(), 2);
    let loaded = file.load();
    assert!(loaded.warning.is_none(), "{:?}", loaded.warning);
    assert_eq!(loaded.settings.wind_speed, wind + 3.0);
    assert_eq!(loaded.settings.volume, 0.5);
    let _ = std::fs::remove_dir_all(&dir);
}
