//! Colour conventions of the sky: linear Rec.709/sRGB primaries (D65 white), luminance
//! 0.2126 R + 0.7152 G + 0.0722 B, and the conversion from CIE xyY.

use glam::Vec3;

/// Rec.709 luminance weights: Y = LUMINANCE · (R, G, B), the Y row of sRGB → XYZ.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Chromaticity (x, y) of the sun above the atmosphere as the renderer shows it: the white
/// point, D65. The white balance of an eye adapted to daylight: the sun above the atmosphere
/// (about a 5800-5900 K black body, between D55 and D65) is white, and everything the
/// atmosphere does to its light (the blue sky, the red sunset, a grey overcast) is relative to
/// it, as in Bruneton's sky demo, which white-balances to the sun. (A 5778 K black body drawn
/// unbalanced made every daylight 1.2x redder than blue and an overcast sky beige.)
pub const SUN_CHROMATICITY: [f32; 2] = [0.3127, 0.3290];

/// XYZ → linear sRGB (D65), rows R, G, B.
const XYZ_TO_RGB: [[f32; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// xyY → linear sRGB (D65), negative channels (outside the gamut) clamped to 0.
pub fn xyy_to_rgb(x: f32, y: f32, lum: f32) -> Vec3 {
    let xyz = Vec3::new(x * lum / y, lum, (1.0 - x - y) * lum / y);
    Vec3::from_array(XYZ_TO_RGB.map(|row| Vec3::from_array(row).dot(xyz))).max(Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn d65_is_white_and_luminance_is_kept() {
        let white = xyy_to_rgb(0.3127, 0.3290, 1.0);
        assert!((white - Vec3::ONE).abs().max_element() < 2e-3, "{white}");
        let sun = xyy_to_rgb(SUN_CHROMATICITY[0], SUN_CHROMATICITY[1], 1.0);
        assert!(
            (LUMINANCE.dot(sun) - 1.0).abs() < 2e-3 && (sun - white).abs().max_element() < 1e-6
        );
    }
}
