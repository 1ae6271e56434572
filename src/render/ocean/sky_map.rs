//! The sky the pass draws, reflects and fogs with: the atmosphere and clouds
//! ([`crate::render::sky`]) baked on the CPU into a GGX-prefiltered environment map (RGBA16F, one mip per roughness)
//! and uploaded once, with the sun's and the sky's light and the exposure the shaders scale by.
//! Its second layer is the same sky as the display shows it (exposed and through the tone
//! curve, `render::tonemap`): the pixels that see the sky read it and are done, the curve not
//! run per pixel.
//! Made when the renderer is (and again when the sun moves): never per frame.

use ash::vk;
use glam::Vec3;

use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Image, ImageDesc};
use crate::render::sampler::sampler_with;
use crate::render::sky::{self, EnvMap, Sky, SunSky, SUN_ANGULAR_RADIUS_DEG};
use crate::render::upload::{upload_layers, Level};

/// Level 0 of the environment map: texels along the azimuth (diamond-angle spaced: 2π/320 at
/// the diagonals, π/320 at the axes; the sky seen directly reads level 0, and clouds' edges
/// need the detail: at 160 they showed the texels)...
pub const ENV_WIDTH: u32 = 320;
/// ...and from the horizon to the zenith (square-root spaced, the horizon finest; 128 keeps two
/// rows in the roughest level).
pub const ENV_HEIGHT: u32 = 128;
/// Levels: roughness 0, 1/6, ..., 1.
pub const ENV_LEVELS: u32 = 7;

/// The light the shaders need besides the map (absolute units: kcd/m², klux).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyLight {
    /// Unit vector toward the sun.
    pub sun_direction: Vec3,
    /// Radiance of the sun's disc (kcd/m², linear sRGB).
    pub sun_radiance: Vec3,
    /// Sun illuminance at normal incidence (klux).
    pub sun_illuminance: Vec3,
    /// Illuminance of the sky dome on a horizontal surface (klux).
    pub sky_illuminance: Vec3,
    /// Multiplier from kcd/m² to the tonemapper's input ([`sky::exposure`]).
    pub exposure: f32,
    /// Cosine of the sun disc's angular radius.
    pub sun_cos_radius: f32,
    /// Levels of the map.
    pub levels: u32,
}

/// The environment map on the GPU and the light it was baked with.
pub(super) struct SkyMap {
    image: Image,
    sampler: vk::Sampler,
    light: SkyLight,
}

impl SkyMap {
    /// Bakes the sky of `sun` and uploads it (waits for the copy: set-up only). Nothing is left
    /// behind when a step fails.
    pub fn new(ctx: &GpuContext, sun: &SunSky) -> Result<Self, RenderError> {
        let (sky, map) = bake(sun);
        let mut this = Self {
            image: Image::null(),
            sampler: vk::Sampler::null(),
            light: light_of(&sky, map.levels.len() as u32),
        };
        if let Err(e) = this.create(ctx, &map) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, ctx: &GpuContext, map: &EnvMap) -> Result<(), RenderError> {
        let levels = map.levels.len() as u32;
        self.image = Image::new(
            ctx,
            ImageDesc {
                format: vk::Format::R16G16B16A16_SFLOAT,
                extent: vk::Extent2D {
                    width: map.width,
                    height: map.height,
                },
                layers: 2,
                mips: levels,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                aspect: vk::ImageAspectFlags::COLOR,
                transient: false,
            },
        )?;
        // u wraps around the azimuth; v stops at the horizon and the zenith.
        let address = [
            vk::SamplerAddressMode::REPEAT,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
        ];
        self.sampler = sampler_with(ctx, levels as f32, address)?;
        upload(ctx, map, self.light.exposure, &self.image)
    }

    /// The descriptor of the map (binding 4).
    pub fn descriptor(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }
    }

    /// The sun's and the sky's light and the exposure.
    pub fn light(&self) -> &SkyLight {
        &self.light
    }

    /// Frees what was made. The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the sampler; a null handle is a no-op.
        unsafe { ctx.device.destroy_sampler(self.sampler, None) };
        self.sampler = vk::Sampler::null();
        self.image.destroy(ctx);
    }
}

/// The sky of `sun` and its baked map.
fn bake(sun: &SunSky) -> (Sky, EnvMap) {
    let sky = Sky::new(sun);
    let map = sky::bake(&sky, ENV_WIDTH, ENV_HEIGHT, ENV_LEVELS);
    (sky, map)
}

/// What the shaders need of `sky`.
fn light_of(sky: &Sky, levels: u32) -> SkyLight {
    SkyLight {
        sun_direction: sky.sun_direction(),
        sun_radiance: sky.sun_radiance(),
        sun_illuminance: sky.sun_illuminance(),
        sky_illuminance: sky.sky_illuminance(),
        exposure: sky::exposure(sky),
        sun_cos_radius: SUN_ANGULAR_RADIUS_DEG.to_radians().cos(),
        levels,
    }
}

/// Copies every level of `map` (as half floats) into layer 0 of `image` and the same exposed
/// and tone-mapped (`display` in `shaders/common.glsl`) into layer 1, ready for sampling.
fn upload(ctx: &GpuContext, map: &EnvMap, exposure: f32, image: &Image) -> Result<(), RenderError> {
    let halves = |shown: fn(Vec3, f32) -> Vec3| -> Vec<Vec<u8>> {
        map.levels
            .iter()
            .map(|level| {
                let texels: Vec<[u16; 4]> = level
                    .iter()
                    .map(|t| {
                        let c = shown(Vec3::new(t[0], t[1], t[2]), exposure);
                        [c.x, c.y, c.z, t[3]].map(|c| half::f16::from_f32(c).to_bits())
                    })
                    .collect();
                bytemuck::cast_slice(&texels).to_vec()
            })
            .collect()
    };
    let radiance = halves(|c, _| c);
    let display = halves(displayed);
    upload_layers(
        ctx,
        image,
        &[&levels_of(map, &radiance), &levels_of(map, &display)],
    )
}

/// The levels of one layer of `map`, their texels `bytes`.
fn levels_of<'a>(map: &EnvMap, bytes: &'a [Vec<u8>]) -> Vec<Level<'a>> {
    bytes
        .iter()
        .enumerate()
        .map(|(m, bytes)| {
            let (width, height) = map.level_size(m);
            Level {
                bytes,
                width,
                height,
            }
        })
        .collect()
}

/// Half precision's largest finite value, less a margin: what `display` in
/// `shaders/common.glsl` holds the exposed radiance under.
const HALF_MAX: f32 = 65000.0;

/// What the display shows of radiance `c` (kcd/m²) at `exposure`: as the shaders' `display`.
pub fn displayed(c: Vec3, exposure: f32) -> Vec3 {
    crate::render::tonemap::pbr_neutral((c.max(Vec3::ZERO) * exposure).min(Vec3::splat(HALF_MAX)))
}
