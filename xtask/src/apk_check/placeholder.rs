//! The placeholder OpenXR loader apk-check packages: an arm64 `.so` of empty entry points,
//! and an AAR holding it where the Khronos AAR has its loader.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::runner::write;
use crate::apk::MIN_API;
use crate::process::capture;
use crate::{android_stubs, openxr_loader, Failure, Result};

/// A placeholder `libopenxr_loader.so`: an arm64 shared object with the loader's entry
/// points as empty functions (for packaging checks only; it does nothing).
pub fn fake_loader(work: &Path) -> Result<PathBuf> {
    let dir = work.join("fake-loader");
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    let asm = dir.join("loader.S");
    let mut text = String::from("// Placeholder OpenXR loader for apk-check.\n");
    for f in [
        "xrGetInstanceProcAddr",
        "xrInitializeLoaderKHR",
        "xrCreateInstance",
    ] {
        text.push_str(&format!(
            ".text\n.globl {f}\n.type {f}, %function\n{f}:\nret\n"
        ));
    }
    write(&asm, text.as_bytes())?;
    let so = dir.join("libopenxr_loader.so");
    android_stubs::link_shared(MIN_API, &asm, None, "libopenxr_loader.so", &so)?;
    Ok(so)
}

/// A placeholder AAR holding `so` where the Khronos AAR has its arm64 loader.
pub fn fake_aar(work: &Path, so: &Path) -> Result<PathBuf> {
    let root = work.join("fake-aar");
    let member = root.join(openxr_loader::AAR_MEMBER);
    if let Some(dir) = member.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    }
    std::fs::copy(so, &member)
        .map_err(|e| Failure::Msg(format!("cannot copy to {}: {e}", member.display())))?;
    write(
        &root.join("AndroidManifest.xml"),
        b"<manifest package=\"org.khronos.openxr.openxr_loader_for_android\"/>\n",
    )?;
    let aar = work.join("openxr_loader_for_android-placeholder.aar");
    capture(
        Command::new("zip")
            .args(["-q", "-r"])
            .arg(&aar)
            .args(["AndroidManifest.xml", "prefab"])
            .current_dir(&root),
    )?;
    Ok(aar)
}
