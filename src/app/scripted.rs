//! A scripted user for long runs (`vr-ocean xr --soak-minutes`, issue 44's soak): wraps a
//! frame loop and, on a 30-second cycle of the session's unpaused display time, does what a
//! person at play does: raises and lowers the sea state, throws crates, launches a boat, opens
//! the panel and presses its Beaufort, spawn and reset buttons and drags its wind slider,
//! cycles the preset, moves the sun, turns the wind, then puts the preset back. Every second
//! cycle ends where the first began (the sea state, wind, sun and preset back, the bodies
//! reset), so a soak compares memory at like states. Only while the app is not paused (input
//! is ignored then anyway; the script's clock waits). Once a minute of wall time it samples
//! the process's resident memory and open file descriptors ([`ResourceSample`]), so a soak
//! can show they stay flat.
//!
//! Everything else is the wrapped backend's: every [`FrameLoop`] call is forwarded.

use std::time::{Duration, Instant};

use crate::lod::QualityPreset;
use crate::render::{GpuContext, TargetImages};
use crate::ui::panel::{Comfort, Panel, PointerEvent, Widgets};
use crate::xr::gpu_governor::{GovernorCaps, GovernorState};
use crate::xr::{Acquired, FrameLoop, FrameState, Tweak, XrError};

/// Seconds of one cycle of the script (of its own clock).
pub const CYCLE_S: i64 = 30;

/// How often the process's resources are sampled (wall time).
pub const SAMPLE_EVERY: Duration = Duration::from_secs(60);

/// The process's resources at one moment (Linux and Android: from `/proc/self`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResourceSample {
    /// Seconds since the scripted user started.
    pub at_s: f64,
    /// Resident memory (KiB).
    pub rss_kib: u64,
    /// Open file descriptors.
    pub fds: u64,
}

impl ResourceSample {
    /// This process now, `at_s` seconds into the run; `None` where `/proc` has no answer.
    pub fn now(at_s: f64) -> Option<Self> {
        Self::of(None, at_s)
    }

    /// Process `pid` (`None`: this one) now, `at_s` seconds into the run, from
    /// `/proc/<pid>/status` and `/proc/<pid>/fd`; `None` where they cannot be read.
    pub fn of(pid: Option<u32>, at_s: f64) -> Option<Self> {
        let dir = pid.map_or_else(|| "/proc/self".to_string(), |p| format!("/proc/{p}"));
        let status = std::fs::read_to_string(format!("{dir}/status")).ok()?;
        let rss_kib = status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))?
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .ok()?;
        let fds = std::fs::read_dir(format!("{dir}/fd")).ok()?.count() as u64;
        Some(Self { at_s, rss_kib, fds })
    }
}

impl std::fmt::Display for ResourceSample {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "soak: t={:.0} s rss={} KiB fds={}",
            self.at_s, self.rss_kib, self.fds
        )
    }
}

/// One step of the script.
#[derive(Clone, Copy, Debug)]
enum Act {
    Tweak(Tweak),
    Pointer(PointerEvent),
    /// Aim at a fraction across and down a widget of the panel.
    Aim(fn(&Widgets, u32) -> [f32; 4], f32, f32),
    /// Back to the run's preset.
    HomePreset,
}

/// What happens at each second of the cycle (`cycle` counts cycles: alternating directions).
fn acts_at(second: i64, cycle: u32) -> [Option<Act>; 2] {
    let sign = if cycle.is_multiple_of(2) { 1.0 } else { -1.0 };
    let beaufort =
        |w: &Widgets, cycle: u32| w.beaufort[if cycle.is_multiple_of(2) { 6 } else { 3 }];
    let wind = |w: &Widgets, _| w.wind;
    let spawn = |w: &Widgets, _| w.spawn;
    let reset = |w: &Widgets, _| w.reset;
    let one = |a| [Some(a), None];
    match second {
        0 => one(Act::Tweak(Tweak::SeaState(if cycle.is_multiple_of(2) {
            2
        } else {
            -2
        }))),
        2 => one(Act::Tweak(Tweak::Throw)),
        4 => one(Act::Tweak(Tweak::LaunchBoat(3.0))),
        6 => one(Act::Pointer(PointerEvent::Menu)),
        7 => [
            Some(Act::Aim(beaufort, 0.5, 0.5)),
            Some(Act::Pointer(PointerEvent::Trigger(true))),
        ],
        8 => one(Act::Pointer(PointerEvent::Trigger(false))),
        9 => [
            Some(Act::Aim(spawn, 0.5, 0.5)),
            Some(Act::Pointer(PointerEvent::Trigger(true))),
        ],
        10 => one(Act::Pointer(PointerEvent::Trigger(false))),
        11 => [
            Some(Act::Aim(wind, 0.3, 0.5)),
            Some(Act::Pointer(PointerEvent::Trigger(true))),
        ],
        12 => one(Act::Aim(wind, 0.6, 0.5)),
        13 => one(Act::Pointer(PointerEvent::Trigger(false))),
        14 => [
            Some(Act::Aim(reset, 0.5, 0.5)),
            Some(Act::Pointer(PointerEvent::Trigger(true))),
        ],
        15 => one(Act::Pointer(PointerEvent::Trigger(false))),
        16 => [
            Some(Act::Pointer(PointerEvent::Aim(None))),
            Some(Act::Pointer(PointerEvent::Menu)),
        ],
        18 => one(Act::Tweak(Tweak::NextPreset)),
        21 => one(Act::Tweak(Tweak::Sun {
            elevation: 4.0 * sign,
            azimuth: 10.0,
        })),
        24 => one(Act::Tweak(Tweak::WindDirection(25.0 * sign))),
        27 => one(Act::HomePreset),
        _ => [None, None],
    }
}

/// A frame loop whose frames carry a scripted user's input; see the module's docs.
pub struct ScriptedUser<'a> {
    inner: &'a mut dyn FrameLoop,
    /// The run's preset, chosen again at the end of each cycle.
    home: QualityPreset,
    /// The script's own clock (s): the display periods of the frames not paused, so a pause
    /// delays the script instead of skipping its acts (every session goes through the same
    /// states).
    script_s: f64,
    /// The last whole second of the script's clock whose acts were played.
    played: Option<i64>,
    /// The panel's widgets as last shown (the app shows the panel every frame).
    widgets: Option<Widgets>,
    started: Instant,
    /// When to ask the backend to end the session; asked once.
    deadline: Option<Instant>,
    quit_asked: bool,
    last_sample: Instant,
    /// Resources sampled so far (capacity reserved for `deadline`'s length: no allocation
    /// per frame).
    samples: Vec<ResourceSample>,
    /// Acts played.
    acts: u64,
    /// Times the app paused (the focus lost), and whether the last frame was paused.
    pauses: u32,
    was_paused: bool,
}

impl<'a> ScriptedUser<'a> {
    /// Plays the script over `inner`'s frames, going back to preset `home` each cycle; after
    /// `run_for` (when given) the session is asked to end (the backend's
    /// [`FrameLoop::request_quit`]).
    pub fn new(
        inner: &'a mut dyn FrameLoop,
        home: QualityPreset,
        run_for: Option<Duration>,
    ) -> Self {
        let now = Instant::now();
        let minutes = run_for.map_or(60, |d| d.as_secs() / 60 + 2) as usize;
        Self {
            inner,
            home,
            script_s: 0.0,
            played: None,
            widgets: None,
            started: now,
            deadline: run_for.map(|d| now + d),
            quit_asked: false,
            last_sample: now,
            samples: Vec::with_capacity(minutes + 2),
            acts: 0,
            pauses: 0,
            // A session's frames before it is first FOCUSED are paused too: not a loss.
            was_paused: true,
        }
    }

    /// The resources sampled (one at the first frame, then one a minute).
    pub fn samples(&self) -> &[ResourceSample] {
        &self.samples
    }

    /// Acts played so far.
    pub fn acts(&self) -> u64 {
        self.acts
    }

    /// Seconds since the scripted user started (its samples' clock).
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Times the app paused (lost the focus) so far.
    pub fn pauses(&self) -> u32 {
        self.pauses
    }

    fn sample(&mut self) {
        if let Some(s) = ResourceSample::now(self.started.elapsed().as_secs_f64()) {
            println!("{s}");
            if self.samples.len() < self.samples.capacity() {
                self.samples.push(s);
            }
        }
        self.last_sample = Instant::now();
    }

    /// Puts the acts of the seconds since the last frame into `frame`.
    fn play(&mut self, frame: &mut FrameState) {
        self.pauses += u32::from(frame.paused && !self.was_paused);
        self.was_paused = frame.paused;
        if frame.paused {
            return;
        }
        let now = self.script_s.floor() as i64;
        self.script_s += frame.period.clamp(0.0, 1.0);
        let from = self.played.map_or(now, |p| p + 1);
        self.played = Some(now);
        // At most a few seconds are caught up (after a long wait, only the latest).
        for second in from.max(now - 2)..=now {
            let cycle = (second.div_euclid(CYCLE_S)) as u32;
            for act in acts_at(second.rem_euclid(CYCLE_S), cycle)
                .into_iter()
                .flatten()
            {
                let done = match act {
                    Act::Tweak(t) => put(&mut frame.tweaks, t),
                    Act::HomePreset => put(&mut frame.tweaks, Tweak::Preset(self.home)),
                    Act::Pointer(p) => put(&mut frame.pointer, p),
                    Act::Aim(widget, fx, fy) => match self.widgets.as_ref() {
                        Some(w) => {
                            let r = widget(w, cycle);
                            let at = [r[0] + fx * (r[2] - r[0]), r[1] + fy * (r[3] - r[1])];
                            put(&mut frame.pointer, PointerEvent::Aim(Some(at)))
                        }
                        None => false,
                    },
                };
                self.acts += u64::from(done);
            }
        }
    }
}

/// Puts `item` in the first empty slot; false when all are taken.
fn put<T>(slots: &mut [Option<T>], item: T) -> bool {
    match slots.iter_mut().find(|s| s.is_none()) {
        Some(s) => {
            *s = Some(item);
            true
        }
        None => false,
    }
}

impl FrameLoop for ScriptedUser<'_> {
    fn gpu(&self) -> &GpuContext {
        self.inner.gpu()
    }
    fn targets(&self) -> TargetImages<'_> {
        self.inner.targets()
    }
    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        if self.samples.is_empty() {
            self.sample();
        }
        if !self.quit_asked && self.deadline.is_some_and(|d| Instant::now() >= d) {
            self.quit_asked = true;
            if !self.inner.request_quit() {
                return Ok(None);
            }
        }
        let mut state = self.inner.begin_frame()?;
        if let Some(s) = state.as_mut() {
            self.play(s);
        }
        Ok(state)
    }
    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        self.inner.acquire_image()
    }
    fn release_image(&mut self) -> Result<(), XrError> {
        self.inner.release_image()
    }
    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError> {
        let r = self.inner.end_frame(frame);
        if self.last_sample.elapsed() >= SAMPLE_EVERY {
            self.sample();
        }
        r
    }
    fn show_stats(&mut self, text: &str) {
        self.inner.show_stats(text);
    }
    fn report_gpu_time(&mut self, gpu: Duration) {
        self.inner.report_gpu_time(gpu);
    }
    fn report_cpu_wait(&mut self, waited: Duration) {
        self.inner.report_cpu_wait(waited);
    }
    fn hand_workers(&mut self, workers: &crate::sim::workers::WorkerThreads) {
        self.inner.hand_workers(workers);
    }
    fn governor_caps(&self) -> GovernorCaps {
        self.inner.governor_caps()
    }
    fn set_foveation_boost(&mut self, boost: bool) -> bool {
        self.inner.set_foveation_boost(boost)
    }
    fn set_render_rect(&mut self, rect: ash::vk::Rect2D) -> bool {
        self.inner.set_render_rect(rect)
    }
    fn render_rect(&self) -> ash::vk::Rect2D {
        self.inner.render_rect()
    }
    fn report_governor(&mut self, state: GovernorState) {
        self.inner.report_governor(state);
    }
    fn haptic_tick(&mut self, hand: usize) {
        self.inner.haptic_tick(hand);
    }
    fn panel_pixels_per_point(&self) -> Option<f32> {
        self.inner.panel_pixels_per_point()
    }
    fn panel_draws_cursor(&self) -> bool {
        self.inner.panel_draws_cursor()
    }
    fn show_panel(&mut self, panel: &mut Panel) -> Result<(), XrError> {
        self.widgets = Some(*panel.widgets());
        self.inner.show_panel(panel)
    }
    fn panel_haptic(&mut self) {
        self.inner.panel_haptic();
    }
    fn request_quit(&mut self) -> bool {
        self.inner.request_quit()
    }
    fn set_comfort(&mut self, comfort: Comfort) {
        self.inner.set_comfort(comfort);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_process_is_sampled_by_id_as_by_self() {
        if cfg!(any(target_os = "linux", target_os = "android")) {
            let own = ResourceSample::now(0.0).expect("/proc/self");
            let by_id = ResourceSample::of(Some(std::process::id()), 0.0).expect("/proc/<pid>");
            assert!(own.rss_kib > 0 && by_id.rss_kib > 0);
            assert!(
                by_id.rss_kib.abs_diff(own.rss_kib) < own.rss_kib / 2,
                "{own:?} {by_id:?}"
            );
            assert!(own.fds >= 3 && by_id.fds >= 3);
        }
    }

    #[test]
    fn a_cycle_plays_every_kind_of_act_and_never_aims_at_quit() {
        let mut tweaks = 0;
        let mut menus = 0;
        let mut presses = 0;
        let mut releases = 0;
        for s in 0..CYCLE_S {
            for a in acts_at(s, 0).into_iter().flatten() {
                match a {
                    Act::Tweak(_) | Act::HomePreset => tweaks += 1,
                    Act::Pointer(PointerEvent::Menu) => menus += 1,
                    Act::Pointer(PointerEvent::Trigger(true)) => presses += 1,
                    Act::Pointer(PointerEvent::Trigger(false)) => releases += 1,
                    _ => {}
                }
            }
        }
        assert_eq!(tweaks, 7);
        // Opened and closed; every press released.
        assert_eq!(menus, 2);
        assert_eq!((presses, releases), (4, 4));
        // The Beaufort buttons pressed stay inside the eleven.
        let w = Widgets {
            beaufort: [[0.0; 4]; 11],
            wind: [0.0; 4],
            sun: [0.0; 4],
            spawn: [0.0; 4],
            reset: [0.0; 4],
            quit: [9.0; 4],
            water: [0.0; 4],
            perf: [0.0; 4],
        };
        for cycle in 0..20 {
            for s in 0..CYCLE_S {
                for a in acts_at(s, cycle).into_iter().flatten() {
                    if let Act::Aim(f, _, _) = a {
                        assert_ne!(f(&w, cycle), w.quit);
                    }
                }
            }
        }
    }
}
