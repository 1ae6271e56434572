//! The tools of the user build: the NDK's clang and objcopy (`ANDROID_NDK_HOME`), the SDK's
//! build-tools and newest fitting platform (`ANDROID_HOME`/`ANDROID_SDK_ROOT`).

use std::path::{Path, PathBuf};

use super::{env_dir, keytool, linker_var, report_missing, rust_tools, MissingTool, Tools};
use crate::apk::{ANDROID_TARGET, MIN_API};
use crate::Result;

/// The NDK's prebuilt host directory name.
fn ndk_host_tag() -> &'static str {
    match std::env::consts::OS {
        "macos" => "darwin-x86_64",
        "windows" => "windows-x86_64",
        _ => "linux-x86_64",
    }
}

/// Sorts version-like directory names (`34.0.0`, `android-32`) numerically.
fn version_key(name: &str) -> Vec<u64> {
    name.split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap_or(0))
        .collect()
}

/// The newest subdirectory of `dir` satisfying `ok`.
fn newest(dir: &Path, ok: impl Fn(&Path) -> bool) -> Option<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| ok(p))
        .collect();
    found.sort_by_key(|p| version_key(&p.file_name().unwrap_or_default().to_string_lossy()));
    found.pop()
}

/// The platform jar to link resources against: android-34 (the target SDK) when installed,
/// else the newest installed at or above [`MIN_API`].
fn platform_jar(sdk: &Path) -> Option<PathBuf> {
    let platforms = sdk.join("platforms");
    let preferred = platforms.join("android-34/android.jar");
    if preferred.is_file() {
        return Some(preferred);
    }
    newest(&platforms, |p| {
        p.join("android.jar").is_file()
            && version_key(&p.file_name().unwrap_or_default().to_string_lossy())
                .first()
                .is_some_and(|&v| v >= u64::from(MIN_API))
    })
    .map(|p| p.join("android.jar"))
}

/// The tools of the user build: NDK and SDK.
pub fn ndk_tools() -> Result<Tools> {
    let mut missing = Vec::new();
    rust_tools(&mut missing)?;
    let exe = if cfg!(windows) { ".exe" } else { "" };
    let script = if cfg!(windows) { ".cmd" } else { "" };
    let ndk = env_dir(&["ANDROID_NDK_HOME", "ANDROID_NDK_ROOT"]);
    let mut clang = PathBuf::new();
    let mut llvm_ar = PathBuf::new();
    let mut objcopy = PathBuf::new();
    match &ndk {
        None => missing.push(MissingTool {
            what: "ANDROID_NDK_HOME (the Android NDK, r23 or later)".into(),
            from: "Android Studio's SDK Manager (NDK (Side by side)) or \
                   https://developer.android.com/ndk/downloads; then export \
                   ANDROID_NDK_HOME=<its directory>"
                .into(),
        }),
        Some(ndk) => {
            let bin = ndk
                .join("toolchains/llvm/prebuilt")
                .join(ndk_host_tag())
                .join("bin");
            clang = bin.join(format!("aarch64-linux-android{MIN_API}-clang{script}"));
            llvm_ar = bin.join(format!("llvm-ar{exe}"));
            objcopy = bin.join(format!("llvm-objcopy{exe}"));
            if !objcopy.is_file() {
                missing.push(MissingTool {
                    what: objcopy.display().to_string(),
                    from: "an NDK r23 or later (ANDROID_NDK_HOME points at one without it)".into(),
                });
            }
            if !clang.is_file() {
                missing.push(MissingTool {
                    what: clang.display().to_string(),
                    from: "an NDK r23 or later (ANDROID_NDK_HOME points at one without it)".into(),
                });
            }
        }
    }
    let sdk = env_dir(&["ANDROID_HOME", "ANDROID_SDK_ROOT"]);
    let mut build_tools = PathBuf::new();
    let mut android_jar = PathBuf::new();
    match &sdk {
        None => missing.push(MissingTool {
            what: "ANDROID_HOME or ANDROID_SDK_ROOT (the Android SDK: build-tools and a platform)"
                .into(),
            from: "Android Studio, or the command-line tools: sdkmanager \"build-tools;34.0.0\" \
                   \"platforms;android-34\" \"platform-tools\"; then export ANDROID_HOME=<the \
                   SDK directory>"
                .into(),
        }),
        Some(sdk) => {
            match newest(&sdk.join("build-tools"), |p| {
                p.join(format!("aapt2{exe}")).is_file()
            }) {
                Some(bt) => build_tools = bt,
                None => missing.push(MissingTool {
                    what: "Android SDK build-tools (aapt, aapt2, zipalign, apksigner)".into(),
                    from: "sdkmanager \"build-tools;34.0.0\"".into(),
                }),
            }
            match platform_jar(sdk) {
                Some(jar) => android_jar = jar,
                None => missing.push(MissingTool {
                    what: format!("an Android platform (android.jar), API {MIN_API} or later"),
                    from: "sdkmanager \"platforms;android-34\"".into(),
                }),
            }
        }
    }
    let tool = |name: &str, ext: &str, missing: &mut Vec<MissingTool>| {
        let p = build_tools.join(format!("{name}{ext}"));
        if !build_tools.as_os_str().is_empty() && !p.is_file() {
            missing.push(MissingTool {
                what: p.display().to_string(),
                from: "the SDK's build-tools (sdkmanager \"build-tools;34.0.0\")".into(),
            });
        }
        p
    };
    let aapt = tool("aapt", exe, &mut missing);
    let aapt2 = tool("aapt2", exe, &mut missing);
    let zipalign = tool("zipalign", exe, &mut missing);
    let apksigner = tool(
        "apksigner",
        if cfg!(windows) { ".bat" } else { "" },
        &mut missing,
    );
    let keytool = keytool(&mut missing);
    report_missing(&missing, "cargo xtask apk")?;
    let triple_env = ANDROID_TARGET.replace('-', "_");
    Ok(Tools {
        aapt,
        aapt2,
        zipalign,
        apksigner,
        keytool,
        android_jar,
        objcopy,
        cargo_env: vec![
            (linker_var(), clang.display().to_string()),
            (format!("CC_{triple_env}"), clang.display().to_string()),
            (format!("AR_{triple_env}"), llvm_ar.display().to_string()),
            // Android wants a DT_SONAME; rustc sets none for a cdylib.
            (
                "CARGO_ENCODED_RUSTFLAGS".into(),
                "-C\x1flink-arg=-Wl,-soname,libvr_ocean.so".into(),
            ),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_sort_numerically() {
        let mut v = vec!["9.0.0", "34.0.0", "30.0.3", "android-32", "android-4"];
        v.sort_by_key(|s| version_key(s));
        assert_eq!(v, ["android-4", "9.0.0", "30.0.3", "android-32", "34.0.0"]);
    }
}
