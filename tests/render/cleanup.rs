//! Renderer creation is all or nothing: a failure injected at every object creation in turn
//! (`GpuContext::fail_creation_after`) must return that error and leave no Vulkan object
//! behind, which the validation layer reports when the device is destroyed.

use crate::common;

use ash::vk;
use vr_ocean::lod::OceanLod;
use vr_ocean::render::memory::{Image, ImageDesc};
use vr_ocean::render::{Msaa, OceanRenderer, RenderError, StereoMode, TargetImages, DEPTH_FORMAT};
use vr_ocean::xr::desktop::{EyeSize, HeadlessXr};
use vr_ocean::xr::FrameLoop;

/// Which target images the renderer is handed.
#[derive(Clone, Copy, Debug)]
enum Depth {
    /// None: the renderer makes its own transient depth image.
    Own,
    /// Two 2-layer depth images of the caller's (an OpenXR depth swapchain).
    Given,
}

/// Tries to create a renderer with the `successes + 1`-th creation failing. Returns whether
/// creation succeeded (the injection came too late); panics on a leak or a wrong error.
fn attempt(stereo: StereoMode, depth: Depth, msaa: Msaa, successes: u32) -> bool {
    let mut opts = common::gpu::small_options(stereo, Vec::new());
    opts.renderer.msaa = msaa;
    let size = EyeSize::new(48, 40).unwrap();
    let xr = HeadlessXr::new(
        &common::gpu::validated(),
        size,
        common::gpu::standing(4.0, 0.0, 0.0),
        1,
    )
    .unwrap_or_else(|e| panic!("cannot start headless Vulkan (lavapipe): {e}"));
    let ctx = xr.gpu();
    let log = ctx.validation.clone().expect("validation layer loaded");
    let mut depth_images: Vec<Image> = Vec::new();
    if let Depth::Given = depth {
        for _ in 0..2 {
            depth_images.push(
                Image::new(
                    ctx,
                    ImageDesc {
                        format: DEPTH_FORMAT,
                        extent: size.extent(),
                        layers: 2,
                        mips: 1,
                        samples: vk::SampleCountFlags::TYPE_1,
                        usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                        aspect: vk::ImageAspectFlags::DEPTH,
                        transient: false,
                    },
                )
                .unwrap(),
            );
        }
    }
    let raw_depth: Vec<vk::Image> = depth_images.iter().map(|i| i.raw).collect();
    let targets = TargetImages {
        depth: &raw_depth,
        ..xr.targets()
    };
    let lod = OceanLod::new(opts.lod);
    ctx.fail_creation_after(successes);
    let result = OceanRenderer::new(ctx, &opts.ocean, &lod, targets, opts.renderer);
    ctx.fail_creation_after(u32::MAX);
    let made = match result {
        Ok(mut r) => {
            r.destroy(ctx);
            true
        }
        Err(RenderError::Vk {
            result: vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
            ..
        }) => false,
        Err(e) => panic!("{stereo:?}/{depth:?}, failure after {successes}: unexpected error {e}"),
    };
    for mut i in depth_images {
        i.destroy(ctx);
    }
    drop(xr);
    assert_eq!(
        log.errors(),
        0,
        "{stereo:?}/{depth:?}, failure after {successes} creations: validation errors (leaked \
         objects are reported at device destruction): {:?}",
        log.messages()
    );
    made
}

#[test]
fn a_failure_at_any_creation_step_leaks_nothing() {
    // Given depth images are single-sample (kept for the compositor); our own can be
    // multisampled, with the multisampled colour and the resolve.
    for (stereo, depth, msaa) in [
        (StereoMode::Multiview, Depth::Given, Msaa::X1),
        (StereoMode::TwoPass, Depth::Own, Msaa::X4),
    ] {
        let mut steps = 0;
        while !attempt(stereo, depth, msaa, steps) {
            steps += 1;
            assert!(steps < 500, "renderer creation never succeeds");
        }
        // Pipelines, textures, meshes, targets and two slots: dozens of objects, each of
        // whose failures was injected above.
        assert!(
            steps > 30,
            "{stereo:?}/{depth:?}: only {steps} creations seen"
        );
        println!(
            "{stereo:?}/{depth:?}/{msaa:?}: {steps} creation steps, each failure left nothing \
             behind"
        );
    }
}
