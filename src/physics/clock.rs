//! The fixed-step clock: frames of any length become whole physics steps plus a fraction to
//! interpolate by ("fix your timestep").

use std::time::Duration;

/// Most fixed steps one frame may run. A longer frame (a hitch, a breakpoint, the app
/// suspended) drops the rest of its time instead of spiralling: every step costs time, and
/// catching up on seconds would make the next frame longer still.
pub const MAX_CATCH_UP_STEPS: u32 = 5;

/// What a frame's time became.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ticks {
    /// Fixed steps to run now.
    pub steps: u32,
    /// Fraction of a step left over, in [0, 1): how far to interpolate from the previous
    /// step's poses to the last one's.
    pub alpha: f32,
    /// Time dropped because of [`MAX_CATCH_UP_STEPS`] (s).
    pub dropped: f64,
}

/// An accumulator of frame time against a fixed step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedClock {
    step: f64,
    accumulator: f64,
}

impl FixedClock {
    /// A clock stepping every `step` seconds (clamped to at least 1 µs).
    pub fn new(step: f64) -> Self {
        Self {
            step: step.max(1e-6),
            accumulator: 0.0,
        }
    }

    /// The fixed step (s).
    pub fn step(&self) -> f64 {
        self.step
    }

    /// Adds a frame's time and says how many steps to run and the fraction left.
    pub fn advance(&mut self, frame: Duration) -> Ticks {
        self.accumulator += frame.as_secs_f64();
        let whole = (self.accumulator / self.step).floor();
        let steps = whole.min(MAX_CATCH_UP_STEPS as f64);
        self.accumulator -= steps * self.step;
        let mut dropped = 0.0;
        if whole > steps {
            // Keep the fraction, drop the whole steps beyond the cap.
            let keep = self.accumulator % self.step;
            dropped = self.accumulator - keep;
            self.accumulator = keep;
        }
        Ticks {
            steps: steps as u32,
            alpha: self.alpha(),
            dropped,
        }
    }

    /// The fraction of a step accumulated, in [0, 1).
    pub fn alpha(&self) -> f32 {
        ((self.accumulator / self.step) as f32).clamp(0.0, 0.999_999)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_become_whole_steps_and_a_fraction() {
        let mut c = FixedClock::new(1.0 / 90.0);
        // 72 Hz frames: 1.25 steps each on average.
        let mut total = 0;
        for _ in 0..72 {
            let t = c.advance(Duration::from_secs_f64(1.0 / 72.0));
            assert!(t.steps <= 2 && (0.0..1.0).contains(&t.alpha));
            total += t.steps;
        }
        assert!((89..=90).contains(&total), "{total} steps in one second");
        // 120 Hz frames: some frames run no step.
        let zero = (0..12)
            .filter(|_| c.advance(Duration::from_secs_f64(1.0 / 120.0)).steps == 0)
            .count();
        assert!(zero >= 2);
    }

    #[test]
    fn a_long_hitch_is_capped() {
        let mut c = FixedClock::new(1.0 / 90.0);
        let t = c.advance(Duration::from_secs(2));
        assert_eq!(t.steps, MAX_CATCH_UP_STEPS);
        assert!(t.dropped > 1.9 && t.alpha < 1.0);
        assert_eq!(c.advance(Duration::ZERO).steps, 0);
    }
}
