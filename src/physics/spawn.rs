//! `--bodies N`: how many, which, and where around the viewer.

use glam::{Quat, Vec2, Vec3};

use crate::physics::body::BodySpec;
use crate::physics::error::PhysicsError;
use crate::physics::kind::BodyKind;
use crate::physics::slot::{BodyId, BodyState};
use crate::physics::world::Floaters;
use crate::physics::{Pose, MAX_BODIES};
use crate::sim::Surfaces;

/// How many bodies to spawn: 0 to [`MAX_BODIES`] by construction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct BodyCount(usize);

impl BodyCount {
    /// The bodies a session floats unless told otherwise (`--bodies`, the headset app): one
    /// of each of [`default_body`]'s mix.
    pub const DEFAULT: BodyCount = BodyCount(8);

    /// `n` bodies, or [`PhysicsError::TooManyBodies`] (which names `--bodies`) above
    /// [`MAX_BODIES`].
    pub fn new(n: usize) -> Result<Self, PhysicsError> {
        if n > MAX_BODIES {
            return Err(PhysicsError::TooManyBodies {
                requested: n,
                limit: MAX_BODIES,
            });
        }
        Ok(Self(n))
    }

    /// The count.
    pub const fn get(self) -> usize {
        self.0
    }
}

/// Free water between the deck's edge and the first ring of bodies (m).
pub const DECK_CLEARANCE: f32 = 1.5;

/// Spacing of the spawn spiral (m): about one body per this squared of water.
pub const SPAWN_SPACING: f32 = 3.0;

/// Spiral positions tried before a body is declared impossible to place.
const MAX_TRIES: usize = 4096;

/// The `i`-th body of the default mix: per eight, three buoys, four crates of three sizes
/// and densities, one boat. All lighter than water.
pub fn default_body(i: usize) -> BodySpec {
    let (kind, size, density) = match i % 8 {
        0 | 3 | 7 => (BodyKind::Buoy, Vec3::new(0.6, 0.8, 0.6), 300.0),
        1 | 6 => (BodyKind::Crate, Vec3::new(0.6, 0.45, 0.6), 450.0),
        2 => (BodyKind::Crate, Vec3::new(0.8, 0.5, 1.0), 300.0),
        4 => (BodyKind::Crate, Vec3::new(0.4, 0.4, 0.4), 600.0),
        _ => (BodyKind::Boat, Vec3::new(1.4, 0.5, 3.0), 250.0),
    };
    // Every value above is in range.
    BodySpec::new(kind, size, density).unwrap_or_else(|_| unreachable!("in range"))
}

impl Floaters {
    /// Spawns `count` bodies of the [`default_body`] mix on a sunflower spiral around
    /// `centre` (x, z) (m), outside the deck, each floating at its own draft on the water of
    /// `surfaces`. Fails before spawning any if they would not fit in the world or `centre`
    /// is not finite; fails at the first body no free spot is found for (keeping those
    /// before it).
    pub fn spawn_around(
        &mut self,
        count: BodyCount,
        centre: Vec2,
        surfaces: &Surfaces,
    ) -> Result<Vec<BodyId>, PhysicsError> {
        if !centre.is_finite() {
            return Err(PhysicsError::NotFinite {
                what: "spawn centre",
            });
        }
        let free = MAX_BODIES - self.live();
        if count.get() > free {
            return Err(PhysicsError::TooManyBodies {
                requested: self.live() + count.get(),
                limit: MAX_BODIES,
            });
        }
        let inner = self.deck().map_or(0.0, |d| {
            let offset = Vec2::from(d.centre).distance(centre);
            offset + 0.5 * Vec2::from(d.size).length()
        }) + DECK_CLEARANCE;
        let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
        let mut ids = Vec::with_capacity(count.get());
        let mut k = 0usize;
        for i in 0..count.get() {
            let spec = default_body(i);
            let mut last = None;
            loop {
                if k >= MAX_TRIES {
                    let err = last.unwrap_or(PhysicsError::CannotPlace {
                        kind: spec.kind(),
                        position: [centre.x, 0.0, centre.y],
                        reason: "no free water found around the viewer: ask for fewer --bodies",
                    });
                    return Err(err);
                }
                let r = inner + spec.bounding_radius() + SPAWN_SPACING * (k as f32 * 0.5).sqrt();
                let a = k as f32 * golden;
                k += 1;
                let xz = centre + r * Vec2::new(a.cos(), a.sin());
                let water = surfaces.height_at(xz.x, xz.y);
                let afloat = (spec.density() / self.config().water_density).min(1.0);
                let y = water + spec.size().y * (0.5 - afloat);
                let pose = Pose {
                    position: Vec3::new(xz.x, y, xz.y),
                    rotation: Quat::from_rotation_y(2.4 * i as f32),
                };
                match self.spawn(spec, pose) {
                    Ok(id) => {
                        ids.push(id);
                        break;
                    }
                    Err(e @ PhysicsError::CannotPlace { .. }) => last = Some(e),
                    Err(e) => return Err(e),
                }
            }
        }
        Ok(ids)
    }

    /// Puts every free body farther than `radius` (m, horizontally) from `centre` back on the
    /// water of `surfaces`, at rest and at its draft, at the same bearing a third of `radius`
    /// out (turned a little further when that spot is taken). Over a long session the sea's
    /// drift and the user's throws would otherwise carry them all out of sight. Returns how
    /// many moved. Allocates only when one does (rapier's new body), never in steady state.
    pub fn bring_back(&mut self, centre: Vec2, radius: f32, surfaces: &Surfaces) -> usize {
        let mut moved = 0;
        for slot in 0..self.slots.len() {
            let s = &self.slots[slot];
            let offset = Vec2::new(s.curr.position.x, s.curr.position.z) - centre;
            if s.state != BodyState::Floating || offset.length() <= radius || !offset.is_finite() {
                continue;
            }
            let spec = s.spec;
            let bearing = offset.y.atan2(offset.x);
            let afloat = (spec.density() / self.config().water_density).min(1.0);
            for k in 0..8 {
                let a = bearing + 0.2 * k as f32;
                let xz = centre + radius / 3.0 * Vec2::new(a.cos(), a.sin());
                let water = surfaces.height_at(xz.x, xz.y);
                let pose = Pose {
                    position: Vec3::new(xz.x, water + spec.size().y * (0.5 - afloat), xz.y),
                    rotation: Quat::from_rotation_y(a),
                };
                if self.check_placement(&spec, &pose, Some(slot)).is_ok() {
                    self.place(slot, spec, pose);
                    moved += 1;
                    break;
                }
            }
        }
        moved
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_limit_is_named() {
        assert_eq!(BodyCount::new(64).unwrap().get(), 64);
        let e = BodyCount::new(65).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--bodies 65: at most 64 floating bodies (0 = none)"
        );
    }

    #[test]
    fn the_mix_has_every_kind() {
        let kinds: Vec<BodyKind> = (0..8).map(|i| default_body(i).kind()).collect();
        for k in [BodyKind::Buoy, BodyKind::Crate, BodyKind::Boat] {
            assert!(kinds.contains(&k));
        }
    }
}
