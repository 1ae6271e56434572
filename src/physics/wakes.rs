//! The bodies and the interaction layer talk in the same step (issue 30): every floating body
//! presses the layer with its displaced volume and splashes it when it plunges in, and every
//! body's heights include the layer's waves, so a buoy rocks in a thrown crate's rings and in
//! a drifting boat's wake. Hands (OpenXR controllers in the water) add their own sources.
//!
//! A body's own hollow (the layer's steady answer to its own weight) is added back to the
//! heights it reads ([`WaveSource::head_at`]): without that it would sink into it, deepen it,
//! and sink further.
//!
//! Sources are made after rapier's step from the new poses: the layer then steps once per
//! physics step, so its waves are at most one step (11 ms) behind the bodies.

use glam::{Vec2, Vec3};

use super::world::{BodyState, Floaters, Slot};
use super::MAX_BODIES;
use crate::sim::interaction::{InteractionConfig, InteractionLayer, WaveSource};

/// Most hand sources a step takes (two controllers, room to spare).
pub const MAX_HAND_SOURCES: usize = 4;

/// A body's vertical speed (m/s) at which its entry makes full foam.
const FOAM_ENTRY_SPEED: f32 = 3.0;

/// The layer, its sources, and what each body put in last.
pub(crate) struct Wakes {
    pub(crate) layer: InteractionLayer,
    sources: Vec<WaveSource>,
    hands: Vec<WaveSource>,
    /// Per slot: the source it put in at the last step (its hollow), if floating.
    own: Vec<Option<WaveSource>>,
    centre: Vec2,
}

impl Wakes {
    pub(crate) fn new(config: InteractionConfig, centre: Vec2) -> Self {
        Self {
            layer: InteractionLayer::new(config, centre.x, centre.y),
            sources: Vec::with_capacity(MAX_BODIES + MAX_HAND_SOURCES),
            hands: Vec::with_capacity(MAX_HAND_SOURCES),
            own: vec![None; MAX_BODIES],
            centre,
        }
    }

    /// The layer's height at `p` for the body in `slot`: the waves, without its own hollow.
    pub(crate) fn height_for(&self, slot: usize, p: [f32; 2]) -> f32 {
        let h = self.layer.height_at(p[0], p[1]);
        match &self.own[slot] {
            Some(s) => h + s.head_at(p[0], p[1], self.layer.config().cell_m),
            None => h,
        }
    }

    /// One layer step after rapier's: a source per floating body, then the hands'.
    pub(crate) fn step(&mut self, slots: &[Slot], velocities: impl Fn(&Slot) -> Vec3) {
        self.sources.clear();
        for (i, s) in slots.iter().enumerate() {
            let before = self.own[i].map_or(0.0, |o| o.volume);
            self.own[i] = None;
            if s.state != BodyState::Floating || s.submerged <= 0.0 {
                continue;
            }
            let size = s.spec.size();
            let radius = 0.5 * size.x.max(size.z);
            let full = s.spec.volume();
            // The entry: water pushed down at the body's sinking speed over its radius, in
            // proportion to the share of its volume that went under this step.
            let sinking = (-velocities(s).y).max(0.0);
            let entered = ((s.submerged - before) / full).clamp(0.0, 1.0);
            let src = WaveSource {
                x: s.curr.position.x,
                z: s.curr.position.z,
                radius,
                // The displaced volume's centroid: half its mean depth under the hull's area.
                depth: 0.5 * s.submerged / s.hull.area().max(1e-3),
                volume: s.submerged,
                impulse: 0.5 * sinking * radius * entered,
                foam: (sinking / FOAM_ENTRY_SPEED * entered * 4.0).min(1.0),
            };
            if src.is_valid() {
                self.own[i] = Some(src);
                self.sources.push(src);
            }
        }
        self.sources.extend_from_slice(&self.hands);
        self.hands.clear();
        self.layer.recentre(self.centre.x, self.centre.y);
        self.layer.step(&self.sources);
    }
}

impl Floaters {
    /// Turns the interaction layer on (`Some`: bodies and hands make waves, and feel them) or
    /// off, centred on `centre` (world x, z).
    pub fn set_interaction(&mut self, config: Option<InteractionConfig>, centre: Vec2) {
        self.wakes = config.map(|c| Wakes::new(c, centre));
    }

    /// The interaction layer, when on.
    pub fn interaction(&self) -> Option<&InteractionLayer> {
        self.wakes.as_ref().map(|w| &w.layer)
    }

    /// Where the layer should be centred from the next step on (the viewer, world x, z).
    pub fn follow(&mut self, centre: Vec2) {
        if let Some(w) = &mut self.wakes {
            w.centre = centre;
        }
    }

    /// Adds a hand's disturbance to the next step (dropped beyond [`MAX_HAND_SOURCES`] a
    /// step, or when the layer is off).
    pub fn disturb(&mut self, source: WaveSource) {
        if let Some(w) = &mut self.wakes {
            if w.hands.len() < MAX_HAND_SOURCES && source.is_valid() {
                w.hands.push(source);
            }
        }
    }
}
