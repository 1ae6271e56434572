//! Making a renderer: the settings checked before anything exists, then its parts created one
//! after the other, all or nothing (whatever exists is destroyed when a later step fails).

use super::foam_pattern::FoamPattern;
use super::frame::{TargetImages, MAX_CASCADES};
use super::interaction::InteractionTexture;
use super::mesh::MeshBuffers;
use super::pipelines::Pipelines;
use super::probe::PathProbe;
use super::sky_map::SkyMap;
use super::slots::{SlotSizes, Slots};
use super::textures::CascadeTextures;
use super::RendererSettings;
use crate::lod::OceanLod;
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::render_pass::PassLayout;
use crate::render::targets::Targets;
use crate::sim::OceanConfig;

/// The parts of a renderer, made one after the other; whatever exists is destroyed when a
/// later step fails.
#[derive(Default)]
pub(super) struct Parts {
    pub pipelines: Option<Pipelines>,
    pub textures: Option<CascadeTextures>,
    pub interaction: Option<InteractionTexture>,
    pub mesh: Option<MeshBuffers>,
    pub targets: Option<Targets>,
    pub sky: Option<SkyMap>,
    pub foam: Option<FoamPattern>,
    pub probe: Option<PathProbe>,
    pub slots: Option<Slots>,
}

impl Parts {
    pub fn destroy(&mut self, ctx: &GpuContext) {
        if let Some(mut p) = self.probe.take() {
            p.destroy(ctx);
        }
        if let Some(mut s) = self.slots.take() {
            s.destroy(ctx);
        }
        if let Some(mut t) = self.targets.take() {
            t.destroy(ctx);
        }
        if let Some(mut f) = self.foam.take() {
            f.destroy(ctx);
        }
        if let Some(mut s) = self.sky.take() {
            s.destroy(ctx);
        }
        if let Some(mut m) = self.mesh.take() {
            m.destroy(ctx);
        }
        if let Some(mut t) = self.textures.take() {
            t.destroy(ctx);
        }
        if let Some(mut t) = self.interaction.take() {
            t.destroy(ctx);
        }
        if let Some(mut p) = self.pipelines.take() {
            p.destroy(ctx);
        }
    }
}

/// Checks the settings and targets before anything is created.
pub(super) fn validate(
    config: &OceanConfig,
    targets: TargetImages<'_>,
    settings: &RendererSettings,
) -> Result<(), RenderError> {
    if settings.frames_in_flight < 2 || settings.frames_in_flight > 4 {
        return Err(RenderError::Invalid(format!(
            "frames in flight: {} is outside [2, 4]",
            settings.frames_in_flight
        )));
    }
    if !(settings.fog_distance.is_finite() && settings.fog_distance > 0.0) {
        return Err(RenderError::Invalid(format!(
            "fog distance {} m: must be a positive number of metres",
            settings.fog_distance
        )));
    }
    if config.patch_sizes.len() > MAX_CASCADES {
        return Err(RenderError::Invalid(format!(
            "{} cascades: the renderer draws at most {MAX_CASCADES}",
            config.patch_sizes.len()
        )));
    }
    if !targets.density_maps.is_empty() && targets.density_maps.len() != targets.images.len() {
        return Err(RenderError::Invalid(format!(
            "{} density maps for {} colour images: one each",
            targets.density_maps.len(),
            targets.images.len()
        )));
    }
    if targets.extent.width == 0 || targets.extent.height == 0 {
        return Err(RenderError::Invalid(format!(
            "target size {}x{}: both sides must be at least 1 pixel",
            targets.extent.width, targets.extent.height
        )));
    }
    Ok(())
}

/// Makes the parts in order into `parts` (the caller destroys them if this fails).
pub(super) fn make_parts(
    ctx: &GpuContext,
    config: &OceanConfig,
    lod: &OceanLod,
    targets: TargetImages<'_>,
    settings: &RendererSettings,
    parts: &mut Parts,
) -> Result<(), RenderError> {
    let pass = PassLayout {
        mode: settings.stereo,
        colour_format: targets.format,
        msaa: settings.msaa,
        store_depth: !targets.depth.is_empty(),
        density_map: !targets.density_maps.is_empty(),
    };
    let pipelines = parts
        .pipelines
        .insert(Pipelines::new(ctx, pass, settings.count_paths)?);
    let taps = settings.anisotropy.on_device(ctx.max_anisotropy);
    if taps < settings.anisotropy.taps() {
        log::warn!(
            "anisotropic filtering: {} taps asked for, {} drawn ({})",
            settings.anisotropy.taps(),
            taps,
            ctx.max_anisotropy.map_or(
                "the device has no samplerAnisotropy".to_string(),
                |m| format!("the device filters up to {m}x")
            )
        );
    }
    let textures = parts
        .textures
        .insert(CascadeTextures::new(ctx, config, taps)?);
    let interaction = parts
        .interaction
        .insert(InteractionTexture::new(ctx, settings.interaction)?);
    parts.mesh = Some(MeshBuffers::new(ctx, lod)?);
    parts.targets = Some(Targets::new(
        ctx,
        &pipelines.layout_of_pass,
        pipelines.render_pass,
        targets,
    )?);
    let map = lod.settings().map_width() as usize;
    let sizes = SlotSizes {
        staging: InteractionTexture::staging_offset(CascadeTextures::staging_size(config))
            + InteractionTexture::staging_size(settings.interaction),
        instances: map * map + 1,
    };
    let frames = settings.frames_in_flight;
    let sky = parts.sky.insert(SkyMap::new(ctx, &settings.sun)?);
    let [disp, norm, caps, norm_aniso] = textures.descriptors();
    let finest = config.patch_sizes.last().copied().unwrap_or(16.0) as f64;
    let nyquist = std::f64::consts::PI * config.grid.n() as f64 / finest;
    let foam = parts.foam.insert(FoamPattern::new(ctx, nyquist)?);
    let images = [
        disp,
        norm,
        caps,
        sky.descriptor(),
        foam.descriptor(),
        interaction.descriptor(),
        norm_aniso,
    ];
    let tally = if settings.count_paths {
        Some(
            parts
                .probe
                .insert(PathProbe::new(ctx, frames)?)
                .descriptor(),
        )
    } else {
        None
    };
    parts.slots = Some(Slots::new(ctx, pipelines, &images, tally, sizes, frames)?);
    Ok(())
}
