//! SPIR-V of the GLSL in `shaders/` (Vulkan 1.1): compiled by `build.rs` with glslang, or the
//! committed `shaders/spirv/` on machines without it.

/// SPIR-V words, 4-byte aligned as `vkCreateShaderModule` requires.
macro_rules! spirv {
    ($name:literal) => {{
        #[repr(C, align(4))]
        struct Aligned<T: ?Sized>(T);
        const BYTES: &Aligned<[u8]> = &Aligned(*include_bytes!(concat!(
            env!("OUT_DIR"),
            "/",
            $name,
            ".spv"
        )));
        // SAFETY: 4-byte aligned and SPIR-V is a whole number of words.
        unsafe { std::slice::from_raw_parts(BYTES.0.as_ptr() as *const u32, BYTES.0.len() / 4) }
    }};
}

/// Ocean vertex shader, eye from `gl_ViewIndex`.
pub const OCEAN_VERT_MULTIVIEW: &[u32] = spirv!("ocean_mv.vert");
/// Ocean vertex shader, eye from a push constant.
pub const OCEAN_VERT: &[u32] = spirv!("ocean.vert");
/// Ocean fragment shader.
pub const OCEAN_FRAG: &[u32] = spirv!("ocean.frag");
/// Ocean fragment shader with the view from under the water and the waterline (issue 45), for
/// frames some of which are under it.
pub const OCEAN_FRAG_UNDER: &[u32] = spirv!("ocean_under.frag");
/// Ocean fragment shader for a pass with a fragment density map (fixed foveation): peripheral
/// fragments, which cover several pixels, never take the supersampled path.
pub const OCEAN_FRAG_FDM: &[u32] = spirv!("ocean_fdm.frag");
/// The same with the view from under the water.
pub const OCEAN_FRAG_FDM_UNDER: &[u32] = spirv!("ocean_fdm_under.frag");
/// Ocean fragment shader tallying its pixels' paths into a storage buffer (binding 6): the
/// counting variant of `vr-ocean gpu-budget`.
pub const OCEAN_FRAG_COUNT: &[u32] = spirv!("ocean_count.frag");

/// The comfort vignette's vertex shader, eye from `gl_ViewIndex`.
pub const VIGNETTE_VERT_MULTIVIEW: &[u32] = spirv!("vignette_mv.vert");
/// The comfort vignette's vertex shader, eye from a push constant.
pub const VIGNETTE_VERT: &[u32] = spirv!("vignette.vert");
/// The comfort vignette's fragment shader: black by the ring's alpha.
pub const VIGNETTE_FRAG: &[u32] = spirv!("vignette.frag");

/// Solids (bodies, deck) vertex shader, eye from `gl_ViewIndex`.
pub const SOLID_VERT_MULTIVIEW: &[u32] = spirv!("solid_mv.vert");
/// Solids vertex shader, eye from a push constant.
pub const SOLID_VERT: &[u32] = spirv!("solid.vert");
/// Solids fragment shader.
pub const SOLID_FRAG: &[u32] = spirv!("solid.frag");

/// The control panel's vertex shader (egui triangles in points).
pub const PANEL_VERT: &[u32] = spirv!("panel.vert");
/// The control panel's fragment shader (vertex colour times texture, premultiplied).
pub const PANEL_FRAG: &[u32] = spirv!("panel.frag");

/// The optimized cost variants (`shaders/shader_table.rs` `COST_SHADERS`), never run: their
/// instructions are counted by [`crate::render::budget`].
pub mod cost {
    /// The sky.
    pub const SKY: &[u32] = spirv!("cost_sky.frag");
    /// Water shaded once (specular anti-aliasing's single path).
    pub const SINGLE: &[u32] = spirv!("cost_single.frag");
    /// Water with its highlight supersampled, no cascade sampled again.
    pub const SUPERSAMPLED: &[u32] = spirv!("cost_super0.frag");
    /// Water with its highlight supersampled, the finest cascade sampled again.
    pub const SUPERSAMPLED_RESAMPLE: &[u32] = spirv!("cost_super1.frag");
    /// Water shaded once, with foam.
    pub const FOAM: &[u32] = spirv!("cost_foam.frag");
    /// Water without anti-aliasing.
    pub const PLAIN: &[u32] = spirv!("cost_plain.frag");
    /// Water shaded once, with the detail near the viewer.
    pub const DETAIL: &[u32] = spirv!("cost_detail.frag");
    /// The ocean's vertex shader (multiview).
    pub const VERTEX: &[u32] = spirv!("cost_ocean.vert");
    /// Every path's work at once (each branch taken): what a device that runs both sides of
    /// every branch pays per fragment.
    pub const UNION: &[u32] = spirv!("cost_union.frag");
    /// Water shaded once, its colour through the tone curve's knee (every other variant takes
    /// the curve's linear part only).
    pub const KNEE: &[u32] = spirv!("cost_knee.frag");
    /// The surface seen from under the water (issue 45).
    pub const BELOW: &[u32] = spirv!("cost_below.frag");
    /// The water itself, where a ray from under the water meets nothing.
    pub const DEPTHS: &[u32] = spirv!("cost_depths.frag");
}

/// The calibration kernels' geometry: one triangle over the viewport or a grid of small ones
/// (`render::calibration`).
pub const CALIBRATE_VERT: &[u32] = spirv!("calibrate.vert");

/// The calibration kernels (`shaders/calibrate.frag`, optimized like the cost variants): run by
/// `render::calibration` and counted by [`crate::render::budget`].
pub mod calibration {
    /// Nothing but the fragment's write.
    pub const BASE: &[u32] = spirv!("cal_base.frag");
    /// FP32 arithmetic.
    pub const ALU: &[u32] = spirv!("cal_alu.frag");
    /// The same arithmetic in relaxed precision.
    pub const RELAXED: &[u32] = spirv!("cal_relaxed.frag");
    /// Special functions (inverse square root, exp2).
    pub const SPECIAL: &[u32] = spirv!("cal_special.frag");
    /// Trilinear samples.
    pub const TRILINEAR: &[u32] = spirv!("cal_trilinear.frag");
    /// Anisotropic samples (4:1 footprint).
    pub const ANISOTROPIC: &[u32] = spirv!("cal_anisotropic.frag");
    /// Trilinear samples mixed with FP32 arithmetic.
    pub const MIXED: &[u32] = spirv!("cal_mixed.frag");
    /// Samples at an explicit level of detail, per lane.
    pub const LOD: &[u32] = spirv!("cal_lod.frag");
    /// Samples with explicit gradients.
    pub const GRAD: &[u32] = spirv!("cal_grad.frag");
    /// Level-of-detail queries.
    pub const QUERY: &[u32] = spirv!("cal_query.frag");
    /// The explicit-level samples' kernel's work behind a branch no lane takes.
    pub const BRANCH: &[u32] = spirv!("cal_branch.frag");
}

/// Every module with its name, for validation with `spirv-val`.
pub const ALL: [(&str, &[u32]); 36] = [
    ("ocean_mv.vert", OCEAN_VERT_MULTIVIEW),
    ("ocean.vert", OCEAN_VERT),
    ("ocean.frag", OCEAN_FRAG),
    ("ocean_under.frag", OCEAN_FRAG_UNDER),
    ("ocean_fdm.frag", OCEAN_FRAG_FDM),
    ("ocean_fdm_under.frag", OCEAN_FRAG_FDM_UNDER),
    ("ocean_count.frag", OCEAN_FRAG_COUNT),
    ("cost_sky.frag", cost::SKY),
    ("cost_single.frag", cost::SINGLE),
    ("cost_super0.frag", cost::SUPERSAMPLED),
    ("cost_super1.frag", cost::SUPERSAMPLED_RESAMPLE),
    ("cost_foam.frag", cost::FOAM),
    ("cost_plain.frag", cost::PLAIN),
    ("cost_detail.frag", cost::DETAIL),
    ("cost_ocean.vert", cost::VERTEX),
    ("cost_union.frag", cost::UNION),
    ("cost_knee.frag", cost::KNEE),
    ("cost_below.frag", cost::BELOW),
    ("cost_depths.frag", cost::DEPTHS),
    ("solid_mv.vert", SOLID_VERT_MULTIVIEW),
    ("solid.vert", SOLID_VERT),
    ("solid.frag", SOLID_FRAG),
    ("panel.vert", PANEL_VERT),
    ("panel.frag", PANEL_FRAG),
    ("calibrate.vert", CALIBRATE_VERT),
    ("cal_base.frag", calibration::BASE),
    ("cal_alu.frag", calibration::ALU),
    ("cal_relaxed.frag", calibration::RELAXED),
    ("cal_special.frag", calibration::SPECIAL),
    ("cal_trilinear.frag", calibration::TRILINEAR),
    ("cal_anisotropic.frag", calibration::ANISOTROPIC),
    ("cal_mixed.frag", calibration::MIXED),
    ("cal_lod.frag", calibration::LOD),
    ("cal_grad.frag", calibration::GRAD),
    ("cal_query.frag", calibration::QUERY),
    ("cal_branch.frag", calibration::BRANCH),
];
