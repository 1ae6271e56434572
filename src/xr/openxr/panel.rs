//! The control panel on a quad layer (issue 31): `XrCompositionLayerQuad` with its own
//! one-layer sRGB swapchain, so the compositor samples the panel's pixels directly (sharp text,
//! no eye-buffer pixels spent). The swapchain is made the first time the panel opens; an image
//! is acquired, painted ([`PanelCanvas`]) and released only on frames where the panel drew a
//! new one, and every frame the panel is open the quad is submitted after the projection
//! layer. Where it floats and what the controllers do to it: [`super::panel_aim`].

use ash::vk;
use ash::vk::Handle as _;
use glam::{Quat, Vec3};
use openxr as xr;

use super::error::backend;
use super::error::Call;
use super::panel_aim::{AimFrame, AimPointer, HandAim, PanelQuad};
use super::session::LOCAL_EYE_HEIGHT;
use super::OpenXr;
use crate::render::barrier::Access;
use crate::render::memory;
use crate::render::panel::{PanelCanvas, PanelTarget};
use crate::render::GpuContext;
use crate::ui::panel::Panel;
use crate::xr::XrError;

/// Image pixels per egui point on the headset: the 440×560-point panel is 1100×1400 pixels,
/// about 26 per degree at its size and distance ([`super::panel_aim::PANEL_WIDTH`]).
pub const PANEL_PIXELS_PER_POINT: f32 = 2.5;

/// The panel's swapchain and a view of each of its images.
struct PanelSwapchain {
    handle: xr::Swapchain<xr::Vulkan>,
    views: Vec<vk::ImageView>,
    extent: vk::Extent2D,
}

/// The quad layer's state.
#[derive(Default)]
pub(super) struct QuadPanel {
    swapchain: Option<PanelSwapchain>,
    canvas: Option<PanelCanvas>,
    /// The panel generation the swapchain's last released image shows.
    painted: Option<u64>,
    /// Where the open panel floats (tracking space); `None` while closed.
    quad: Option<PanelQuad>,
    aim: AimPointer,
    /// The head in tracking space at the last located frame: where the panel opens.
    pub head: Option<(Vec3, Quat)>,
    /// The hand that drives the panel (its haptic tick).
    hand: usize,
    /// Images acquired for the panel so far.
    pub acquired: u64,
    /// Frames submitted with the quad.
    pub frames_with_quad: u64,
}

/// The quad to submit this frame.
pub(super) struct QuadLayer<'a> {
    pub swapchain: &'a xr::Swapchain<xr::Vulkan>,
    pub extent: vk::Extent2D,
    pub quad: PanelQuad,
}

impl QuadPanel {
    /// Whether the panel is open (its triggers are the panel's, not the wind's).
    pub fn is_open(&self) -> bool {
        self.quad.is_some()
    }

    /// The quad layer, when the panel is open and an image of it was released.
    pub fn layer(&self) -> Option<QuadLayer<'_>> {
        let s = self.swapchain.as_ref().filter(|_| self.painted.is_some())?;
        Some(QuadLayer {
            swapchain: &s.handle,
            extent: s.extent,
            quad: self.quad?,
        })
    }

    /// One frame of aiming: `menu` pressed, each hand's aim ray (tracking space) and
    /// trigger. Returns the panel's events and the rays that meet it.
    pub fn aim(
        &mut self,
        menu: bool,
        aims: [Option<(Vec3, Vec3)>; 2],
        triggers: [f32; 2],
    ) -> AimFrame {
        let hands = std::array::from_fn(|i| {
            aims[i].map(|(origin, direction)| HandAim {
                origin,
                direction,
                trigger: triggers[i],
            })
        });
        let frame = self.aim.update(menu, hands, self.quad.as_ref());
        self.hand = frame.hand;
        frame
    }

    /// Frees the image views and the canvas, then the swapchain. Waits for the device.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        ctx.wait_idle();
        if let Some(mut c) = self.canvas.take() {
            c.destroy(ctx);
        }
        if let Some(s) = self.swapchain.take() {
            for v in s.views {
                // SAFETY: the device is idle; the view belongs to it.
                unsafe { ctx.device.destroy_image_view(v, None) };
            }
        }
        self.painted = None;
    }
}

impl OpenXr {
    /// [`crate::xr::FrameLoop::show_panel`]: places the panel when it opens, paints a new image
    /// of it into its swapchain when it changed.
    pub(super) fn show_quad_panel(&mut self, panel: &mut Panel) -> Result<(), XrError> {
        if !panel.is_open() {
            self.panel.quad = None;
            return Ok(());
        }
        let [w, h] = panel.size_px();
        if self.panel.quad.is_none() {
            let (head, view) = self
                .panel
                .head
                .unwrap_or((Vec3::new(0.0, LOCAL_EYE_HEIGHT, 0.0), Quat::IDENTITY));
            self.panel.quad = Some(PanelQuad::in_front_of(head, view, [w, h]));
        }
        if self.panel.painted == Some(panel.generation()) || panel.primitives().is_empty() {
            return Ok(());
        }
        let extent = vk::Extent2D {
            width: w,
            height: h,
        };
        if self.panel.swapchain.is_none() {
            let made = self.panel_swapchain(extent)?;
            self.panel.swapchain = Some(made);
        }
        let ctx = self.ctx.as_ref().expect("context exists until drop");
        let format = self.session().colour.format;
        let canvas = match self.panel.canvas.as_mut() {
            Some(c) => c,
            None => self.panel.canvas.insert(PanelCanvas::new(
                ctx,
                PanelTarget {
                    format,
                    // The compositor takes swapchain images in COLOR_ATTACHMENT_OPTIMAL.
                    then: Access::ColourAttachment,
                },
            )?),
        };
        let Some(s) = self.panel.swapchain.as_mut() else {
            unreachable!("made above");
        };
        let i = s
            .handle
            .acquire_image()
            .call("xrAcquireSwapchainImage (panel)")?;
        self.panel.acquired += 1;
        s.handle
            .wait_image(xr::Duration::INFINITE)
            .call("xrWaitSwapchainImage (panel)")?;
        let painted = canvas.paint(ctx, panel, s.views[i as usize], s.extent);
        // Released even when the paint failed: the swapchain stays usable.
        s.handle
            .release_image()
            .call("xrReleaseSwapchainImage (panel)")?;
        painted?;
        self.panel.painted = Some(panel.generation());
        Ok(())
    }

    /// A tick on the hand that drives the panel.
    pub(super) fn panel_tick(&self) {
        if let Some(s) = self.session.as_ref() {
            s.input.tick_hand(&s.session, self.panel.hand);
        }
    }

    /// The panel's swapchain of `extent` in the colour swapchain's sRGB format, with a view
    /// of each image.
    fn panel_swapchain(&self, extent: vk::Extent2D) -> Result<PanelSwapchain, XrError> {
        let ctx = self.ctx.as_ref().expect("context exists until drop");
        let s = self.session();
        let format = s.colour.format;
        let handle = s
            .session
            .create_swapchain(&xr::SwapchainCreateInfo {
                create_flags: xr::SwapchainCreateFlags::EMPTY,
                usage_flags: xr::SwapchainUsageFlags::COLOR_ATTACHMENT,
                format: format.as_raw() as u32,
                sample_count: 1,
                width: extent.width,
                height: extent.height,
                face_count: 1,
                array_size: 1,
                mip_count: 1,
            })
            .call("xrCreateSwapchain (panel)")?;
        let images = handle
            .enumerate_images()
            .call("xrEnumerateSwapchainImages (panel)")?;
        let mut made = PanelSwapchain {
            handle,
            views: Vec::with_capacity(images.len()),
            extent,
        };
        for raw in images {
            let image = vk::Image::from_raw(raw);
            let colour = vk::ImageAspectFlags::COLOR;
            // The view is destroyed before the swapchain (`QuadPanel::destroy`).
            match memory::create_view(ctx, image, format, colour, 0, 1, 1) {
                Ok(v) => made.views.push(v),
                Err(e) => {
                    for v in made.views.drain(..) {
                        // SAFETY: the view was made above and is not in use.
                        unsafe { ctx.device.destroy_image_view(v, None) };
                    }
                    return Err(e.into());
                }
            }
        }
        log::info!(
            "panel: quad layer {}x{} ({format:?}, {} images)",
            extent.width,
            extent.height,
            made.views.len()
        );
        if made.views.is_empty() {
            return Err(backend("the runtime gave the panel's swapchain no images"));
        }
        Ok(made)
    }
}
