//! `cargo xtask shaders`: compiles the shaders into the committed SPIR-V (`shaders/spirv/`).

use std::process::Command;

use crate::process::{capture, say, workspace_root};
use crate::setup::{ensure_apt_packages, SHADER_APT_PACKAGES};
use crate::{Failure, Result};

/// The shader table and the sources fingerprint, shared with `build.rs`.
mod shader_table {
    include!("../../../shaders/shader_table.rs");
}

/// Compiles every shader of the table into `shaders/spirv/` and records the fingerprint of
/// the sources they came from.
pub fn cmd_shaders() -> Result<()> {
    ensure_apt_packages(SHADER_APT_PACKAGES)?;
    let src = workspace_root().join("shaders");
    let dir = src.join("spirv");
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    let tool = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    for (file, stem, defines) in shader_table::SHADERS {
        let out = dir.join(format!("{stem}.spv"));
        let mut cmd = Command::new(&tool);
        cmd.args(shader_table::glslang_args(
            &src.join(file),
            &out,
            &src,
            defines,
        ));
        let text = capture(&mut cmd)?;
        say(&format!(
            "{stem}.spv: {}",
            text.lines().last().unwrap_or("ok").trim()
        ));
    }
    // The cost variants of `vr-ocean gpu-budget`: compiled, then optimized (spirv-opt).
    let scratch = std::env::temp_dir().join(format!("vr-ocean-shaders-{}", std::process::id()));
    std::fs::create_dir_all(&scratch)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", scratch.display())))?;
    for (file, stem, defines) in shader_table::COST_SHADERS {
        let raw = scratch.join(format!("{stem}.spv"));
        let out = dir.join(format!("{stem}.spv"));
        let mut cmd = Command::new(&tool);
        cmd.args(shader_table::glslang_args(
            &src.join(file),
            &raw,
            &src,
            defines,
        ));
        capture(&mut cmd)?;
        let mut opt = Command::new("spirv-opt");
        opt.args(shader_table::optimizer_args(&raw, &out));
        capture(&mut opt)?;
        say(&format!("{stem}.spv: optimized"));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let fingerprint = shader_table::sources_fingerprint(&src)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", src.display())))?;
    let file = dir.join(shader_table::SOURCES_FINGERPRINT_FILE);
    std::fs::write(&file, format!("{fingerprint}\n"))
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", file.display())))?;
    say(&format!(
        "wrote {} ({} modules, sources {fingerprint})",
        dir.display(),
        shader_table::SHADERS.len() + shader_table::COST_SHADERS.len()
    ));
    Ok(())
}
