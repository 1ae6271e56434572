//! The edge between our glam (0.34) and rapier's (glam 0.33, through glamx): component copies.

use glam::{Quat, Vec3};
use rapier3d::math::{Pose as RPose, Rotation, Vector};

use crate::physics::Pose;

/// Our vector as rapier's.
#[inline]
pub(crate) fn to_rapier(v: Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// Rapier's vector as ours.
#[inline]
pub(crate) fn from_rapier(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// Rapier's rotation as ours.
#[inline]
pub(crate) fn quat_from_rapier(q: Rotation) -> Quat {
    Quat::from_xyzw(q.x, q.y, q.z, q.w)
}

/// Our pose as rapier's.
#[inline]
pub(crate) fn pose_to_rapier(p: &Pose) -> RPose {
    let q = p.rotation;
    RPose::from_parts(
        to_rapier(p.position),
        Rotation::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// Rapier's pose as ours.
#[inline]
pub(crate) fn pose_from_rapier(p: &RPose) -> Pose {
    Pose {
        position: from_rapier(p.translation),
        rotation: quat_from_rapier(p.rotation),
    }
}
