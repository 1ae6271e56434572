//! `android_main`: where the APK's code starts (android-activity calls it on its own thread
//! after NativeActivity loaded `libvr_ocean.so` and called `ANativeActivity_onCreate`).

use android_activity::AndroidApp;

use super::frame_loop::ActivityFrameLoop;
use super::options::{apply_settings, run_options, xr_options};
use super::LOG_TAG;
use crate::app::keep::SettingsKeeper;
use crate::app::{self, AppError, SoundSink};
use crate::ui::SettingsFile;
use crate::xr::openxr::OpenXr;
use crate::xr::FrameLoop;

/// The entry point android-activity's NativeActivity glue calls. When it returns, the glue
/// finishes the activity.
#[no_mangle]
fn android_main(app: AndroidApp) {
    android_logger::init_once(
        android_logger::Config::default()
            .with_max_level(log::LevelFilter::Info)
            .with_tag(LOG_TAG),
    );
    install_panic_hook();
    log::info!("vr-ocean {} starting", env!("CARGO_PKG_VERSION"));
    match run(app) {
        Ok(()) => log::info!("vr-ocean finished"),
        Err(e) => log::error!("vr-ocean stopped: {e}"),
    }
}

/// Logs every panic with its location and a backtrace before android-activity's own handler
/// finishes the activity.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let thread = std::thread::current();
        log::error!(
            "panic on thread {}: {info}\n{}",
            thread.name().unwrap_or("<unnamed>"),
            std::backtrace::Backtrace::force_capture()
        );
    }));
}

/// Connects to the OpenXR runtime through the activity and runs the ocean until the session
/// ends.
fn run(app: AndroidApp) -> Result<(), AppError> {
    // SAFETY: android-activity gives the process's JavaVM and a global reference to the
    // Activity, valid while `app` lives. `app` moves into the frame loop next to the backend,
    // which is declared (so dropped) before it.
    let xr = unsafe { OpenXr::new_android(xr_options(), app.vm_as_ptr(), app.activity_as_ptr()) }?;
    let cores = std::thread::available_parallelism().ok().map(|n| n.get());
    let max_khz =
        crate::sim::workers::core_max_khz(std::path::Path::new("/sys/devices/system/cpu"));
    let mut options = run_options(&xr.headset().defaults(), xr.preset(), &max_khz, cores)?;
    // The user's choices of the last session, kept in the app's internal files directory.
    let kept = app.internal_data_path().map(|d| SettingsFile::in_dir(&d));
    if let Some(file) = &kept {
        let loaded = file.load();
        if let Some(w) = &loaded.warning {
            log::warn!("settings: {w}");
        }
        apply_settings(&mut options, &loaded.settings)?;
    }
    log::info!(
        "OpenXR session ready on {:?}: {} simulation threads (core clocks {max_khz:?} kHz), \
         preset {}, device {}",
        xr.headset(),
        options.threads,
        options.lod.preset().name(),
        xr.gpu().device_name
    );
    let mut frame_loop = ActivityFrameLoop::new(xr, app);
    // The choices are kept as they settle and at the end, however the session ended (the
    // runtime lost, the process about to be killed).
    let audio = options.audio.sink != SoundSink::Off;
    let mut keeper = SettingsKeeper::new(kept.as_ref(), options.audio.volume, audio);
    let result = app::run(&mut frame_loop, &options, &mut keeper);
    log::info!("openxr summary: {}", frame_loop.xr().summary().line());
    drop(frame_loop);
    let report = result?;
    log::info!("{} frames rendered", report.frames);
    if let Some(sound) = &report.audio {
        // The under-runs, reopened streams and paused time, in logcat.
        log::info!("{sound}");
    }
    for (name, p) in app::timing::TIMINGS.iter().zip(report.times.all()) {
        log::info!(
            "{name:<12} p50 {:>7.3} p95 {:>7.3} p99 {:>7.3} ms",
            p.p50,
            p.p95,
            p.p99
        );
    }
    Ok(())
}
