//! Quest-class extensions, each used only when the runtime lists it: the display refresh rate
//! (`XR_FB_display_refresh_rate`), fixed foveation (`XR_FB_foveation` +
//! `XR_FB_swapchain_update_state`) and CPU/GPU performance levels
//! (`XR_EXT_performance_settings`). The choices are pure and tested here; the calls live in
//! the backend.

use openxr as xr;

/// Fixed foveated rendering: how much the periphery's shading rate drops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Foveation {
    /// Full rate everywhere.
    Off,
    /// Slight.
    Low,
    /// Moderate (the default: invisible at the Quest's lens edges).
    Medium,
    /// Strong.
    High,
}

impl Foveation {
    /// The level of `XrFoveationLevelProfileCreateInfoFB`.
    pub fn level(self) -> xr::FoveationLevelFB {
        match self {
            Foveation::Off => xr::FoveationLevelFB::NONE,
            Foveation::Low => xr::FoveationLevelFB::LOW,
            Foveation::Medium => xr::FoveationLevelFB::MEDIUM,
            Foveation::High => xr::FoveationLevelFB::HIGH,
        }
    }
}

/// A performance level hint of `XR_EXT_performance_settings`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PerfLevel {
    /// Save power.
    PowerSavings,
    /// Low, sustainable.
    SustainedLow,
    /// High, sustainable (the default for the ocean).
    SustainedHigh,
    /// Beyond the thermally sustainable range, for short sections.
    Boost,
}

impl PerfLevel {
    /// The extension's level.
    pub fn raw(self) -> xr::sys::PerfSettingsLevelEXT {
        match self {
            PerfLevel::PowerSavings => xr::sys::PerfSettingsLevelEXT::POWER_SAVINGS,
            PerfLevel::SustainedLow => xr::sys::PerfSettingsLevelEXT::SUSTAINED_LOW,
            PerfLevel::SustainedHigh => xr::sys::PerfSettingsLevelEXT::SUSTAINED_HIGH,
            PerfLevel::Boost => xr::sys::PerfSettingsLevelEXT::BOOST,
        }
    }
}

/// Picks the display refresh rate and steps it down when frames do not fit its budget.
///
/// It starts at the highest offered rate at or under the cap. A frame "misses" when the app's
/// CPU time for it exceeds [`RefreshGovernor::BUDGET_SHARE`] of the period; when more than a
/// tenth of the frames of a 2-second window miss, the next lower rate is asked for. It never
/// steps back up on its own: a rate that did not hold is not retried in the same session.
#[derive(Clone, Debug)]
pub struct RefreshGovernor {
    rates: Vec<f32>,
    current: usize,
    window: u32,
    misses: u32,
}

impl RefreshGovernor {
    /// Share of the frame period the app's CPU work may take.
    pub const BUDGET_SHARE: f64 = 0.85;

    /// Rates offered by the runtime, the highest at or under `cap` (Hz) first; `None` when
    /// none is at or under the cap.
    pub fn new(offered: &[f32], cap: f32) -> Option<Self> {
        let mut rates: Vec<f32> = offered
            .iter()
            .copied()
            .filter(|r| r.is_finite() && *r > 0.0 && *r <= cap)
            .collect();
        rates.sort_by(|a, b| b.total_cmp(a));
        rates.dedup();
        (!rates.is_empty()).then_some(Self {
            rates,
            current: 0,
            window: 0,
            misses: 0,
        })
    }

    /// The rate to use now (Hz).
    pub fn rate(&self) -> f32 {
        self.rates[self.current]
    }

    /// One frame's CPU cost (s). Returns the new rate when it should change.
    pub fn observe(&mut self, cost: f64) -> Option<f32> {
        let period = 1.0 / self.rate() as f64;
        self.window += 1;
        if cost > Self::BUDGET_SHARE * period {
            self.misses += 1;
        }
        let frames = (2.0 * self.rate()).ceil() as u32;
        if self.window < frames {
            return None;
        }
        let too_many = self.misses * 10 > self.window;
        self.window = 0;
        self.misses = 0;
        if too_many && self.current + 1 < self.rates.len() {
            self.current += 1;
            return Some(self.rate());
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_at_the_highest_rate_under_the_cap() {
        let quest3 = [72.0, 80.0, 90.0, 120.0];
        assert_eq!(RefreshGovernor::new(&quest3, 120.0).unwrap().rate(), 120.0);
        assert_eq!(RefreshGovernor::new(&quest3, 100.0).unwrap().rate(), 90.0);
        // Monado's null compositor offers only 20 Hz.
        assert_eq!(RefreshGovernor::new(&[20.0], 120.0).unwrap().rate(), 20.0);
        assert!(RefreshGovernor::new(&[72.0], 60.0).is_none());
        assert!(RefreshGovernor::new(&[], 120.0).is_none());
    }

    #[test]
    fn steps_down_when_frames_miss_and_holds_when_they_fit() {
        let mut g = RefreshGovernor::new(&[72.0, 90.0, 120.0], 120.0).unwrap();
        // 10 ms frames fit 120 Hz? No: 0.85 × 8.33 ms = 7.1 ms. Two seconds of them step down.
        let mut changes = Vec::new();
        for _ in 0..240 {
            if let Some(r) = g.observe(0.010) {
                changes.push(r);
            }
        }
        assert_eq!(changes, [90.0]);
        // At 90 Hz (budget 9.4 ms) 10 ms still misses: down to 72 (budget 11.8 ms).
        for _ in 0..180 {
            if let Some(r) = g.observe(0.010) {
                changes.push(r);
            }
        }
        assert_eq!(changes, [90.0, 72.0]);
        // 72 Hz holds; nothing lower to go to anyway.
        for _ in 0..1000 {
            assert_eq!(g.observe(0.010), None);
        }
        assert_eq!(g.rate(), 72.0);
    }

    #[test]
    fn a_few_slow_frames_are_tolerated() {
        let mut g = RefreshGovernor::new(&[90.0, 120.0], 120.0).unwrap();
        // 5 % of frames over budget (a hitch now and then).
        for i in 0..2400 {
            let cost = if i % 20 == 0 { 0.020 } else { 0.004 };
            assert_eq!(g.observe(cost), None);
        }
        assert_eq!(g.rate(), 120.0);
    }
}
