//! The refresh-rate governor: which of the runtime's display rates (`XR_FB_display_refresh_rate`)
//! the app asks for, stepped down when the frames do not fit and back up when they fit the
//! faster rate with room to spare.
//!
//! What it measures is the app's own work per frame, not its waits: the span from
//! `xrWaitFrame`'s return to `xrEndFrame` less the time blocked on the GPU (the frame slot's
//! fence) and on the compositor (`xrWaitSwapchainImage`). A GPU-bound frame's waits would
//! otherwise read as CPU time and lower the rate before the GPU-time governor
//! ([`crate::xr::gpu_governor`]) tried its cheaper steps. The GPU pass counts only once that
//! governor has no level left: it acts first.
//!
//! Pure and allocation-free per frame; time is counted in frames at the current rate, so tests
//! script it exactly.

/// One rendered frame's cost, as the governor weighs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCost {
    /// The app's CPU work (s): from `xrWaitFrame`'s return to `xrEndFrame`, waits removed.
    pub cpu: f64,
    /// The last measured GPU pass (s), when timestamps gave one.
    pub gpu: Option<f64>,
    /// Whether the GPU-time governor still has a cheaper level: GPU time then does not count
    /// against this rate (that governor acts first).
    pub gpu_levels_left: bool,
}

/// Picks the display refresh rate and steps it down and back up.
///
/// Only rates of at least [`RefreshGovernor::MIN_RATE`] (72 Hz) are ever chosen: Meta's store
/// rules (VRC.Quest.Performance.1) require interactive apps to run at 72, 80, 90, 96, 100 or
/// 120 Hz; 60 Hz is for media apps. It starts at the highest offered rate in [72 Hz, cap].
///
/// - **Down**: a frame misses when its cost exceeds [`Self::DOWN_SHARE`] of the period; when
///   more than a tenth of a 2-second window's frames miss, the next lower rate is asked for.
/// - **Up**, with hysteresis: when [`Self::UP_WINDOWS`] windows in a row fit
///   [`Self::UP_SHARE`] of the *next higher* rate's period (95 % of their frames), and the
///   higher rate's hold has passed. The hold starts at [`Self::FIRST_HOLD_S`] after a step down
///   and doubles each time that rate fails again (at most [`Self::MAX_HOLD_S`]), so a rate that
///   does not hold is retried ever more rarely instead of see-sawing.
#[derive(Clone, Debug)]
pub struct RefreshGovernor {
    /// Offered rates in [72 Hz, cap], highest first.
    rates: Vec<f32>,
    /// Per rate, seconds at a lower rate before it is tried again.
    holds: Vec<f64>,
    current: usize,
    /// Frames in the current window, and of them: over the down share, over the up share.
    window: u32,
    misses: u32,
    tight: u32,
    /// Consecutive windows with headroom for the higher rate.
    roomy_windows: u32,
    /// Seconds since the rate last changed.
    since_change: f64,
}

impl RefreshGovernor {
    /// Share of the frame period a frame may take before it counts as a miss.
    pub const DOWN_SHARE: f64 = 0.85;
    /// Share of the higher rate's period a frame must fit for the higher rate to be tried.
    pub const UP_SHARE: f64 = 0.65;
    /// Windows (2 s each) in a row with headroom before stepping up.
    pub const UP_WINDOWS: u32 = 3;
    /// Seconds a rate that just failed waits before it is tried again.
    pub const FIRST_HOLD_S: f64 = 10.0;
    /// The longest wait before a rate that keeps failing is tried again (s).
    pub const MAX_HOLD_S: f64 = 320.0;
    /// The lowest rate an interactive app may use (Hz).
    pub const MIN_RATE: f32 = 72.0;

    /// Rates offered by the runtime in [[`Self::MIN_RATE`], `cap`] (Hz), the highest first;
    /// `None` when none is (the runtime's own rate is then left alone).
    pub fn new(offered: &[f32], cap: f32) -> Option<Self> {
        let mut rates: Vec<f32> = offered
            .iter()
            .copied()
            .filter(|r| r.is_finite() && *r >= Self::MIN_RATE - 0.5 && *r <= cap)
            .collect();
        rates.sort_by(|a, b| b.total_cmp(a));
        rates.dedup();
        (!rates.is_empty()).then(|| Self {
            holds: vec![0.0; rates.len()],
            rates,
            current: 0,
            window: 0,
            misses: 0,
            tight: 0,
            roomy_windows: 0,
            since_change: 0.0,
        })
    }

    /// The rate to use now (Hz).
    pub fn rate(&self) -> f32 {
        self.rates[self.current]
    }

    /// One rendered frame's cost. Returns the new rate when it should change.
    pub fn observe(&mut self, cost: FrameCost) -> Option<f32> {
        let period = 1.0 / self.rate() as f64;
        self.since_change += period;
        let gpu = if cost.gpu_levels_left {
            0.0
        } else {
            cost.gpu.unwrap_or(0.0)
        };
        if cost.cpu.max(gpu) > Self::DOWN_SHARE * period {
            self.misses += 1;
        }
        if let Some(&higher) = self.current.checked_sub(1).and_then(|i| self.rates.get(i)) {
            // Headroom for the faster rate counts the GPU pass whatever the GPU governor's
            // level: a faster rate must not push it back down.
            let worst = cost.cpu.max(cost.gpu.unwrap_or(0.0));
            if worst > Self::UP_SHARE / higher as f64 {
                self.tight += 1;
            }
        }
        self.window += 1;
        if self.window < (2.0 * self.rate()).ceil() as u32 {
            return None;
        }
        let (frames, misses, tight) = (self.window, self.misses, self.tight);
        self.window = 0;
        self.misses = 0;
        self.tight = 0;
        if misses * 10 > frames {
            self.roomy_windows = 0;
            if self.current + 1 < self.rates.len() {
                // This rate failed: it waits before the next try, longer each time.
                let hold = &mut self.holds[self.current];
                *hold = (*hold * 2.0).clamp(Self::FIRST_HOLD_S, Self::MAX_HOLD_S);
                return Some(self.change(self.current + 1));
            }
            return None;
        }
        if self.current == 0 || tight * 20 > frames {
            self.roomy_windows = 0;
            return None;
        }
        self.roomy_windows += 1;
        if self.roomy_windows >= Self::UP_WINDOWS
            && self.since_change >= self.holds[self.current - 1]
        {
            return Some(self.change(self.current - 1));
        }
        None
    }

    fn change(&mut self, to: usize) -> f32 {
        self.current = to;
        self.roomy_windows = 0;
        self.since_change = 0.0;
        self.rate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cpu(s: f64) -> FrameCost {
        FrameCost {
            cpu: s,
            gpu: None,
            gpu_levels_left: true,
        }
    }

    /// Feeds `frames` frames of `cost`; the rates changed to, in order.
    fn run(g: &mut RefreshGovernor, frames: u32, cost: FrameCost) -> Vec<f32> {
        (0..frames).filter_map(|_| g.observe(cost)).collect()
    }

    #[test]
    fn starts_at_the_highest_rate_under_the_cap() {
        let quest3 = [72.0, 80.0, 90.0, 120.0];
        assert_eq!(RefreshGovernor::new(&quest3, 120.0).unwrap().rate(), 120.0);
        assert_eq!(RefreshGovernor::new(&quest3, 100.0).unwrap().rate(), 90.0);
        // Monado's null compositor offers only 20 Hz: below 72, so nothing is asked for.
        assert!(RefreshGovernor::new(&[20.0], 120.0).is_none());
        assert!(RefreshGovernor::new(&[72.0], 60.0).is_none());
        // Quest 2 offers 60 Hz too; an interactive app never takes it.
        let quest2 = [60.0, 72.0, 80.0, 90.0, 120.0];
        assert_eq!(RefreshGovernor::new(&quest2, 72.0).unwrap().rate(), 72.0);
        assert!(RefreshGovernor::new(&[], 120.0).is_none());
    }

    #[test]
    fn steps_down_when_frames_miss_and_holds_when_they_fit() {
        let mut g = RefreshGovernor::new(&[72.0, 90.0, 120.0], 120.0).unwrap();
        // 10 ms frames fit 120 Hz? No: 0.85 × 8.33 ms = 7.1 ms. Two seconds of them step down.
        assert_eq!(run(&mut g, 240, cpu(0.010)), [90.0]);
        // At 90 Hz (budget 9.4 ms) 10 ms still misses: down to 72 (budget 11.8 ms).
        assert_eq!(run(&mut g, 180, cpu(0.010)), [72.0]);
        // 72 Hz holds, and 10 ms has no room for 90 Hz (0.65 × 11.1 ms = 7.2 ms): no change.
        assert_eq!(run(&mut g, 10_000, cpu(0.010)), [0.0f32; 0]);
        assert_eq!(g.rate(), 72.0);
    }

    #[test]
    fn never_steps_below_72_hz() {
        // The rates the fault layer offers in the OpenXR test: 60, 72, 90.
        let mut g = RefreshGovernor::new(&[60.0, 72.0, 90.0], 120.0).unwrap();
        // Frames far too slow for any rate: it steps down once, then holds at 72.
        assert_eq!(run(&mut g, 2000, cpu(0.050)), [72.0]);
        assert_eq!(g.rate(), 72.0);
    }

    #[test]
    fn a_few_slow_frames_are_tolerated() {
        let mut g = RefreshGovernor::new(&[90.0, 120.0], 120.0).unwrap();
        // 5 % of frames over budget (a hitch now and then).
        for i in 0..2400 {
            let c = if i % 20 == 0 { 0.020 } else { 0.004 };
            assert_eq!(g.observe(cpu(c)), None);
        }
        assert_eq!(g.rate(), 120.0);
    }

    #[test]
    fn gpu_time_counts_only_once_the_gpu_governor_has_no_level_left() {
        let gpu = |levels_left| FrameCost {
            cpu: 0.003,
            gpu: Some(0.010),
            gpu_levels_left: levels_left,
        };
        let mut g = RefreshGovernor::new(&[90.0, 120.0], 120.0).unwrap();
        assert_eq!(run(&mut g, 2400, gpu(true)), [0.0f32; 0]);
        assert_eq!(run(&mut g, 240, gpu(false)), [90.0]);
    }

    #[test]
    fn steps_back_up_after_the_hold_and_backs_off_when_the_rate_fails_again() {
        let mut g = RefreshGovernor::new(&[72.0, 90.0], 120.0).unwrap();
        assert_eq!(run(&mut g, 180, cpu(0.012)), [72.0]);
        // Light frames (4 ms: room for 90 Hz) at 72 Hz: back up after the first hold (10 s),
        // not after the 3 roomy windows (6 s) alone.
        let mut frames_to_up = 0;
        while g.observe(cpu(0.004)).is_none() {
            frames_to_up += 1;
            assert!(frames_to_up < 72 * 60, "never stepped back up");
        }
        assert_eq!(g.rate(), 90.0);
        let secs = (frames_to_up + 1) as f64 / 72.0;
        assert!((10.0..=12.1).contains(&secs), "{secs} s to step up");
        // The load comes back: down again, and the next try waits twice as long (20 s).
        assert_eq!(run(&mut g, 180, cpu(0.012)), [72.0]);
        let mut frames_to_up = 0;
        while g.observe(cpu(0.004)).is_none() {
            frames_to_up += 1;
            assert!(frames_to_up < 72 * 120, "never stepped back up");
        }
        let secs = (frames_to_up + 1) as f64 / 72.0;
        assert!(
            (20.0..=22.1).contains(&secs),
            "{secs} s to step up the second time"
        );
    }

    #[test]
    fn no_step_up_without_room_for_the_faster_rate() {
        let mut g = RefreshGovernor::new(&[72.0, 90.0], 120.0).unwrap();
        assert_eq!(run(&mut g, 180, cpu(0.012)), [72.0]);
        // 8 ms fits 72 Hz (11.8 ms) but not 65 % of 90 Hz's 11.1 ms (7.2 ms): it stays.
        assert_eq!(run(&mut g, 72 * 120, cpu(0.008)), [0.0f32; 0]);
        // A GPU pass that would not fit either keeps it down, whatever the GPU level.
        let gpu_heavy = FrameCost {
            cpu: 0.002,
            gpu: Some(0.009),
            gpu_levels_left: true,
        };
        assert_eq!(run(&mut g, 72 * 120, gpu_heavy), [0.0f32; 0]);
        assert_eq!(g.rate(), 72.0);
    }
}
