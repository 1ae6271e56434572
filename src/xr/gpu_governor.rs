//! The GPU-time governor: steps rendering quality down when the GPU pass does not fit its
//! share of the frame budget, and back up when there is headroom for a while.
//!
//! Why: the refresh governor (`openxr::refresh::RefreshGovernor`) acts on GPU time only once
//! this one has no cheaper level left, and stops at 72 Hz, where a Quest 2 already starts; estimates of this scene's GPU cost on
//! the XR2 are good to about ±50 %, so the app has to adapt at run time where they are wrong
//! (issue 28). Meta recommends dynamic resolution for the same reason.
//!
//! A pure, allocation-free state machine: per rendered frame it takes the GPU pass time
//! (from timestamps; `None` when there was none), the frame period and a monotonic time in
//! seconds (passed in, so tests script time). The levels ([`QualityStep`]) are stepped one at
//! a time, cheapest loss first, from [`QualityStep::Full`], the settings as configured:
//!
//! 0. [`QualityStep::FullSize`], *above* the start: the eye images at the runtime's
//!    recommended size where the headset's default scale is under it (a Quest 2 starts at
//!    0.89 of it, by a GPU model no headset has confirmed: where the GPU has room, the image
//!    takes it back);
//! 1. [`QualityStep::NoSupersampling`]: the specular AA's supersampling off where it is on
//!    (the desktop; about a third of the pass) and the normal maps' anisotropic filtering (the
//!    filtered lobe stays);
//! 2. [`QualityStep::FoveationUp`]: one fixed-foveation level higher;
//! 3. [`QualityStep::Scale85`] and [`QualityStep::Scale70`]: the eye images rendered into a
//!    centred sub-rectangle, 0.85 and 0.7 of the runtime's recommended size (Meta's render
//!    scale; the compositor scales it back), each only where the images are larger;
//! 4. [`QualityStep::LodDown`]: the LOD quality preset one lower (a rebuild: rare).
//!
//! Levels that cannot be applied (supersampling already off, no foveation to raise, no
//! sub-rectangle on a window, a scale the images start at or under) are left out when the governor is made ([`GpuGovernor::new`]), so a step is never wasted.
//!
//! Rules (constants on [`GpuGovernor`]): the statistic is the median of the GPU time as a
//! share of the period over the last [`GpuGovernor::WINDOW_S`] (robust to single spikes); it
//! steps down when that median exceeds [`GpuGovernor::DOWN_SHARE`], and up when it stayed
//! under [`GpuGovernor::UP_SHARE`] for [`GpuGovernor::UP_HOLD_S`] (after a step up,
//! [`GpuGovernor::MIN_INTERVAL_S`] more of headroom at the new level suffice for the next).
//! Between the two shares nothing changes (hysteresis). Never two changes within
//! [`GpuGovernor::MIN_INTERVAL_S`]. A step up that had to be taken back within
//! [`GpuGovernor::REVERSAL_S`] blocks stepping up to that level for a back-off that doubles
//! each time (from [`GpuGovernor::BACKOFF_S`] up to [`GpuGovernor::MAX_BACKOFF_S`]), so a
//! load that fits one level but not the next settles instead of oscillating.

use std::time::Duration;

use super::render_scale::RenderScales;

/// A quality level, from the best ([`QualityStep::FullSize`]) to the cheapest; the governor
/// starts at [`QualityStep::Full`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum QualityStep {
    /// Everything as configured, the eye images at the runtime's recommended size (where the
    /// configured scale is smaller and the images leave room: [`RenderScales`]).
    FullSize,
    /// Everything as configured.
    Full,
    /// The specular AA's supersampling and the normal maps' anisotropic filtering off.
    NoSupersampling,
    /// One fixed-foveation level higher.
    FoveationUp,
    /// Rendered at 0.85 of the eye size.
    Scale85,
    /// Rendered at 0.7 of the eye size.
    Scale70,
    /// The LOD quality preset one lower.
    LodDown,
}

impl QualityStep {
    /// Every level, best first.
    pub const ALL: [QualityStep; LEVELS] = [
        QualityStep::FullSize,
        QualityStep::Full,
        QualityStep::NoSupersampling,
        QualityStep::FoveationUp,
        QualityStep::Scale85,
        QualityStep::Scale70,
        QualityStep::LodDown,
    ];

    /// A short name for logs, the title bar and the session summary.
    pub fn name(self) -> &'static str {
        match self {
            QualityStep::FullSize => "full-size",
            QualityStep::Full => "full",
            QualityStep::NoSupersampling => "no-ssaa",
            QualityStep::FoveationUp => "foveation+1",
            QualityStep::Scale85 => "scale-0.85",
            QualityStep::Scale70 => "scale-0.7",
            QualityStep::LodDown => "lod-1",
        }
    }

    /// The render scale at this level: the eye images' drawn share of the runtime's
    /// recommended size on both sides, for images of `scales`.
    pub fn render_scale(self, scales: RenderScales) -> f32 {
        match self {
            QualityStep::FullSize => scales.images.min(1.0).max(scales.start),
            QualityStep::Full | QualityStep::NoSupersampling | QualityStep::FoveationUp => {
                scales.start
            }
            QualityStep::Scale85 => scales.start.min(0.85),
            QualityStep::Scale70 | QualityStep::LodDown => scales.start.min(0.7),
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// How many quality levels there are.
const LEVELS: usize = 7;

/// What the backend lets the governor change besides the renderer's own settings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GovernorCaps {
    /// The specular AA supersamples or the normal maps are filtered anisotropically now, so
    /// turning both off saves something ([`QualityStep::NoSupersampling`]; the app's to say).
    pub supersampling: bool,
    /// Fixed foveation can be raised one level ([`QualityStep::FoveationUp`]).
    pub foveation: bool,
    /// `Some(scales)`: the eye images can be shown from a sub-rectangle
    /// ([`QualityStep::FullSize`], [`QualityStep::Scale85`], [`QualityStep::Scale70`]) of
    /// images `scales.images` of the runtime's recommended size, `scales.start` of it drawn as
    /// configured. The steps' scales are shares of the recommended size, as Meta's render
    /// scale is (VRC.Quest.Performance.4 recommends at least 0.85), so a step that would not
    /// change the drawn size is left out ([`render_rect_share`]).
    pub render_rect: Option<RenderScales>,
    /// A lower LOD preset exists ([`QualityStep::LodDown`]; the app's to say).
    pub lod: bool,
}

/// The governor's state for logs and summaries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GovernorState {
    /// The level now.
    pub level: QualityStep,
    /// Level changes so far.
    pub changes: u32,
    /// True when no cheaper level is left: the refresh governor may act on GPU time.
    pub exhausted: bool,
}

/// Samples kept (more than a window holds at 120 Hz).
const RING: usize = 64;

/// Fewest samples in the window for a decision.
const MIN_SAMPLES: usize = 8;

/// The GPU-time governor (see the module documentation).
#[derive(Clone, Debug)]
pub struct GpuGovernor {
    available: [bool; LEVELS],
    level: QualityStep,
    /// (time s, GPU time / period) of recent frames; `len` valid, `head` the next write.
    samples: [(f64, f32); RING],
    len: usize,
    head: usize,
    last_change: f64,
    /// Whether the last change was a step up.
    last_up: bool,
    /// Since when the median has been under [`Self::UP_SHARE`].
    headroom_since: Option<f64>,
    /// Per level: stepping up to it is blocked until this time.
    blocked_until: [f64; LEVELS],
    /// Per level: the current back-off after a reversed step up to it (s).
    backoff: [f64; LEVELS],
    changes: u32,
}

impl GpuGovernor {
    /// Share of the frame period above which the GPU pass is over budget.
    pub const DOWN_SHARE: f64 = 0.8;
    /// Share of the frame period under which there is headroom.
    pub const UP_SHARE: f64 = 0.6;
    /// Length of the window whose median is compared (s).
    pub const WINDOW_S: f64 = 0.33;
    /// Headroom held this long before the first step up (s).
    pub const UP_HOLD_S: f64 = 2.0;
    /// Never two changes closer than this (s).
    pub const MIN_INTERVAL_S: f64 = 1.0;
    /// A step down this soon after a step up takes it back (s).
    pub const REVERSAL_S: f64 = 3.0;
    /// The first back-off after a reversed step up (s).
    pub const BACKOFF_S: f64 = 8.0;
    /// The longest back-off (s).
    pub const MAX_BACKOFF_S: f64 = 64.0;

    /// A governor at [`QualityStep::Full`] (the configured settings) that uses only the
    /// levels `caps` allow.
    pub fn new(caps: GovernorCaps) -> Self {
        let mut available = [true; LEVELS];
        available[QualityStep::NoSupersampling.index()] = caps.supersampling;
        available[QualityStep::FoveationUp.index()] = caps.foveation;
        // A render-scale step is one where the drawn size differs from the start's (the full
        // size is never under it, the others never over it).
        for step in [
            QualityStep::FullSize,
            QualityStep::Scale85,
            QualityStep::Scale70,
        ] {
            available[step.index()] = caps
                .render_rect
                .is_some_and(|s| step.render_scale(s) != s.start);
        }
        available[QualityStep::LodDown.index()] = caps.lod;
        Self {
            available,
            level: QualityStep::Full,
            samples: [(0.0, 0.0); RING],
            len: 0,
            head: 0,
            last_change: f64::NEG_INFINITY,
            last_up: false,
            headroom_since: None,
            blocked_until: [f64::NEG_INFINITY; LEVELS],
            backoff: [Self::BACKOFF_S; LEVELS],
            changes: 0,
        }
    }

    /// The level now.
    pub fn level(&self) -> QualityStep {
        self.level
    }

    /// The state for logs and summaries.
    pub fn state(&self) -> GovernorState {
        GovernorState {
            level: self.level,
            changes: self.changes,
            exhausted: self.lower(self.level).is_none(),
        }
    }

    /// One rendered frame at time `now` (s, monotonic) with frame period `period` (s) and the
    /// GPU pass time `gpu` (`None`: not measured; such frames are not evidence either way).
    /// Returns the new level when it changes.
    pub fn observe(&mut self, gpu: Option<Duration>, period: f64, now: f64) -> Option<QualityStep> {
        if let Some(g) = gpu {
            if period > 0.0 && period.is_finite() {
                self.samples[self.head] = (now, (g.as_secs_f64() / period) as f32);
                self.head = (self.head + 1) % RING;
                self.len = (self.len + 1).min(RING);
            }
        }
        let Some(median) = self.median(now) else {
            self.headroom_since = None;
            return None;
        };
        if median < Self::UP_SHARE {
            self.headroom_since.get_or_insert(now);
        } else {
            self.headroom_since = None;
        }
        if now - self.last_change < Self::MIN_INTERVAL_S {
            return None;
        }
        if median > Self::DOWN_SHARE {
            let next = self.lower(self.level)?;
            if self.last_up && now - self.last_change < Self::REVERSAL_S {
                // The step up to this level did not hold: wait longer before trying again.
                let i = self.level.index();
                self.blocked_until[i] = now + self.backoff[i];
                self.backoff[i] = (self.backoff[i] * 2.0).min(Self::MAX_BACKOFF_S);
            }
            return Some(self.change(next, false, now));
        }
        let since = self.headroom_since?;
        let hold = if self.last_up {
            Self::MIN_INTERVAL_S
        } else {
            Self::UP_HOLD_S
        };
        let next = self.higher(self.level)?;
        if now - since >= hold && now >= self.blocked_until[next.index()] {
            return Some(self.change(next, true, now));
        }
        None
    }

    fn change(&mut self, to: QualityStep, up: bool, now: f64) -> QualityStep {
        self.level = to;
        self.last_change = now;
        self.last_up = up;
        self.changes += 1;
        // The window restarts: samples of the old level say nothing about the new one.
        self.len = 0;
        self.head = 0;
        self.headroom_since = None;
        to
    }

    /// The next cheaper available level.
    fn lower(&self, from: QualityStep) -> Option<QualityStep> {
        QualityStep::ALL[from.index() + 1..]
            .iter()
            .copied()
            .find(|l| self.available[l.index()])
    }

    /// The next better available level.
    fn higher(&self, from: QualityStep) -> Option<QualityStep> {
        QualityStep::ALL[..from.index()]
            .iter()
            .rev()
            .copied()
            .find(|l| self.available[l.index()])
    }

    /// The median share over the window ending at `now`; `None` with too few samples.
    fn median(&self, now: f64) -> Option<f64> {
        let mut window = [0.0f32; RING];
        let mut n = 0;
        for &(t, share) in &self.samples[..self.len] {
            if now - t < Self::WINDOW_S {
                window[n] = share;
                n += 1;
            }
        }
        if n < MIN_SAMPLES {
            return None;
        }
        let w = &mut window[..n];
        w.sort_unstable_by(f32::total_cmp);
        // The lower median: half the window over budget is not yet over budget.
        Some(f64::from(w[(n - 1) / 2]))
    }
}

/// The share of the swapchain's images (each side) that `step` draws, for images of
/// `scales`: the step's render scale over the images', at most 1.
pub fn render_rect_share(step: QualityStep, scales: RenderScales) -> f32 {
    if scales.images > 0.0 {
        (step.render_scale(scales) / scales.images).min(1.0)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PERIOD: f64 = 1.0 / 72.0;

    fn all() -> GovernorCaps {
        GovernorCaps {
            supersampling: true,
            foveation: true,
            render_rect: Some(RenderScales::whole(1.0)),
            lod: true,
        }
    }

    /// Runs `g` from frame `from` to `to` (at 72 Hz) with the GPU time `load(t)` as a share
    /// of the period; returns the changes as (time, level).
    fn run(
        g: &mut GpuGovernor,
        frames: std::ops::Range<u32>,
        load: impl Fn(f64) -> Option<f64>,
    ) -> Vec<(f64, QualityStep)> {
        let mut out = Vec::new();
        for i in frames {
            let t = f64::from(i) * PERIOD;
            let gpu = load(t).map(|s| Duration::from_secs_f64(s * PERIOD));
            if let Some(l) = g.observe(gpu, PERIOD, t) {
                out.push((t, l));
            }
        }
        out
    }

    fn min_gap(changes: &[(f64, QualityStep)]) -> f64 {
        changes
            .windows(2)
            .map(|w| w[1].0 - w[0].0)
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn steps_down_within_a_second_and_recovers_within_a_few() {
        let mut g = GpuGovernor::new(all());
        // Fits (0.4) until 2 s, then 1.2 of the budget until 5 s, then fits again.
        let load = |t: f64| Some(if (2.0..5.0).contains(&t) { 1.2 } else { 0.4 });
        let changes = run(&mut g, 0..72 * 14, load);
        let (first_t, first) = changes[0];
        assert!((2.0..3.0).contains(&first_t), "{changes:?}");
        assert_eq!(first, QualityStep::NoSupersampling);
        // Down one level at a time while the load lasts: three steps in 3 s.
        let downs: Vec<_> = changes.iter().filter(|c| c.0 < 5.0).map(|c| c.1).collect();
        assert_eq!(
            downs,
            [
                QualityStep::NoSupersampling,
                QualityStep::FoveationUp,
                QualityStep::Scale85
            ]
        );
        let (last_t, last) = *changes.last().unwrap();
        assert_eq!(last, QualityStep::Full, "{changes:?}");
        assert!(
            last_t < 5.0 + 4.5,
            "back to full {} s after the load",
            last_t - 5.0
        );
        assert!(
            min_gap(&changes) >= GpuGovernor::MIN_INTERVAL_S,
            "{changes:?}"
        );
        assert_eq!(g.state().changes as usize, changes.len());
    }

    #[test]
    fn a_lasting_load_walks_every_level_once_a_second_at_most_and_stops() {
        let mut g = GpuGovernor::new(all());
        let changes = run(&mut g, 0..72 * 20, |_| Some(3.0));
        let levels: Vec<_> = changes.iter().map(|c| c.1).collect();
        // Every level below the start (the full size is above it, and these images are
        // drawn whole).
        assert_eq!(levels, QualityStep::ALL[2..]);
        assert!(min_gap(&changes) >= 1.0);
        assert!(g.state().exhausted);
    }

    #[test]
    fn levels_the_backend_cannot_apply_are_skipped() {
        let mut g = GpuGovernor::new(GovernorCaps {
            supersampling: true,
            ..GovernorCaps::default()
        });
        let changes = run(&mut g, 0..72 * 10, |_| Some(2.0));
        let levels: Vec<_> = changes.iter().map(|c| c.1).collect();
        assert_eq!(levels, [QualityStep::NoSupersampling]);
        assert!(g.state().exhausted);
        // Supersampling already off and a window: nothing to step, ever.
        let mut g = GpuGovernor::new(GovernorCaps::default());
        assert!(run(&mut g, 0..72 * 10, |_| Some(2.0)).is_empty());
        assert!(g.state().exhausted);
    }

    #[test]
    fn a_load_between_the_thresholds_changes_nothing() {
        for share in [0.61, 0.7, 0.79] {
            let mut g = GpuGovernor::new(all());
            assert!(run(&mut g, 0..72 * 60, |_| Some(share)).is_empty());
        }
        // Nor does it climb back from a lower level while between them.
        let mut g = GpuGovernor::new(all());
        let changes = run(&mut g, 0..30, |_| Some(1.0));
        assert_eq!(changes.len(), 1);
        assert!(run(&mut g, 30..72 * 60, |_| Some(0.7)).is_empty());
    }

    #[test]
    fn a_level_that_fits_next_to_one_that_does_not_settles() {
        // Full costs 0.9 of the budget, anything cheaper 0.5: the worst case for oscillation.
        let mut g = GpuGovernor::new(all());
        let mut changes = Vec::new();
        for i in 0..72 * 120 {
            let t = f64::from(i) * PERIOD;
            let share = if g.level() == QualityStep::Full {
                0.9
            } else {
                0.5
            };
            let gpu = Duration::from_secs_f64(share * PERIOD);
            if let Some(l) = g.observe(Some(gpu), PERIOD, t) {
                changes.push((t, l));
            }
        }
        // Each retry of full waits twice as long as the last (up to a minute): a handful of
        // changes in two minutes, not one every second or two.
        assert!(changes.len() <= 10, "{changes:?}");
        let ups: Vec<f64> = changes
            .iter()
            .filter(|c| c.1 == QualityStep::Full)
            .map(|c| c.0)
            .collect();
        for w in ups.windows(3) {
            assert!(w[2] - w[1] > w[1] - w[0], "retries back off: {ups:?}");
        }
        assert!(min_gap(&changes) >= 1.0);
    }

    #[test]
    fn occasional_spikes_are_tolerated() {
        let mut g = GpuGovernor::new(all());
        // One frame in five at three times the budget.
        let changes = run(&mut g, 0..72 * 30, |t| {
            Some(if ((t / PERIOD).round() as u32).is_multiple_of(5) {
                3.0
            } else {
                0.5
            })
        });
        assert!(changes.is_empty(), "{changes:?}");
    }

    #[test]
    fn missing_gpu_times_are_no_evidence() {
        // Never measured: never changes.
        let mut g = GpuGovernor::new(all());
        assert!(run(&mut g, 0..72 * 30, |_| None).is_empty());
        // Measured every third frame: the window still fills and the load is seen.
        let mut g = GpuGovernor::new(all());
        let changes = run(&mut g, 0..72 * 3, |t| {
            ((t / PERIOD).round() as u32)
                .is_multiple_of(3)
                .then_some(1.5)
        });
        assert_eq!(
            changes.first().map(|c| c.1),
            Some(QualityStep::NoSupersampling)
        );
        assert!(changes[0].0 < 1.0);
        // Over budget, then the times stop coming: it holds its level, neither way.
        let mut g = GpuGovernor::new(all());
        run(&mut g, 0..72, |_| Some(1.5));
        // Only what is still in the window counts: nothing changes once it has emptied.
        let late = run(&mut g, 72..72 * 30, |_| None);
        assert!(
            late.iter().all(|c| c.0 < 1.0 + GpuGovernor::WINDOW_S),
            "{late:?}"
        );
        let level = g.level();
        assert!(run(&mut g, 72 * 30..72 * 60, |_| None).is_empty());
        assert_eq!(g.level(), level);
        // Nonsense periods are ignored.
        assert_eq!(g.observe(Some(Duration::from_millis(5)), 0.0, 31.0), None);
    }

    #[test]
    fn render_scale_steps_are_shares_of_the_recommended_size() {
        // A start under the recommended size (as a Quest 2's): images at that size, 0.9 drawn.
        let quest2 = RenderScales {
            images: 1.0,
            start: 0.9,
        };
        let share = |step, scales| render_rect_share(step, scales);
        assert_eq!(share(QualityStep::FullSize, quest2), 1.0);
        assert!((share(QualityStep::Full, quest2) - 0.9).abs() < 1e-6);
        assert!((share(QualityStep::Scale85, quest2) - 0.85).abs() < 1e-6);
        assert!((share(QualityStep::Scale70, quest2) - 0.7).abs() < 1e-6);
        // A swapchain the user asked to be 0.9: the 0.85 step draws 0.944 of it.
        let chosen = RenderScales::whole(0.9);
        assert!((share(QualityStep::Scale85, chosen) - 0.85 / 0.9).abs() < 1e-6);
        assert!((share(QualityStep::Scale70, chosen) - 0.7 / 0.9).abs() < 1e-6);
        assert_eq!(share(QualityStep::FoveationUp, chosen), 1.0);
        assert_eq!(share(QualityStep::FullSize, chosen), 1.0);
        let shown = |scales: RenderScales, load: f64| {
            let mut g = GpuGovernor::new(GovernorCaps {
                render_rect: Some(scales),
                ..GovernorCaps::default()
            });
            let changes = run(&mut g, 0..72 * 20, |_| Some(load));
            changes.iter().map(|c| c.1).collect::<Vec<_>>()
        };
        // Under load the steps go down from the start; with room, up to the full size (and
        // only there: the configured scale is where it starts, not a ceiling).
        assert_eq!(
            shown(quest2, 2.0),
            [QualityStep::Scale85, QualityStep::Scale70]
        );
        assert_eq!(shown(quest2, 0.3), [QualityStep::FullSize]);
        // Images the user sized: nothing above them; steps at or above the start left out.
        assert!(shown(chosen, 0.3).is_empty());
        assert_eq!(
            shown(chosen, 2.0),
            [QualityStep::Scale85, QualityStep::Scale70]
        );
        assert_eq!(
            shown(RenderScales::whole(0.85), 2.0),
            [QualityStep::Scale70]
        );
        assert!(shown(RenderScales::whole(0.7), 2.0).is_empty());
    }
}
