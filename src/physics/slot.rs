//! A body's slot in the world and the ids that name it: the vocabulary the world, the hands,
//! the wakes and the throws share (a leaf of the physics room: it names no other part of it
//! but the body's shape).

use glam::Vec2;
use rapier3d::prelude::RigidBodyHandle;

use crate::physics::body::{BodySpec, Hull};
use crate::physics::Pose;

/// A body of a [`Floaters`](crate::physics::Floaters) world: its slot, stable while it lives (a sunk body's slot may be
/// reused by [`Floaters::throw_from`](crate::physics::Floaters::throw_from)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub(crate) usize);

impl BodyId {
    /// The slot index (0..[`MAX_BODIES`](crate::physics::MAX_BODIES)).
    pub fn index(self) -> usize {
        self.0
    }
}

/// What a body is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyState {
    /// Free: gravity, water and contacts move it.
    Floating,
    /// Following a hand ([`Floaters::grab`](crate::physics::Floaters::grab)).
    Held,
    /// Sank below the floor: out of the simulation, not drawn.
    Sunk,
}

/// A hand's hold on a body: the body's pose relative to the hand and where it should be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hold {
    pub(crate) offset: Pose,
    pub(crate) target: Pose,
}

/// One body's slot.
pub(crate) struct Slot {
    pub(crate) spec: BodySpec,
    pub(crate) hull: Hull,
    pub(crate) handle: RigidBodyHandle,
    pub(crate) state: BodyState,
    pub(crate) prev: Pose,
    pub(crate) curr: Pose,
    pub(crate) flow: Vec2,
    /// Real mass (kg) and the added mass riding with it (kg).
    pub(crate) mass: f32,
    pub(crate) added: f32,
    /// Largest inverse principal moment of inertia (1/(kg·m²)).
    pub(crate) inv_inertia: f32,
    pub(crate) hold: Option<Hold>,
    pub(crate) submerged: f32,
    /// Where this step's samples of this body start.
    pub(crate) first_sample: usize,
    /// When it was last thrown ([`Floaters::throw_from`](crate::physics::Floaters::throw_from) reuses the oldest).
    pub(crate) thrown: u64,
    /// The speed its motor holds along its bow (m/s), for a launched boat.
    pub(crate) motor: Option<f32>,
}
