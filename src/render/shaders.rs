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
/// Ocean fragment shader for a pass with a fragment density map (fixed foveation): peripheral
/// fragments, which cover several pixels, never take the supersampled path.
pub const OCEAN_FRAG_FDM: &[u32] = spirv!("ocean_fdm.frag");
/// Ocean fragment shader tallying its pixels' paths into a storage buffer (binding 6): the
/// counting variant of `vr-ocean gpu-budget`.
pub const OCEAN_FRAG_COUNT: &[u32] = spirv!("ocean_count.frag");

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
}

/// Every module with its name, for validation with `spirv-val`.
pub const ALL: [(&str, &[u32]); 18] = [
    ("ocean_mv.vert", OCEAN_VERT_MULTIVIEW),
    ("ocean.vert", OCEAN_VERT),
    ("ocean.frag", OCEAN_FRAG),
    ("ocean_fdm.frag", OCEAN_FRAG_FDM),
    ("ocean_count.frag", OCEAN_FRAG_COUNT),
    ("cost_sky.frag", cost::SKY),
    ("cost_single.frag", cost::SINGLE),
    ("cost_super0.frag", cost::SUPERSAMPLED),
    ("cost_super1.frag", cost::SUPERSAMPLED_RESAMPLE),
    ("cost_foam.frag", cost::FOAM),
    ("cost_plain.frag", cost::PLAIN),
    ("cost_detail.frag", cost::DETAIL),
    ("cost_ocean.vert", cost::VERTEX),
    ("solid_mv.vert", SOLID_VERT_MULTIVIEW),
    ("solid.vert", SOLID_VERT),
    ("solid.frag", SOLID_FRAG),
    ("panel.vert", PANEL_VERT),
    ("panel.frag", PANEL_FRAG),
];
