//! The shaders' SPIR-V. The GLSL in `shaders/` is the source; `shaders/spirv/` holds the
//! SPIR-V made from it (`cargo xtask shaders`, glslang), committed so that a plain `cargo
//! build` needs no shader compiler. Each build:
//!
//! - with glslang's `glslangValidator` on the machine (Debian `glslang-tools`, or the path in
//!   `GLSLANG_VALIDATOR`): compiles the GLSL afresh, so an edited shader takes effect at once,
//!   and warns when the committed SPIR-V no longer matches the sources;
//! - without it: uses the committed SPIR-V, which must have been made from the current sources
//!   (their fingerprint is recorded next to it); otherwise it stops with one line saying what
//!   to install.
//!
//! The shader table and the fingerprint live in `shaders/shader_table.rs`, shared with xtask.
//! A build script that fails prints one `error:` line and exits 1: never a panic.

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

include!("shaders/shader_table.rs");

fn main() {
    let root = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let src = root.join("shaders");
    let committed = src.join("spirv");
    let Some(out) = env::var_os("OUT_DIR").map(PathBuf::from) else {
        fail("OUT_DIR is not set: run this through cargo");
    };
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    let fingerprint = sources_fingerprint(&src).unwrap_or_else(|e| {
        fail(&format!(
            "cannot read the shaders in {}: {e}",
            src.display()
        ))
    });
    let recorded = std::fs::read_to_string(committed.join(SOURCES_FINGERPRINT_FILE))
        .map(|s| s.trim().to_string())
        .unwrap_or_default();
    let up_to_date = recorded == fingerprint;
    let tool = env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    for (file, stem, defines) in SHADERS {
        let target = out.join(format!("{stem}.spv"));
        match compile(&tool, &src.join(file), &target, &src, defines) {
            Compiled::Yes => {}
            Compiled::NoTool(why) if up_to_date => {
                let spv = committed.join(format!("{stem}.spv"));
                if let Err(e) = std::fs::copy(&spv, &target) {
                    fail(&format!("cannot copy {}: {e}", spv.display()));
                }
                let _ = why;
            }
            Compiled::NoTool(why) => fail(&format!(
                "the GLSL in shaders/ changed since shaders/spirv/ was made, and {tool} cannot \
                 run ({why}): install glslang's compiler (Debian/Ubuntu: apt install \
                 glslang-tools) or set GLSLANG_VALIDATOR, then `cargo xtask shaders`"
            )),
        }
    }
    // The cost variants also need `spirv-opt` (Debian `spirv-tools`); without it the committed
    // ones stand in (a test fails when they are stale).
    let optimizer = env::var("SPIRV_OPT").unwrap_or_else(|_| "spirv-opt".into());
    println!("cargo:rerun-if-env-changed=SPIRV_OPT");
    for (file, stem, defines) in COST_SHADERS {
        let target = out.join(format!("{stem}.spv"));
        let raw = out.join(format!("{stem}.unoptimized.spv"));
        let made = matches!(
            compile(&tool, &src.join(file), &raw, &src, defines),
            Compiled::Yes
        ) && optimize(&optimizer, &raw, &target);
        if !made {
            let spv = committed.join(format!("{stem}.spv"));
            if let Err(e) = std::fs::copy(&spv, &target) {
                fail(&format!(
                    "cannot copy {}: {e} (or install glslang-tools and spirv-tools)",
                    spv.display()
                ));
            }
        }
    }
    if !up_to_date {
        println!(
            "cargo:warning=shaders/spirv/ is stale (made from other GLSL): run `cargo xtask \
             shaders` and commit it, so builds without glslang get these shaders"
        );
    }
}

/// What happened to one shader.
enum Compiled {
    /// Compiled from the GLSL.
    Yes,
    /// The compiler could not be run (why).
    NoTool(String),
}

fn compile(tool: &str, input: &Path, output: &Path, include: &Path, defines: &[&str]) -> Compiled {
    let result = match Command::new(tool)
        .args(glslang_args(input, output, include, defines))
        .output()
    {
        Ok(r) => r,
        Err(e) => return Compiled::NoTool(e.to_string()),
    };
    if !result.status.success() {
        // A shader that does not compile is the author's error, with glslang's words.
        let log = format!(
            "{}{}",
            String::from_utf8_lossy(&result.stdout),
            String::from_utf8_lossy(&result.stderr)
        );
        fail(&format!(
            "{tool} failed on {}: {}",
            input.display(),
            log.trim().replace('\n', " | ")
        ));
    }
    Compiled::Yes
}

/// Runs `spirv-opt -O` on `input`; false when the optimizer cannot be run. A module it rejects
/// is the author's error.
fn optimize(tool: &str, input: &Path, output: &Path) -> bool {
    let result = match Command::new(tool)
        .args(optimizer_args(input, output))
        .output()
    {
        Ok(r) => r,
        Err(_) => return false,
    };
    if !result.status.success() {
        fail(&format!(
            "{tool} failed on {}: {}",
            input.display(),
            String::from_utf8_lossy(&result.stderr)
                .trim()
                .replace('\n', " | ")
        ));
    }
    true
}

/// Stops the build with one line (cargo shows it under "failed to run custom build command").
fn fail(msg: &str) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(1);
}
