//! The mesh's collapse by its thickness on the screen (issue 43, item 3: triangles of a
//! pixel's size, designed with the morph ranges rather than against them).
//!
//! Seen at a grazing angle, a lattice of spacing h at distance d from an eye H above the water
//! is h·H/d² radians thick on the screen: the quadtree's far patches, sized in metres, draw
//! slivers under a pixel tall, each pixel then shaded by several of them and each of their 2×2
//! quads mostly empty lanes. The quadtree cannot choose coarser far levels (a CDLOD level needs
//! a band of distances wider than a patch's diagonal), so the mesh collapses instead: beyond
//! the CDLOD morph, each vertex keeps walking up the lattices (`morph::chain_offset`), the
//! lattice of spacing h sliding onto the next coarser one as its thickness falls from
//! [`ScreenCollapse::START_PX`] to half of it. Every vertex's walk depends only on its lattice
//! point and its distance, as the CDLOD morph does, so patches and the skirt stay watertight.
//!
//! Waves shorter than the collapsed lattice can show fade from the mesh before it collapses
//! (`render::ocean::pass::cascade_fades`, [`ScreenCollapse::spacing_bound`]); the normals, per
//! pixel, keep them.

use super::LodSettings;

/// How the mesh collapses by its thickness on the screen, for one frame's viewer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenCollapse {
    /// The eye's height above the mean surface (m) times the pixels per radian.
    height_px: f32,
    /// [`ScreenCollapse::SLOPE`] times the pixels per radian.
    slope_px: f32,
    /// The finest lattice level that collapses ([`ScreenCollapse::new`]); `u32::MAX`: none.
    min_level: u32,
    /// The spacing (m) of the coarsest lattice a collapse reaches (level `min_level − 1`).
    coarsest: f32,
}

impl ScreenCollapse {
    /// The thickness (pixels) where a lattice starts collapsing onto the next coarser one; it
    /// has at half of it, where the next one starts: the far triangles are 1 to 2 pixels
    /// thick. (4 pixels saved 4 points more of the Quest 2's top-deck budget, but the far
    /// swell's troughs, drawn by waves the coarser mesh no longer carries, paled visibly:
    /// BENCHMARKS.md.)
    pub const START_PX: f32 = 2.0;

    /// The slope of the sea toward the eye that the thickness allows for (a wave's face seen
    /// from near the water is thicker than the flat sea under it): h·(H + SLOPE·d)/d².
    pub const SLOPE: f32 = 0.05;

    /// The lattices a vertex walks up at most (mirrored in `shaders/ocean.vert`).
    pub const CHAIN_STEPS: u32 = 3;

    /// No collapse: the quadtree's own mesh (tests of the CDLOD morph, captures from above).
    pub const NONE: Self = Self {
        height_px: 0.0,
        slope_px: 0.0,
        min_level: u32::MAX,
        coarsest: 0.0,
    };

    /// For a viewer `viewer_height` metres above (or below) the mean surface and a screen of
    /// `pixels_per_radian` at its centre. Only lattices of level ≥ max(3, L + 2 − log2 V,
    /// L + 1 − [`Self::CHAIN_STEPS`]) collapse (L the finest level): onto level 2 at the
    /// coarsest, whose parities mod 4 the grid's snap keeps (`lod` module docs); only where
    /// every patch reaching that lattice counts those parities alike (a patch's corner at a
    /// multiple of 4 of its spacings); and only lattices every patch's chain reaches, so that
    /// no patch walks a shared vertex further than its neighbour does. A non-finite or
    /// non-positive scale gives [`ScreenCollapse::NONE`].
    pub fn new(settings: &LodSettings, viewer_height: f32, pixels_per_radian: f32) -> Self {
        if !(pixels_per_radian.is_finite() && pixels_per_radian > 0.0 && viewer_height.is_finite())
        {
            return Self::NONE;
        }
        let log_v = settings.vertices().trailing_zeros();
        let finest = settings.max_level() + 1;
        let min_level = 3
            .max(finest.saturating_sub(log_v - 1))
            .max(finest.saturating_sub(Self::CHAIN_STEPS));
        Self {
            height_px: viewer_height.abs() * pixels_per_radian,
            slope_px: Self::SLOPE * pixels_per_radian,
            min_level,
            coarsest: settings.vertex_spacing(min_level - 1),
        }
    }

    /// The pixels per radian at the centre of an eye `width` pixels wide seeing `fov`.
    pub fn pixels_per_radian(fov: &crate::base::Fov, width: u32) -> f32 {
        width as f32 / (fov.angle_right.tan() - fov.angle_left.tan())
    }

    /// The thickness (pixels) of a lattice spacing `spacing` at `distance`, taken at least
    /// 1 mm as in the shader (under an eye on the water, H = 0, the point below it is thick,
    /// not 0 / 0).
    pub fn thickness(&self, spacing: f32, distance: f32) -> f32 {
        let d = distance.max(1e-3);
        spacing * (self.height_px + self.slope_px * d) / (d * d)
    }

    /// How far (0 to 1) the level-`level` lattice of spacing `spacing` has collapsed onto the
    /// next coarser one at `distance`.
    pub fn factor(&self, spacing: f32, distance: f32, level: u32) -> f32 {
        if level < self.min_level {
            return 0.0;
        }
        (2.0 - 2.0 * self.thickness(spacing, distance) / Self::START_PX).clamp(0.0, 1.0)
    }

    /// An upper bound of the mesh's spacing at `distance` from its collapse alone: a lattice
    /// thinner than [`Self::START_PX`] has moved onto one twice as coarse, so the spacing
    /// stays under twice the one START_PX thick, and under the coarsest lattice a collapse
    /// reaches. (0 without a collapse.)
    pub fn spacing_bound(&self, distance: f32) -> f32 {
        let per_metre = (self.height_px + self.slope_px * distance) / (distance * distance);
        (2.0 * Self::START_PX / per_metre.max(f32::MIN_POSITIVE)).min(self.coarsest)
    }

    /// The distance beyond which the collapse alone lets the spacing exceed `spacing`
    /// ([`Self::spacing_bound`]): the root of 2·START·d² = spacing·(H + SLOPE·d)·ppr, or
    /// `f32::MAX` for a spacing the collapse never reaches.
    pub fn distance_of_spacing(&self, spacing: f32) -> f32 {
        if spacing >= self.coarsest {
            return f32::MAX;
        }
        let a = 2.0 * Self::START_PX;
        let (b, c) = (spacing * self.slope_px, spacing * self.height_px);
        (b + (b * b + 4.0 * a * c).sqrt()) / (2.0 * a)
    }

    /// The uniform `lod_screen` of `shaders/common.glsl`: x = H·ppr, y = SLOPE·ppr, both in
    /// units of half [`Self::START_PX`] (the shader's thickness is then 2 where the collapse
    /// is complete), z = START_PX, w = the finest level that collapses (2^24 for none).
    pub fn uniform(&self) -> [f32; 4] {
        let level = if self.min_level == u32::MAX {
            16_777_216.0
        } else {
            self.min_level as f32
        };
        let unit = 2.0 / Self::START_PX;
        [
            self.height_px * unit,
            self.slope_px * unit,
            Self::START_PX,
            level,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::{OceanSize, QualityPreset};

    fn quest(preset: QualityPreset, height: f32) -> ScreenCollapse {
        let st = LodSettings::new(preset, OceanSize::new(2048.0).unwrap());
        ScreenCollapse::new(&st, height, 900.0)
    }

    #[test]
    fn a_lattice_collapses_from_start_to_half_of_it_and_the_next_takes_over() {
        let c = quest(QualityPreset::Medium, 9.7);
        let h = 2.0;
        // The distances where the 2 m lattice is START and START/2 pixels thick.
        let at = |px: f32| {
            let (mut lo, mut hi) = (1.0f32, 1e5f32);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if c.thickness(h, mid) > px {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let (start, full) = (
            at(ScreenCollapse::START_PX),
            at(0.5 * ScreenCollapse::START_PX),
        );
        assert!(start < full);
        assert_eq!(c.factor(h, 0.9 * start, 5), 0.0);
        assert!((c.factor(h, full * 1.001, 5) - 1.0).abs() < 1e-6);
        let mid = c.factor(h, 0.5 * (start + full), 5);
        assert!(mid > 0.1 && mid < 0.9, "{mid}");
        // The next lattice (2h) starts where this one is complete.
        assert!(c.factor(2.0 * h, full * 0.999, 4) < 1e-3);
        assert!(c.factor(2.0 * h, full * 1.05, 4) > 0.0);
        // Not below the finest collapsing level (level 2 is never left).
        assert_eq!(c.factor(h, 10.0 * full, 2), 0.0);
    }

    #[test]
    fn the_shaders_uniform_gives_the_same_factor() {
        let c = quest(QualityPreset::High, 1.7);
        let u = c.uniform();
        for (h, d) in [
            (1.0, 30.0),
            (1.0, 80.0),
            (2.0, 150.0),
            (4.0, 400.0),
            (0.5, 20.0),
        ] {
            let shader = (2.0 - h * (u[0] + u[1] * d) / (d * d)).clamp(0.0, 1.0);
            assert!((shader - c.factor(h, d, 5)).abs() < 1e-5, "{h} m at {d} m");
        }
        assert_eq!(u[3], 3.0, "the Quest's ocean collapses lattices 5, 4 and 3");
    }

    #[test]
    fn the_fade_distance_inverts_the_spacing_bound() {
        let c = quest(QualityPreset::Medium, 9.7);
        for s in [1.0, 4.0, 10.0] {
            let d = c.distance_of_spacing(s);
            assert!((c.spacing_bound(d) - s).abs() < 1e-3 * s, "{s} m at {d} m");
            assert!(c.spacing_bound(0.9 * d) < s);
        }
        // The coarsest lattice it reaches is level 2's (16 m at medium, S = 2048).
        assert_eq!(c.distance_of_spacing(16.0), f32::MAX);
        assert!(c.spacing_bound(1e5) <= 16.0);
    }

    #[test]
    fn the_point_under_an_eye_on_the_water_does_not_move() {
        let c = quest(QualityPreset::Medium, 0.0);
        for d in [0.0, 1e-4, 0.5] {
            assert_eq!(c.factor(2.0, d, 5), 0.0, "at {d} m");
        }
        assert!(c.factor(2.0, 2000.0, 5) > 0.0);
    }

    #[test]
    fn nothing_collapses_without_a_screen() {
        let st = LodSettings::new(QualityPreset::Low, OceanSize::new(2048.0).unwrap());
        for ppr in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(ScreenCollapse::new(&st, 1.7, ppr), ScreenCollapse::NONE);
        }
        assert_eq!(ScreenCollapse::NONE.factor(1.0, 1e4, 5), 0.0);
        assert_eq!(ScreenCollapse::NONE.distance_of_spacing(1.0), f32::MAX);
    }
}
