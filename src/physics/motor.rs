//! A boat under way: `Floaters::launch_boat` puts a small boat on the water ahead of a point,
//! its bow along a heading, and a motor holds its speed through the water along its bow (a
//! force on the hull, the rest left to the water's drag), so it leaves a wake in the
//! interaction layer. Camera paths launch one (`boat T SPEED`) for reproducible wake images.

use glam::{Quat, Vec3};

use crate::physics::error::{self, PhysicsError};
use crate::physics::slot::BodyId;
use crate::physics::spawn::default_body;
use crate::physics::world::Floaters;
use crate::physics::Pose;

/// Fastest motor speed (m/s): a small boat's hull speed is a few m/s.
pub const MAX_MOTOR_SPEED: f32 = 10.0;

/// How far ahead of the point a launched boat appears (m).
pub const LAUNCH_DISTANCE: f32 = 6.0;

/// The motor closes the gap to its speed over this time (s): short, so the water's drag leaves
/// it a few percent under its speed.
const MOTOR_TIME_S: f32 = 0.05;

/// The boat of the default mix.
const BOAT: usize = 5;

impl Floaters {
    /// Puts a boat on the water [`LAUNCH_DISTANCE`] m ahead of `origin` along the horizontal
    /// part of `heading`, bow that way, its motor holding `speed` (m/s, 0 to
    /// [`MAX_MOTOR_SPEED`]). Refused like [`Floaters::spawn`] (no room, in the way) or when
    /// `heading` has no horizontal part.
    pub fn launch_boat(
        &mut self,
        origin: Vec3,
        heading: Vec3,
        speed: f32,
    ) -> Result<BodyId, PhysicsError> {
        error::check("boat speed", speed, 0.0, MAX_MOTOR_SPEED, "0 to 10 m/s")?;
        let flat = Vec3::new(heading.x, 0.0, heading.z);
        let dir = flat.try_normalize().filter(|_| origin.is_finite()).ok_or(
            PhysicsError::OutOfRange {
                what: "boat heading's horizontal length",
                value: flat.length(),
                range: "greater than 0 (not straight up or down)",
            },
        )?;
        let at = Vec3::new(origin.x, 0.0, origin.z) + dir * LAUNCH_DISTANCE;
        // The bow is the hull's −z end.
        let yaw = Quat::from_rotation_arc(Vec3::NEG_Z, dir);
        let pose = Pose {
            position: at,
            rotation: yaw,
        };
        let id = self.spawn(default_body(BOAT), pose)?;
        self.slots[id.index()].motor = Some(speed);
        Ok(id)
    }

    /// The motor's force (N, world) on the body in `slot` moving at `linvel`: towards its
    /// speed along its bow, horizontally.
    pub(crate) fn motor_force(&self, slot: usize, linvel: Vec3) -> Vec3 {
        let s = &self.slots[slot];
        let Some(speed) = s.motor else {
            return Vec3::ZERO;
        };
        let bow = s.curr.rotation * Vec3::NEG_Z;
        let Some(bow) = Vec3::new(bow.x, 0.0, bow.z).try_normalize() else {
            return Vec3::ZERO;
        };
        let along = linvel.dot(bow);
        bow * (s.mass + s.added) * (speed - along) / MOTOR_TIME_S
    }
}
