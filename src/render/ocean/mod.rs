//! The ocean renderer: uploads the simulation's textures and the LOD's instances through a
//! per-frame ring, records one multiview pass (or two passes) of at most 16 patch draws, the
//! skirt and the sky, and times the pass with GPU timestamps. One file per job, following the
//! objects' lifetimes:
//!
//! - `slots`: the frames-in-flight ring (what the CPU writes per frame);
//! - `textures`: the cascade textures, their samplers and the upload;
//! - `interaction`: the interaction layer's texture, uploaded each frame it stepped;
//! - `sky_map`: the sky's prefiltered environment map and its light, baked when the sun moves;
//! - `foam_pattern`: the tiling foam texture the whitecap coverage thresholds, made at start-up;
//! - `mesh`: the patch, skirt and sky meshes, uploaded once;
//! - `pass`: the uniforms, cascade fades and the pass's recording;
//! - `solids`: the floating bodies' and the deck's meshes and instances;
//! - `vignette`: the comfort vignette's rings, drawn last while the view is moved;
//! - `probe`: the counting variant's tally and pipeline statistics (`vr-ocean gpu-budget`);
//! - `parts`: the settings' checks and the parts made in order, all or nothing.
//!
//! Invariants:
//! - A slot is reused only after its fence signals, so the CPU never writes memory the GPU
//!   still reads, and the frame loop never waits for the whole device.
//! - The cascade textures exist once on the GPU; each frame's copy into them is ordered after
//!   the previous frame's reads by a pipeline barrier in the same queue.
//! - Nothing here allocates per frame: every buffer, region list and set is sized at creation.
//! - Creation is all or nothing: when a step fails, every part made before it is destroyed
//!   (tested by injecting a failure at each creation in turn).

mod anisotropy;
mod foam_pattern;
pub(crate) mod frame;
mod interaction;
mod mesh;
mod parts;
mod pass;
pub mod pipelines;
mod probe;
mod settings;
mod sky_map;
mod slots;
pub mod solids;
mod textures;
mod underwater;
pub mod vignette;

use std::time::Instant;

use ash::vk;

use self::foam_pattern::FoamPattern;
use self::interaction::InteractionTexture;
use self::mesh::MeshBuffers;
use self::parts::{make_parts, validate, Parts};
use self::pass::{PassConstants, PassRecorder, ResolveAfter};
use self::pipelines::Pipelines;
use self::probe::PathProbe;
use self::sky_map::SkyMap;
use self::slots::{Slots, TIMESTAMP_QUERIES};
use self::textures::CascadeTextures;
use super::budget::PathCounts;
use super::context::GpuContext;
use super::error::RenderError;
use super::render_pass::StereoMode;
use super::sky::SunSky;
use super::targets::Targets;
use crate::lod::{OceanLod, ScreenCollapse};
use crate::sim::OceanConfig;
pub use anisotropy::Anisotropy;
pub use frame::{FrameInput, FrameReport, TargetImages, MAX_CASCADES};
pub use settings::{
    default_sun, foam_streak_stretch, RendererSettings, MAX_STREAK_STRETCH, STREAKS_FROM,
    STREAKS_FULL, TONEMAP_RAMP_TOP,
};
pub use sky_map::SkyLight;
pub use solids::{Shape, Solid, SolidInstance, SolidKind, SolidVertex, MAX_SOLIDS};
pub use underwater::{Underwater, WATERLINE_MARGIN_M};

/// Draws the ocean and the sky for both eyes.
pub struct OceanRenderer {
    settings: RendererSettings,
    pipelines: Pipelines,
    textures: CascadeTextures,
    interaction: InteractionTexture,
    /// The layer time last uploaded (`None`: none yet, or the zero texels).
    layer_uploaded: Option<f64>,
    /// Where the layer's part of each slot's staging buffer starts (bytes).
    textures_staging: u64,
    mesh: MeshBuffers,
    targets: Targets,
    sky: SkyMap,
    foam: FoamPattern,
    probe: Option<PathProbe>,
    slots: Slots,
    pass: PassConstants,
    extent: vk::Extent2D,
    /// The part of each eye image drawn (all of it unless [`OceanRenderer::set_render_area`]).
    area: vk::Rect2D,
    /// Whether the anisotropic sampler is read ([`OceanRenderer::set_anisotropic`]).
    anisotropic: bool,
    frame: u64,
}

impl OceanRenderer {
    /// Creates everything for drawing `config`'s cascades on `lod`'s meshes into `targets`.
    /// All or nothing: when a step fails, what was made before it is destroyed.
    pub fn new(
        ctx: &GpuContext,
        config: &OceanConfig,
        lod: &OceanLod,
        targets: TargetImages<'_>,
        settings: RendererSettings,
    ) -> Result<Self, RenderError> {
        validate(config, targets, &settings)?;
        settings
            .sun
            .validate()
            .map_err(|e| RenderError::Invalid(e.to_string()))?;
        let mut parts = Parts::default();
        if let Err(e) = make_parts(ctx, config, lod, targets, &settings, &mut parts) {
            parts.destroy(ctx);
            return Err(e);
        }
        let Parts {
            pipelines: Some(pipelines),
            textures: Some(textures),
            interaction: Some(interaction),
            mesh: Some(mesh),
            targets: Some(out_targets),
            sky: Some(sky),
            foam: Some(foam),
            probe,
            slots: Some(slots),
        } = parts
        else {
            unreachable!("make_parts returned Ok with every part made");
        };
        Ok(Self {
            settings,
            pipelines,
            textures,
            interaction,
            layer_uploaded: None,
            textures_staging: InteractionTexture::staging_offset(CascadeTextures::staging_size(
                config,
            )),
            mesh,
            targets: out_targets,
            sky,
            foam,
            probe,
            slots,
            pass: PassConstants::new(config, lod.settings()),
            extent: targets.extent,
            area: vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: targets.extent,
            },
            anisotropic: true,
            frame: 0,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &RendererSettings {
        &self.settings
    }

    /// Device memory of the pass's transient attachments (multisampled colour and depth, or
    /// the depth alone), bytes: for reports.
    pub fn attachment_bytes(&self) -> u64 {
        self.targets.transient_bytes()
    }

    /// This frame's collapse of the mesh by its thickness on the screen, for the finer of
    /// the two eyes at the drawn width, or the one the settings size it for (a lowered render
    /// scale draws fewer pixels of the same view, so its triangles are thinner on the screen:
    /// the mesh collapses as the pixels do, as `gpu-budget` counts a scaled headset's eye).
    fn screen_collapse(width: u32, input: &FrameInput<'_>) -> ScreenCollapse {
        let ppr = input
            .eyes
            .iter()
            .map(|e| ScreenCollapse::pixels_per_radian(&e.fov, width))
            .fold(0.0, f32::max);
        let viewer = (input.eyes[0].position + input.eyes[1].position) * 0.5;
        ScreenCollapse::new(input.lod.settings(), viewer.y, ppr)
    }

    /// Records and submits one frame into target `input.image`. Waits only for the frame that
    /// last used this slot (`frames_in_flight` frames ago).
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        input: &FrameInput<'_>,
    ) -> Result<FrameReport, RenderError> {
        if input.image as usize >= self.targets.colours
            || input.depth as usize >= self.targets.depths
        {
            return Err(RenderError::Invalid(format!(
                "target image {} of {} (depth {} of {})",
                input.image, self.targets.colours, input.depth, self.targets.depths
            )));
        }
        let ring = self.slots.ring.len();
        let index = (self.frame % ring as u64) as usize;
        self.frame += 1;
        let t0 = Instant::now();
        let taps = self.anisotropy_taps();
        let slot = &mut self.slots.ring[index];
        slot.wait(ctx)?;
        if let Some(p) = self.probe.as_mut() {
            p.collect(ctx, index)?;
        }
        let mut wait = t0.elapsed();
        let t1 = Instant::now();
        // The slot's fence has signalled, so its timestamps are ready (on a CPU device they
        // are read before the submit below instead).
        let mut gpu_pass = if slot.submitted && !ctx.cpu_device {
            slot.read_timestamps(ctx)
        } else {
            None
        };
        // The pixels drawn (a render scale's sub-rectangle has the same field of view).
        let width = self
            .settings
            .mesh_eye_width
            .unwrap_or(self.area.extent.width);
        let collapse = Self::screen_collapse(width, input);
        let mut globals = self
            .pass
            .globals(input, &self.settings, self.sky.light(), &collapse);
        globals.filtering[0] = taps as f32;
        globals.filtering[1] = if self.settings.supersampling {
            1.0
        } else {
            0.0
        };
        slot.write_globals(&globals);
        let skirt_instance = slot.write_instances(input.lod)?;
        let solid_draws = slot.write_solids(input.solids)?;
        // Textures, when the simulation moved on since this slot last uploaded.
        let time = input.surfaces.time();
        let upload = slot.uploaded != Some(time) || self.frame <= 1;
        if upload {
            self.textures
                .stage(slot.staging.bytes_mut(), input.surfaces);
            slot.uploaded = Some(time);
        }
        // The interaction layer, when it stepped since the last upload (the zero texels once).
        let layer = self.settings.drawn_layer(input.interaction);
        let layer_time = layer.map(|l| l.time());
        let layer_upload =
            self.frame <= 1 || (layer.is_some() && self.layer_uploaded != layer_time);
        let layer_offset = self.textures_staging;
        if layer_upload {
            self.interaction.stage(
                &mut slot.staging.bytes_mut()[layer_offset as usize..],
                layer,
            );
            self.layer_uploaded = layer_time;
        }
        slot.begin(ctx)?;
        let (d, cmd) = (&ctx.device, slot.cmd);
        if upload {
            self.textures.record_upload(d, cmd, slot.staging.raw);
        }
        if layer_upload {
            self.interaction
                .record_upload(d, cmd, slot.staging.raw, layer_offset);
        }
        let timed = ctx.timestamp_period.is_some();
        if timed {
            // SAFETY: `cmd` is recording; the pool has TIMESTAMP_QUERIES queries.
            unsafe {
                d.cmd_reset_query_pool(cmd, slot.queries, 0, TIMESTAMP_QUERIES);
                d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, slot.queries, 0);
            }
        }
        let recorder = PassRecorder {
            device: d,
            cmd,
            pipelines: &self.pipelines,
            mesh: &self.mesh,
            instances: slot.instances.raw,
            solids: slot.solids.raw,
            set: slot.set,
            area: self.area,
            vertices_per_side: self.pass.vertices_per_side,
            // The pipeline with the view from below only where the frame needs it.
            under: globals.underwater[0] > 0.5,
            vignette: globals.vignette[0] > 0.0,
            resolve_after: self
                .pipelines
                .layout_of_pass
                .resolves_after_pass()
                .then(|| self.targets.msaa_colour())
                .flatten()
                .map(|msaa| ResolveAfter {
                    msaa,
                    target: self.targets.image(input.image),
                }),
        };
        let passes: &[u32] = match self.settings.stereo {
            StereoMode::Multiview => &[0],
            StereoMode::TwoPass => &[0, 1],
        };
        let mut draws = 0;
        if let Some(p) = self.probe.as_mut() {
            p.begin(d, cmd, index);
        }
        for &eye in passes {
            let fb = self.targets.framebuffer(input.image, input.depth, eye);
            draws += recorder.record(fb, eye, input.lod, skirt_instance, &solid_draws);
        }
        if let Some(p) = self.probe.as_ref() {
            p.end(d, cmd, index);
        }
        // SAFETY: `cmd` is recording, outside a render pass.
        unsafe {
            if timed {
                d.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, slot.queries, 1);
            }
            d.end_command_buffer(cmd)
                .map_err(RenderError::vk("vkEndCommandBuffer"))?;
        }
        let record = t1.elapsed();
        if ctx.cpu_device {
            // lavapipe idles the device in vkGetQueryPoolResults. Reading the previous frame's
            // timestamps here, after recording this one, waits only for work that this submit
            // would queue behind anyway; at the top of the frame it would also stall recording.
            let prev = &self.slots.ring[(index + ring - 1) % ring];
            if prev.submitted {
                let w = Instant::now();
                gpu_pass = prev.read_timestamps(ctx);
                wait += w.elapsed();
            }
        }
        let slot = &mut self.slots.ring[index];
        let t2 = Instant::now();
        let cmds = [slot.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the fence is not in use (it signalled); the command buffer is executable.
        // The fence is reset only now: an error above leaves it signalled, so no later wait
        // hangs.
        unsafe {
            d.reset_fences(&[slot.fence])
                .map_err(RenderError::vk("vkResetFences"))?;
            d.queue_submit(ctx.queue, &submit, slot.fence)
                .map_err(RenderError::vk("vkQueueSubmit"))?;
        }
        slot.submitted = true;
        Ok(FrameReport {
            wait,
            record,
            submit: t2.elapsed(),
            gpu_pass,
            draws,
        })
    }

    /// Moves the sun (a user's time-of-day key, not the steady state): bakes and uploads the new
    /// sky, waiting for the frames in flight first. On an error the old sky stays.
    pub fn set_sun(&mut self, ctx: &GpuContext, sun: SunSky) -> Result<(), RenderError> {
        sun.validate()
            .map_err(|e| RenderError::Invalid(e.to_string()))?;
        self.wait_all(ctx)?;
        let new = SkyMap::new(ctx, &sun)?;
        let mut old = std::mem::replace(&mut self.sky, new);
        old.destroy(ctx);
        for slot in &self.slots.ring {
            slot.write_sky(ctx, self.sky.descriptor());
        }
        self.settings.sun = sun;
        Ok(())
    }

    /// Turns the specular AA (the filtered lobe, and the supersampling where that is on) on or
    /// off from the next frame: only the uniform it writes changes, nothing is rebuilt.
    pub fn set_specular_aa(&mut self, on: bool) {
        self.settings.specular_aa = on;
    }

    /// Turns the specular AA's supersampling on or off from the next frame (the GPU-time
    /// governor's first step; the filtered lobe stays): only the uniform changes.
    pub fn set_supersampling(&mut self, on: bool) {
        self.settings.supersampling = on;
    }

    /// Turns the anisotropic filtering of the normal maps off or back on from the next frame
    /// (the GPU-time governor's first step, with the supersampling): only the uniform changes.
    pub fn set_anisotropic(&mut self, on: bool) {
        self.anisotropic = on;
    }

    /// The most taps the normal maps' samples take now: the setting within the device's
    /// limit while on, 1 when off or where the device has no anisotropic filtering.
    pub fn anisotropy_taps(&self) -> u32 {
        if self.anisotropic {
            self.textures.anisotropy_taps()
        } else {
            1
        }
    }

    /// Draws into `area` of each eye image from the next frame (the GPU-time governor's render
    /// scale; the whole image by default): viewport, scissor and render area shrink, the
    /// projection stays, nothing is reallocated. Refused unless `area` is non-empty and lies
    /// in the images.
    pub fn set_render_area(&mut self, area: vk::Rect2D) -> Result<(), RenderError> {
        let fits = |offset: i32, len: u32, full: u32| {
            offset >= 0 && len > 0 && offset as u64 + u64::from(len) <= u64::from(full)
        };
        if !(fits(area.offset.x, area.extent.width, self.extent.width)
            && fits(area.offset.y, area.extent.height, self.extent.height))
        {
            return Err(RenderError::Invalid(format!(
                "render area {}x{} at ({}, {}) does not lie in the {}x{} eye image",
                area.extent.width,
                area.extent.height,
                area.offset.x,
                area.offset.y,
                self.extent.width,
                self.extent.height
            )));
        }
        self.area = area;
        Ok(())
    }

    /// The shading paths and invocations counted per frame so far, when the renderer counts
    /// ([`RendererSettings::count_paths`]); waits for every frame in flight first.
    pub fn path_counts(&mut self, ctx: &GpuContext) -> Result<Option<PathCounts>, RenderError> {
        self.wait_all(ctx)?;
        self.probe.as_mut().map(|p| p.counts(ctx)).transpose()
    }

    /// Waits for every frame in flight (shutdown and read-back only).
    pub fn wait_all(&self, ctx: &GpuContext) -> Result<(), RenderError> {
        let ring = &self.slots.ring;
        let fences: [vk::Fence; 4] =
            std::array::from_fn(|i| ring.get(i).map_or(vk::Fence::null(), |s| s.fence));
        // SAFETY: the fences are alive.
        unsafe {
            ctx.device
                .wait_for_fences(&fences[..ring.len()], true, u64::MAX)
        }
        .map_err(RenderError::vk("vkWaitForFences"))
    }

    /// Frees everything. The caller makes sure the GPU is idle (e.g. [`GpuContext::wait_idle`]).
    pub fn destroy(&mut self, ctx: &GpuContext) {
        if let Some(p) = self.probe.as_mut() {
            p.destroy(ctx);
        }
        self.slots.destroy(ctx);
        self.targets.destroy(ctx);
        self.foam.destroy(ctx);
        self.sky.destroy(ctx);
        self.mesh.destroy(ctx);
        self.textures.destroy(ctx);
        self.interaction.destroy(ctx);
        self.pipelines.destroy(ctx);
    }
}
