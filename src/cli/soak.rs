//! `vr-ocean xr --soak-minutes M`: the OpenXR path played by a scripted user
//! ([`app::scripted::ScriptedUser`]) for M minutes, through as many sessions as it takes: when
//! the runtime or the session goes away, a new instance is made once the runtime is back (as
//! a Quest relaunches an app), in the same process, so whatever a session leaks adds up. It
//! prints the process's memory and open files once a minute and a summary at the end; a test
//! (`tests/soak/monado.rs`, `cargo xtask soak`) takes the focus away, kills the runtime once and
//! judges the numbers.

use std::time::{Duration, Instant};

use super::report::CmdResult;
use super::report::ValidationWatch;
use vr_ocean::app::scripted::{ResourceSample, ScriptedUser};
use vr_ocean::app::{self, RunHooks, RunOptions};
use vr_ocean::xr::openxr::OpenXr;
use vr_ocean::xr::XrError;

/// How long to wait for the runtime to come back after a lost session.
pub const RECONNECT_FOR: Duration = Duration::from_secs(120);

/// Memory is judged from this far into the soak (the caches, pools and first sessions
/// warmed), or from half-way in a soak shorter than twice this.
pub const WARM_AFTER_S: f64 = 150.0;

/// Runs sessions from `open` for `minutes`, each played by the scripted user; `open` may fit
/// `opts` to the device it got.
pub fn soak(
    minutes: f64,
    open: &mut dyn FnMut(&mut RunOptions) -> Result<OpenXr, XrError>,
    opts: &mut RunOptions,
    hooks: &mut dyn RunHooks,
) -> CmdResult {
    if !(minutes > 0.0 && minutes <= 24.0 * 60.0) {
        return Err(format!("--soak-minutes {minutes}: must be in (0, 1440]").into());
    }
    let started = Instant::now();
    let deadline = started + Duration::from_secs_f64(minutes * 60.0);
    let (mut sessions, mut lost, mut pauses, mut acts) = (0u32, 0u32, 0u32, 0u64);
    let (mut underruns, mut late_wakes) = (0u64, 0u64);
    let mut samples: Vec<ResourceSample> = Vec::new();
    while Instant::now() < deadline {
        let mut xr = match open(opts) {
            Ok(xr) => xr,
            Err(e) if sessions > 0 => {
                // The runtime is not back yet: try again until it is, or give up.
                let waited = Instant::now();
                let mut last = e;
                let xr = loop {
                    if waited.elapsed() > RECONNECT_FOR {
                        return Err(format!(
                            "soak: the runtime did not come back in {} s: {last}",
                            RECONNECT_FOR.as_secs()
                        )
                        .into());
                    }
                    std::thread::sleep(Duration::from_secs(1));
                    match open(opts) {
                        Ok(xr) => break xr,
                        Err(e) => last = e,
                    }
                };
                xr
            }
            Err(e) => return Err(e.into()),
        };
        sessions += 1;
        let validation = ValidationWatch::of(vr_ocean::xr::FrameLoop::gpu(&xr));
        let left = deadline.saturating_duration_since(Instant::now());
        let mut user = ScriptedUser::new(&mut xr, opts.lod.preset(), Some(left));
        let result = app::run(&mut user, opts, hooks);
        pauses += user.pauses();
        acts += user.acts();
        let offset = started.elapsed().as_secs_f64() - user.elapsed_s();
        samples.extend(user.samples().iter().map(|s| ResourceSample {
            at_s: s.at_s + offset,
            ..*s
        }));
        let summary = xr.summary();
        drop(xr);
        println!("openxr summary: {}", summary.line());
        validation.check()?;
        match result {
            Ok(report) => {
                if let Some(a) = &report.audio {
                    println!("{a}");
                    underruns += a.underruns;
                    late_wakes += a.late_wakes;
                }
                println!(
                    "soak: session {sessions} ended after {} frames",
                    report.frames
                );
            }
            Err(app::AppError::Xr(e)) if e.is_lost() => {
                lost += 1;
                println!("soak: session {sessions} lost ({e}); waiting for the runtime");
            }
            Err(e) => return Err(e.into()),
        }
    }
    if let Some(s) = ResourceSample::now(started.elapsed().as_secs_f64()) {
        println!("{s}");
        samples.push(s);
    }
    let warm_after = WARM_AFTER_S.min(0.5 * minutes * 60.0);
    let warm = samples.iter().find(|s| s.at_s >= warm_after);
    let last = samples.last();
    let resources = match (warm, last) {
        (Some(w), Some(l)) => format!(
            "rss {} -> {} KiB after warm-up, fds {} -> {}",
            w.rss_kib, l.rss_kib, w.fds, l.fds
        ),
        // A chroot without /proc mounted (the Monado test samples from outside).
        _ => "rss and fds not readable here (no /proc)".into(),
    };
    println!(
        "soak summary: {:.1} min, {sessions} sessions ({lost} lost), {pauses} focus losses, \
         {acts} scripted acts, {resources}, {underruns} under-runs ({late_wakes} late wakes)",
        started.elapsed().as_secs_f64() / 60.0,
    );
    Ok(())
}
