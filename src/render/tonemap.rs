//! The tone curve the shaders apply (`tonemap` in `shaders/common.glsl`): Khronos PBR Neutral,
//! mirrored here so tests can check what the GPU wrote against it, and the sRGB encoding the
//! target applies after it.
//!
//! PBR Neutral keeps colours below [`START`] unchanged (but for a small offset that takes the
//! toe to black) and compresses the peak channel above it toward 1, desaturating as it goes,
//! so a bright sun glint turns white instead of clipping to a hue.

use glam::Vec3;

/// Where the compression starts (0.8 − 0.04).
pub const START: f32 = 0.8 - 0.04;

/// How fast compressed colours go grey.
pub const DESATURATION: f32 = 0.15;

/// Khronos PBR Neutral: linear exposed radiance in, linear display value in [0, 1] out.
pub fn pbr_neutral(c: Vec3) -> Vec3 {
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - Vec3::splat(offset);
    let peak = c.max_element();
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let new_peak = 1.0 - d * d / (peak + d - START);
    let c = c * (new_peak / peak);
    let grey = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.lerp(Vec3::splat(new_peak), grey)
}

/// The inverse of [`pbr_neutral`]: a display value (linear, in [0, 1)) back to the exposed
/// radiance the shader tone-mapped, to measure light in rendered images (a sunset's glitter is
/// compressed by the knee; its ratio to the water beside it is a ratio of radiance). Exact but
/// for rounding; ill-conditioned near white, where 8-bit codes no longer tell radiances apart:
/// a peak at or above `1 - 1e-4` is refused (`None`).
pub fn pbr_neutral_inverse(display: Vec3) -> Option<Vec3> {
    let new_peak = display.max_element();
    if !(0.0..1.0 - 1e-4).contains(&new_peak) || display.min_element() < 0.0 {
        return None;
    }
    let d = 1.0 - START;
    let shifted = if new_peak < START {
        display
    } else {
        // The peak before compression, the grey it was mixed with, then the mix undone.
        let peak = d * d / (1.0 - new_peak) - d + START;
        let grey = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
        // (A channel that rounding put under the grey it was mixed with is taken as none.)
        ((display - Vec3::splat(grey * new_peak)) / (1.0 - grey) * (peak / new_peak))
            .max(Vec3::ZERO)
    };
    // The toe: the offset is x − 6.25 x² for the smallest channel x < 0.08, which leaves it at
    // 6.25 x² (< 0.04); else 0.04.
    let y = shifted.min_element();
    let offset = if y < 0.04 {
        let x = (y / 6.25).sqrt();
        x - y
    } else {
        0.04
    };
    Some(shifted + Vec3::splat(offset))
}

/// The sRGB transfer function (IEC 61966-2-1) the target applies on store: linear [0, 1] to
/// encoded [0, 1].
pub fn srgb_encode(linear: f32) -> f32 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_encode`]: an 8-bit sRGB code to linear [0, 1] (reading rendered images
/// back, in tests and tools).
pub fn srgb_decode(code: u8) -> f32 {
    let c = code as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_inverts_encode() {
        for code in 0..=255u8 {
            let back = (255.0 * srgb_encode(srgb_decode(code))).round() as u8;
            assert_eq!(back, code);
        }
    }

    #[test]
    fn the_curve_is_monotonic_bounded_and_linear_below_its_knee() {
        let mut last = -1.0;
        for i in 0..=2000 {
            let v = i as f32 * 0.01;
            let y = pbr_neutral(Vec3::splat(v)).x;
            assert!(y >= last - 1e-6 && y <= 1.0, "{v}: {y}");
            last = y;
        }
        // Above the toe and below the knee, grey passes shifted by the 0.04 offset only.
        let y = pbr_neutral(Vec3::splat(0.5)).x;
        assert!((y - 0.46).abs() < 1e-6, "{y}");
        // Bright light desaturates toward white: a 4:1 orange at 40 comes out within 12 % of
        // grey (unmapped, it would clip to 1, 1, 1 only by losing its hue at the clip).
        let c = pbr_neutral(Vec3::new(40.0, 20.0, 10.0));
        assert!(c.max_element() <= 1.0 && c.min_element() > 0.88, "{c}");
    }

    #[test]
    fn the_inverse_curve_gives_back_the_radiance() {
        for c in [
            Vec3::new(0.01, 0.02, 0.005),
            Vec3::new(0.3, 0.2, 0.1),
            Vec3::new(0.9, 0.5, 0.2),
            Vec3::new(3.0, 1.5, 0.4),
            Vec3::new(12.0, 9.0, 7.0),
        ] {
            let back = pbr_neutral_inverse(pbr_neutral(c)).expect("below white");
            assert!(
                (back - c).abs().max_element() < 2e-3 * c.max_element().max(1.0),
                "{c} -> {back}"
            );
        }
        // White and out-of-range values are refused, not guessed.
        assert_eq!(pbr_neutral_inverse(Vec3::ONE), None);
        assert_eq!(pbr_neutral_inverse(Vec3::new(0.5, -0.1, 0.2)), None);
    }

    #[test]
    fn srgb_encoding_matches_its_definition() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.214_041) - 0.5).abs() < 1e-4);
    }
}
