//! The views the frame loop hands from the XR backends to the LOD and the renderer: an eye's
//! field of view and pose, in OpenXR's conventions (y up, metres, radians).

use glam::{Quat, Vec3};

use super::ParamError;

/// An eye's field of view as OpenXR reports it (`XrFovf`), in radians: `angle_left` and
/// `angle_down` are usually negative. The view looks along −z with +y up and +x right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fov {
    /// Angle of the left edge (rad, negative when left of the view axis).
    pub angle_left: f32,
    /// Angle of the right edge (rad).
    pub angle_right: f32,
    /// Angle of the top edge (rad).
    pub angle_up: f32,
    /// Angle of the bottom edge (rad, negative when below the view axis).
    pub angle_down: f32,
}

impl Fov {
    /// Quest-3-like per-eye fields of view, left eye then right, as OpenXR reports them
    /// (asymmetric, the wider side outward). For views with no runtime behind them: `lod-svg`,
    /// tests and benchmarks.
    pub const QUEST_EYES: [Fov; 2] = [
        Fov {
            angle_left: -0.942,
            angle_right: 0.698,
            angle_up: 0.768,
            angle_down: -0.873,
        },
        Fov {
            angle_left: -0.698,
            angle_right: 0.942,
            angle_up: 0.768,
            angle_down: -0.873,
        },
    ];

    /// A symmetric field of view of `horizontal` × `vertical` radians.
    pub fn symmetric(horizontal: f32, vertical: f32) -> Self {
        Self {
            angle_left: -horizontal / 2.0,
            angle_right: horizontal / 2.0,
            angle_up: vertical / 2.0,
            angle_down: -vertical / 2.0,
        }
    }

    /// Checks every angle is finite and in (−π/2, π/2) and each opening (right − left,
    /// up − down) is positive, so each is in (0, π).
    pub fn validate(&self) -> Result<(), ParamError> {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let range = "an angle in (-π/2, π/2) rad";
        for (name, a) in [
            ("fov.angle_left", self.angle_left),
            ("fov.angle_right", self.angle_right),
            ("fov.angle_up", self.angle_up),
            ("fov.angle_down", self.angle_down),
        ] {
            if !(a.is_finite() && a.abs() < half_pi) {
                return Err(ParamError::new(name, a as f64, range));
            }
        }
        let h = self.angle_right - self.angle_left;
        if h <= 0.0 {
            return Err(ParamError::new(
                "fov horizontal (angle_right - angle_left)",
                h as f64,
                "an opening in (0, π) rad",
            ));
        }
        let v = self.angle_up - self.angle_down;
        if v <= 0.0 {
            return Err(ParamError::new(
                "fov vertical (angle_up - angle_down)",
                v as f64,
                "an opening in (0, π) rad",
            ));
        }
        Ok(())
    }
}

/// An eye's pose in world space (OpenXR `XrPosef`: y up, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeView {
    /// Eye position (m).
    pub position: Vec3,
    /// Eye orientation (unit quaternion; normalised on use).
    pub orientation: Quat,
    /// Field of view.
    pub fov: Fov,
}

impl EyeView {
    /// An eye at `position` turned by `yaw` about +y then `pitch` about its x axis (rad; yaw 0,
    /// pitch 0 looks along −z; positive pitch looks up).
    pub fn looking(position: Vec3, yaw: f32, pitch: f32, fov: Fov) -> Self {
        Self {
            position,
            orientation: Quat::from_rotation_y(yaw) * Quat::from_rotation_x(pitch),
            fov,
        }
    }
}
