//! Every SPIR-V module the renderer loads passes `spirv-val` (Debian `spirv-tools`) for the
//! Vulkan 1.1 environment.

mod common;

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
