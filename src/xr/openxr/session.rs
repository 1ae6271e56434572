//! Session creation: the session on our Vulkan device, the reference space the user stands in
//! (LOCAL_FLOOR when offered, then STAGE, then LOCAL), the 2-layer sRGB colour swapchain and,
//! when asked for and the runtime takes it (`XR_KHR_composition_layer_depth`), the depth
//! swapchain, and the actions.

use ash::vk;
use openxr as xr;

use super::error::backend;
use super::error::Call;
use super::foveation;
use super::input::Input;
use super::swapchain::{self, ArraySwapchain};
use crate::render::GpuContext;
use crate::xr::XrError;

/// Standing eye height assumed when the runtime offers only LOCAL space (m above its floor).
pub(super) const LOCAL_EYE_HEIGHT: f32 = 1.6;

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
    /// LOCAL_FLOOR, STAGE or LOCAL.
    pub space_name: &'static str,
    /// Height of the space's origin above the mean sea level (m).
    pub origin_height: f32,
}

/// What the session is created with.
pub(super) struct SessionSettings {
    /// Per-eye image size.
    pub extent: vk::Extent2D,
    /// Height of the user's floor above the mean sea level (m).
    pub deck_height: f32,
    /// Submit depth to the compositor (a depth swapchain stored every frame).
    pub submit_depth: bool,
    /// Create the colour swapchain with fragment density maps (every foveation piece is
    /// there: `foveation::FoveationSupport::plan`).
    pub foveated: bool,
}

/// The reference space to stand in, best first: LOCAL_FLOOR (a floor-level origin the user can
/// recentre; core in OpenXR 1.1, `XR_EXT_local_floor` here), STAGE (the room's floor, not
/// recentred), LOCAL (eye level: the deck goes an assumed eye height lower). Returns the type,
/// its name and the origin's height above the sea for a floor `deck_height` above it.
pub fn choose_space(
    offered: &[xr::ReferenceSpaceType],
    deck_height: f32,
) -> (xr::ReferenceSpaceType, &'static str, f32) {
    if offered.contains(&xr::ReferenceSpaceType::LOCAL_FLOOR) {
        (
            xr::ReferenceSpaceType::LOCAL_FLOOR,
            "LOCAL_FLOOR",
            deck_height,
        )
    } else if offered.contains(&xr::ReferenceSpaceType::STAGE) {
        (xr::ReferenceSpaceType::STAGE, "STAGE", deck_height)
    } else {
        (
            xr::ReferenceSpaceType::LOCAL,
            "LOCAL",
            deck_height + LOCAL_EYE_HEIGHT,
        )
    }
}

impl Session {
    /// Creates the session on `ctx` (made by the runtime for `system`), its space, swapchains
    /// and actions.
    pub fn new(
        instance: &xr::Instance,
        ctx: &GpuContext,
        system: xr::SystemId,
        settings: &SessionSettings,
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
        let (space_type, space_name, origin_height) = choose_space(&spaces, settings.deck_height);
        let space = session
            .create_reference_space(space_type, xr::Posef::IDENTITY)
            .call("xrCreateReferenceSpace")?;
        log::info!("reference space: {space_name}");
        let facts = SessionFacts {
            space_name,
            origin_height,
        };
        let (colour, depth) = swapchains(instance, &session, settings)?;
        let mut input = Input::new(instance).map_err(backend)?;
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
    settings: &SessionSettings,
) -> Result<(ArraySwapchain, Option<ArraySwapchain>), XrError> {
    let (extent, submit_depth) = (settings.extent, settings.submit_depth);
    let formats = session
        .enumerate_swapchain_formats()
        .call("xrEnumerateSwapchainFormats")?;
    let formats: Vec<i64> = formats.iter().map(|&f| f as i64).collect();
    let colour_format = swapchain::choose_colour_format(&formats).map_err(backend)?;
    // Transfer destination too: the two-pass fallback with MSAA resolves into it.
    let usage = xr::SwapchainUsageFlags::COLOR_ATTACHMENT | xr::SwapchainUsageFlags::TRANSFER_DST;
    let foveated = if settings.foveated {
        foveation::create_foveated_swapchain(session, colour_format, extent, usage)
            .map_err(|e| log::warn!("fixed foveation off: {e}"))
            .ok()
    } else {
        None
    };
    let colour = match foveated {
        Some(c) => c,
        None => ArraySwapchain::new(session, colour_format, extent, usage).map_err(backend)?,
    };
    let takes_depth =
        instance.exts().khr_composition_layer_depth.is_some() && swapchain::offers_depth(&formats);
    let depth = if submit_depth && takes_depth {
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
        if submit_depth {
            log::warn!(
                "depth is not submitted: the runtime lacks XR_KHR_composition_layer_depth or \
                 the D32 format"
            );
        }
        // No feature here uses submitted depth (no space warp; Quest's positional timewarp
        // estimates its own): it would store two depth layers to memory every frame for
        // nothing, so by default depth stays transient and discarded.
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
