//! The render targets of a stereo pass (the ocean's, and the calibration kernels' made the same
//! way): views and framebuffers for every pair of a colour image (the XR backend's, 2 layers)
//! and a depth image (the given depth images, or one transient image of our own), per pass (one
//! with multiview, one per eye without). With MSAA the pass draws into transient multisampled
//! colour and depth images of our own and resolves into the colour image.

use ash::vk;

use crate::render::barrier::{self, Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{create_view, Image, ImageDesc};
use crate::render::ocean::frame::TargetImages;
use crate::render::render_pass::{PassLayout, StereoMode, DENSITY_MAP_FORMAT, DEPTH_FORMAT};

/// What the framebuffers are made for.
struct Pass {
    mode: StereoMode,
    layout_of_pass: PassLayout,
    render_pass: vk::RenderPass,
}

/// (first layer, layer count) of each pass's view.
type LayerRanges = &'static [(u32, u32)];

/// Views and framebuffers of the target images.
pub(crate) struct Targets {
    /// Transient multisampled colour (MSAA only), shared by all frames.
    own_colour: Option<Image>,
    /// Transient depth (multisampled with MSAA), when no depth images are given.
    own_depth: Option<Image>,
    /// Colour images.
    pub colours: usize,
    /// Depth images.
    pub depths: usize,
    passes: usize,
    /// The colour images (the XR backend's).
    images: Vec<vk::Image>,
    views: Vec<vk::ImageView>,
    framebuffers: Vec<vk::Framebuffer>,
}

/// A transient attachment of our own: never stored, lazily allocated where the device can.
/// `layers`: 2 for multiview; 1 for two passes, which reuse it eye after eye (the render
/// pass's external dependency orders the reuse), as a tiler reuses its tile memory.
/// With `stored`, an image a transfer reads after the pass (the two-pass resolve): ordinary
/// memory instead.
#[allow(clippy::too_many_arguments)]
fn transient(
    ctx: &GpuContext,
    format: vk::Format,
    extent: vk::Extent2D,
    samples: vk::SampleCountFlags,
    layers: u32,
    usage: vk::ImageUsageFlags,
    aspect: vk::ImageAspectFlags,
    stored: bool,
) -> Result<Image, RenderError> {
    let usage = if stored {
        usage | vk::ImageUsageFlags::TRANSFER_SRC
    } else {
        usage | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
    };
    Image::new(
        ctx,
        ImageDesc {
            format,
            extent,
            layers,
            mips: 1,
            samples,
            usage,
            aspect,
            transient: !stored,
        },
    )
}

impl Targets {
    /// Views and framebuffers for every (colour, depth, pass); the transient attachments are
    /// shared by all frames (the render pass's external dependency orders their reuse).
    /// Nothing is left behind when a step fails.
    pub fn new(
        ctx: &GpuContext,
        layout: &PassLayout,
        render_pass: vk::RenderPass,
        t: TargetImages<'_>,
    ) -> Result<Self, RenderError> {
        let p = Pass {
            mode: layout.mode,
            layout_of_pass: *layout,
            render_pass,
        };
        let mut out = Self {
            own_colour: None,
            own_depth: None,
            colours: t.images.len(),
            depths: t.depth.len().max(1),
            passes: match p.mode {
                StereoMode::Multiview => 1,
                StereoMode::TwoPass => 2,
            },
            images: t.images.to_vec(),
            views: Vec::new(),
            framebuffers: Vec::new(),
        };
        if let Err(e) = out.create(ctx, &p, t) {
            out.destroy(ctx);
            return Err(e);
        }
        Ok(out)
    }

    fn create(
        &mut self,
        ctx: &GpuContext,
        p: &Pass,
        t: TargetImages<'_>,
    ) -> Result<(), RenderError> {
        let msaa = p.layout_of_pass.msaa;
        let samples = msaa.flag();
        // Views per pass of a 2-layer image (the eye images, given depth), and of our own
        // transient attachments (2 layers with multiview, 1 reused by both passes without).
        let (layouts, own_layers, own_layouts): (LayerRanges, u32, LayerRanges) = match p.mode {
            StereoMode::Multiview => (&[(0, 2)], 2, &[(0, 2)]),
            StereoMode::TwoPass => (&[(0, 1), (1, 1)], 1, &[(0, 1), (0, 1)]),
        };
        if msaa.resolves() {
            self.own_colour = Some(transient(
                ctx,
                t.format,
                t.extent,
                samples,
                own_layers,
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
                vk::ImageAspectFlags::COLOR,
                p.layout_of_pass.resolves_after_pass(),
            )?);
        }
        if t.depth.is_empty() {
            self.own_depth = Some(transient(
                ctx,
                DEPTH_FORMAT,
                t.extent,
                samples,
                own_layers,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
                false,
            )?);
        }
        // Views: [colour image][pass], then [depth image][pass], then [own colour][pass].
        let colour = vk::ImageAspectFlags::COLOR;
        let depth_aspect = vk::ImageAspectFlags::DEPTH;
        for &image in t.images {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, t.format, colour, base, count, 1);
                self.views.push(v?);
            }
        }
        let own_depth = self.own_depth.as_ref().map(|d| [d.raw]);
        let (depth_images, depth_layouts): (&[vk::Image], _) = match &own_depth {
            Some(d) => (d, own_layouts),
            None => (t.depth, layouts),
        };
        for &image in depth_images {
            for &(base, count) in depth_layouts {
                let v = create_view(ctx, image, DEPTH_FORMAT, depth_aspect, base, count, 1);
                self.views.push(v?);
            }
        }
        let msaa_view0 = self.views.len();
        if let Some(c) = self.own_colour.as_ref().map(|c| c.raw) {
            for &(base, count) in own_layouts {
                let v = create_view(ctx, c, t.format, colour, base, count, 1);
                self.views.push(v?);
            }
        }
        // Density maps (fixed foveation): one per colour image, viewed per pass like it.
        let density_view0 = self.views.len();
        for &image in t.density_maps {
            for &(base, count) in layouts {
                let v = create_view(ctx, image, DENSITY_MAP_FORMAT, colour, base, count, 1);
                self.views.push(v?);
            }
        }
        let depth_view0 = self.colours * self.passes;
        for c in 0..self.colours {
            for d in 0..self.depths {
                for pass in 0..self.passes {
                    let target = self.views[c * self.passes + pass];
                    let depth = self.views[depth_view0 + d * self.passes + pass];
                    let mut attachments = [vk::ImageView::null(); 4];
                    let mut n = 0;
                    let mut push = |v: vk::ImageView| {
                        attachments[n] = v;
                        n += 1;
                    };
                    if msaa.resolves() {
                        push(self.views[msaa_view0 + pass]);
                        push(depth);
                        if p.layout_of_pass.resolves_in_pass() {
                            push(target);
                        }
                        // Resolved after the pass: the pass draws the multisampled image only.
                    } else {
                        push(target);
                        push(depth);
                    }
                    if p.layout_of_pass.density_map {
                        push(self.views[density_view0 + c * self.passes + pass]);
                    }
                    let attachments = &attachments[..n];
                    let info = vk::FramebufferCreateInfo::default()
                        .render_pass(p.render_pass)
                        .attachments(attachments)
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

    /// Colour image `i`.
    pub fn image(&self, i: u32) -> vk::Image {
        self.images[i as usize]
    }

    /// The multisampled colour image (MSAA only): what a resolve after the pass reads.
    pub fn msaa_colour(&self) -> Option<vk::Image> {
        self.own_colour.as_ref().map(|c| c.raw)
    }

    /// Device memory of the transient attachments (bytes), for reports.
    pub fn transient_bytes(&self) -> u64 {
        self.own_colour
            .iter()
            .chain(&self.own_depth)
            .map(|i| i.bytes)
            .sum()
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
        for mut i in self
            .own_colour
            .take()
            .into_iter()
            .chain(self.own_depth.take())
        {
            i.destroy(ctx);
        }
    }
}

/// Records the resolve of a pass's multisampled colour `msaa` (1 layer, in
/// `TRANSFER_SRC_OPTIMAL` after the pass) into layer `eye` of the 2-layer eye image `target`
/// over `area` (the two-pass fallback's resolve after each pass). The layer's contents before
/// are discarded; `from` is how it was last used. It ends in `COLOR_ATTACHMENT_OPTIMAL`, as a
/// resolve in the pass would leave it.
pub(crate) fn resolve_eye(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    msaa: vk::Image,
    target: vk::Image,
    eye: u32,
    area: vk::Rect2D,
    from: Access,
) {
    let to_write = ImageBarrier::colour(target, 2, from, Access::TransferWrite)
        .layer(eye)
        .discard();
    barrier::record(d, cmd, [to_write], None);
    let layers = |layer| vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: layer,
        layer_count: 1,
    };
    let offset = vk::Offset3D {
        x: area.offset.x,
        y: area.offset.y,
        z: 0,
    };
    let region = vk::ImageResolve {
        src_subresource: layers(0),
        src_offset: offset,
        dst_subresource: layers(eye),
        dst_offset: offset,
        extent: vk::Extent3D {
            width: area.extent.width,
            height: area.extent.height,
            depth: 1,
        },
    };
    // SAFETY: `cmd` is recording outside a render pass (the caller's contract); the
    // multisampled image is in TRANSFER_SRC_OPTIMAL (the pass's final layout, its writes made
    // visible by the pass's dependency) and the eye layer in TRANSFER_DST_OPTIMAL; the region
    // fits both.
    unsafe {
        d.cmd_resolve_image(
            cmd,
            msaa,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            target,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
        )
    };
    let done =
        ImageBarrier::colour(target, 2, Access::TransferWrite, Access::ColourAttachment).layer(eye);
    barrier::record(d, cmd, [done], None);
}
