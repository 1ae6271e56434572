//! The world's clock: the runtime's display times less the time the user was away
//! ([`crate::xr::FrameState::paused`]), so that the sea, the bodies and the sound stop while the
//! user is in the system menu or has taken the headset off, and go on from where they stopped
//! (no jump of the sea, no burst of a pause's worth of physics) when the user is back.

/// Maps display times to world times across pauses.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorldClock {
    /// Display seconds spent paused, over the finished pauses.
    away: f64,
    /// The display time the current pause began at.
    paused_at: Option<f64>,
    /// Pauses begun so far.
    pauses: u32,
}

impl WorldClock {
    /// The world time of a frame shown at `display` (s), `paused` or not. While paused it
    /// stays at the time the pause began; afterwards it runs on from there.
    pub fn world_time(&mut self, display: f64, paused: bool) -> f64 {
        match (paused, self.paused_at) {
            (true, None) => {
                self.paused_at = Some(display);
                self.pauses += 1;
                display - self.away
            }
            (true, Some(began)) => began - self.away,
            (false, Some(began)) => {
                // A runtime's display times only grow; a clock that went back adds nothing.
                self.away += (display - began).max(0.0);
                self.paused_at = None;
                display - self.away
            }
            (false, None) => display - self.away,
        }
    }

    /// Display seconds the world has stood still so far, up to `display`.
    pub fn away(&self, display: f64) -> f64 {
        self.away
            + self
                .paused_at
                .map_or(0.0, |began| (display - began).max(0.0))
    }

    /// Pauses begun so far.
    pub fn pauses(&self) -> u32 {
        self.pauses
    }

    /// Whether the world stands still now.
    pub fn paused(&self) -> bool {
        self.paused_at.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_world_stops_while_paused_and_runs_on_from_there() {
        let mut c = WorldClock::default();
        let period = 1.0 / 72.0;
        let mut last = 0.0;
        let mut seen = Vec::new();
        for i in 0..400 {
            let display = 10.0 + i as f64 * period;
            // Away for frames 100-299: 200 frames, 2.78 s.
            let paused = (100..300).contains(&i);
            let w = c.world_time(display, paused);
            if i > 0 && !paused {
                let step = w - last;
                // Never a jump: a frame's step after the pause as before it.
                assert!(
                    (step - period).abs() < 1e-9 || (i == 300 && step.abs() < 1e-9),
                    "frame {i}: {step}"
                );
            }
            if paused {
                assert_eq!(w, 10.0 + 100.0 * period - 0.0, "frame {i}");
            }
            last = w;
            seen.push(w);
        }
        assert!((c.away(10.0 + 399.0 * period) - 200.0 * period).abs() < 1e-9);
        assert_eq!(c.pauses(), 1);
        assert!(!c.paused());
        // The world ran 200 frames fewer than the display.
        assert!((seen[399] - (10.0 + 199.0 * period)).abs() < 1e-9);
    }

    #[test]
    fn pauses_add_up_and_a_clock_that_went_back_adds_nothing() {
        let mut c = WorldClock::default();
        assert_eq!(c.world_time(1.0, false), 1.0);
        assert_eq!(c.world_time(2.0, true), 2.0);
        assert!(c.paused());
        assert_eq!(c.away(3.0), 1.0);
        assert_eq!(c.world_time(4.0, true), 2.0);
        assert_eq!(c.world_time(5.0, false), 2.0);
        assert_eq!(c.world_time(6.0, true), 3.0);
        assert_eq!(c.world_time(5.5, false), 2.5);
        assert_eq!(c.away(7.0), 3.0);
        assert_eq!(c.pauses(), 2);
    }
}
