//! Impacts: the moments bodies hit the water, for the ears (issue 32). A body counts as
//! entering when it had been out of the water (less than [`DRY`] of its hull's wet length
//! under) for at least [`AIRBORNE`] and is now in it, moving down: a body bobbing on the
//! crests, or a hull flickering across the threshold, does not splash at every step. Events carry the physics clock's
//! time of the step that saw the entry; the app reads and clears them each frame.

use glam::Vec3;

use super::{MAX_BODIES, PHYSICS_DT};

/// Most impacts kept between two reads (more in one frame are dropped).
pub const MAX_IMPACTS: usize = 16;

/// Wet fraction below which a body is out of the water.
pub const DRY: f32 = 0.02;

/// How long a body must have been out of the water for its entry to count (s): a thrown
/// body's flight, not a boat's hull lifting off a crest for a few steps.
pub const AIRBORNE: f32 = 0.25;

/// Slowest entry that counts (m/s, downward).
pub const MIN_IMPACT_SPEED: f32 = 0.5;

/// A body hitting the water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// The physics clock's time of the step that saw it (s, [`crate::physics::Floaters::time`]).
    pub time: f64,
    /// Where (the body's position, m).
    pub position: Vec3,
    /// Its downward speed (m/s).
    pub speed: f32,
    /// Its mass (kg).
    pub mass: f32,
    /// Its size: half its mean width (m).
    pub radius: f32,
}

/// What the step sees: the impacts so far and which bodies are out of the water.
pub(crate) struct Impacts {
    events: Vec<Impact>,
    /// Steps each body has been out of the water.
    dry: [u32; MAX_BODIES],
}

impl Impacts {
    pub(crate) fn new() -> Self {
        Self {
            events: Vec::with_capacity(MAX_IMPACTS),
            dry: [0; MAX_BODIES],
        }
    }

    /// One floating body in one step: its wet fraction and motion after the water's forces.
    pub(crate) fn observe(&mut self, slot: usize, wet: f32, impact: Impact) {
        let Some(dry) = self.dry.get_mut(slot) else {
            return;
        };
        if wet < DRY {
            *dry = dry.saturating_add(1);
        } else if std::mem::take(dry) as f32 * PHYSICS_DT >= AIRBORNE {
            let fast = impact.speed >= MIN_IMPACT_SPEED && impact.speed.is_finite();
            if fast && self.events.len() < MAX_IMPACTS {
                self.events.push(impact);
            }
        }
    }

    /// A body left the water's forces (held, sunk): out of the water for the next entry.
    pub(crate) fn lift(&mut self, slot: usize) {
        if let Some(d) = self.dry.get_mut(slot) {
            *d = u32::MAX;
        }
    }

    pub(crate) fn events(&self) -> &[Impact] {
        &self.events
    }

    pub(crate) fn clear(&mut self) {
        self.events.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(speed: f32) -> Impact {
        Impact {
            time: 1.0,
            position: Vec3::ZERO,
            speed,
            mass: 10.0,
            radius: 0.2,
        }
    }

    #[test]
    fn an_entry_counts_once_until_the_body_is_out_again() {
        let mut i = Impacts::new();
        // Spawned afloat: no splash.
        i.observe(0, 0.5, hit(1.0));
        assert!(i.events().is_empty());
        for _ in 0..30 {
            i.observe(0, 0.0, hit(1.0));
        }
        i.observe(0, 0.3, hit(4.0));
        i.observe(0, 0.6, hit(3.0));
        assert_eq!(i.events().len(), 1);
        assert_eq!(i.events()[0].speed, 4.0);
        // Out and gently back in: too slow to count.
        for _ in 0..30 {
            i.observe(0, 0.0, hit(0.1));
        }
        i.observe(0, 0.2, hit(0.1));
        assert_eq!(i.events().len(), 1);
        // Out for a few steps (a hull lifting off a crest) and back in fast: no splash.
        for _ in 0..3 {
            i.observe(0, 0.0, hit(2.0));
        }
        i.observe(0, 0.2, hit(2.0));
        assert_eq!(i.events().len(), 1);
        // Held, then dropped in.
        i.lift(0);
        i.observe(0, 0.2, hit(2.0));
        assert_eq!(i.events().len(), 2);
        i.clear();
        assert!(i.events().is_empty());
    }
}
