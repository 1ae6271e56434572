//! The simulation's textures: the cascades' displacement (RGBA16F, one layer per cascade) and
//! normal/foam (RGBA8 with the eq. 55 mip chain), and the whitecap coverage of the whole surface
//! (R8 with its mip chain, one layer per level of [`crate::sim::whitecaps`], toroidal: sampled
//! with REPEAT at world uv = (x/s + ½)/T) live once on the GPU. Each frame that brings
//! new surfaces stages them into its slot's buffer and records the copy, ordered after the
//! previous frame's reads by a barrier in the same queue.

use ash::vk;

use crate::render::barrier::{Access, ImageBarrier};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::{Image, ImageDesc};
use crate::render::sampler::{sampler, sampler_of};
use crate::render::transfer::{colour_region, record_staged_copies};
use crate::sim::whitecaps::{WHITECAP_LEVELS, WHITECAP_TEXELS};
use crate::sim::{pack, GridSize, OceanConfig, Surfaces};

/// The three texture arrays, their samplers and the copy regions of one upload.
pub(super) struct CascadeTextures {
    displacement: Image,
    normals: Image,
    whitecaps: Image,
    disp_sampler: vk::Sampler,
    normal_sampler: vk::Sampler,
    /// The normal maps' anisotropic sampler (null when the renderer filters without).
    normal_aniso_sampler: vk::Sampler,
    /// Its most taps (1: none).
    taps: u32,
    whitecap_sampler: vk::Sampler,
    /// Copy regions of the last staged upload: the displacement layers first, then every mip
    /// of every normal/foam layer, then every mip of every whitecap level. Sized at creation.
    regions: Vec<vk::BufferImageCopy>,
    /// How many of `regions` are the displacement's.
    disp_regions: usize,
    /// Where the whitecaps' regions start in `regions`.
    whitecap_regions: usize,
}

/// The whitecap maps' grid (one side of [`WHITECAP_TEXELS`]).
fn whitecap_grid() -> GridSize {
    GridSize::new(WHITECAP_TEXELS as u32).expect("WHITECAP_TEXELS is a power of two")
}

impl CascadeTextures {
    /// The images and samplers for `config`'s grid and cascades, the normal maps also through
    /// an anisotropic sampler of `taps` (when above 1). Nothing is left behind when a step
    /// fails.
    pub fn new(ctx: &GpuContext, config: &OceanConfig, taps: u32) -> Result<Self, RenderError> {
        let mut this = Self {
            displacement: Image::null(),
            normals: Image::null(),
            whitecaps: Image::null(),
            disp_sampler: vk::Sampler::null(),
            normal_sampler: vk::Sampler::null(),
            normal_aniso_sampler: vk::Sampler::null(),
            taps: 1,
            whitecap_sampler: vk::Sampler::null(),
            regions: Vec::new(),
            disp_regions: 0,
            whitecap_regions: 0,
        };
        if let Err(e) = this.create(ctx, config, taps) {
            this.destroy(ctx);
            return Err(e);
        }
        Ok(this)
    }

    fn create(
        &mut self,
        ctx: &GpuContext,
        config: &OceanConfig,
        taps: u32,
    ) -> Result<(), RenderError> {
        let n = config.grid.n() as u32;
        let cascades = config.patch_sizes.len() as u32;
        let mips = config.grid.mip_levels();
        let desc = |format, mips| ImageDesc {
            format,
            extent: vk::Extent2D {
                width: n,
                height: n,
            },
            layers: cascades,
            mips,
            samples: vk::SampleCountFlags::TYPE_1,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
            transient: false,
        };
        self.displacement = Image::new(ctx, desc(vk::Format::R16G16B16A16_SFLOAT, 1))?;
        self.normals = Image::new(ctx, desc(vk::Format::R8G8B8A8_UNORM, mips))?;
        self.disp_sampler = sampler(ctx, 0.0)?;
        self.normal_sampler = sampler(ctx, mips as f32)?;
        if taps > 1 {
            let address = [vk::SamplerAddressMode::REPEAT; 2];
            self.normal_aniso_sampler = sampler_of(ctx, mips as f32, address, taps as f32)?;
            self.taps = taps;
        }
        let wg = whitecap_grid();
        let side = WHITECAP_TEXELS as u32;
        self.whitecaps = Image::new(
            ctx,
            ImageDesc {
                extent: vk::Extent2D {
                    width: side,
                    height: side,
                },
                layers: WHITECAP_LEVELS as u32,
                ..desc(vk::Format::R8_UNORM, wg.mip_levels())
            },
        )?;
        self.whitecap_sampler = sampler(ctx, wg.mip_levels() as f32)?;
        self.regions = Vec::with_capacity(
            cascades as usize * (1 + mips as usize) + WHITECAP_LEVELS * wg.mip_levels() as usize,
        );
        Ok(())
    }

    /// Bytes of one frame's staging copy for `config`.
    pub fn staging_size(config: &OceanConfig) -> u64 {
        let n = config.grid.n() as u64;
        let per_cascade = n * n * 8 + pack::mip_chain_len(config.grid) as u64 * 4;
        let whitecaps = WHITECAP_LEVELS as u64 * pack::mip_chain_len(whitecap_grid()) as u64;
        per_cascade * config.patch_sizes.len() as u64 + whitecaps
    }

    /// The most taps of the normal maps' anisotropic sampler (1: there is none).
    pub fn anisotropy_taps(&self) -> u32 {
        self.taps
    }

    /// The descriptor infos of the displacement (binding 1), normal/foam (binding 2) and
    /// whitecap (binding 3) arrays, and of the normal/foam array through the anisotropic
    /// sampler (binding 8; the trilinear one when there is none).
    pub fn descriptors(&self) -> [vk::DescriptorImageInfo; 4] {
        let info = |sampler, image_view| vk::DescriptorImageInfo {
            sampler,
            image_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        [
            info(self.disp_sampler, self.displacement.view),
            info(self.normal_sampler, self.normals.view),
            info(self.whitecap_sampler, self.whitecaps.view),
            info(
                if self.normal_aniso_sampler == vk::Sampler::null() {
                    self.normal_sampler
                } else {
                    self.normal_aniso_sampler
                },
                self.normals.view,
            ),
        ]
    }

    /// Copies `surfaces` into `staging` (a slot's mapped buffer of [`Self::staging_size`]
    /// bytes) and notes the copy regions. No allocation.
    pub fn stage(&mut self, staging: &mut [u8], surfaces: &Surfaces) {
        let grid = surfaces.cascades[0].grid;
        let n = grid.n() as u32;
        self.regions.clear();
        let mut offset = 0usize;
        for (c, s) in surfaces.cascades.iter().enumerate() {
            let disp: &[u8] = bytemuck::cast_slice(&s.displacement_f16);
            staging[offset..offset + disp.len()].copy_from_slice(disp);
            self.regions.push(region(offset, c as u32, 0, n));
            offset += disp.len();
        }
        self.disp_regions = self.regions.len();
        for (c, s) in surfaces.cascades.iter().enumerate() {
            let chain: &[u8] = bytemuck::cast_slice(&s.normal_foam);
            staging[offset..offset + chain.len()].copy_from_slice(chain);
            for level in 0..grid.mip_levels() {
                let at = offset + 4 * pack::mip_offset(grid, level);
                self.regions.push(region(at, c as u32, level, n >> level));
            }
            offset += chain.len();
        }
        self.whitecap_regions = self.regions.len();
        let wg = whitecap_grid();
        for (l, level) in surfaces.whitecaps.levels.iter().enumerate() {
            let chain = &level.coverage[..];
            staging[offset..offset + chain.len()].copy_from_slice(chain);
            for mip in 0..wg.mip_levels() {
                let at = offset + pack::mip_offset(wg, mip);
                self.regions
                    .push(region(at, l as u32, mip, WHITECAP_TEXELS as u32 >> mip));
            }
            offset += chain.len();
        }
    }

    /// Records the copy of the last staged upload from `staging`: shader reads of the previous
    /// frame → transfer writes (contents discarded: every texel is rewritten) → shader reads.
    pub fn record_upload(&self, d: &ash::Device, cmd: vk::CommandBuffer, staging: vk::Buffer) {
        let (disp, norm, caps) = (&self.displacement, &self.normals, &self.whitecaps);
        let to_copy = [
            ImageBarrier::colour(
                disp.raw,
                disp.layers,
                Access::ShaderSampled,
                Access::TransferWrite,
            )
            .discard(),
            ImageBarrier::colour(
                norm.raw,
                norm.layers,
                Access::ShaderSampled,
                Access::TransferWrite,
            )
            .mips(norm.mips)
            .discard(),
            ImageBarrier::colour(
                caps.raw,
                caps.layers,
                Access::ShaderSampled,
                Access::TransferWrite,
            )
            .mips(caps.mips)
            .discard(),
        ];
        let (disp_regions, rest) = self.regions.split_at(self.disp_regions);
        let (norm_regions, cap_regions) = rest.split_at(self.whitecap_regions - self.disp_regions);
        // Every region lies inside the staging buffer and its image (`stage`).
        record_staged_copies(
            d,
            cmd,
            staging,
            to_copy,
            [disp_regions, norm_regions, cap_regions],
        );
    }

    /// Frees what was made. The GPU must be done with it.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        // SAFETY: the GPU no longer uses the samplers; null handles are no-ops.
        unsafe {
            ctx.device.destroy_sampler(self.disp_sampler, None);
            ctx.device.destroy_sampler(self.normal_sampler, None);
            ctx.device.destroy_sampler(self.normal_aniso_sampler, None);
            ctx.device.destroy_sampler(self.whitecap_sampler, None);
        }
        self.disp_sampler = vk::Sampler::null();
        self.normal_sampler = vk::Sampler::null();
        self.whitecap_sampler = vk::Sampler::null();
        self.displacement.destroy(ctx);
        self.normals.destroy(ctx);
        self.whitecaps.destroy(ctx);
    }
}

/// The copy of a square level of `side` texels at `offset` of the staging buffer into `layer`.
pub(super) fn region(offset: usize, layer: u32, level: u32, side: u32) -> vk::BufferImageCopy {
    colour_region(offset as u64, layer, level, [0, 0], [side, side])
}
