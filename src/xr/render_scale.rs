//! The eye images' render scale: how much of the swapchain's images is drawn, as a share of
//! the runtime's recommended size (Meta's render scale), and the centred rectangle that is.
//! The GPU-time governor's render-scale steps ([`super::gpu_governor`]) and the backends'
//! shown rectangle both come from here.

use ash::vk;

/// The eye images' sizes as shares of the runtime's recommended size (each side): what the
/// swapchain holds and what is drawn of it at the start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderScales {
    /// The swapchain images (the most that can be drawn).
    pub images: f32,
    /// What is drawn as configured ([`super::gpu_governor::QualityStep::Full`]): at most
    /// `images`.
    pub start: f32,
}

impl RenderScales {
    /// Images drawn whole: the configured scale is the swapchain's.
    pub fn whole(scale: f32) -> Self {
        Self {
            images: scale,
            start: scale,
        }
    }
}

/// The centred sub-rectangle of an eye image of `extent` rendered at `scale` (at least 1×1
/// pixel): its centre stays where the fixed foveation's full-rate centre is.
pub fn scaled_rect(extent: vk::Extent2D, scale: f32) -> vk::Rect2D {
    let side =
        |full: u32| ((full as f32 * scale.clamp(0.0, 1.0)).round() as u32).clamp(1, full.max(1));
    let (w, h) = (side(extent.width), side(extent.height));
    vk::Rect2D {
        offset: vk::Offset2D {
            x: ((extent.width - w) / 2) as i32,
            y: ((extent.height - h) / 2) as i32,
        },
        extent: vk::Extent2D {
            width: w,
            height: h,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_rects_are_centred_and_never_empty() {
        let e = vk::Extent2D {
            width: 1440,
            height: 1584,
        };
        let r = scaled_rect(e, 0.7);
        assert_eq!((r.extent.width, r.extent.height), (1008, 1109));
        assert_eq!((r.offset.x, r.offset.y), (216, 237));
        assert_eq!(scaled_rect(e, 1.0).extent, e);
        let tiny = scaled_rect(
            vk::Extent2D {
                width: 1,
                height: 1,
            },
            0.1,
        );
        assert_eq!((tiny.extent.width, tiny.offset.x), (1, 0));
    }
}
