//! `cargo xtask apk|install|launch`: the Quest APK.
//!
//! * User build (`apk [--release]`): `ANDROID_NDK_HOME` and `ANDROID_HOME`/`ANDROID_SDK_ROOT`
//!   name the NDK and SDK. `libvr_ocean.so` is linked by the NDK's clang for
//!   `aarch64-linux-android` API 29; the SDK's build-tools package it (`aapt2 compile/link`
//!   against the platform's `android.jar`, `aapt add` for the native libraries, stored
//!   uncompressed), `zipalign -p 4`, and `apksigner` signs it with the debug keystore
//!   (`~/.android/debug.keystore`, made with `keytool` on first use). The OpenXR loader is
//!   required ([`openxr_loader`]).
//! * Verification build (`apk --verify-without-ndk`, for CI): no NDK or SDK. `rust-lld` links
//!   against stub system libraries generated for API 29 ([`android_stubs`](crate::android_stubs))
//!   with `-z defs`, `_Unwind_*` come from the `unwinding` crate (feature
//!   `verify-without-ndk`), and Debian's `aapt`/`aapt2` (with `framework-res.apk` of API 29
//!   as `-I`), `zipalign` and `apksigner` package it. Without `--openxr-loader` it is built
//!   without the loader and says loudly that such an APK cannot run.
//!
//! By job: [`args`] (the command lines), [`tools`] (finding the tools of either build, and
//! naming what is missing), [`build`] (the library, then packaging), [`sign`] (the debug
//! keystore and apksigner), [`paths`] (the target directory and where the APKs go), [`quest`] (the app's ids and the
//! Quest's target and API level), [`device`]
//! (`install` and `launch` over adb).

mod args;
mod build;
mod device;
mod paths;
mod quest;
mod sign;
mod tools;

pub use args::{parse_apk_args, parse_release_flag, ApkOpts};
use build::build_apk;
pub use device::{cmd_install, cmd_launch};
pub use paths::{apk_path, target_dir};
pub use quest::{ACTIVITY, ANDROID_TARGET, DEBIAN_FRAMEWORK_RES, LOG_TAG, MIN_API, PACKAGE};

use crate::openxr_loader;
use crate::process::say;
use crate::Result;

/// `cargo xtask apk`.
pub fn cmd_apk(opts: &ApkOpts) -> Result<()> {
    let built = build_apk(opts)?;
    if !built.has_loader {
        loud_warning();
    }
    say(&format!("APK: {}", built.path.display()));
    Ok(())
}

/// The banner of an APK without the OpenXR loader: it cannot run on a headset.
fn loud_warning() {
    let rule = "!".repeat(78);
    println!(
        "{rule}\nWARNING: this APK has NO OpenXR loader (lib/arm64-v8a/libopenxr_loader.so) and \
         cannot run on a headset:\nvr-ocean would stop at start-up with \"no OpenXR loader \
         could be loaded\". It is for CI's checks only.\n{}\n{rule}",
        openxr_loader::missing_message("--verify-without-ndk without --openxr-loader")
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::process::workspace_root;

    #[test]
    fn manifest_matches_the_constants() {
        let manifest =
            std::fs::read_to_string(workspace_root().join("android/AndroidManifest.xml")).unwrap();
        assert!(manifest.contains(&format!("package=\"{PACKAGE}\"")));
        assert!(manifest.contains(&format!("android:name=\"{ACTIVITY}\"")));
        assert!(
            manifest.contains("android:name=\"android.app.lib_name\" android:value=\"vr_ocean\"")
        );
        let tag = std::fs::read_to_string(workspace_root().join("src/android/mod.rs")).unwrap();
        assert!(tag.contains(&format!("pub const LOG_TAG: &str = \"{LOG_TAG}\";")));
    }
}
