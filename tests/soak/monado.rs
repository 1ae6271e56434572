//! Issue 44's soak: `vr-ocean xr --soak-minutes M` on Monado, played by its scripted user (the
//! sea state up and down, crates thrown, a boat launched, the panel opened, pressed, dragged
//! and closed, presets cycled, the sun moved), while this test takes the focus away twice (a
//! second client, as the Quest's system menu does) and kills the runtime once (the client makes
//! a new instance when it is back, in the same process). Judged: the process exits cleanly;
//! the sessions and losses as scripted; both focus losses seen; resident memory flat: the peak
//! over the last session's last two script cycles (its states repeat every two cycles of a
//! clock that stands still while paused) within 5 % of its own first two cycles and of the
//! same peak of the first session after a loss (10 % between sessions in the CI soak, whose
//! 100-s sessions' peaks scatter more), so neither a leak within a session nor one that each
//! lost session leaves goes unseen (the first session's peak is reported: the
//! first loss leaves a one-time step); open file
//! descriptors not growing; both read by this test from the host's `/proc/<pid>` every 5 s
//! (the root has no `/proc` of its own); no under-run of the sound's clock that the host did
//! not cause; zero Vulkan validation messages (leaked objects included: each
//! session's device is destroyed under the layer) and zero OpenXR core validation messages.
//!
//! `M` is `VR_OCEAN_SOAK_MINUTES` (default 5: three sessions of 100 s, the `openxr (Monado)`
//! step of `cargo xtask test`), the losses `VR_OCEAN_SOAK_LOSSES` (default 2);
//! `cargo xtask soak` runs 20. Needs root and the Monado root, like `tests/openxr_monado/`.

use crate::common;

use std::path::Path;
use std::time::{Duration, Instant};

use common::monado::{self, Monado};
use vr_ocean::app::scripted::ResourceSample;

const EXE: &str = env!("CARGO_BIN_EXE_vr-ocean");
const NAME: &str = "soak";

/// The number before `tail` in `line` (`"2 sessions"` → 2).
fn number_before(line: &str, tail: &str) -> f64 {
    line.split(tail)
        .next()
        .and_then(|h| h.rsplit([' ', '(', ',']).find(|w| !w.is_empty()))
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("no number before {tail:?} in {line:?}"))
}

/// The soak client's process: the one whose command line has `--soak-minutes`.
fn soak_pid() -> Option<u32> {
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: u32 = e.file_name().to_str()?.parse().ok()?;
        let cmdline = std::fs::read(e.path().join("cmdline")).ok()?;
        let is_soak = cmdline.split(|&b| b == 0).any(|a| a == b"--soak-minutes");
        is_soak.then_some(pid)
    })
}

#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test; cargo xtask soak)"]
fn a_soak_through_focus_losses_and_a_lost_runtime_stays_flat() {
    let minutes: f64 = std::env::var("VR_OCEAN_SOAK_MINUTES")
        .ok()
        .map(|m| m.parse().expect("VR_OCEAN_SOAK_MINUTES: minutes"))
        .unwrap_or(5.0);
    let total = Duration::from_secs_f64(minutes * 60.0);
    let root = monado::root_from_env();
    let first_service = Monado::start_with(&root, NAME, false);
    let done = std::sync::atomic::AtomicBool::new(false);
    let mut env = monado::xr_validation_env(NAME);
    env.push(("RUST_LOG".into(), "info".into()));
    let m = minutes.to_string();
    let args = [
        "xr",
        "--grid",
        "64",
        "--preset",
        "low",
        "--soak-minutes",
        &m,
        "--validation",
    ];
    let thief_args = [
        "xr", "--frames", "200", "--grid", "64", "--preset", "low", "--audio", "off",
    ];
    let start = Instant::now();
    let wait_until = |share: f64| {
        let at = total.mul_f64(share);
        if let Some(left) = at.checked_sub(start.elapsed()) {
            std::thread::sleep(left);
        }
    };
    // The runtime killed `losses` times, evenly; the focus taken in the middle of the first
    // and of the last session.
    let losses: u32 = std::env::var("VR_OCEAN_SOAK_LOSSES")
        .ok()
        .map(|m| m.parse().expect("VR_OCEAN_SOAK_LOSSES: a count"))
        .unwrap_or(2);
    let sessions = f64::from(losses + 1);
    let mut services = vec![first_service];
    let (run, kills, samples) = std::thread::scope(|s| {
        let sampler = s.spawn(|| {
            let mut samples = Vec::new();
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                let at = start.elapsed().as_secs_f64();
                if let Some(x) = soak_pid().and_then(|pid| ResourceSample::of(Some(pid), at)) {
                    samples.push(x);
                }
                std::thread::sleep(Duration::from_secs(5));
            }
            samples
        });
        let client = s.spawn(|| {
            monado::run_client(
                &root,
                NAME,
                Path::new(EXE),
                &args,
                &monado::env_refs(&env),
                total + Duration::from_secs(600),
            )
        });
        let steal_focus = |service: &Monado, what: &str| {
            // 200 frames: 10 s at Monado's 20 Hz.
            let thief = service.client(
                Path::new(EXE),
                &thief_args,
                &[("RUST_LOG", "info")],
                Duration::from_secs(180),
            );
            assert!(thief.success(), "{what}: {thief}");
        };
        let mut kills = Vec::new();
        wait_until(0.5 / sessions);
        steal_focus(&services[0], "the first focus thief");
        for k in 1..=losses {
            wait_until(f64::from(k) / sessions);
            kills.push(start.elapsed().as_secs_f64());
            services.last().expect("a service").kill_service();
            std::thread::sleep(Duration::from_secs(3));
            services.push(Monado::start_with(&root, NAME, false));
        }
        wait_until((sessions - 0.5) / sessions);
        steal_focus(services.last().expect("a service"), "the last focus thief");
        let run = client.join().unwrap();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        (run, kills, sampler.join().unwrap())
    });
    for service in services.into_iter().rev() {
        let _ = service.finish();
    }
    for l in run.stdout.lines().filter(|l| l.starts_with("soak")) {
        println!("{l}");
    }
    assert!(run.success(), "{run}");
    let summary = run
        .stdout
        .lines()
        .find(|l| l.starts_with("soak summary:"))
        .unwrap_or_else(|| panic!("no soak summary\n{run}"));
    for line in run.stdout.lines().filter(|l| l.starts_with("audio (")) {
        println!("{line}");
    }

    // Memory: each session's peak RSS over its last two script cycles (60 s of the script's
    // clock, which stands still while paused: 70 s of wall time with a focus thief), after its
    // first 20 s. The first session is the reference only for the report: the first lost
    // session leaves a one-time step behind (see below); the judged growth is from the
    // second session (the first after a loss) to the last, and within the last.
    const WINDOW_S: f64 = 70.0;
    let end = samples.last().expect("samples").at_s + 0.1;
    let bounds: Vec<(f64, f64)> = std::iter::once(0.0)
        .chain(kills.iter().copied())
        .zip(kills.iter().copied().chain(std::iter::once(end)))
        .collect();
    let peak_in = |from: f64, to: f64| {
        samples
            .iter()
            .filter(|x| (from..to).contains(&x.at_s))
            .map(|x| x.rss_kib)
            .max()
            .unwrap_or_else(|| panic!("no sample in {from:.0}-{to:.0} s: {samples:?}"))
    };
    let peaks: Vec<u64> = bounds
        .iter()
        .map(|&(from, to)| peak_in((to - WINDOW_S).max(from + 20.0), to))
        .collect();
    let (last_from, last_to) = *bounds.last().expect("a session");
    let last_early = peak_in(last_from + 20.0, (last_from + 20.0 + WINDOW_S).min(last_to));
    for x in samples.iter().step_by(6) {
        println!(
            "soak (host): t={:.0} s rss={} KiB fds={}",
            x.at_s, x.rss_kib, x.fds
        );
    }
    let fds_first = samples
        .iter()
        .rev()
        .find(|x| x.at_s < bounds[0].1)
        .map_or(0, |x| x.fds);
    let fds_end = samples.last().map_or(0, |x| x.fds);
    let pct = |a: u64, b: u64| 100.0 * (b as f64 / a as f64 - 1.0);
    let after_loss = peaks.get(1).copied().unwrap_or(peaks[0]);
    let last = *peaks.last().expect("a session");
    println!(
        "soak (host): {} samples over {end:.0} s; sessions' peak rss {peaks:?} KiB: the first \
         loss {:+.1} %, from the first session after a loss to the last {:+.1} %, within the \
         last {:+.1} % ({last_early} -> {last}); fds {fds_first} -> {fds_end}",
        samples.len(),
        pct(peaks[0], after_loss),
        pct(after_loss, last),
        pct(last_early, last),
    );
    assert_eq!(number_before(summary, " sessions"), sessions, "{summary}");
    assert_eq!(
        number_before(summary, " lost"),
        f64::from(losses),
        "{summary}"
    );
    assert_eq!(number_before(summary, " focus losses"), 2.0, "{summary}");
    assert!(
        number_before(summary, " scripted acts") >= 10.0,
        "{summary}"
    );
    for (k, &(from, to)) in bounds.iter().enumerate() {
        assert!(
            to - from >= WINDOW_S + 20.0,
            "session {} of {:.0} s is too short to judge memory (a soak of at least 5 min)",
            k + 1,
            to - from
        );
    }
    assert!(
        losses >= 2,
        "judging memory needs two sessions after a loss"
    );
    // Sessions of 100 s (the CI soak) sample each state only a few times: their peaks were
    // measured −1.3 .. +5.9 % apart in four runs with nothing changed (Zen 5), so they are held
    // to 10 %; sessions of 5 minutes and more (`cargo xtask soak`) to 5 %.
    let shortest = bounds
        .iter()
        .map(|(f, t)| t - f)
        .fold(f64::INFINITY, f64::min);
    let between = if shortest >= 300.0 { 1.05 } else { 1.10 };
    assert!(
        last as f64 <= after_loss as f64 * between,
        "resident memory grew from session to session: peak {after_loss} -> {last} KiB \
         (allowed {:+.0} %)",
        100.0 * (between - 1.0)
    );
    assert!(
        last as f64 <= last_early as f64 * 1.05,
        "resident memory grew within the last session: peak {last_early} -> {last} KiB"
    );
    assert!(
        fds_end <= fds_first + 2,
        "open files grew {fds_first} -> {fds_end}"
    );
    // Every late buffer (if any) a real-time thread woken late by the host, none slow.
    let underruns = number_before(summary, " under-runs");
    let late_wakes = number_before(summary, " late wakes)");
    assert_eq!(underruns, late_wakes, "{summary}");

    assert!(
        !run.stderr.contains("Vulkan validation"),
        "Vulkan validation messages\n{run}"
    );
    let xr_problems = monado::xr_validation_errors(&root, NAME);
    assert!(
        xr_problems.is_empty(),
        "OpenXR core validation: {xr_problems:#?}"
    );
    assert!(!run.stderr.contains("panicked"), "{run}");
}
