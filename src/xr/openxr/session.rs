//! Session creation: the session on our Vulkan device, the reference space the user stands in
//! (STAGE when offered, LOCAL otherwise), the 2-layer sRGB colour swapchain and, with
//! `XR_KHR_composition_layer_depth`, the depth swapchain, and the actions.

use ash::vk;
use openxr as xr;

use super::error::Call;
use super::input::Input;
use super::swapchain::{self, ArraySwapchain};
use super::{backend, LOCAL_EYE_HEIGHT};
use crate::render::GpuContext;
use crate::xr::XrError;

/// Session objects, destroyed before the Vulkan device (dropping this destroys them).
pub(super) struct Session {
    /// The session.
    pub session: xr::Session<xr::Vulkan>,
    /// `xrWaitFrame`.
    pub waiter: xr::FrameWaiter,
    /// `xrBeginFrame` / `xrEndFrame`.
    pub stream: xr::FrameStream<xr::Vulkan>,
    /// The tracking space the views and layers are located in.
    pub space: xr::Space,
    /// The colour swapchain the pass draws into.
    pub colour: ArraySwapchain,
    /// The depth swapchain handed to the compositor, when submitted.
    pub depth: Option<ArraySwapchain>,
    /// The controllers' actions.
    pub input: Input,
    /// Kept alive while the swapchain uses it.
    pub foveation: Option<xr::FoveationProfileFB>,
}

/// What the session was set up with, for the locomotion and the summary.
pub(super) struct SessionFacts {
    /// STAGE or LOCAL.
    pub space_name: &'static str,
    /// Height of the space's origin above the mean sea level (m).
    pub origin_height: f32,
}

impl Session {
    /// Creates the session on `ctx` (made by the runtime for `system`), its space, swapchains
    /// of `extent` per eye and actions. The user's floor is `deck_height` above the sea.
    pub fn new(
        instance: &xr::Instance,
        ctx: &GpuContext,
        system: xr::SystemId,
        extent: vk::Extent2D,
        deck_height: f32,
    ) -> Result<(Self, SessionFacts), XrError> {
        // SAFETY: the handles come from the context the runtime created for this system; the
        // queue is only used from this thread.
        let (session, waiter, stream) = unsafe {
            instance.create_session::<xr::Vulkan>(
                system,
                &xr::vulkan::SessionCreateInfo {
                    instance: vk::Handle::as_raw(ctx.instance.handle()) as _,
                    physical_device: vk::Handle::as_raw(ctx.physical) as _,
                    device: vk::Handle::as_raw(ctx.device.handle()) as _,
                    queue_family_index: ctx.queue_family,
                    queue_index: 0,
                },
            )
        }
        .call("xrCreateSession")?;
        let spaces = session
            .enumerate_reference_spaces()
            .call("xrEnumerateReferenceSpaces")?;
        let facts = if spaces.contains(&xr::ReferenceSpaceType::STAGE) {
            SessionFacts {
                space_name: "STAGE",
                origin_height: deck_height,
            }
        } else {
            SessionFacts {
                space_name: "LOCAL",
                origin_height: deck_height + LOCAL_EYE_HEIGHT,
            }
        };
        let (space_type, call) = if facts.space_name == "STAGE" {
            (
                xr::ReferenceSpaceType::STAGE,
                "xrCreateReferenceSpace(STAGE)",
            )
        } else {
            (
                xr::ReferenceSpaceType::LOCAL,
                "xrCreateReferenceSpace(LOCAL)",
            )
        };
        let space = session
            .create_reference_space(space_type, xr::Posef::IDENTITY)
            .call(call)?;
        let (colour, depth) = swapchains(instance, &session, extent)?;
        let input = Input::new(instance).map_err(backend)?;
        input.attach(&session).map_err(backend)?;
        Ok((
            Self {
                session,
                waiter,
                stream,
                space,
                colour,
                depth,
                input,
                foveation: None,
            },
            facts,
        ))
    }
}

/// The colour swapchain in our preferred sRGB format and, where the runtime takes depth
/// layers and offers our depth format, the depth swapchain.
fn swapchains(
    instance: &xr::Instance,
    session: &xr::Session<xr::Vulkan>,
    extent: vk::Extent2D,
) -> Result<(ArraySwapchain, Option<ArraySwapchain>), XrError> {
    let formats = session
        .enumerate_swapchain_formats()
        .call("xrEnumerateSwapchainFormats")?;
    let formats: Vec<i64> = formats.iter().map(|&f| f as i64).collect();
    let colour_format = swapchain::choose_colour_format(&formats).map_err(backend)?;
    let colour = ArraySwapchain::new(
        session,
        colour_format,
        extent,
        xr::SwapchainUsageFlags::COLOR_ATTACHMENT,
    )
    .map_err(backend)?;
    let depth = if instance.exts().khr_composition_layer_depth.is_some()
        && swapchain::offers_depth(&formats)
    {
        Some(
            ArraySwapchain::new(
                session,
                crate::render::DEPTH_FORMAT,
                extent,
                xr::SwapchainUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            )
            .map_err(backend)?,
        )
    } else {
        log::info!("depth is not submitted (no XR_KHR_composition_layer_depth or D32 format)");
        None
    };
    log::info!(
        "swapchains: {}x{} per eye, 2 layers, {colour_format:?} ({} images){}",
        extent.width,
        extent.height,
        colour.images.len(),
        if depth.is_some() {
            ", depth D32_SFLOAT submitted"
        } else {
            ""
        }
    );
    Ok((colour, depth))
}
