//! Making the backend: [`OpenXr::new`] (and `new_android`) load the loader, create the
//! instance, let the runtime make the Vulkan device, then the session, its swapchains, the
//! Quest extensions and the frame loop's state, in that order; any failure is an error that
//! names what is missing, and what was made so far is dropped in reverse.

use glam::Vec3;
use openxr as xr;

use super::error::backend;
use super::error::{Call, CallError};
use super::foveation::FoveationSupport;
use super::lifecycle::Lifecycle;
use super::quest::{Foveation, Headset};
use super::quest_setup::{self, QuestSettings};
use super::session::{Session, SessionSettings};
use super::stats::{FrameStats, Summary};
use super::{frame, instance, panel, swapchain, threads, vulkan, OpenXr, OpenXrOptions};
use crate::render::{ContextOptions, GpuContext};
use crate::xr::locomotion::{Locomotion, LocomotionSettings};
use crate::xr::render_scale::{scaled_rect, RenderScales};
use crate::xr::XrError;

impl OpenXr {
    /// Loads the OpenXR loader, connects to the active runtime and sets everything up for the
    /// frame loop. Every failure is an error whose message names what is missing.
    pub fn new(options: OpenXrOptions) -> Result<Self, XrError> {
        instance::validate(&options)?;
        let entry = instance::load_entry(&())?;
        let instance = instance::create_instance(&entry, &(), false)?;
        Self::with_instance(instance, options)
    }

    /// On Android: like [`OpenXr::new`], with the loader initialised through
    /// `XR_KHR_loader_init_android` and the instance created with
    /// `XR_KHR_android_create_instance`, both from the app's Java VM and Activity.
    ///
    /// # Safety
    ///
    /// `java_vm` must be the process's `JavaVM*` and `activity` a valid JNI reference to the
    /// `android.app.Activity` that drives the session, both alive while the backend is.
    #[cfg(target_os = "android")]
    pub unsafe fn new_android(
        options: OpenXrOptions,
        java_vm: *mut std::ffi::c_void,
        activity: *mut std::ffi::c_void,
    ) -> Result<Self, XrError> {
        instance::validate(&options)?;
        // SAFETY: the caller's contract.
        let platform = unsafe { xr::AndroidPlatformInfo::new(java_vm, activity) };
        let entry = instance::load_entry(&platform)?;
        let instance = instance::create_instance(&entry, &platform, true)?;
        Self::with_instance(instance, options)
    }

    fn with_instance(instance: xr::Instance, options: OpenXrOptions) -> Result<Self, XrError> {
        let start_in_water = options.in_water;
        let props = instance.properties().call("xrGetInstanceProperties")?;
        let runtime = format!("{} {}", props.runtime_name, props.runtime_version);
        log::info!("OpenXR runtime: {runtime}");
        let system = instance
            .system(xr::FormFactor::HEAD_MOUNTED_DISPLAY)
            .map_err(|e| match e {
                xr::sys::Result::ERROR_FORM_FACTOR_UNAVAILABLE => backend(format!(
                    "the OpenXR runtime ({runtime}) has no headset right now \
                     (XR_ERROR_FORM_FACTOR_UNAVAILABLE): connect and switch on the headset"
                )),
                e => CallError::new("xrGetSystem", e).into(),
            })?;
        let sys_props = instance
            .system_properties(system)
            .call("xrGetSystemProperties")?;
        let headset = Headset::from_system_name(&sys_props.system_name);
        let defaults = headset.defaults();
        log::info!("OpenXR system: {} ({headset:?})", sys_props.system_name);
        // A scale the user chose sizes the images; the headset's default under the
        // recommended size is drawn in images of that size, so that the GPU-time governor can
        // take the rest where the GPU has room (`QualityStep::FullSize`).
        let scales = match options.resolution_scale {
            Some(chosen) => RenderScales::whole(chosen),
            None => RenderScales {
                images: defaults.resolution_scale.max(1.0),
                start: defaults.resolution_scale,
            },
        };
        let views = instance
            .enumerate_view_configuration_views(system, xr::ViewConfigurationType::PRIMARY_STEREO)
            .map_err(|e| {
                backend(format!(
                    "the runtime has no PRIMARY_STEREO view configuration: {e:?} ({e})"
                ))
            })?;
        if views.len() != 2 {
            return Err(backend(format!(
                "PRIMARY_STEREO has {} views, expected 2",
                views.len()
            )));
        }
        let extent = swapchain::eye_extent(&views[0], scales.images).map_err(backend)?;
        let requirements = instance
            .graphics_requirements::<xr::Vulkan>(system)
            .call("xrGetVulkanGraphicsRequirements2KHR")?;
        let choice = vulkan::api_version(&requirements);
        if let Some(w) = &choice.warning {
            log::warn!("{w}");
        }
        let api_version = choice.version;
        let level = options.foveation.unwrap_or(defaults.foveation);
        let mut fov = FoveationSupport::of_runtime(&instance);
        let factory = vulkan::RuntimeVulkan::new(&instance, system);
        let ctx = GpuContext::with_factory(
            &ContextOptions {
                validation: options.validation,
                api_version,
                fragment_density_map: level != Foveation::Off && fov.runtime_complete(),
                ..ContextOptions::default()
            },
            &factory,
        )?;
        fov.device = ctx.fragment_density_map;
        let foveation_plan = fov.plan(level);
        if !ctx.multiview {
            log::warn!("the device has no multiview; rendering both eyes in two passes");
        }
        let settings = SessionSettings {
            extent,
            deck_height: options.deck_height,
            submit_depth: options.submit_depth,
            foveated: foveation_plan.is_ok(),
        };
        let (mut session, facts) = Session::new(&instance, &ctx, system, &settings)?;
        if let Err(why) = &foveation_plan {
            log::info!("{why}");
        }
        let quest = QuestSettings {
            foveation: level,
            max_refresh_rate: options
                .max_refresh_rate
                .unwrap_or(defaults.max_refresh_rate),
            perf_levels: options.perf_levels,
        };
        let refresh = quest_setup::start(&instance, &mut session, &quest);
        let refresh_rate = refresh
            .as_ref()
            .map(|g| g.rate())
            .or_else(|| quest_setup::current_refresh_rate(&instance, &session.session));
        let summary = Summary {
            runtime,
            eye_size: (extent.width, extent.height),
            colour_format: format!("{:?}", session.colour.format),
            depth: session.depth.is_some(),
            space: facts.space_name.into(),
            refresh_rate,
            ..Summary::default()
        };
        let threads = threads::ThreadSettings::start(&instance, &session.session);
        Ok(Self {
            session: Some(session),
            ctx: Some(ctx),
            instance,
            lifecycle: Lifecycle::new(),
            headset,
            preset: options.preset.unwrap_or(defaults.preset),
            options,
            extent,
            scales,
            render_rect: scaled_rect(extent, scales.start / scales.images),
            foveation: (level, false),
            gpu_levels_left: false,
            locomotion: Locomotion::new(
                Vec3::new(0.0, facts.origin_height, 0.0),
                LocomotionSettings::default(),
            ),
            water_surface: None,
            want_water: start_in_water.then_some(true),
            refresh,
            pending: None,
            index: 0,
            last_gpu: None,
            exit_sent: false,
            tracking: frame::Tracking::default(),
            threads,
            stats: FrameStats::new(summary),
            event_buffer: xr::EventDataBuffer::new(),
            panel: panel::QuadPanel::default(),
        })
    }
}
