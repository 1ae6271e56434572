//! The control panel over the window's view (issue 31): the panel painted
//! ([`PanelCanvas`]) into an sRGB image of its own, on its own command buffer, only when the
//! panel drew a new image ([`Panel::generation`]); each presented frame then blits that image
//! over the eyes at its [`OverlayPlacement`]. The panel is opaque, so a blit composites it.

use ash::vk;

use crate::render::barrier::Access;
use crate::render::memory::{Image, ImageDesc};
use crate::render::panel::{PanelCanvas, PanelTarget};
use crate::render::{GpuContext, RenderError};
use crate::ui::panel::Panel;

/// The overlay image's format: the painter encodes to sRGB on write, a blit to the window's
/// format (sRGB or not) converts.
const FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// The margin kept around the panel in the window (pixels).
const MARGIN: f32 = 16.0;

/// Where the panel's image sits in the window: its top-left corner and its scale (1 at
/// most: shrunk to fit a small window, never blown up and blurred).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayPlacement {
    /// Top-left corner in window pixels.
    pub origin: [f32; 2],
    /// Window pixels per panel pixel.
    pub scale: f32,
    /// The panel image's size (pixels).
    pub panel: [u32; 2],
}

impl OverlayPlacement {
    /// The panel centred in a window of `window` pixels, shrunk to fit inside a margin.
    pub fn centred(window: vk::Extent2D, panel: [u32; 2]) -> Self {
        let (w, h) = (window.width as f32, window.height as f32);
        let (pw, ph) = (panel[0].max(1) as f32, panel[1].max(1) as f32);
        let scale = ((w - 2.0 * MARGIN) / pw)
            .min((h - 2.0 * MARGIN) / ph)
            .min(1.0)
            .max(1.0 / pw.max(ph));
        let size = [pw * scale, ph * scale];
        Self {
            origin: [
                ((w - size[0]) / 2.0).floor().max(0.0),
                ((h - size[1]) / 2.0).floor().max(0.0),
            ],
            scale,
            panel,
        }
    }

    /// The panel pixel under window pixel `at`, or `None` off the panel.
    pub fn panel_pixel(&self, at: [f32; 2]) -> Option<[f32; 2]> {
        let p = [
            (at[0] - self.origin[0]) / self.scale,
            (at[1] - self.origin[1]) / self.scale,
        ];
        let inside = p[0] >= 0.0
            && p[1] >= 0.0
            && p[0] < self.panel[0] as f32
            && p[1] < self.panel[1] as f32;
        inside.then_some(p)
    }

    /// The blit's destination corners in the window.
    fn corners(&self) -> [vk::Offset3D; 2] {
        let at = |i: usize| (self.origin[i] + self.panel[i] as f32 * self.scale).round() as i32;
        [
            vk::Offset3D {
                x: self.origin[0] as i32,
                y: self.origin[1] as i32,
                z: 0,
            },
            vk::Offset3D {
                x: at(0).max(self.origin[0] as i32 + 1),
                y: at(1).max(self.origin[1] as i32 + 1),
                z: 1,
            },
        ]
    }
}

/// A painted panel image and where to blit it, for one frame's present.
#[derive(Clone, Copy, Debug)]
pub struct OverlayBlit {
    /// The image, in `TRANSFER_SRC_OPTIMAL` (the painter's pass leaves it so).
    pub image: vk::Image,
    /// Where it goes.
    pub placement: OverlayPlacement,
}

impl OverlayBlit {
    /// The blit region: the whole panel image onto its place.
    pub fn region(&self) -> vk::ImageBlit {
        let sub = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        vk::ImageBlit {
            src_subresource: sub,
            src_offsets: [
                vk::Offset3D::default(),
                vk::Offset3D {
                    x: self.placement.panel[0] as i32,
                    y: self.placement.panel[1] as i32,
                    z: 1,
                },
            ],
            dst_subresource: sub,
            dst_offsets: self.placement.corners(),
        }
    }
}

/// The panel's canvas and the image it paints.
#[derive(Default)]
pub struct Overlay {
    canvas: Option<PanelCanvas>,
    image: Option<Image>,
    /// The panel generation the image shows.
    painted: Option<u64>,
}

impl Overlay {
    /// Paints `panel`'s latest image when it is newer than the one painted (submitted on the
    /// queue before the frame's present, which blits it).
    pub fn paint(&mut self, ctx: &GpuContext, panel: &mut Panel) -> Result<(), RenderError> {
        if self.painted == Some(panel.generation()) || panel.primitives().is_empty() {
            return Ok(());
        }
        let [w, h] = panel.size_px();
        let extent = vk::Extent2D {
            width: w,
            height: h,
        };
        if self.image.as_ref().is_some_and(|i| i.extent != extent) {
            // A new size (never in a run today): earlier presents may still read the old one.
            ctx.wait_idle();
            if let Some(mut old) = self.image.take() {
                old.destroy(ctx);
            }
        }
        if self.image.is_none() {
            self.image = Some(Image::new(
                ctx,
                ImageDesc {
                    format: FORMAT,
                    extent,
                    layers: 1,
                    mips: 1,
                    samples: vk::SampleCountFlags::TYPE_1,
                    usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSFER_SRC,
                    aspect: vk::ImageAspectFlags::COLOR,
                    transient: false,
                },
            )?);
        }
        if self.canvas.is_none() {
            // The pass waits for earlier blits' reads of the image (its external dependency
            // starts at the transfer stage) and leaves it ready for the next ones.
            self.canvas = Some(PanelCanvas::new(
                ctx,
                PanelTarget {
                    format: FORMAT,
                    then: Access::TransferRead,
                },
            )?);
        }
        let (Some(canvas), Some(image)) = (self.canvas.as_mut(), self.image.as_ref()) else {
            unreachable!("both made above");
        };
        canvas.paint(ctx, panel, image.view, extent)?;
        self.painted = Some(panel.generation());
        Ok(())
    }

    /// The painted image centred in a window of `window` pixels, once a paint was
    /// submitted.
    pub fn blit(&self, window: vk::Extent2D) -> Option<OverlayBlit> {
        let image = self.image.as_ref().filter(|_| self.painted.is_some())?;
        Some(OverlayBlit {
            image: image.raw,
            placement: OverlayPlacement::centred(window, [image.extent.width, image.extent.height]),
        })
    }

    /// Frees everything. Waits for the device first.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        ctx.wait_idle();
        if let Some(mut c) = self.canvas.take() {
            c.destroy(ctx);
        }
        if let Some(mut i) = self.image.take() {
            i.destroy(ctx);
        }
        self.painted = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_panel_sits_centred_and_shrinks_to_fit_never_grows() {
        let ext = |width, height| vk::Extent2D { width, height };
        // Fits at 1:1 in the default window.
        let p = OverlayPlacement::centred(ext(1600, 800), [440, 560]);
        assert_eq!((p.scale, p.origin), (1.0, [580.0, 120.0]));
        assert_eq!(p.panel_pixel([580.0, 120.0]), Some([0.0, 0.0]));
        assert_eq!(p.panel_pixel([1019.5, 679.5]), Some([439.5, 559.5]));
        assert_eq!(p.panel_pixel([579.0, 300.0]), None);
        assert_eq!(p.panel_pixel([700.0, 680.0]), None);
        let c = p.corners();
        assert_eq!((c[0].x, c[0].y, c[1].x, c[1].y), (580, 120, 1020, 680));
        // A short window shrinks it to the height less the margins, still centred.
        let p = OverlayPlacement::centred(ext(1280, 400), [440, 560]);
        assert!((p.scale - (400.0 - 32.0) / 560.0).abs() < 1e-6);
        assert_eq!(p.origin[1], 16.0);
        let mid = p.panel_pixel([640.0, 200.0]).unwrap();
        assert!((mid[0] - 220.0).abs() < 1.0 && (mid[1] - 280.0).abs() < 1.0);
        // A tiny window still gets a panel of at least a pixel inside it.
        let p = OverlayPlacement::centred(ext(2, 1), [440, 560]);
        let c = p.corners();
        assert!(c[1].x > c[0].x && c[1].y > c[0].y);
    }
}
