//! Stereo frustum culling: the union of the two eye frusta, with the positive-vertex AABB test
//! of eq. 59-60 on boxes padded by the simulation's real maximum displacement (eq. 61).
//!
//! Conservative: a patch is drawn when its box (footprint + β × the simulation's real max |Dx|,
//! |h|, |Dz|) passes all planes of either eye; no patch a brute-force point test says an eye
//! sees is ever dropped (tested). Culling filters leaves only; stitch flags come from the full
//! tree, so culled neighbours never change what is drawn.

use glam::{Vec3, Vec4};

use crate::base::{EyeView, Fov, ParamError};

/// Near-plane distance (m) of the culling frusta. The far plane is at infinity (the usual VR
/// infinite reverse-Z projection), so five of eq. 60's six planes are tested.
pub const NEAR_PLANE: f32 = 0.05;

fn validate_position(name: &'static str, p: Vec3) -> Result<(), ParamError> {
    for c in p.to_array() {
        if !(c.is_finite() && c.abs() <= MAX_COORDINATE) {
            return Err(ParamError::new(
                name,
                c as f64,
                "finite coordinates within ±1e7 m",
            ));
        }
    }
    Ok(())
}

/// Largest accepted camera coordinate (m); beyond it f32 cannot place a vertex to a centimetre.
pub const MAX_COORDINATE: f32 = 1.0e7;

/// Checks a viewer position: finite, within ±[`MAX_COORDINATE`].
pub fn validate_viewer(p: Vec3) -> Result<(), ParamError> {
    validate_position("camera position", p)
}

/// One eye's culling volume: five inward planes (n, d) with n·x + d ≥ 0 inside (eq. 60).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    planes: [Vec4; 5],
}

impl Frustum {
    /// The frustum of `eye` (validated) with near plane [`NEAR_PLANE`].
    pub fn new(eye: &EyeView) -> Result<Self, ParamError> {
        eye.fov.validate()?;
        validate_position("eye position", eye.position)?;
        let q = eye.orientation;
        let len = q.length();
        if !(len.is_finite() && len > 1e-6) {
            return Err(ParamError::new(
                "eye orientation",
                len as f64,
                "a finite non-zero quaternion",
            ));
        }
        let q = q / len;
        let f = eye.fov;
        let (tl, tr, tu, td) = (
            f.angle_left.tan(),
            f.angle_right.tan(),
            f.angle_up.tan(),
            f.angle_down.tan(),
        );
        // View space (looking along −z): inside means x ≥ tl·(−z), x ≤ tr·(−z), y ≤ tu·(−z),
        // y ≥ td·(−z), −z ≥ near.
        let view = [
            (Vec3::new(1.0, 0.0, tl), 0.0),
            (Vec3::new(-1.0, 0.0, -tr), 0.0),
            (Vec3::new(0.0, -1.0, -tu), 0.0),
            (Vec3::new(0.0, 1.0, td), 0.0),
            (Vec3::new(0.0, 0.0, -1.0), -NEAR_PLANE),
        ];
        // n_v·x_v + d_v with x_v = q⁻¹(x − p) is (q·n_v)·x + d_v − (q·n_v)·p in world space.
        let planes = view.map(|(n, d): (Vec3, f32)| {
            let len = n.length();
            let n = q * (n / len);
            n.extend(d / len - n.dot(eye.position))
        });
        Ok(Self { planes })
    }

    /// The five planes (xyz = inward unit normal, w = d).
    pub fn planes(&self) -> &[Vec4; 5] {
        &self.planes
    }

    /// Eq. 59-60: the box (centre `c`, half-extents `e`) is kept unless it lies wholly outside one
    /// plane, tested at its positive vertex. Conservative: may keep a box that is just outside
    /// near an edge of the frustum, never drops one that intersects it.
    #[inline]
    pub fn intersects_aabb(&self, c: Vec3, e: Vec3) -> bool {
        self.planes.iter().all(|p| {
            let n = p.truncate();
            // n · (c + select(−e, e, n ≥ 0)) + d = n·c + |n|·e + d.
            n.dot(c) + n.abs().dot(e) + p.w >= 0.0
        })
    }
}

/// The two eyes of one frame: patches are kept when either eye's frustum may see them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StereoFrustum {
    eyes: [EyeView; 2],
    frusta: [Frustum; 2],
}

impl StereoFrustum {
    /// Validates both eyes (FOV angles, positions, orientations) and builds their frusta.
    pub fn new(left: EyeView, right: EyeView) -> Result<Self, ParamError> {
        Ok(Self {
            frusta: [Frustum::new(&left)?, Frustum::new(&right)?],
            eyes: [left, right],
        })
    }

    /// Both eyes of a head at `head` looking along `yaw`/`pitch` (rad, as
    /// [`EyeView::looking`]), `ipd` metres apart, with per-eye `fovs` (left, right).
    pub fn from_head(
        head: Vec3,
        yaw: f32,
        pitch: f32,
        ipd: f32,
        fovs: [Fov; 2],
    ) -> Result<Self, ParamError> {
        let right = Vec3::new(yaw.cos(), 0.0, -yaw.sin()) * (ipd / 2.0);
        Self::new(
            EyeView::looking(head - right, yaw, pitch, fovs[0]),
            EyeView::looking(head + right, yaw, pitch, fovs[1]),
        )
    }

    /// The eyes, left then right.
    pub fn eyes(&self) -> &[EyeView; 2] {
        &self.eyes
    }

    /// The frusta, left then right.
    pub fn frusta(&self) -> &[Frustum; 2] {
        &self.frusta
    }

    /// The point between the eyes: the viewer the LOD distances are measured from.
    pub fn centre(&self) -> Vec3 {
        (self.eyes[0].position + self.eyes[1].position) * 0.5
    }

    /// Union culling: the box is kept when it passes all planes of either eye.
    #[inline]
    pub fn intersects_aabb(&self, c: Vec3, e: Vec3) -> bool {
        self.frusta[0].intersects_aabb(c, e) || self.frusta[1].intersects_aabb(c, e)
    }
}

/// The simulation's maximum displacement (max |Dx|, max |h|, max |Dz|, metres), as
/// [`crate::sim::Surfaces::max_displacement`] returns it: the padding of every patch's box.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaxDisplacement([f32; 3]);

impl MaxDisplacement {
    /// Validates: each component finite and in [0, 1000] m.
    pub fn new(d: [f32; 3]) -> Result<Self, ParamError> {
        for c in d {
            if !(c.is_finite() && (0.0..=1000.0).contains(&c)) {
                return Err(ParamError::new(
                    "max displacement",
                    c as f64,
                    "finite components in [0, 1000] (m)",
                ));
            }
        }
        Ok(Self(d))
    }

    /// (max |Dx|, max |h|, max |Dz|) in metres.
    pub fn get(self) -> [f32; 3] {
        self.0
    }
}

/// The culling box of a patch of size `s` centred at (cx, 0, cz) (eq. 61 with the real
/// displacement): half-extents (s/2 + β·max|Dx|, β·max|h|, s/2 + β·max|Dz|).
///
/// Eq. 61 widens the patch itself by β (s·β/2) because its h_max = 0.03·S is a guess. Here the
/// padding is the simulation's measured maximum displacement, so the patch is not widened and β
/// is the safety margin on that maximum instead (it covers a sea state that grows between the
/// measured step and the drawn frame). The thesis's h_max/2 vertical extent is replaced by the
/// ±max|h| the surface actually spans.
pub fn patch_box(centre_xz: [f32; 2], size: f32, beta: f32, pad: MaxDisplacement) -> (Vec3, Vec3) {
    let [dx, h, dz] = pad.get();
    let half = size * 0.5;
    (
        Vec3::new(centre_xz[0], 0.0, centre_xz[1]),
        Vec3::new(half + beta * dx, beta * h, half + beta * dz),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_fov_is_named() {
        let ok = Fov::symmetric(1.6, 1.6);
        assert!(ok.validate().is_ok());
        let e = Fov::symmetric(0.0, 1.0).validate().unwrap_err();
        assert!(e.parameter.contains("horizontal"));
        let e = Fov::symmetric(1.0, -1.0).validate().unwrap_err();
        assert!(e.parameter.contains("angle_up"));
        let e = Fov::symmetric(std::f32::consts::PI, 1.0)
            .validate()
            .unwrap_err();
        assert!(e.parameter.contains("angle_left"));
        let mut f = ok;
        f.angle_up = f32::NAN;
        assert_eq!(f.validate().unwrap_err().parameter, "fov.angle_up");
    }

    #[test]
    fn boxes_in_front_are_kept_behind_are_culled() {
        let eye = EyeView::looking(Vec3::new(0.0, 2.0, 0.0), 0.0, 0.0, Fov::symmetric(1.5, 1.5));
        let f = Frustum::new(&eye).unwrap();
        assert!(f.intersects_aabb(Vec3::new(0.0, 0.0, -20.0), Vec3::splat(1.0)));
        assert!(!f.intersects_aabb(Vec3::new(0.0, 0.0, 20.0), Vec3::splat(1.0)));
        assert!(!f.intersects_aabb(Vec3::new(-200.0, 0.0, -20.0), Vec3::splat(1.0)));
        assert!(!f.intersects_aabb(Vec3::new(0.0, 50.0, -20.0), Vec3::splat(1.0)));
    }
}
