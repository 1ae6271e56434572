//! The bodies and the interaction layer talk in the same step (issue 30): every floating body
//! presses the layer with its displaced volume and splashes it when it plunges in, and every
//! body's heights include the layer's waves (their mean over its hull: `world.rs`), so a buoy
//! heaves in a thrown crate's rings and in a boat's wake. Hands (OpenXR controllers in the
//! water) add their own sources, and so does a floating user's body (`Floaters::wade`).
//!
//! A body's own hollow (the layer's steady answer to its own weight) is taken out of the
//! heights it reads (`Wakes::height_for`): reading it, it would sink into it, deepen it and
//! sink further. What is taken out is at most what the layer is lowered: while the hollow
//! forms after an entry, the body is not lifted by water that is not there. (Reading only the
//! layer on a circle around the body instead was tried: a buoy then excited itself into
//! 0.3 m oscillations.)
//!
//! Sources are made after rapier's step from the new poses: the layer then steps once per
//! physics step, so its waves are at most one step (11 ms) behind the bodies.

use glam::{Vec2, Vec3};

use super::hands::HandInput;
use super::slot::{BodyState, Slot};
use super::MAX_BODIES;
use crate::sim::interaction::{InteractionConfig, InteractionLayer, WaveSource};
use crate::sim::Surfaces;

/// Most sources one body puts in (along its length).
pub const MAX_SOURCES_PER_BODY: usize = 3;

/// Most hand sources a step takes (two controllers, room to spare).
pub const MAX_HAND_SOURCES: usize = 4;

/// A hand's volume in the water, with its wrist (m³).
pub const HAND_VOLUME: f32 = 6.0e-4;

/// A hand's radius (m).
pub const HAND_RADIUS: f32 = 0.06;

/// A hand's cross-section against the water when it sweeps (m²).
pub const HAND_AREA: f32 = 0.015;

/// A body's vertical speed (m/s) at which its entry makes full foam.
const FOAM_ENTRY_SPEED: f32 = 3.0;

/// Radius of a floating user's body at the waterline (m): the shoulders' half width, and the
/// footprint the head's float height is averaged over.
pub const SWIMMER_RADIUS: f32 = 0.35;

/// The water a floating user's head and shoulders push aside at the surface (m³): what the
/// body makes waves with at rest; swimming adds its dynamic pressure.
pub const SWIMMER_VOLUME: f32 = 0.02;

/// The frontal area a swimmer pushes through the water (m²).
pub const SWIMMER_AREA: f32 = 0.12;

/// What presses on the water from outside the physics' bodies (`Wakes::press`).
struct Presser {
    radius: f32,
    volume: f32,
    /// Area the dynamic pressure acts over (m²).
    area: f32,
    /// Most foam a plunge makes.
    foam: f32,
    /// Whether the water it is under includes the layer's own waves (a hand: yes; a
    /// floating body: not its own hollow).
    reads_layer: bool,
}

const HAND: Presser = Presser {
    radius: HAND_RADIUS,
    volume: HAND_VOLUME,
    area: HAND_AREA,
    foam: 0.3,
    reads_layer: true,
};

const SWIMMER: Presser = Presser {
    radius: SWIMMER_RADIUS,
    volume: SWIMMER_VOLUME,
    area: SWIMMER_AREA,
    foam: 0.0,
    reads_layer: false,
};

/// The layer, its sources, and what each body put in last.
pub(crate) struct Wakes {
    pub(crate) layer: InteractionLayer,
    sources: Vec<WaveSource>,
    hands: Vec<WaveSource>,
    /// Per slot: the sources it put in at the last step (its hollow), if floating.
    own: Vec<Vec<WaveSource>>,
    centre: Vec2,
}

impl Wakes {
    pub(crate) fn new(config: InteractionConfig, centre: Vec2) -> Self {
        Self {
            layer: InteractionLayer::new(config, centre.x, centre.y),
            sources: Vec::with_capacity(MAX_BODIES * MAX_SOURCES_PER_BODY + MAX_HAND_SOURCES),
            hands: Vec::with_capacity(MAX_HAND_SOURCES),
            own: (0..MAX_BODIES)
                .map(|_| Vec::with_capacity(MAX_SOURCES_PER_BODY))
                .collect(),
            centre,
        }
    }

    /// The layer's height at `p` for the body in `slot`, less its own hollow: at most the
    /// hollow's depth there ([`WaveSource::head_at`] of the sources it put in last), and no
    /// more than the layer is actually lowered there (while the hollow forms, after an
    /// entry, the body must not be lifted by water that is not there).
    pub(crate) fn height_for(&self, slot: usize, p: [f32; 2]) -> f32 {
        let h = self.layer.height_at(p[0], p[1]);
        let cell = self.layer.config().cell_m;
        let hollow: f32 = self.own[slot]
            .iter()
            .map(|s| s.head_at(p[0], p[1], cell))
            .sum();
        h + hollow.min((-h).max(0.0))
    }

    /// One layer step after rapier's: sources for every floating body, then the hands'.
    pub(crate) fn step(&mut self, slots: &[Slot], velocities: impl Fn(&Slot) -> Vec3) {
        self.sources.clear();
        for (i, s) in slots.iter().enumerate() {
            let before: f32 = self.own[i].iter().map(|o| o.volume).sum();
            self.own[i].clear();
            if s.state != BodyState::Floating || s.submerged <= 0.0 {
                continue;
            }
            // A long body presses the water along its length: one source per beam's length
            // of it (up to three; a boat's bow and stern make their own waves), each a disc
            // of its beam. One blob of its length would be too smooth to make any wave
            // shorter than itself.
            let size = s.spec.size();
            let (long, short, axis) = if size.z >= size.x {
                (size.z, size.x, Vec3::Z)
            } else {
                (size.x, size.z, Vec3::X)
            };
            let count = ((long / short).round() as usize).clamp(1, MAX_SOURCES_PER_BODY);
            let axis = s.curr.rotation * axis;
            let full = s.spec.volume();
            // The entry: water pushed down at the body's sinking speed over its radius, in
            // proportion to the share of its volume that went under this step.
            let sinking = (-velocities(s).y).max(0.0);
            let entered = ((s.submerged - before) / full).clamp(0.0, 1.0);
            let radius = 0.5 * short;
            for k in 0..count {
                let along = ((k as f32 + 0.5) / count as f32 - 0.5) * long;
                let centre = s.curr.position + axis * along;
                let src = WaveSource {
                    x: centre.x,
                    z: centre.z,
                    radius,
                    // The displaced volume's centroid: half its mean depth under the hull.
                    depth: 0.5 * s.submerged / s.hull.area().max(1e-3),
                    volume: s.submerged / count as f32,
                    impulse: 0.5 * sinking * radius * entered,
                    foam: (sinking / FOAM_ENTRY_SPEED * entered * 4.0).min(1.0),
                };
                if src.is_valid() {
                    self.own[i].push(src);
                    self.sources.push(src);
                }
            }
        }
        self.sources.extend_from_slice(&self.hands);
        self.hands.clear();
        self.layer.recentre(self.centre.x, self.centre.y);
        self.layer.step(&self.sources);
    }
}

impl Wakes {
    /// Where the layer should be centred from the next step on (the viewer, world x, z).
    pub(crate) fn follow(&mut self, centre: Vec2) {
        self.centre = centre;
    }

    /// Adds a disturbance to the next step (dropped beyond [`MAX_HAND_SOURCES`] a step).
    pub(crate) fn disturb(&mut self, source: WaveSource) {
        if self.hands.len() < MAX_HAND_SOURCES && source.is_valid() {
            self.hands.push(source);
        }
    }

    /// A floating user's body under `head`, moving at `velocity` (m/s): see
    /// [`Floaters::wade`](crate::physics::Floaters::wade).
    pub(crate) fn wade(&mut self, head: Vec3, velocity: Vec3, surfaces: &Surfaces, g: f32) -> bool {
        let flat = Vec3::new(velocity.x, 0.0, velocity.z);
        let shoulders = head - Vec3::Y * 0.25;
        self.press(shoulders, flat, velocity, &SWIMMER, surfaces, g)
    }

    /// A hand at `input` in the water of `surfaces`: see
    /// [`Floaters::dip`](crate::physics::Floaters::dip).
    pub(crate) fn dip(&mut self, input: &HandInput, surfaces: &Surfaces, g: f32) -> bool {
        let v = input.linvel;
        self.press(input.pose.position, v, v, &HAND, surfaces, g)
    }

    /// `what` at `p` (m) presses on the water of `surfaces` when it is under it: with its
    /// volume, the dynamic pressure of `flow` (m/s) over its area, and the plunge of `velocity`
    /// (its downward part, m/s), under gravity `g` (m/s²). Returns whether it is in the water.
    fn press(
        &mut self,
        p: Vec3,
        flow: Vec3,
        velocity: Vec3,
        what: &Presser,
        surfaces: &Surfaces,
        g: f32,
    ) -> bool {
        if !p.is_finite() || !velocity.is_finite() {
            return false;
        }
        let layer = if what.reads_layer {
            self.layer.height_at(p.x, p.z)
        } else {
            0.0
        };
        let depth = surfaces.height_at(p.x, p.z) + layer - p.y;
        if depth.is_nan() || depth <= 0.0 {
            return false;
        }
        let dynamic = what.area * flow.length_squared() / (2.0 * g);
        let plunge = (-velocity.y).max(0.0);
        self.disturb(WaveSource {
            x: p.x,
            z: p.z,
            radius: what.radius,
            depth: (0.5 * depth).min(what.radius),
            volume: what.volume + dynamic,
            impulse: 0.5 * plunge * what.radius,
            foam: (plunge / FOAM_ENTRY_SPEED * what.foam).min(what.foam),
        });
        true
    }
}
