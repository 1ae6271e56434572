//! The ocean's shading paths, each as a pipeline of its own ([`WATER_PATHS`]), and every
//! pipeline a headset draws built once on a device that reports its compiler's statistics
//! ([`headset_pipelines`]): what `shader-stats` and the Adreno report read.

use ash::vk;

use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::statistics::PipelineStatistics;

/// One of the ocean's shading paths as a pipeline of its own.
#[derive(Clone, Copy, Debug)]
pub struct WaterPath {
    /// Its name in `gpu-budget`'s `adreno_paths`.
    pub name: &'static str,
    /// Its pipeline's label.
    pub label: &'static str,
    /// Its cost variant's fragment shader (`render::shaders::cost`).
    pub module: &'static [u32],
}

/// The ocean's shading paths as pipelines of their own: each cost variant's fragment shader
/// with the ocean's vertex shader, in the ocean's pass.
pub const WATER_PATHS: [WaterPath; 11] = {
    use crate::render::shaders::cost;
    const fn path(name: &'static str, label: &'static str, module: &'static [u32]) -> WaterPath {
        WaterPath {
            name,
            label,
            module,
        }
    }
    [
        path("sky", "water path: sky", cost::SKY),
        path("single", "water path: single", cost::SINGLE),
        path(
            "supersampled",
            "water path: supersampled",
            cost::SUPERSAMPLED,
        ),
        path(
            "supersampled_resampled",
            "water path: supersampled, the finest cascade again",
            cost::SUPERSAMPLED_RESAMPLE,
        ),
        path("foam", "water path: single with foam", cost::FOAM),
        path("plain", "water path: plain", cost::PLAIN),
        path("detail", "water path: single with detail", cost::DETAIL),
        path("union", "water path: every branch", cost::UNION),
        path(
            "knee",
            "water path: single through the tone curve's knee",
            cost::KNEE,
        ),
        path("below", "water path: the surface from below", cost::BELOW),
        path("depths", "water path: the depths", cost::DEPTHS),
    ]
};

/// Builds, on `ctx` (which captures statistics), every pipeline a headset draws in `pass` (the
/// ocean, its solids, the control panel) and each water path as a pipeline of its own
/// ([`WATER_PATHS`]), then frees them; returns what the driver's compiler reported.
pub fn headset_pipelines(
    ctx: &GpuContext,
    pass: crate::render::render_pass::PassLayout,
) -> Result<Vec<PipelineStatistics>, RenderError> {
    use crate::render::ocean::pipelines::{ocean_program, Pipelines};
    use crate::render::program::{build, Target};
    let Some(log) = ctx.pipeline_statistics.as_ref() else {
        return Err(RenderError::Unsupported(format!(
            "compiler statistics (VK_KHR_pipeline_executable_properties) on {}",
            ctx.device_name
        )));
    };
    let mut pipelines = Pipelines::new(ctx, pass, false)?;
    let multiview = pass.mode == crate::render::render_pass::StereoMode::Multiview;
    let target = Target {
        layout: pipelines.layout,
        render_pass: pipelines.render_pass,
        msaa: pass.msaa,
    };
    let mut made = Vec::new();
    let mut result = Ok(());
    for path in &WATER_PATHS {
        match build(
            ctx,
            &ocean_program(path.label, multiview, path.module),
            target,
        ) {
            Ok(p) => made.push(p),
            Err(e) => {
                result = Err(e);
                break;
            }
        }
    }
    if result.is_ok() {
        let panel = crate::render::panel::PanelPainter::new(
            ctx,
            crate::render::panel::PanelTarget {
                format: vk::Format::R8G8B8A8_SRGB,
                then: crate::render::barrier::Access::ColourAttachment,
            },
        );
        match panel {
            Ok(mut p) => p.destroy(ctx),
            Err(e) => result = Err(e),
        }
    }
    // SAFETY: the pipelines were never used.
    unsafe {
        for p in made {
            ctx.device.destroy_pipeline(p, None);
        }
    }
    pipelines.destroy(ctx);
    result.map(|()| log.pipelines())
}
