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

/// Solids (bodies, deck) vertex shader, eye from `gl_ViewIndex`.
pub const SOLID_VERT_MULTIVIEW: &[u32] = spirv!("solid_mv.vert");
/// Solids vertex shader, eye from a push constant.
pub const SOLID_VERT: &[u32] = spirv!("solid.vert");
/// Solids fragment shader.
pub const SOLID_FRAG: &[u32] = spirv!("solid.frag");

/// Every module with its name, for validation with `spirv-val`.
pub const ALL: [(&str, &[u32]); 6] = [
    ("ocean_mv.vert", OCEAN_VERT_MULTIVIEW),
    ("ocean.vert", OCEAN_VERT),
    ("ocean.frag", OCEAN_FRAG),
    ("solid_mv.vert", SOLID_VERT_MULTIVIEW),
    ("solid.vert", SOLID_VERT),
    ("solid.frag", SOLID_FRAG),
];
