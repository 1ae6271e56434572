//! Per-eye matrices and the per-frame uniform block the shaders read (`shaders/common.glsl`).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

use crate::base::{EyeView, Fov};

/// Near plane (m), the same the LOD's frusta use.
pub const NEAR: f32 = crate::lod::frustum::NEAR_PLANE;

/// Vulkan projection for an asymmetric OpenXR-style field of view, with reversed Z and an
/// infinite far plane: depth = near / distance, so 1 at the near plane and → 0 at the horizon.
/// Reversed Z with a float depth buffer keeps precision where an ocean needs it, from the
/// user's feet to tens of kilometres. Clip y points down (Vulkan).
pub fn projection(fov: &Fov, near: f32) -> Mat4 {
    let (l, r) = (fov.angle_left.tan(), fov.angle_right.tan());
    let (u, d) = (fov.angle_up.tan(), fov.angle_down.tan());
    let (w, h) = (r - l, u - d);
    Mat4::from_cols(
        Vec4::new(2.0 / w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -2.0 / h, 0.0, 0.0),
        Vec4::new((r + l) / w, -(u + d) / h, 0.0, -1.0),
        Vec4::new(0.0, 0.0, near, 0.0),
    )
}

/// World → view transform of an eye (view space: x right, y up, looking down −z).
pub fn view(eye: &EyeView) -> Mat4 {
    Mat4::from_rotation_translation(eye.orientation, eye.position).inverse()
}

/// The uniform block, std140, mirrored by `Globals` in `shaders/common.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Globals {
    /// Projection × view per eye.
    pub view_proj: [[f32; 16]; 2],
    /// Inverse of projection × view rotation per eye: clip → world direction for the sky.
    pub sky_from_clip: [[f32; 16]; 2],
    /// Eye positions (xyz, w unused).
    pub eye_pos: [[f32; 4]; 2],
    /// The LOD viewer (xyz) and the simulation time (w).
    pub lod_viewer: [f32; 4],
    /// Unit direction towards the sun (xyz) and the sea's significant wave height (w, m).
    pub sun: [f32; 4],
    /// Patch size L of cascades 0..3 (m).
    pub patch_size: [f32; 4],
    /// Distance where each cascade's displacement starts to fade (m).
    pub fade_start: [f32; 4],
    /// Distance where it is gone (m).
    pub fade_end: [f32; 4],
    /// Cascade count, grid N, 1 / fog distance (1/m), sky marker flag.
    pub params: [f32; 4],
    /// Specular anti-aliasing: slope variance of the unresolved waves, on (1) or off (0), the
    /// Toksvig variance of level-0 normals (the material's, not filtering), and the GGX α² of
    /// level-0 smoothness.
    pub specular_aa: [f32; 4],
    /// Per whitecap level ([`crate::sim::whitecaps`]): the window's centre x, z (m), the
    /// lattice spacing (m) and the level's mean coverage (negative: whitecaps off).
    pub whitecaps: [[f32; 4]; 2],
    /// The sun disc's radiance (rgb, kcd/m²) and the cosine of its angular radius (w).
    pub sun_radiance: [f32; 4],
    /// Sun illuminance at normal incidence (rgb, klux) and the exposure (w: kcd/m² to the
    /// tonemapper's input).
    pub sun_illuminance: [f32; 4],
    /// The sky dome's illuminance on a horizontal surface (rgb, klux) and the environment map's
    /// level count (w).
    pub sky_illuminance: [f32; 4],
    /// 1 / patch size of cascades 0..3 (1/m): the shaders multiply where they would divide.
    pub inv_patch_size: [f32; 4],
    /// log2 of each cascade's patch over the finest's: its mip level below the finest's.
    pub lod_offset: [f32; 4],
    /// 1 / each whitecap level's side (x, y; 1/m), half a cascade texel (z: 0.5 / N), and
    /// 1 / the crest height light shines through (w; 1/m).
    pub derived: [f32; 4],
    /// The radiance of a white Lambertian surface facing up (rgb, kcd/m²): the horizontal
    /// illuminance of the sun and the sky over π.
    pub diffuse: [f32; 4],
    /// The interaction layer ([`crate::sim::interaction`]): world x, z of its cell (0, 0)
    /// (m), 1 / its side (1/m) and half a cell in texture units (w; negative: no layer).
    pub interaction: [f32; 4],
    /// The distances (m) where the layer's displacement of the mesh starts and ends fading
    /// (x, y), as a cascade's (its waves would alias on the coarser mesh beyond).
    pub interaction_fade: [f32; 4],
    /// Foam streaks: the unit direction (x, z) the wind blows toward, and 1 / the foam
    /// pattern's stretch along it (z; 1: round cells, no streaks); w: 1 = foam lit on its
    /// normal (0: as level foam, for comparisons).
    pub foam_streak: [f32; 4],
    /// Detail slopes ([`crate::sim::detail`], in the foam pattern's G and B): 1 / the tile's
    /// side (x; 1/m), the decoded slope per unit of code (y: the range times the unresolved
    /// slope deviation; 0: off), and the detail's mip level less the finest cascade's (z).
    pub detail: [f32; 4],
    /// How far (x, z) (m) the surface's mean drift has carried the foam
    /// ([`crate::sim::whitecaps::Whitecaps::drift`]): the whitecap lattices, the foam pattern
    /// and the bubbles are drawn at rest position − this; z, w unused.
    pub foam_drift: [f32; 4],
    /// Filtering: the most taps the normal maps' anisotropic sampler takes now (x; 1: the
    /// trilinear sampler is read, [`crate::render::ocean::Anisotropy`]); y: 1 = the specular
    /// AA also supersamples the minified highlight
    /// ([`crate::render::ocean::RendererSettings::supersampling`]); z, w unused.
    pub filtering: [f32; 4],
    /// The sun's disc as the display shows it (rgb: its radiance exposed and through the tone
    /// curve, `ocean::sky_map::displayed`): the sky's pixels mix it over the map's display
    /// layer by the disc's coverage.
    pub sun_display: [f32; 4],
    /// Per eye, for the waterline (issue 45): the unit direction the eye looks along (xyz)
    /// and the near plane's distance (w, m): a pixel's point on the near plane is the eye plus
    /// its ray scaled to that depth.
    pub waterline: [[f32; 4]; 2],
    /// Under the surface: x the side the view is drawn from (0 above the water, 1 below, 2
    /// the surface may cross the near plane: each pixel decides from its own point there,
    /// [`crate::render::ocean::Underwater`]); y how deep (m) the eyes are under the surface
    /// (negative above it; the light in the water fades with it); z, w unused.
    pub underwater: [f32; 4],
    /// The comfort vignette's strength (x, 0 none to 1 narrowest; drawn only when above 0,
    /// [`crate::render::ocean::vignette`]); y, z, w unused.
    pub vignette: [f32; 4],
    /// The mesh's collapse by its thickness on the screen ([`crate::lod::ScreenCollapse`],
    /// its [`uniform`](crate::lod::ScreenCollapse::uniform)).
    pub lod_screen: [f32; 4],
}

impl Globals {
    /// Fills the per-eye part from the two views.
    pub fn set_eyes(&mut self, eyes: &[EyeView; 2]) {
        for (i, eye) in eyes.iter().enumerate() {
            let p = projection(&eye.fov, NEAR);
            self.view_proj[i] = (p * view(eye)).to_cols_array();
            let rot = Mat4::from_quat(eye.orientation.inverse());
            self.sky_from_clip[i] = (p * rot).inverse().to_cols_array();
            self.eye_pos[i] = eye.position.extend(1.0).to_array();
            self.waterline[i] = (eye.orientation * Vec3::NEG_Z).extend(NEAR).to_array();
        }
    }
}

/// Where world point `p` lands in an eye's image: pixel coordinates (x right, y down) for an
/// image of `width` × `height`, or `None` behind the eye. Tests use it to find the horizon and
/// the expected parallax.
pub fn project_to_pixel(eye: &EyeView, p: Vec3, width: u32, height: u32) -> Option<(f32, f32)> {
    let c = projection(&eye.fov, NEAR) * view(eye) * p.extend(1.0);
    (c.w > 0.0).then(|| {
        let (x, y) = (c.x / c.w, c.y / c.w);
        (
            (x * 0.5 + 0.5) * width as f32,
            (y * 0.5 + 0.5) * height as f32,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn projection_maps_fov_edges_to_ndc_edges_with_reversed_depth() {
        let fov = Fov::QUEST_EYES[0];
        let p = projection(&fov, 0.05);
        let at = |x: f32, y: f32, z: f32| {
            let c = p * Vec4::new(x, y, z, 1.0);
            c.truncate() / c.w
        };
        // A point on the left edge of the field of view at 10 m.
        let l = at(10.0 * fov.angle_left.tan(), 0.0, -10.0);
        assert!((l.x + 1.0).abs() < 1e-5, "{l}");
        let u = at(0.0, 10.0 * fov.angle_up.tan(), -10.0);
        assert!((u.y + 1.0).abs() < 1e-5, "up is ndc y = -1 in Vulkan: {u}");
        assert!((at(0.0, 0.0, -0.05).z - 1.0).abs() < 1e-6);
        assert!((at(0.0, 0.0, -100.0).z - 0.0005).abs() < 1e-7);
    }

    #[test]
    fn sky_matrix_turns_clip_positions_into_view_directions() {
        let eye = EyeView {
            position: Vec3::new(5.0, 2.0, -3.0),
            orientation: Quat::from_rotation_y(0.7),
            fov: Fov::QUEST_EYES[1],
        };
        let mut g = Globals::zeroed();
        g.set_eyes(&[eye, eye]);
        let m = Mat4::from_cols_array(&g.sky_from_clip[0]);
        // Pick a world direction, project it, and map the pixel back.
        let dir = Vec3::new(0.3, 0.1, -1.0).normalize();
        let world_dir = eye.orientation * dir;
        let c = projection(&eye.fov, NEAR) * Vec4::new(dir.x, dir.y, dir.z, 1.0);
        let back = m * Vec4::new(c.x / c.w, c.y / c.w, 1.0, 1.0);
        let back = (back.truncate() / back.w).normalize();
        assert!(back.distance(world_dir) < 1e-4, "{back} vs {world_dir}");
    }
}
