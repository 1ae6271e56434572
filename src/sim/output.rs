//! What one step publishes: every cascade's fields and the whole surface's (whitecaps, the
//! statistics the renderer shades with), double-buffered against the renderer
//! ([`crate::sim::step`]).

use crate::sim::config::OceanConfig;
use crate::sim::query;
use crate::sim::surface::{CascadeSurface, FloatCopies};
use crate::sim::whitecaps::Whitecaps;

/// One step's output for every cascade, coarsest first.
pub struct Surfaces {
    /// Per-cascade fields.
    pub cascades: Vec<CascadeSurface>,
    /// Slope variance (mean |∇h|²) no cascade's grid shows: BRDF roughness for the renderer
    /// (see [`crate::sim::spectrum::unresolved_slope_variance`]).
    pub unresolved_slope_variance: f32,
    /// Length of the level-0 normals (eq. 49 of the material roughness): the renderer's
    /// specular anti-aliasing counts only the shortening beyond it, which is filtering.
    pub base_normal_length: f32,
    /// Foam coverage of the whole surface around the viewer ([`crate::sim::whitecaps`]).
    pub whitecaps: Whitecaps,
    /// Expected significant wave height 4·√(Σ variance) (m) of all cascades: the renderer
    /// tells crests from troughs by height over it.
    pub significant_height: f32,
    /// The shown sea's wind: its speed at 10 m (m/s) and the unit direction (x, z) it blows
    /// toward, both following a change's blend with the waves: the renderer streaks foam
    /// along it and the sound blows with it.
    pub wind: (f32, [f32; 2]),
}

impl Surfaces {
    /// Zeroed surfaces shaped for `config`, with level-0 normals only as RGBA8 (what a
    /// renderer needs).
    pub fn new(config: &OceanConfig) -> Self {
        Self::with_base(config, FloatCopies::Skip)
    }

    /// Zeroed surfaces that also keep full-precision level-0 normals and foam (export, checks).
    pub fn with_float_copies(config: &OceanConfig) -> Self {
        Self::with_base(config, FloatCopies::Keep)
    }

    fn with_base(config: &OceanConfig, base: FloatCopies) -> Self {
        Self {
            cascades: config
                .patch_sizes
                .iter()
                .map(|&l| CascadeSurface::new(config.grid, l, base))
                .collect(),
            unresolved_slope_variance: 0.0,
            base_normal_length: 1.0,
            whitecaps: Whitecaps::default(),
            significant_height: 0.0,
            wind: (0.0, [1.0, 0.0]),
        }
    }

    /// Simulation time (s) of these fields.
    pub fn time(&self) -> f64 {
        self.cascades[0].time
    }

    /// Water height (m) at world (x, z) on the displaced surface of all cascades.
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        query::height_at(&self.cascades, x, z)
    }

    /// The mean height over a disc of `radius` about (x, z) ([`query::footprint_height`]).
    pub fn footprint_height_at(&self, x: f32, z: f32, radius: f32) -> f32 {
        query::footprint_height(&self.cascades, x, z, radius)
    }

    /// Heights at many [x, z] points, lazily.
    pub fn heights_at<'a>(&'a self, points: &'a [[f32; 2]]) -> impl Iterator<Item = f32> + 'a {
        query::heights_at(&self.cascades, points)
    }

    /// Largest |Dx|, |h|, |Dz| of the summed cascades (an upper bound: the sum of each
    /// cascade's maximum), for padding LOD bounding boxes.
    pub fn max_displacement(&self) -> [f32; 3] {
        self.cascades.iter().fold([0.0; 3], |a, c| {
            let m = c.max_displacement;
            [a[0] + m[0], a[1] + m[1], a[2] + m[2]]
        })
    }
}
