//! Floating at the surface: the eyes ride the sea's height under the head, low-passed so
//! that the chop does not shake the view while the swell still lifts it, or stay at a fixed
//! height over the mean level (the comfort option: the water moves, the user does not); a
//! held button ducks under and lets the user come back up. Pure: the backend feeds it the
//! sea's height and the button each frame.

/// How a floating user rides the water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatSettings {
    /// Eyes above the water while floating (m): a swimmer's, chin at the surface.
    pub eye_above_water: f32,
    /// Time constant of the ride's low pass (s). The height fed in is already the mean over
    /// the body's footprint (waves shorter than the body are averaged away, as its buoyancy
    /// does); this smooths what is left frame to frame and halves a chop of 2.5 Hz, while
    /// the swell (5-12 s) is ridden with a lag of about 8 cm per metre of wave.
    pub smoothing_s: f32,
    /// Swim speed at full stick (m/s): a strong swimmer's crawl.
    pub swim_speed: f32,
    /// How far a duck takes the eyes down from the floating height (m).
    pub duck_depth: f32,
    /// Speed of going down and coming back up (m/s).
    pub duck_speed: f32,
}

impl Default for FloatSettings {
    fn default() -> Self {
        Self {
            eye_above_water: 0.15,
            smoothing_s: 0.1,
            swim_speed: 1.2,
            duck_depth: 1.5,
            duck_speed: 1.2,
        }
    }
}

/// The floating user's state: where the eyes should be, and how fast the water moves them.
#[derive(Clone, Copy, Debug)]
pub struct Afloat {
    settings: FloatSettings,
    /// Ride the waves (true) or keep the eyes at a fixed height over the mean level.
    ride: bool,
    /// The low-passed height of the sea under the head (m); `None` before the first sample.
    surface: Option<f32>,
    /// How far ducked (m, 0 to `duck_depth`).
    dive: f32,
    /// The eye height's rate of change over the last step (m/s), for the comfort vignette.
    vertical_speed: f32,
}

impl Afloat {
    /// Afloat with `settings`, riding the waves or at a fixed height (`ride`).
    pub fn new(settings: FloatSettings, ride: bool) -> Self {
        Self {
            settings,
            ride,
            surface: None,
            dive: 0.0,
            vertical_speed: 0.0,
        }
    }

    /// The settings it floats by.
    pub fn settings(&self) -> FloatSettings {
        self.settings
    }

    /// Rides the waves (`true`) or keeps a fixed height from now on (the comfort option).
    pub fn set_ride(&mut self, ride: bool) {
        self.ride = ride;
    }

    /// One frame of `dt` seconds: `surface` is the sea's height under the head (m over the
    /// mean level; `None` or not finite when unknown: the last one is held), `duck` whether
    /// the duck button is held. Returns the eyes' height over the mean level.
    pub fn step(&mut self, surface: Option<f32>, duck: bool, dt: f32) -> f32 {
        let before = self.eye_height();
        let dt = if dt.is_finite() { dt.max(0.0) } else { 0.0 };
        if let Some(h) = surface.filter(|h| h.is_finite()) {
            let kept = self.surface.unwrap_or(h);
            // First order: the share of the gap closed in dt for time constant τ.
            let a = 1.0 - (-dt / self.settings.smoothing_s.max(1e-3)).exp();
            self.surface = Some(kept + (h - kept) * a);
        }
        let target = if duck { self.settings.duck_depth } else { 0.0 };
        let step = self.settings.duck_speed * dt;
        self.dive += (target - self.dive).clamp(-step, step);
        let after = self.eye_height();
        self.vertical_speed = if dt > 0.0 { (after - before) / dt } else { 0.0 };
        after
    }

    /// The eyes' height over the mean level now (m).
    pub fn eye_height(&self) -> f32 {
        let water = if self.ride {
            self.surface.unwrap_or(0.0)
        } else {
            0.0
        };
        water + self.settings.eye_above_water - self.dive
    }

    /// How fast the eyes moved up or down in the last step (m/s).
    pub fn vertical_speed(&self) -> f32 {
        self.vertical_speed
    }

    /// Whether the user is ducking (going down or held under).
    pub fn ducked(&self) -> bool {
        self.dive > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 72.0;

    /// Rides a sea of two waves (a swell of `period` s and a chop of 0.4 s) for a minute;
    /// returns the eyes' height relative to the water (min, max) and the amplitudes of the
    /// eyes' swell and chop motion.
    fn ride(period: f32) -> ((f32, f32), f32, f32) {
        let mut a = Afloat::new(FloatSettings::default(), true);
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        let (mut swell_c, mut swell_s, mut chop_c, mut chop_s) = (0.0, 0.0, 0.0, 0.0);
        let n = (60.0 / DT) as usize;
        for i in 0..n {
            let t = i as f32 * DT;
            let (ws, wc) = (std::f32::consts::TAU / period, std::f32::consts::TAU / 0.4);
            let h = 1.0 * (ws * t).sin() + 0.1 * (wc * t).sin();
            let eye = a.step(Some(h), false, DT);
            if t > 10.0 {
                lo = lo.min(eye - h);
                hi = hi.max(eye - h);
                swell_c += eye * (ws * t).cos();
                swell_s += eye * (ws * t).sin();
                chop_c += eye * (wc * t).cos();
                chop_s += eye * (wc * t).sin();
            }
        }
        let m = (n as f32 - 10.0 / DT) / 2.0;
        (
            (lo, hi),
            (swell_c * swell_c + swell_s * swell_s).sqrt() / m,
            (chop_c * chop_c + chop_s * chop_s).sqrt() / m,
        )
    }

    #[test]
    fn the_swell_is_ridden_and_the_chop_smoothed_away() {
        let ((lo, hi), swell, chop) = ride(8.0);
        // A 1 m swell of 8 s lifts the eyes by nearly all of it; what is left of a chop of
        // 0.4 s (10 cm) by about half of its height.
        assert!(swell > 0.97 && swell < 1.01, "swell {swell}");
        assert!(chop < 0.06, "chop {chop}");
        // A 2 m swell with a chop on it: the eyes dip at most 3 cm into it.
        assert!(lo > -0.03 && hi < 0.36, "eyes over the water {lo}..{hi}");
    }

    #[test]
    fn fixed_height_ignores_the_sea_and_ducking_goes_under_and_back() {
        let mut a = Afloat::new(FloatSettings::default(), false);
        for i in 0..200 {
            let e = a.step(Some((i as f32 * 0.1).sin() * 2.0), false, DT);
            assert!((e - 0.15).abs() < 1e-6, "{e}");
        }
        // Ducking: down at the duck speed to the duck depth, never past it.
        let mut deepest = f32::MAX;
        for _ in 0..(3.0 / DT) as usize {
            deepest = deepest.min(a.step(Some(0.0), true, DT));
            assert!(a.vertical_speed() <= 0.0 && a.vertical_speed() >= -1.2 - 1e-4);
        }
        assert!((deepest - (0.15 - 1.5)).abs() < 1e-4, "{deepest}");
        assert!(a.ducked());
        // Let go: back up in 1.25 s.
        for _ in 0..(1.3 / DT) as usize {
            a.step(Some(0.0), false, DT);
        }
        assert!(!a.ducked() && (a.eye_height() - 0.15).abs() < 1e-5);
        // Riding again picks the sea up where it is now.
        a.set_ride(true);
        for _ in 0..(3.0 / DT) as usize {
            a.step(Some(0.8), false, DT);
        }
        assert!((a.eye_height() - 0.95).abs() < 1e-3, "{}", a.eye_height());
    }

    #[test]
    fn unknown_heights_hold_the_last_one() {
        let mut a = Afloat::new(FloatSettings::default(), true);
        for _ in 0..500 {
            a.step(Some(0.5), false, DT);
        }
        let before = a.eye_height();
        a.step(None, false, DT);
        a.step(Some(f32::NAN), false, DT);
        a.step(Some(0.5), false, f32::NAN);
        assert_eq!(a.eye_height(), before);
        assert!((before - 0.65).abs() < 1e-4);
    }
}
