//! The tools of the verification build (`--verify-without-ndk`, CI): Debian's packages and
//! rustup's rust-lld, linking against the API 29 stubs with `-z defs`.

use std::path::{Path, PathBuf};

use super::{host_triple, keytool, linker_var, report_missing, rust_tools, MissingTool, Tools};
use crate::apk::DEBIAN_FRAMEWORK_RES;
use crate::process::which;
use crate::Result;

/// The tools of the verification build: Debian packages and rustup's rust-lld.
pub fn verify_tools(stubs: &Path) -> Result<Tools> {
    let mut missing = Vec::new();
    let sysroot = rust_tools(&mut missing)?;
    let mut debian = |tool: &str, package: &str| {
        which(tool).unwrap_or_else(|| {
            missing.push(MissingTool {
                what: tool.into(),
                from: format!("Debian package {package} (apt install {package})"),
            });
            PathBuf::from(tool)
        })
    };
    let aapt = debian("aapt", "aapt");
    let aapt2 = debian("aapt2", "aapt");
    let zipalign = debian("zipalign", "zipalign");
    let apksigner = debian("apksigner", "apksigner");
    debian("clang", "clang");
    debian("ld.lld", "lld");
    let keytool = keytool(&mut missing);
    let android_jar = PathBuf::from(DEBIAN_FRAMEWORK_RES);
    if !android_jar.is_file() {
        missing.push(MissingTool {
            what: DEBIAN_FRAMEWORK_RES.into(),
            from: "Debian package android-framework-res (apt install android-framework-res)".into(),
        });
    }
    let lld = sysroot
        .join("lib/rustlib")
        .join(host_triple()?)
        .join("bin/rust-lld");
    if !lld.is_file() {
        missing.push(MissingTool {
            what: "rust-lld".into(),
            from: format!("the Rust toolchain (rustup's; expected {})", lld.display()),
        });
    }
    report_missing(&missing, "the verification build (--verify-without-ndk)")?;
    let objcopy = lld.with_file_name("rust-objcopy");
    // rust-lld as ld.lld; -z defs: any import the API 29 stubs lack fails the link.
    let flags = [
        "-C",
        "linker-flavor=ld.lld",
        "-C",
        "link-arg=-zdefs",
        "-C",
        "link-arg=-soname=libvr_ocean.so",
        "-L",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("native={}", stubs.display())])
    .collect::<Vec<_>>()
    .join("\x1f");
    Ok(Tools {
        aapt,
        aapt2,
        zipalign,
        apksigner,
        keytool,
        android_jar,
        objcopy,
        cargo_env: vec![
            (linker_var(), lld.display().to_string()),
            ("CARGO_ENCODED_RUSTFLAGS".into(), flags),
        ],
    })
}
