//! Which side of the surface a frame is drawn from (issue 45): above the water, below it, or,
//! where the displaced surface may cross an eye's near plane, each pixel from its own point on
//! that plane (the waterline across the eyes, decided in the shaders without a full-screen
//! copy, which is what sinks water on a tiled GPU).

use glam::Vec3;

use crate::base::EyeView;
use crate::render::camera::NEAR;
use crate::sim::query::{self, Side};
use crate::sim::surface::CascadeSurface;

/// Height (m) of what may lift the drawn surface beyond the cascades the CPU queries: the
/// interaction layer's rings and wakes (their crests stay under a decimetre), the mesh's
/// interpolation between its vertices, and the meniscus's own width. Within this of the
/// surface the near plane counts as crossed and the shaders decide per pixel.
pub const WATERLINE_MARGIN_M: f32 = 0.25;

/// The side a frame is drawn from: `Globals::underwater.x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Underwater {
    /// Both eyes' near planes are clear above the surface: the view from the air.
    Above,
    /// Both are under it: the view from the water.
    Below,
    /// The surface may cross a near plane: each pixel decides from its point there.
    PerPixel,
}

impl Underwater {
    /// The side of `eyes`' near planes (their corners and centres) on the surface of
    /// `cascades`, and how deep (m) the eyes' midpoint is under it (negative above).
    pub fn of(cascades: &[CascadeSurface], eyes: &[EyeView; 2]) -> (Self, f32) {
        let mut points = [[0.0; 3]; 10];
        for (eye, chunk) in eyes.iter().zip(points.chunks_mut(5)) {
            near_plane_points(eye, chunk);
        }
        let side = match query::side_of_all(cascades, &points, WATERLINE_MARGIN_M) {
            Some(Side::Above) => Self::Above,
            Some(Side::Below) => Self::Below,
            None => Self::PerPixel,
        };
        let mid = (eyes[0].position + eyes[1].position) * 0.5;
        (side, query::depth_at(cascades, mid.to_array()))
    }

    /// The shader's code for it (`g.underwater.x`).
    pub fn code(self) -> f32 {
        match self {
            Self::Above => 0.0,
            Self::Below => 1.0,
            Self::PerPixel => 2.0,
        }
    }
}

/// The four corners and the centre of `eye`'s near plane (world, m) into `out`.
fn near_plane_points(eye: &EyeView, out: &mut [[f32; 3]]) {
    let rot = eye.orientation.normalize();
    let (right, up, forward) = (rot * Vec3::X, rot * Vec3::Y, rot * Vec3::NEG_Z);
    let f = &eye.fov;
    let centre = eye.position + forward * NEAR;
    let corners = [
        (f.angle_left.tan(), f.angle_up.tan()),
        (f.angle_right.tan(), f.angle_up.tan()),
        (f.angle_left.tan(), f.angle_down.tan()),
        (f.angle_right.tan(), f.angle_down.tan()),
    ];
    out[0] = centre.to_array();
    for (o, (x, y)) in out[1..].iter_mut().zip(corners) {
        *o = (centre + (right * x + up * y) * NEAR).to_array();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Fov;
    use crate::sim::grid::GridSize;
    use crate::sim::surface::FloatCopies;

    fn calm() -> Vec<CascadeSurface> {
        let grid = GridSize::new(16).unwrap();
        vec![CascadeSurface::new(grid, 16.0, FloatCopies::Keep)]
    }

    fn eyes_at(y: f32, pitch: f32) -> [EyeView; 2] {
        let at = |x: f32| EyeView::looking(Vec3::new(x, y, 0.0), 0.0, pitch, Fov::QUEST_EYES[0]);
        [at(-0.032), at(0.032)]
    }

    #[test]
    fn the_side_follows_the_eyes_and_the_line_is_per_pixel() {
        let c = calm();
        assert_eq!(Underwater::of(&c, &eyes_at(1.7, 0.0)).0, Underwater::Above);
        let (below, depth) = Underwater::of(&c, &eyes_at(-4.0, 1.5));
        assert_eq!(below, Underwater::Below);
        assert!((depth - 4.0).abs() < 1e-5, "{depth}");
        assert_eq!(
            Underwater::of(&c, &eyes_at(0.0, 0.0)).0,
            Underwater::PerPixel
        );
        // 10 cm above a calm sea the near plane is within the margin: decided per pixel.
        assert_eq!(
            Underwater::of(&c, &eyes_at(0.1, 0.0)).0,
            Underwater::PerPixel
        );
    }
}
