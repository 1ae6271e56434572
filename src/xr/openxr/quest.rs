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
    /// The next stronger level (the GPU-time governor's foveation step); `None` at the
    /// strongest.
    pub fn higher(self) -> Option<Foveation> {
        match self {
            Foveation::Off => Some(Foveation::Low),
            Foveation::Low => Some(Foveation::Medium),
            Foveation::Medium => Some(Foveation::High),
            Foveation::High => None,
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

/// Which headset the runtime reports (`XrSystemProperties::systemName`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Headset {
    /// Quest 2: XR2 Gen 1, 1832x1920 per eye, 72/90/120 Hz.
    Quest2,
    /// Quest Pro: XR2+ Gen 1, 1800x1920 per eye, 72/90 Hz.
    QuestPro,
    /// Quest 3: XR2 Gen 2, 2064x2208 per eye, 72/80/90/120 Hz.
    Quest3,
    /// Quest 3S: XR2 Gen 2, 1832x1920 per eye, 72/90/120 Hz.
    Quest3S,
    /// Anything else (PC VR, Monado).
    Other,
}

impl Headset {
    /// Recognises the Quest models from the runtime's system name ("Oculus Quest2",
    /// "Meta Quest Pro", "Meta Quest 3", "Meta Quest 3S", ...).
    pub fn from_system_name(name: &str) -> Self {
        let n: String = name
            .chars()
            .filter(|c| !c.is_whitespace())
            .map(|c| c.to_ascii_lowercase())
            .collect();
        if n.contains("quest3s") {
            Headset::Quest3S
        } else if n.contains("quest3") {
            Headset::Quest3
        } else if n.contains("questpro") {
            Headset::QuestPro
        } else if n.contains("quest2") {
            Headset::Quest2
        } else {
            Headset::Other
        }
    }

    /// The settings a session starts with on this headset unless the user chose otherwise.
    ///
    /// The budget (13.9 ms at 72 Hz, 11.1 at 90, 8.3 at 120) has to hold the frame's CPU work
    /// on the render thread (LOD ≈ 0.03 ms, recording and submission well under 1 ms on this
    /// project's x86 measurements) while the next simulation step runs on the workers: one
    /// 256² step of three cascades is about 0.5 ms on one desktop core, so even at 4-6x slower
    /// mobile cores and 2-3 workers it stays within a third of the 11.1 ms budget. The GPU side
    /// (fragment cost per pixel at full resolution) is what the rate caps and foveation levels
    /// below buy margin for: XR2 Gen 1 gets 72 Hz and high foveation, Gen 2 90 Hz. These are
    /// estimates from desktop measurements scaled by the SoCs' published specifications, not
    /// headset measurements (none were possible here); the refresh governor steps down at run
    /// time when frames miss.
    pub fn defaults(self) -> DeviceDefaults {
        match self {
            Headset::Quest2 => DeviceDefaults {
                max_refresh_rate: 72.0,
                foveation: Foveation::High,
                resolution_scale: 1.0,
                preset: crate::lod::QualityPreset::Medium,
                grid: 256,
                workers_cap: 3,
            },
            Headset::QuestPro => DeviceDefaults {
                max_refresh_rate: 90.0,
                foveation: Foveation::Medium,
                resolution_scale: 1.0,
                preset: crate::lod::QualityPreset::Medium,
                grid: 256,
                workers_cap: 3,
            },
            Headset::Quest3 | Headset::Quest3S => DeviceDefaults {
                max_refresh_rate: 90.0,
                foveation: Foveation::Medium,
                resolution_scale: 1.0,
                preset: crate::lod::QualityPreset::High,
                grid: 256,
                workers_cap: 3,
            },
            Headset::Other => DeviceDefaults {
                max_refresh_rate: 120.0,
                foveation: Foveation::Medium,
                resolution_scale: 1.0,
                preset: crate::lod::QualityPreset::High,
                grid: 256,
                workers_cap: usize::MAX,
            },
        }
    }
}

/// Per-headset starting settings (see [`Headset::defaults`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceDefaults {
    /// Highest display refresh rate asked for (Hz).
    pub max_refresh_rate: f32,
    /// Fixed foveation level.
    pub foveation: Foveation,
    /// Factor on the recommended eye size.
    pub resolution_scale: f32,
    /// LOD quality preset.
    pub preset: crate::lod::QualityPreset,
    /// Simulation grid side.
    pub grid: usize,
    /// Most simulation workers (see `sim::workers::recommended_workers`).
    pub workers_cap: usize,
}

/// Picks the display refresh rate and steps it down when frames do not fit its budget.
///
/// Only rates of at least [`RefreshGovernor::MIN_RATE`] (72 Hz) are ever chosen: Meta's store
/// rules (VRC.Quest.Performance.1) require interactive apps to run at 72, 80, 90, 96, 100 or
/// 120 Hz; 60 Hz is for media apps. It starts at the highest offered rate in [72 Hz, cap]. A frame "misses" when its cost
/// (the larger of the app's CPU time after `xrWaitFrame` and the GPU pass) exceeds
/// [`RefreshGovernor::BUDGET_SHARE`] of the period; when more than a
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

    /// One frame's cost (s). Returns the new rate when it should change.
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
    fn headsets_are_recognised_by_system_name() {
        assert_eq!(Headset::from_system_name("Oculus Quest2"), Headset::Quest2);
        assert_eq!(Headset::from_system_name("Meta Quest 2"), Headset::Quest2);
        assert_eq!(
            Headset::from_system_name("Meta Quest Pro"),
            Headset::QuestPro
        );
        assert_eq!(Headset::from_system_name("Meta Quest 3"), Headset::Quest3);
        assert_eq!(Headset::from_system_name("Meta Quest 3S"), Headset::Quest3S);
        assert_eq!(
            Headset::from_system_name("Monado: Simulated HMD"),
            Headset::Other
        );
        // XR2 Gen 1 gets the lowest rate cap and the strongest foveation.
        let q2 = Headset::Quest2.defaults();
        let q3 = Headset::Quest3.defaults();
        assert!(q2.max_refresh_rate < q3.max_refresh_rate);
        assert_eq!(q2.foveation, Foveation::High);
        for h in [
            Headset::Quest2,
            Headset::QuestPro,
            Headset::Quest3,
            Headset::Quest3S,
        ] {
            let d = h.defaults();
            assert!((2..=3).contains(&d.workers_cap.min(3)) && d.workers_cap <= 3);
            assert!(
                1.0 / d.max_refresh_rate >= 1.0 / 90.0 - 1e-6,
                "{h:?}: at most 90 Hz"
            );
        }
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
    fn never_steps_below_72_hz() {
        // The rates the fault layer offers in the OpenXR test: 60, 72, 90.
        let mut g = RefreshGovernor::new(&[60.0, 72.0, 90.0], 120.0).unwrap();
        let mut seen = vec![g.rate()];
        // Frames far too slow for any rate: it steps down once, then holds at 72.
        for _ in 0..2000 {
            if let Some(r) = g.observe(0.050) {
                seen.push(r);
            }
        }
        assert_eq!(seen, [90.0, 72.0]);
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
