//! Building the APK: the native library (cargo), the resources and manifest (aapt2), the
//! native libraries stored uncompressed (aapt), alignment (zipalign), then signing.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::args::ApkOpts;
use super::paths::{apk_path, target_dir};
use super::sign::sign_with_debug_key;
use super::tools::{ndk_tools, verify_tools};
use super::{ANDROID_TARGET, MIN_API};
use crate::openxr_loader::{self, Fallback, Loader};
use crate::process::{cargo, run_checked, say, workspace_root};
use crate::{android_stubs, Failure, Result};

/// What `build_apk` made.
#[derive(Debug)]
pub struct BuiltApk {
    /// The signed APK.
    pub path: PathBuf,
    /// Whether `lib/arm64-v8a/libopenxr_loader.so` is inside.
    pub has_loader: bool,
}

/// Builds, packages and signs the APK.
pub fn build_apk(opts: &ApkOpts) -> Result<BuiltApk> {
    let root = workspace_root();
    let target = target_dir()?;
    let profile = if opts.release { "release" } else { "debug" };
    let kind = if opts.verify_without_ndk {
        format!("{profile}-verify-without-ndk")
    } else {
        profile.to_string()
    };
    let stage = target.join("apk").join(&kind);
    let stubs = target.join("android-stubs").join(format!("api{MIN_API}"));
    let tools = if opts.verify_without_ndk {
        say("verification build without the NDK: rust-lld against API 29 stubs, Debian's aapt2");
        verify_tools(&stubs)?
    } else {
        ndk_tools()?
    };

    let loader = openxr_loader::resolve(
        opts.openxr_loader.as_deref(),
        if opts.verify_without_ndk {
            Fallback::None
        } else {
            Fallback::Download
        },
        &target.join("openxr-loader"),
    )?;
    let loader = match loader {
        Loader::Found(p) => Some(p),
        Loader::Missing(why) if opts.verify_without_ndk => {
            say(&format!("OpenXR loader: none ({why})"));
            None
        }
        Loader::Missing(why) => return Err(Failure::Msg(openxr_loader::missing_message(&why))),
    };

    if opts.verify_without_ndk {
        let start = std::time::Instant::now();
        let counts = android_stubs::build_stubs(&stubs, MIN_API)?;
        say(&format!(
            "stub libraries for API {MIN_API} in {} ({}) in {:.1}s",
            stubs.display(),
            counts
                .iter()
                .map(|(l, n)| format!("{l}: {n} symbols"))
                .collect::<Vec<_>>()
                .join(", "),
            start.elapsed().as_secs_f64()
        ));
    }

    // The native library.
    let mut build = cargo();
    build
        .args([
            "build",
            "--lib",
            "--target",
            ANDROID_TARGET,
            "--no-default-features",
        ])
        .current_dir(&root);
    if opts.release {
        build.arg("--release");
    }
    // The sound's output (cpal on AAudio); no benchmark baselines.
    if opts.verify_without_ndk {
        build.args(["--features", "audio-device,verify-without-ndk"]);
    } else {
        build.args(["--features", "audio-device"]);
    }
    for (k, v) in &tools.cargo_env {
        build.env(k, v);
    }
    run_checked(&mut build)?;
    let so = target
        .join(ANDROID_TARGET)
        .join(profile)
        .join("libvr_ocean.so");
    if !so.is_file() {
        return Err(Failure::Msg(format!(
            "cargo built no {} (is `cdylib` in the [lib] crate-type?)",
            so.display()
        )));
    }

    // Resources and manifest.
    let _ = std::fs::remove_dir_all(&stage);
    let libs = stage.join("lib/arm64-v8a");
    std::fs::create_dir_all(&libs)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", libs.display())))?;
    let res_zip = stage.join("res.zip");
    run_checked(
        Command::new(&tools.aapt2)
            .arg("compile")
            .arg("--dir")
            .arg(root.join("android/res"))
            .arg("-o")
            .arg(&res_zip),
    )?;
    let base = stage.join("base.apk");
    run_checked(
        Command::new(&tools.aapt2)
            .arg("link")
            .arg("-o")
            .arg(&base)
            .arg("-I")
            .arg(&tools.android_jar)
            .arg("--manifest")
            .arg(root.join("android/AndroidManifest.xml"))
            // Older aapt2 (Debian's, API 29) does not know <queries> and
            // <uses-native-library>; keep them with a warning instead of an error.
            .arg("--warn-manifest-validation")
            .arg(&res_zip),
    )?;

    // Native libraries, stored uncompressed (page-aligned by zipalign -p). The packaged
    // library loses its debug info; the one in the target directory keeps it (symbolizing
    // crash dumps).
    run_checked(
        Command::new(&tools.objcopy)
            .arg("--strip-debug")
            .arg(&so)
            .arg(libs.join("libvr_ocean.so")),
    )?;
    let mut members = vec!["lib/arm64-v8a/libvr_ocean.so"];
    if let Some(loader) = &loader {
        copy(loader, &libs.join("libopenxr_loader.so"))?;
        members.push("lib/arm64-v8a/libopenxr_loader.so");
    }
    run_checked(
        Command::new(&tools.aapt)
            .args(["add", "-0", ""])
            .arg(&base)
            .args(&members)
            .current_dir(&stage),
    )?;
    let aligned = stage.join("aligned.apk");
    run_checked(
        Command::new(&tools.zipalign)
            .args(["-p", "-f", "4"])
            .arg(&base)
            .arg(&aligned),
    )?;

    // Signing.
    let out = apk_path(&target, opts.release, opts.verify_without_ndk);
    sign_with_debug_key(&tools, &aligned, &out)?;
    let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
    let mib = |p: &Path| std::fs::metadata(p).map_or(0.0, |m| m.len() as f64 / (1 << 20) as f64);
    say(&format!(
        "signed {} ({:.1} MiB; libvr_ocean.so {:.1} MiB, {:.1} MiB with debug info{})",
        out.display(),
        size as f64 / (1 << 20) as f64,
        mib(&libs.join("libvr_ocean.so")),
        mib(&so),
        if loader.is_some() {
            ", with the OpenXR loader"
        } else {
            ", WITHOUT the OpenXR loader"
        }
    ));
    Ok(BuiltApk {
        path: out,
        has_loader: loader.is_some(),
    })
}

/// Copies `from` to `to`, naming both on failure.
fn copy(from: &Path, to: &Path) -> Result<()> {
    std::fs::copy(from, to).map(|_| ()).map_err(|e| {
        Failure::Msg(format!(
            "cannot copy {} to {}: {e}",
            from.display(),
            to.display()
        ))
    })
}
