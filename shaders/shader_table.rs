// Shared by `build.rs` and `xtask` (through `include!`): which SPIR-V modules are made from
// which GLSL, and the fingerprint of the GLSL that `shaders/spirv/` was generated from.

/// (source, output stem, extra defines): the vertex shader, which picks the eye, is built twice,
/// with and without `MULTIVIEW`, for the multiview pass and the two-pass fallback.
pub const SHADERS: &[(&str, &str, &[&str])] = &[
    ("ocean.vert", "ocean_mv.vert", &["MULTIVIEW=1"]),
    ("ocean.vert", "ocean.vert", &[]),
    ("ocean.frag", "ocean.frag", &[]),
    // With the view from under the water and the waterline (`UNDERWATER`, issue 45): bound
    // only for frames some of which are under it.
    ("ocean.frag", "ocean_under.frag", &["UNDERWATER=1"]),
    // With a fragment density map (fixed foveation): no supersampling in the periphery.
    ("ocean.frag", "ocean_fdm.frag", &["FRAGMENT_DENSITY=1"]),
    ("ocean.frag", "ocean_fdm_under.frag", &["FRAGMENT_DENSITY=1", "UNDERWATER=1"]),
    // The ocean's fragment shader tallying the paths its pixels take (`vr-ocean gpu-budget`),
    // on both sides of the surface.
    ("ocean.frag", "ocean_count.frag", &["COUNT_PATHS=1", "UNDERWATER=1"]),
    ("solid.vert", "solid_mv.vert", &["MULTIVIEW=1"]),
    ("solid.vert", "solid.vert", &[]),
    ("solid.frag", "solid.frag", &[]),
    // The comfort vignette (`render::ocean::vignette`).
    ("vignette.vert", "vignette_mv.vert", &["MULTIVIEW=1"]),
    ("vignette.vert", "vignette.vert", &[]),
    ("vignette.frag", "vignette.frag", &[]),
    ("panel.vert", "panel.vert", &[]),
    ("panel.frag", "panel.frag", &[]),
    // The calibration kernels' geometry (`render::calibration`).
    ("calibrate.vert", "calibrate.vert", &[]),
];

/// The modules `vr-ocean gpu-budget` counts (`render::budget`), each optimized with `spirv-opt
/// -O` (inlined, unrolled, folded) so that its one function is straight-line code, counted
/// instruction by instruction: the ocean's cost variants (its fragment shader with each path's
/// choices fixed, `COST_PATH`, see `shaders/ocean.frag`, 3 cascades, and the vertex shader)
/// and the calibration kernels (`shaders/calibrate.frag`, `KERNEL` rounds of `COUNT`), which
/// the calibration also runs.
pub const COST_SHADERS: &[(&str, &str, &[&str])] = &[
    (
        "ocean.frag",
        "cost_sky.frag",
        &["COST_PATH=1", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_single.frag",
        &["COST_PATH=2", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_super0.frag",
        &["COST_PATH=3", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_super1.frag",
        &["COST_PATH=3", "COST_CASCADES=3", "COST_RESAMPLED=1"],
    ),
    (
        "ocean.frag",
        "cost_foam.frag",
        &["COST_PATH=4", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_plain.frag",
        &["COST_PATH=5", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    ("ocean.vert", "cost_ocean.vert", &["MULTIVIEW=1", "COST_CASCADES=3"]),
    (
        "ocean.frag",
        "cost_detail.frag",
        &["COST_PATH=6", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_union.frag",
        &["COST_PATH=7", "COST_CASCADES=3", "COST_RESAMPLED=3"],
    ),
    // Water shaded once, its colour through the tone curve's knee (the other variants take
    // the curve's linear part only).
    (
        "ocean.frag",
        "cost_knee.frag",
        &["COST_PATH=2", "COST_CASCADES=3", "COST_RESAMPLED=0", "COST_KNEE=1"],
    ),
    // The view from under the water (issue 45): the surface from below, and the depths.
    (
        "ocean.frag",
        "cost_below.frag",
        &["COST_PATH=8", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    (
        "ocean.frag",
        "cost_depths.frag",
        &["COST_PATH=9", "COST_CASCADES=3", "COST_RESAMPLED=0"],
    ),
    ("calibrate.frag", "cal_base.frag", &["KERNEL=0", "COUNT=0"]),
    ("calibrate.frag", "cal_alu.frag", &["KERNEL=1", "COUNT=96"]),
    ("calibrate.frag", "cal_relaxed.frag", &["KERNEL=2", "COUNT=96"]),
    ("calibrate.frag", "cal_special.frag", &["KERNEL=3", "COUNT=24"]),
    ("calibrate.frag", "cal_trilinear.frag", &["KERNEL=4", "COUNT=12"]),
    ("calibrate.frag", "cal_anisotropic.frag", &["KERNEL=5", "COUNT=12"]),
    ("calibrate.frag", "cal_mixed.frag", &["KERNEL=6", "COUNT=8"]),
    ("calibrate.frag", "cal_lod.frag", &["KERNEL=7", "COUNT=12"]),
    ("calibrate.frag", "cal_grad.frag", &["KERNEL=8", "COUNT=12"]),
    ("calibrate.frag", "cal_query.frag", &["KERNEL=9", "COUNT=12"]),
    ("calibrate.frag", "cal_branch.frag", &["KERNEL=10", "COUNT=12"]),
];

/// The `spirv-opt` arguments that optimize `input` into `output` for [`COST_SHADERS`].
pub fn optimizer_args(
    input: &std::path::Path,
    output: &std::path::Path,
) -> Vec<std::ffi::OsString> {
    vec!["-O".into(), input.into(), "-o".into(), output.into()]
}

/// The file in `shaders/spirv/` that records the fingerprint of the sources it was made from.
pub const SOURCES_FINGERPRINT_FILE: &str = "sources.fnv64";

/// FNV-1a (64-bit) over every GLSL file in `dir` (`*.vert`, `*.frag`, `*.glsl`, by name) and the
/// shader table: it changes whenever a source or a define does.
pub fn sources_fingerprint(dir: &std::path::Path) -> std::io::Result<String> {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e, "vert" | "frag" | "glsl"))
        })
        .collect();
    files.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        h ^= 0xff;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    };
    for f in &files {
        eat(f
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("")
            .as_bytes());
        // Line endings do not matter (a checkout may convert them).
        let text = std::fs::read(f)?;
        let text: Vec<u8> = text.into_iter().filter(|&b| b != b'\r').collect();
        eat(&text);
    }
    for (src, stem, defines) in SHADERS.iter().chain(COST_SHADERS) {
        eat(src.as_bytes());
        eat(stem.as_bytes());
        for d in *defines {
            eat(d.as_bytes());
        }
    }
    Ok(format!("{h:016x}"))
}

/// The glslangValidator arguments that compile `input` to `output` with `defines`, for Vulkan
/// 1.1 without debug info; `include_dir` holds `common.glsl`.
pub fn glslang_args(
    input: &std::path::Path,
    output: &std::path::Path,
    include_dir: &std::path::Path,
    defines: &[&str],
) -> Vec<std::ffi::OsString> {
    let mut args: Vec<std::ffi::OsString> = ["-V", "--target-env", "vulkan1.1", "-g0", "-o"]
        .iter()
        .map(|s| s.into())
        .collect();
    args.push(output.into());
    args.push(format!("-I{}", include_dir.display()).into());
    for d in defines {
        args.push(format!("-D{d}").into());
    }
    args.push(input.into());
    args
}
