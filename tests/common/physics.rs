//! Floating-body worlds the physics tests share.

use glam::Vec2;
use vr_ocean::physics::{BodyCount, BodyId, Floaters, PhysicsConfig, MAX_BODIES};
use vr_ocean::sim::Surfaces;

/// The default world (deck included) with [`MAX_BODIES`] bodies spawned around the origin on
/// `surfaces`, and their ids.
pub fn full_world(surfaces: &Surfaces) -> (Floaters, Vec<BodyId>) {
    let mut world = Floaters::new(PhysicsConfig::default()).unwrap();
    let ids = world
        .spawn_around(BodyCount::new(MAX_BODIES).unwrap(), Vec2::ZERO, surfaces)
        .unwrap();
    (world, ids)
}
