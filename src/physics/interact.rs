//! What hands and keys do to bodies: pick the nearest, hold it to a hand, let it go with the
//! hand's velocity, throw a new one from the camera.
//!
//! A held body stays dynamic and is *velocity-driven*: every fixed step its velocity is set to
//! reach its target pose (the hand's pose times the grip offset taken at the grab) in one step,
//! capped at [`MAX_HOLD_SPEED`](crate::physics::hands::MAX_HOLD_SPEED) and
//! [`MAX_HOLD_SPIN`](crate::physics::hands::MAX_HOLD_SPIN); gravity and the water leave it alone.
//! Unlike a kinematic body it still collides as a body with mass: it pushes other bodies
//! and stops at the deck instead of passing through, and the hand's pose is only a target.

use glam::Vec3;

use crate::physics::body::BodySpec;
use crate::physics::convert::to_rapier;
use crate::physics::error::PhysicsError;
use crate::physics::hands::{HandCommand, MAX_THROW_SPEED, MAX_THROW_SPIN};
use crate::physics::slot::{BodyId, BodyState, Hold};
use crate::physics::world::Floaters;
use crate::physics::{Pose, MAX_BODIES};

/// How far in front of the origin [`Floaters::throw_from`] puts the body (m): out of the
/// camera's near plane and the user's head.
pub const THROW_SPAWN_DISTANCE: f32 = 0.7;

/// Edge of the cube that [`Floaters::throw_from`] throws (m).
pub const THROWN_CRATE_SIZE: f32 = 0.35;

/// Its density (kg/m³): floats with a good part above the water.
pub const THROWN_CRATE_DENSITY: f32 = 400.0;

impl Floaters {
    /// The live, free body nearest to `point` within `max_dist` (m), measured to its box
    /// (the body's extents in its own frame): what a hand at `point` would grab.
    pub fn nearest_body(&self, point: Vec3, max_dist: f32) -> Option<BodyId> {
        if !point.is_finite() {
            return None;
        }
        let mut best: Option<(f32, usize)> = None;
        for (i, s) in self.slots.iter().enumerate() {
            if s.state != BodyState::Floating {
                continue;
            }
            let local = s.curr.rotation.conjugate() * (point - s.curr.position);
            let outside = (local.abs() - 0.5 * s.spec.size()).max(Vec3::ZERO);
            let d = outside.length();
            if d <= max_dist && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i));
            }
        }
        best.map(|(_, i)| BodyId(i))
    }

    /// Holds `id` to a hand at `hand`: the first call takes the grip offset (the body's pose
    /// relative to the hand); later calls while held move the target with the hand. Call it
    /// every frame the grip is held.
    pub fn grab(&mut self, id: BodyId, hand: Pose) -> Result<(), PhysicsError> {
        if !hand.is_finite() {
            return Err(PhysicsError::NotFinite { what: "hand pose" });
        }
        let s = self.slot(id)?;
        let (curr, handle, held) = (s.curr, s.handle, s.hold);
        let offset = match held {
            Some(h) => h.offset,
            None => hand.inverse().mul(&curr),
        };
        let target = hand.mul(&offset);
        if held.is_none() {
            if let Some(rb) = self.world.bodies.get_mut(handle) {
                rb.set_gravity_scale(0.0, true);
            }
            self.water.forget(id.0);
        }
        let s = &mut self.slots[id.0];
        s.state = BodyState::Held;
        s.hold = Some(Hold { offset, target });
        Ok(())
    }

    /// Applies what a [`Hand`](crate::physics::Hand) asked for.
    pub fn apply(&mut self, command: &HandCommand) -> Result<(), PhysicsError> {
        match *command {
            HandCommand::Grab { body, hand } => self.grab(body, hand),
            HandCommand::Release {
                body,
                linvel,
                angvel,
            } => self.release(body, linvel, angvel),
        }
    }

    /// Lets a held (or free) body go with velocities `linvel` (m/s) and `angvel` (rad/s),
    /// capped at [`MAX_THROW_SPEED`] and [`MAX_THROW_SPIN`]. Non-finite velocities are refused
    /// and the body stays held.
    pub fn release(&mut self, id: BodyId, linvel: Vec3, angvel: Vec3) -> Result<(), PhysicsError> {
        if !linvel.is_finite() || !angvel.is_finite() {
            return Err(PhysicsError::NotFinite {
                what: "release velocity",
            });
        }
        let s = self.slot(id)?;
        let (handle, mass, added) = (s.handle, s.mass, s.added);
        if let Some(rb) = self.world.bodies.get_mut(handle) {
            rb.set_gravity_scale(mass / (mass + added), true);
            rb.set_linvel(to_rapier(linvel.clamp_length_max(MAX_THROW_SPEED)), true);
            rb.set_angvel(to_rapier(angvel.clamp_length_max(MAX_THROW_SPIN)), true);
        }
        let s = &mut self.slots[id.0];
        s.state = BodyState::Floating;
        s.hold = None;
        self.water.forget(id.0);
        Ok(())
    }

    /// Throws a small crate from `origin` along `direction` at `speed` (m/s, 0 to
    /// [`MAX_THROW_SPEED`]): the window's throw key. It appears [`THROW_SPAWN_DISTANCE`] in
    /// front of `origin`, in a sunk body's slot, else a new one, else the slot of the body
    /// thrown longest ago (or, when none was thrown, of the free body farthest from `origin`).
    pub fn throw_from(
        &mut self,
        origin: Vec3,
        direction: Vec3,
        speed: f32,
    ) -> Result<BodyId, PhysicsError> {
        if !origin.is_finite() || !direction.is_finite() {
            return Err(PhysicsError::NotFinite {
                what: "throw origin or direction",
            });
        }
        let dir = direction.try_normalize().ok_or(PhysicsError::OutOfRange {
            what: "throw direction length",
            value: direction.length(),
            range: "greater than 0",
        })?;
        crate::physics::error::check("throw speed", speed, 0.0, MAX_THROW_SPEED, "0 to 30 m/s")?;
        let spec = BodySpec::crate_box(Vec3::splat(THROWN_CRATE_SIZE), THROWN_CRATE_DENSITY)?;
        let pose = Pose::at(origin + dir * THROW_SPAWN_DISTANCE);
        let slot = self.throw_slot(origin)?;
        self.check_placement(&spec, &pose, Some(slot))?;
        self.place(slot, spec, pose);
        self.throws += 1;
        self.slots[slot].thrown = self.throws;
        let id = BodyId(slot);
        self.release(id, dir * speed, Vec3::new(1.0, 0.0, 0.5))?;
        Ok(id)
    }

    /// The slot [`Floaters::throw_from`] uses (the length of `slots` for a new one).
    fn throw_slot(&self, origin: Vec3) -> Result<usize, PhysicsError> {
        let live = |i: &usize| self.slots[*i].state == BodyState::Floating;
        if let Some(i) = self.slots.iter().position(|s| s.state == BodyState::Sunk) {
            return Ok(i);
        }
        if self.slots.len() < MAX_BODIES {
            return Ok(self.slots.len());
        }
        let thrown = (0..self.slots.len())
            .filter(live)
            .filter(|&i| self.slots[i].thrown > 0)
            .min_by_key(|&i| self.slots[i].thrown);
        thrown
            .or_else(|| {
                (0..self.slots.len()).filter(live).max_by(|&a, &b| {
                    let d = |i: usize| self.slots[i].curr.position.distance_squared(origin);
                    d(a).total_cmp(&d(b))
                })
            })
            .ok_or(PhysicsError::TooManyBodies {
                requested: MAX_BODIES + 1,
                limit: MAX_BODIES,
            })
    }
}
