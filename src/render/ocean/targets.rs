//! The render targets of the pass: views and framebuffers for every pair of a colour image (the
//! XR backend's, 2 layers) and a depth image (the given depth images, or one transient image of
//! our own), per pass (one with multiview, one per eye without).

use ash::vk;

use super::TargetImages;
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{create_view, Image, ImageDesc};
use crate::render::pipeline::{Pipelines, StereoMode, DEPTH_FORMAT};

/// Views and framebuffers of the target images.
pub(super) struct Targets {
    own_depth: Option<Image>,
    /// Colour images.
    pub colours: usize,
    /// Depth images.
    pub depths: usize,
    passes: usize,
    views: Vec<vk::ImageView>,
    framebuffers: Vec<vk::Framebuffer>,
}

impl Targets {
    /// Views and framebuffers for every (colour, depth, pass); the transient depth image, when
    /// no depth images are given, is shared by all frames (the render pass's external
    /// dependency orders its reuse). Nothing is left behind when a step fails.
    pub fn new(ctx: &GpuContext, p: &Pipelines, t: TargetImages<'_>) -> Result<Self, RenderError> {
        let mut out = Self {
            own_depth: None,
            colours: t.images.len(),
            depths: t.depth.len().max(1),
            passes: match p.mode {
                StereoMode::Multiview => 1,
                StereoMode::TwoPass => 2,
            },
            views: Vec::new(),
            framebuffers: Vec::new(),
        };
        if let Err(e) = out.create(ctx, p, t) {
            out.destroy(ctx);
            return Err(e);
        }
        Ok(out)
    }

    fn create(
        &mut self,
        ctx: &GpuContext,
        p: &Pipelines,
        t: TargetImages<'_>,
    ) -> Result<(), RenderError> {
        if t.depth.is_empty() {
            self.own_depth = Some(Image::new(
                ctx,
                ImageDesc {
                    format: DEPTH_FORMAT,
                    extent: t.extent,
                    layers: 2,
                    mips: 1,
                    usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                    aspect: vk::ImageAspectFlags::DEPTH,
                    transient: true,
                },
            )?);
        }
        let own = self.own_depth.as_ref().map(|d| [d.raw]);
        let depth_images: &[vk::Image] = match &own {
            Some(d) => d,
            None => t.depth,
        };
        let layouts: &[(u32, u32)] = match p.mode {
            StereoMode::Multiview => &[(0, 2)],
            StereoMode::TwoPass => &[(0, 1), (1, 1)],
        };
        // Views first: [colour image][pass] then [depth image][pass].
        let colour = vk::ImageAspectFlags::COLOR;
        let depth_aspect = vk::ImageAspectFlags::DEPTH;
        for &image in t.images {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, t.format, colour, base, count, 1);
                self.views.push(v?);
            }
        }
        for &image in depth_images {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, DEPTH_FORMAT, depth_aspect, base, count, 1);
                self.views.push(v?);
            }
        }
        let depth_view0 = self.colours * self.passes;
        for c in 0..self.colours {
            for d in 0..self.depths {
                for pass in 0..self.passes {
                    let attachments = [
                        self.views[c * self.passes + pass],
                        self.views[depth_view0 + d * self.passes + pass],
                    ];
                    let info = vk::FramebufferCreateInfo::default()
                        .render_pass(p.render_pass)
                        .attachments(&attachments)
                        .width(t.extent.width)
                        .height(t.extent.height)
                        .layers(1);
                    // SAFETY: the views and the render pass are alive and compatible.
                    let fb = ctx.create("vkCreateFramebuffer", || unsafe {
                        ctx.device.create_framebuffer(&info, None)
                    });
                    self.framebuffers.push(fb?);
                }
            }
        }
        Ok(())
    }

    /// The framebuffer of colour image `colour`, depth image `depth` and pass `pass`.
    pub fn framebuffer(&self, colour: u32, depth: u32, pass: u32) -> vk::Framebuffer {
        let i = (colour as usize * self.depths + depth as usize) * self.passes + pass as usize;
        self.framebuffers[i]
    }

    /// Frees what was made. The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses them (the owner waited for idle or never submitted).
        unsafe {
            for f in self.framebuffers.drain(..) {
                ctx.device.destroy_framebuffer(f, None);
            }
            for v in self.views.drain(..) {
                ctx.device.destroy_image_view(v, None);
            }
        }
        if let Some(mut d) = self.own_depth.take() {
            d.destroy(ctx);
        }
    }
}
