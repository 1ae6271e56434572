//! The samplers every texture of the renderer is read through: trilinear (mips, linear within
//! and between them), repeating or clamped, and anisotropic where asked.

use ash::vk;

use super::context::GpuContext;
use super::error::RenderError;

/// A trilinear, repeating sampler reading mips 0..=`max_lod`.
pub(crate) fn sampler(ctx: &GpuContext, max_lod: f32) -> Result<vk::Sampler, RenderError> {
    use vk::SamplerAddressMode as A;
    sampler_with(ctx, max_lod, [A::REPEAT, A::REPEAT])
}

/// A trilinear sampler reading mips 0..=`max_lod`, addressing u and v as `address` says (w as
/// v).
pub(crate) fn sampler_with(
    ctx: &GpuContext,
    max_lod: f32,
    address: [vk::SamplerAddressMode; 2],
) -> Result<vk::Sampler, RenderError> {
    sampler_of(ctx, max_lod, address, 1.0)
}

/// [`sampler_with`], anisotropic up to `anisotropy` taps when above 1 (the device must have
/// `samplerAnisotropy` enabled).
pub(crate) fn sampler_of(
    ctx: &GpuContext,
    max_lod: f32,
    address: [vk::SamplerAddressMode; 2],
    anisotropy: f32,
) -> Result<vk::Sampler, RenderError> {
    let info = vk::SamplerCreateInfo::default()
        .anisotropy_enable(anisotropy > 1.0)
        .max_anisotropy(anisotropy.max(1.0))
        .mag_filter(vk::Filter::LINEAR)
        .min_filter(vk::Filter::LINEAR)
        .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
        .address_mode_u(address[0])
        .address_mode_v(address[1])
        .address_mode_w(address[1])
        .min_lod(0.0)
        .max_lod(max_lod);
    // SAFETY: a valid create info on a live device.
    ctx.create("vkCreateSampler", || unsafe {
        ctx.device.create_sampler(&info, None)
    })
}
