//! Helpers shared by the integration tests (each test crate includes this module and uses what
//! it needs).
#![allow(dead_code)]

pub mod fault_layer;
pub mod gpu;
pub mod lod;
pub mod monado;
pub mod physics;

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// A global allocator that counts allocations while counting is on. A test crate installs it
/// with `#[global_allocator] static GLOBAL: common::Counting = common::Counting;`.
pub struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as ours.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Runs `f` with counting on (on every thread) and returns its result and the number of heap
/// allocations made meanwhile. Callers in one crate must not overlap (serialize them).
pub fn count_allocations<R>(f: impl FnOnce() -> R) -> (R, usize) {
    ALLOCATIONS.store(0, Ordering::SeqCst);
    COUNTING.store(true, Ordering::SeqCst);
    let r = f();
    COUNTING.store(false, Ordering::SeqCst);
    (r, ALLOCATIONS.load(Ordering::SeqCst))
}

/// Turns counting on (from zero) or off, for spans that a closure cannot wrap (frame hooks).
pub fn set_counting(on: bool) {
    if on {
        ALLOCATIONS.store(0, Ordering::SeqCst);
    }
    COUNTING.store(on, Ordering::SeqCst);
}

/// Allocations counted since counting was last turned on.
pub fn allocations() -> usize {
    ALLOCATIONS.load(Ordering::SeqCst)
}

/// Runs the `vr-ocean` binary with `args`.
pub fn vr_ocean(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vr-ocean"))
        .args(args)
        // Kept settings in a scratch directory, never the user's.
        .env("XDG_CONFIG_HOME", scratch_path("config"))
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

/// A per-process path under the temp dir (not created).
pub fn scratch_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("vr-ocean-test-{}-{name}", std::process::id()))
}

/// Asserts that `vr-ocean args` fails cleanly (non-zero, no panic) with an error mentioning
/// every string in `names`.
pub fn assert_rejected(args: &[&str], names: &[&str]) {
    let out = vr_ocean(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} must fail");
    assert_ne!(out.status.code(), Some(101), "{args:?} panicked: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    for n in names {
        assert!(
            err.contains(n),
            "{args:?}: error should mention {n:?}: {err}"
        );
    }
}

/// What the sound's report line of a run says (`audio (SINK): S s of sound, B buffers of F
/// frames, U under-runs (W late wakes), ..., SCHED scheduling`).
#[allow(dead_code)]
pub struct SoundLine {
    /// Seconds of sound.
    pub seconds: f64,
    /// Buffers finished late.
    pub underruns: u64,
    /// Of those, the ones whose rendering fitted: the thread woke too late.
    pub late_wakes: u64,
    /// Whether the audio thread ran real-time (SCHED_FIFO).
    pub real_time: bool,
    /// The line itself.
    pub line: String,
}

#[allow(dead_code)]
impl SoundLine {
    /// Whether every late buffer was a real-time thread woken late: the app cannot hold a
    /// SCHED_FIFO thread off its core (it has no real-time thread of its own) and the
    /// rendering fitted, so only the host (a vCPU the hypervisor held) made them late.
    pub fn late_only_by_the_host(&self) -> bool {
        self.underruns > 0 && self.underruns == self.late_wakes && self.real_time
    }
}

/// The sound's report line of a run.
#[allow(dead_code)]
pub fn sound_report(stdout: &str) -> SoundLine {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("audio ("))
        .unwrap_or_else(|| panic!("no audio report line:\n{stdout}"));
    let number_before = |tail: &str| -> f64 {
        let head = line
            .split(tail)
            .next()
            .unwrap_or_else(|| panic!("no {tail:?} in {line:?}"));
        head.rsplit([' ', ',', ':', '('])
            .find(|w| !w.is_empty())
            .and_then(|w| w.parse().ok())
            .unwrap_or_else(|| panic!("no number before {tail:?} in {line:?}"))
    };
    SoundLine {
        seconds: number_before(" s of sound"),
        underruns: number_before(" under-runs") as u64,
        late_wakes: number_before(" late wakes") as u64,
        real_time: line.contains("real-time scheduling"),
        line: line.to_string(),
    }
}

/// Whether `xvfb-run` is installed, for a window test about to use it. Missing under CI
/// (`CI` set, as `cargo xtask test` and `.ci/run` run) it fails the test, naming what to
/// install: a green run must have run the window. Elsewhere the test is skipped, loudly.
#[allow(dead_code)]
pub fn need_xvfb_run(test: &str) -> bool {
    let found = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        assert!(
            std::env::var_os("CI").is_none(),
            "{test}: xvfb-run is missing under CI (apt install xvfb; `cargo xtask test` \
             installs it)"
        );
        eprintln!(
            "SKIPPED {test}: xvfb-run is not installed (apt install xvfb; `cargo xtask test` \
             does); under CI=true this fails"
        );
    }
    found
}

/// `vr-ocean window` on a virtual screen: a small, cheap ocean (320x160, 64² grid, low
/// preset, one simulation thread) plus `args`, keeping its settings under `config` (never the
/// user's).
#[allow(dead_code)]
pub fn xvfb_window(config: &Path, args: &[&str]) -> std::process::Output {
    xvfb_window_sized(config, "320x160", args)
}

/// [`xvfb_window`] with a window of `size` (WIDTHxHEIGHT, at most 1024x768).
#[allow(dead_code)]
pub fn xvfb_window_sized(config: &Path, size: &str, args: &[&str]) -> std::process::Output {
    Command::new("xvfb-run")
        .env("XDG_CONFIG_HOME", config)
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_vr-ocean"))
        .args(["window", "--size", size, "--grid", "64", "--preset", "low"])
        .args(["--threads", "1"])
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("xvfb-run runs")
}
