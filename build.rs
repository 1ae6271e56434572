//! Compiles the GLSL in `shaders/` to SPIR-V (Vulkan 1.1) with glslang's `glslangValidator`
//! (Debian `glslang-tools`, installed by `cargo xtask test`). Each `*.vert`/`*.frag` becomes
//! `$OUT_DIR/<name>.spv`; the vertex shader, which picks the eye, is built twice, with and
//! without `MULTIVIEW`, for the multiview pass and the two-pass fallback.

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

/// (source, output stem, extra defines).
const SHADERS: &[(&str, &str, &[&str])] = &[
    ("ocean.vert", "ocean_mv.vert", &["MULTIVIEW=1"]),
    ("ocean.vert", "ocean.vert", &[]),
    ("ocean.frag", "ocean.frag", &[]),
];

fn main() {
    let src = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap()).join("shaders");
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    let tool = env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    for (file, stem, defines) in SHADERS {
        compile(
            &tool,
            &src.join(file),
            &out.join(format!("{stem}.spv")),
            defines,
        );
    }
}

fn compile(tool: &str, input: &Path, output: &Path, defines: &[&str]) {
    let mut cmd = Command::new(tool);
    cmd.args(["-V", "--target-env", "vulkan1.1", "-g0", "-o"])
        .arg(output)
        .arg(format!("-I{}", input.parent().unwrap().display()));
    for d in defines {
        cmd.arg(format!("-D{d}"));
    }
    cmd.arg(input);
    let result = cmd.output().unwrap_or_else(|e| {
        panic!(
            "cannot run `{tool}` to compile {}: {e}. Install glslang's compiler \
             (Debian/Ubuntu: `apt install glslang-tools`; `cargo xtask test` does it) \
             or point GLSLANG_VALIDATOR at it.",
            input.display()
        )
    });
    if !result.status.success() {
        panic!(
            "{tool} failed on {}:\n{}{}",
            input.display(),
            String::from_utf8_lossy(&result.stdout),
            String::from_utf8_lossy(&result.stderr)
        );
    }
}
