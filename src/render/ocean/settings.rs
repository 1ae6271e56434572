//! The ocean renderer's settings ([`RendererSettings`]): what is fixed when it is made and what
//! can be switched from frame to frame, with the defaults the desktop starts from.

use glam::Vec3;

use super::anisotropy::Anisotropy;
use crate::render::render_pass::{Msaa, StereoMode};
use crate::render::sky::SunSky;
use crate::sim::interaction::InteractionLayer;
use crate::sim::GridSize;

/// Wind (m/s) from which foam is drawn out along the wind: Beaufort 6's top (12 m/s); the
/// scale's force 7 (14 m/s) is where "foam begins to be blown in streaks".
pub const STREAKS_FROM: f32 = 12.0;

/// Wind (m/s) at which the streaks are longest: a gale (Beaufort 8-9, "well-marked streaks").
pub const STREAKS_FULL: f32 = 22.0;

/// How much longer than wide the foam pattern's cells are drawn along the wind at
/// [`STREAKS_FULL`].
pub const MAX_STREAK_STRETCH: f32 = 4.0;

/// The foam pattern's stretch along a wind of `wind` m/s: 1 (round cells) up to
/// [`STREAKS_FROM`], rising linearly to [`MAX_STREAK_STRETCH`] at [`STREAKS_FULL`].
pub fn foam_streak_stretch(wind: f32) -> f32 {
    let t = ((wind - STREAKS_FROM) / (STREAKS_FULL - STREAKS_FROM)).clamp(0.0, 1.0);
    1.0 + (MAX_STREAK_STRETCH - 1.0) * t
}

/// Renderer settings fixed at creation (the specular AA can be switched later).
#[derive(Clone, Copy, Debug)]
pub struct RendererSettings {
    /// Multiview or the two-pass fallback.
    pub stereo: StereoMode,
    /// Samples per pixel (edges anti-aliased by the resolve).
    pub msaa: Msaa,
    /// Specular anti-aliasing: the slope variance a pixel cannot show (unresolved waves,
    /// filtered normal maps, sub-pixel normal variation) widens the sun's highlight instead of
    /// sparkling. Switchable at run time ([`super::OceanRenderer::set_specular_aa`]).
    pub specular_aa: bool,
    /// The specular AA also supersamples the highlight where the finest cascade is minified
    /// (four shading positions per pixel, 1.2-1.5x the pass): a quality option for a device
    /// with headroom (the desktop). Off on the headsets, where the filtered lobe with the
    /// normal maps' anisotropic filtering meets the aliasing gate alone (issue 43,
    /// `tests/render/aliasing.rs`). Switchable at run time
    /// ([`super::OceanRenderer::set_supersampling`]; the GPU-time governor's first step).
    pub supersampling: bool,
    /// Anisotropic filtering of the cascades' normal maps where the device has it
    /// ([`Anisotropy`]; at most its `maxSamplerAnisotropy`). Off by default (a CPU device,
    /// lavapipe, filters every tap in software); the apps ask for it on a GPU. Switchable off
    /// and on at run time ([`super::OceanRenderer::set_anisotropic`]).
    pub anisotropy: Anisotropy,
    /// Whitecaps: foam where the simulation's whole-surface coverage
    /// ([`crate::sim::whitecaps`]) says the sea breaks. Off for comparisons only.
    pub whitecaps: bool,
    /// Foam drawn out into streaks along a strong wind ([`foam_streak_stretch`]). Off for
    /// comparisons only.
    pub foam_streaks: bool,
    /// Foam lit on its own normal (the wave's): brighter on faces turned to the sun. Off (lit
    /// as level foam) for comparisons only.
    pub foam_lit: bool,
    /// Detail near the viewer: the waves shorter than the finest cascade
    /// ([`crate::sim::detail`]) drawn where the eye can see them, faded out with distance.
    /// Off for comparisons only.
    pub detail: bool,
    /// Frames the CPU may record ahead of the GPU (≥ 2); also the staging ring's slot count.
    pub frames_in_flight: usize,
    /// The sun, the air and the clouds: the sky drawn, reflected and fogged with, the sun's light
    /// and the exposure all follow from it.
    pub sun: SunSky,
    /// Distance (m) over which fog reaches 63% (exp(−d/fog)).
    pub fog_distance: f32,
    /// Paint the sky magenta so any sky pixel under the horizon shows (crack tests).
    pub sky_marker: bool,
    /// Paint the sky with a grey ramp, left to right, of exposed values 0 to
    /// [`TONEMAP_RAMP_TOP`] through the tone curve (tests: the curve and the sRGB store read
    /// back as [`crate::render::tonemap`] says).
    pub tonemap_ramp: bool,
    /// The interaction layer's side in cells ([`crate::sim::interaction`]), `None`: no layer
    /// (a frame's layer of another size is not drawn).
    pub interaction: Option<GridSize>,
    /// Count the shading paths the pixels take and the pass's invocations
    /// ([`super::OceanRenderer::path_counts`]; `vr-ocean gpu-budget`): the counting variant of the
    /// fragment shader, which shades the same but writes a tally. Never in a user's run.
    pub count_paths: bool,
    /// The eye width (pixels) the far mesh's collapse by its thickness on the screen is sized
    /// for ([`crate::lod::ScreenCollapse`]); `None`: the drawn area's (a render scale's
    /// sub-rectangle, else the whole image). Comparisons across
    /// sizes (a supersampled reference, counts taken at a fraction of the headset's size) set
    /// it so that every image draws the same surface.
    pub mesh_eye_width: Option<u32>,
}

impl RendererSettings {
    /// `layer` if this renderer draws it: one of the size it was made for
    /// ([`RendererSettings::interaction`]; a renderer made for another preset draws none).
    pub fn drawn_layer<'a>(
        &self,
        layer: Option<&'a InteractionLayer>,
    ) -> Option<&'a InteractionLayer> {
        layer.filter(|l| Some(l.config().cells) == self.interaction)
    }
}

/// The exposed value at the right edge of the tone-map test ramp: past the curve's knee.
pub const TONEMAP_RAMP_TOP: f32 = 1.5;

impl Default for RendererSettings {
    fn default() -> Self {
        Self {
            stereo: StereoMode::Multiview,
            msaa: Msaa::X4,
            specular_aa: true,
            supersampling: true,
            anisotropy: Anisotropy::Off,
            whitecaps: true,
            foam_streaks: true,
            detail: true,
            foam_lit: true,
            frames_in_flight: 2,
            sun: default_sun(),
            fog_distance: 4000.0,
            sky_marker: false,
            tonemap_ramp: false,
            interaction: None,
            count_paths: false,
            mesh_eye_width: None,
        }
    }
}

/// The sun the renderer lights with unless told otherwise: 17.5° high, azimuth −61.8° (toward
/// (0.45, 0.3, −0.84)), clear maritime air (T 2.5): a late-afternoon sun ahead and to the right
/// of a viewer looking along −z.
pub fn default_sun() -> SunSky {
    let d = Vec3::new(0.45, 0.3, -0.84).normalize();
    SunSky {
        elevation_deg: d.y.asin().to_degrees(),
        azimuth_deg: d.z.atan2(d.x).to_degrees(),
        turbidity: 2.5,
        clouds: 0.0,
    }
}
