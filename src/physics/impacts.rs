//! Impacts: the moments bodies hit the water, for the ears (issue 32). A body counts as
//! entering when it had been out of the water (less than [`DRY`] of its hull's wet length
//! under) and is now in it, moving down; it is armed again only once it is out again, so a
//! body bobbing in the waves does not splash at every crest. Events carry the physics clock's
//! time of the step that saw the entry; the app reads and clears them each frame.

use glam::Vec3;

use super::world::Floaters;
use super::MAX_BODIES;

/// Most impacts kept between two reads (more in one frame are dropped).
pub const MAX_IMPACTS: usize = 16;

/// Wet fraction below which a body is out of the water.
pub const DRY: f32 = 0.02;

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
    dry: [bool; MAX_BODIES],
}

impl Impacts {
    pub(crate) fn new() -> Self {
        Self {
            events: Vec::with_capacity(MAX_IMPACTS),
            dry: [false; MAX_BODIES],
        }
    }

    /// One floating body in one step: its wet fraction and motion after the water's forces.
    pub(crate) fn observe(&mut self, slot: usize, wet: f32, impact: Impact) {
        let Some(dry) = self.dry.get_mut(slot) else {
            return;
        };
        if wet < DRY {
            *dry = true;
        } else if *dry {
            *dry = false;
            let fast = impact.speed >= MIN_IMPACT_SPEED && impact.speed.is_finite();
            if fast && self.events.len() < MAX_IMPACTS {
                self.events.push(impact);
            }
        }
    }

    /// A body left the water's forces (held, sunk): out of the water for the next entry.
    pub(crate) fn lift(&mut self, slot: usize) {
        if let Some(d) = self.dry.get_mut(slot) {
            *d = true;
        }
    }

    pub(crate) fn events(&self) -> &[Impact] {
        &self.events
    }

    pub(crate) fn clear(&mut self) {
        self.events.clear();
    }
}

impl Floaters {
    /// Bodies that hit the water since the last [`Floaters::clear_impacts`] (at most
    /// [`MAX_IMPACTS`]), in step order.
    pub fn impacts(&self) -> &[Impact] {
        self.impacts.events()
    }

    /// Forgets the impacts read.
    pub fn clear_impacts(&mut self) {
        self.impacts.clear();
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
        i.observe(0, 0.0, hit(1.0));
        i.observe(0, 0.3, hit(4.0));
        i.observe(0, 0.6, hit(3.0));
        assert_eq!(i.events().len(), 1);
        assert_eq!(i.events()[0].speed, 4.0);
        // Out and gently back in: too slow to count.
        i.observe(0, 0.0, hit(0.1));
        i.observe(0, 0.2, hit(0.1));
        assert_eq!(i.events().len(), 1);
        // Held, then dropped in.
        i.lift(0);
        i.observe(0, 0.2, hit(2.0));
        assert_eq!(i.events().len(), 2);
        i.clear();
        assert!(i.events().is_empty());
    }
}
