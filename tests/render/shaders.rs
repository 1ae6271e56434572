//! Every SPIR-V module the renderer loads passes `spirv-val` (Debian `spirv-tools`) for the
//! Vulkan 1.1 environment.

use crate::common;

use std::process::Command;

use vr_ocean::render::shaders;

#[test]
fn spirv_modules_pass_spirv_val() {
    for (name, words) in shaders::ALL {
        let path = common::scratch_path(&format!("{name}.spv"));
        std::fs::write(&path, bytemuck::cast_slice::<u32, u8>(words)).unwrap();
        let out = Command::new("spirv-val")
            .args(["--target-env", "vulkan1.1"])
            .arg(&path)
            .output()
            .unwrap_or_else(|e| {
                panic!(
                    "cannot run spirv-val ({e}): apt install spirv-tools (cargo xtask test does)"
                )
            });
        let _ = std::fs::remove_file(&path);
        assert!(
            out.status.success(),
            "{name}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(words[0], 0x0723_0203, "{name}: SPIR-V magic");
    }
}

mod shader_table {
    #![allow(dead_code)]
    include!("../../shaders/shader_table.rs");
}

/// `shaders/spirv/` (what builds without glslang use) was made from the GLSL as it is now, and
/// each committed module passes `spirv-val`: a shader edited without `cargo xtask shaders`
/// fails here, not on a user's machine.
#[test]
fn committed_spirv_is_made_from_the_current_glsl() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("shaders");
    let now = shader_table::sources_fingerprint(&src).unwrap();
    let recorded = std::fs::read_to_string(
        src.join("spirv")
            .join(shader_table::SOURCES_FINGERPRINT_FILE),
    )
    .unwrap_or_default();
    assert_eq!(
        recorded.trim(),
        now,
        "shaders/spirv/ is stale: run `cargo xtask shaders` and commit it"
    );
    for (_, stem, _) in shader_table::SHADERS
        .iter()
        .chain(shader_table::COST_SHADERS)
    {
        let path = src.join("spirv").join(format!("{stem}.spv"));
        let out = Command::new("spirv-val")
            .args(["--target-env", "vulkan1.1"])
            .arg(&path)
            .output()
            .expect("spirv-val (apt install spirv-tools)");
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
