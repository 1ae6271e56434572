//! `cargo xtask apk|install|launch`: the Quest APK.
//!
//! * User build (`apk [--release]`): `ANDROID_NDK_HOME` and `ANDROID_HOME`/`ANDROID_SDK_ROOT`
//!   name the NDK and SDK. `libvr_ocean.so` is linked by the NDK's clang for
//!   `aarch64-linux-android` API 29; the SDK's build-tools package it (`aapt2 compile/link`
//!   against the platform's `android.jar`, `aapt add` for the native libraries, stored
//!   uncompressed), `zipalign -p 4`, and `apksigner` signs it with the debug keystore
//!   (`~/.android/debug.keystore`, made with `keytool` on first use). The OpenXR loader is
//!   required ([`openxr_loader`](crate::openxr_loader)).
//! * Verification build (`apk --verify-without-ndk`, for CI): no NDK or SDK. `rust-lld` links
//!   against stub system libraries generated for API 29 ([`android_stubs`](crate::android_stubs))
//!   with `-z defs`, `_Unwind_*` come from the `unwinding` crate (feature
//!   `verify-without-ndk`), and Debian's `aapt`/`aapt2` (with `framework-res.apk` of API 29
//!   as `-I`), `zipalign` and `apksigner` package it. Without `--openxr-loader` it is built
//!   without the loader and says loudly that such an APK cannot run.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::openxr_loader::{self, Fallback, Loader};
use crate::{android_stubs, capture, cargo, run_checked, say, workspace_root, Failure, Result};

/// The Rust target of the Quest.
pub const ANDROID_TARGET: &str = "aarch64-linux-android";

/// The minimum API level (Quest OS is Android 10 and later).
pub const MIN_API: u32 = 29;

/// The application id in `android/AndroidManifest.xml`.
pub const PACKAGE: &str = "com.vrocean.ocean";

/// The launchable activity (Android's own NativeActivity).
pub const ACTIVITY: &str = "android.app.NativeActivity";

/// The logcat tag of the app (`vr_ocean::android::LOG_TAG`).
pub const LOG_TAG: &str = "vr-ocean";

/// Debian's `framework-res.apk` of API 29 (package `android-framework-res`).
pub const DEBIAN_FRAMEWORK_RES: &str = "/usr/share/android-framework-res/framework-res.apk";

/// The debug keystore's password, alias and key password (Android's convention).
const DEBUG_KEY: (&str, &str) = ("android", "androiddebugkey");

/// Options of `cargo xtask apk`.
#[derive(Debug, Default, PartialEq)]
pub struct ApkOpts {
    /// Release profile.
    pub release: bool,
    /// The NDK-less verification build (CI).
    pub verify_without_ndk: bool,
    /// The loader AAR or .so.
    pub openxr_loader: Option<PathBuf>,
}

/// Parses `apk` options.
pub fn parse_apk_args(args: &[String]) -> Result<ApkOpts> {
    let mut opts = ApkOpts::default();
    let mut iter = args.iter();
    while let Some(arg) = iter.next() {
        match arg.as_str() {
            "--release" => opts.release = true,
            "--verify-without-ndk" => opts.verify_without_ndk = true,
            "--openxr-loader" => match iter.next() {
                Some(p) if !p.starts_with("--") => opts.openxr_loader = Some(PathBuf::from(p)),
                _ => return Err(Failure::Usage("--openxr-loader needs a PATH".into())),
            },
            other => {
                if let Some(p) = other.strip_prefix("--openxr-loader=") {
                    opts.openxr_loader = Some(PathBuf::from(p));
                } else {
                    return Err(Failure::Usage(format!("apk: unknown option `{other}`")));
                }
            }
        }
    }
    Ok(opts)
}

/// Parses `install`/`launch` options (`--release` only).
pub fn parse_release_flag(cmd: &str, args: &[String]) -> Result<bool> {
    let mut release = false;
    for arg in args {
        match arg.as_str() {
            "--release" => release = true,
            other => return Err(Failure::Usage(format!("{cmd}: unknown option `{other}`"))),
        }
    }
    Ok(release)
}

/// One tool that was not found, and where it comes from.
#[derive(Debug, PartialEq)]
pub struct MissingTool {
    /// The tool or variable.
    pub what: String,
    /// Where to get it.
    pub from: String,
}

/// The tools a build uses.
#[derive(Debug)]
struct Tools {
    /// For `aapt add` (build-tools still ship aapt).
    aapt: PathBuf,
    aapt2: PathBuf,
    zipalign: PathBuf,
    apksigner: PathBuf,
    keytool: PathBuf,
    /// `-I` of `aapt2 link`.
    android_jar: PathBuf,
    /// Strips debug info from the packaged copy of the library (rustc's `rust-objcopy`, or
    /// the NDK's `llvm-objcopy`).
    objcopy: PathBuf,
    /// Environment for the cargo build (linker, flags). The flags go in
    /// `CARGO_ENCODED_RUSTFLAGS`, which replaces the user's `RUSTFLAGS` for this build.
    cargo_env: Vec<(String, String)>,
}

/// Finds `name` on PATH.
fn which(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join(name))
            .find(|p| p.is_file())
    })
}

/// An environment variable naming an existing directory.
fn env_dir(names: &[&str]) -> Option<PathBuf> {
    names
        .iter()
        .filter_map(std::env::var_os)
        .map(PathBuf::from)
        .find(|p| p.is_dir())
}

/// The rustc sysroot (for rust-lld and the installed targets).
fn sysroot() -> Result<PathBuf> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = capture(Command::new(rustc).args(["--print", "sysroot"]))?;
    Ok(PathBuf::from(out.trim()))
}

fn host_triple() -> Result<String> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = capture(Command::new(rustc).arg("-vV"))?;
    out.lines()
        .find_map(|l| l.strip_prefix("host: "))
        .map(str::to_string)
        .ok_or_else(|| Failure::Msg("rustc -vV printed no host triple".into()))
}

/// Checks the Rust side both builds need.
fn rust_tools(missing: &mut Vec<MissingTool>) -> Result<PathBuf> {
    let sysroot = sysroot()?;
    if !sysroot.join("lib/rustlib").join(ANDROID_TARGET).is_dir() {
        missing.push(MissingTool {
            what: format!("Rust target {ANDROID_TARGET}"),
            from: format!("rustup target add {ANDROID_TARGET}"),
        });
    }
    Ok(sysroot)
}

fn keytool(missing: &mut Vec<MissingTool>) -> PathBuf {
    if let Some(p) = which("keytool") {
        return p;
    }
    if let Some(p) = env_dir(&["JAVA_HOME"])
        .map(|j| j.join("bin/keytool"))
        .filter(|p| p.is_file())
    {
        return p;
    }
    missing.push(MissingTool {
        what: "keytool".into(),
        from: "a Java runtime (Debian: apt install default-jre-headless; or set JAVA_HOME)".into(),
    });
    PathBuf::from("keytool")
}

/// The tools of the verification build: Debian packages and rustup's rust-lld.
fn verify_tools(stubs: &Path) -> Result<Tools> {
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

/// `CARGO_TARGET_AARCH64_LINUX_ANDROID_LINKER`.
fn linker_var() -> String {
    format!(
        "CARGO_TARGET_{}_LINKER",
        ANDROID_TARGET.to_uppercase().replace('-', "_")
    )
}

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
fn ndk_tools() -> Result<Tools> {
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

/// One error naming every missing tool and where it comes from.
pub fn missing_tools_message(missing: &[MissingTool], what: &str) -> String {
    let mut msg = format!("{what} needs tools that are missing:");
    for m in missing {
        msg.push_str(&format!("\n  - {}: from {}", m.what, m.from));
    }
    msg
}

fn report_missing(missing: &[MissingTool], what: &str) -> Result<()> {
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Failure::Msg(missing_tools_message(missing, what)))
    }
}

/// Cargo's target directory (as `cargo metadata` reports it: `CARGO_TARGET_DIR`, config, or
/// the workspace's `target/`).
pub fn target_dir() -> Result<PathBuf> {
    let out = capture(
        cargo()
            .args(["metadata", "--format-version", "1", "--no-deps"])
            .current_dir(workspace_root()),
    )?;
    json_string_field(&out, "target_directory")
        .map(PathBuf::from)
        .ok_or_else(|| Failure::Msg("cargo metadata printed no target_directory".into()))
}

/// The value of `"key":"..."` in a JSON text (enough for cargo metadata's paths).
fn json_string_field(json: &str, key: &str) -> Option<String> {
    let start = json.find(&format!("\"{key}\":\""))? + key.len() + 4;
    let mut out = String::new();
    let mut chars = json[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => return Some(out),
            '\\' => match chars.next()? {
                'n' => out.push('\n'),
                't' => out.push('\t'),
                other => out.push(other),
            },
            c => out.push(c),
        }
    }
    None
}

/// What `build_apk` made.
#[derive(Debug)]
pub struct BuiltApk {
    /// The signed APK.
    pub path: PathBuf,
    /// Whether `lib/arm64-v8a/libopenxr_loader.so` is inside.
    pub has_loader: bool,
}

/// The APK path of a build kind.
pub fn apk_path(target: &Path, release: bool, verify: bool) -> PathBuf {
    let name = match (verify, release) {
        (true, _) => "vr-ocean-verify-without-ndk.apk",
        (false, true) => "vr-ocean-release.apk",
        (false, false) => "vr-ocean-debug.apk",
    };
    target.join("apk").join(name)
}

/// `cargo xtask apk`.
pub fn cmd_apk(opts: &ApkOpts) -> Result<()> {
    let built = build_apk(opts)?;
    if !built.has_loader {
        loud_warning();
    }
    say(&format!("APK: {}", built.path.display()));
    Ok(())
}

fn loud_warning() {
    let rule = "!".repeat(78);
    println!(
        "{rule}\nWARNING: this APK has NO OpenXR loader (lib/arm64-v8a/libopenxr_loader.so) and \
         cannot run on a headset:\nvr-ocean would stop at start-up with \"no OpenXR loader \
         could be loaded\". It is for CI's checks only.\n{}\n{rule}",
        openxr_loader::missing_message("--verify-without-ndk without --openxr-loader")
    );
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
    let keystore = debug_keystore(&tools.keytool)?;
    let out = apk_path(&target, opts.release, opts.verify_without_ndk);
    run_checked(
        Command::new(&tools.apksigner)
            .arg("sign")
            .arg("--ks")
            .arg(&keystore)
            .arg("--ks-pass")
            .arg(format!("pass:{}", DEBUG_KEY.0))
            .arg("--key-pass")
            .arg(format!("pass:{}", DEBUG_KEY.0))
            .arg("--ks-key-alias")
            .arg(DEBUG_KEY.1)
            .arg("--out")
            .arg(&out)
            .arg(&aligned),
    )?;
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

fn copy(from: &Path, to: &Path) -> Result<()> {
    std::fs::copy(from, to).map(|_| ()).map_err(|e| {
        Failure::Msg(format!(
            "cannot copy {} to {}: {e}",
            from.display(),
            to.display()
        ))
    })
}

/// `~/.android/debug.keystore`, made with keytool on first use.
fn debug_keystore(keytool: &Path) -> Result<PathBuf> {
    let home = std::env::var_os("HOME").map(PathBuf::from).ok_or_else(|| {
        Failure::Msg("HOME is not set: cannot find ~/.android/debug.keystore".into())
    })?;
    let dir = home.join(".android");
    let ks = dir.join("debug.keystore");
    if ks.is_file() {
        return Ok(ks);
    }
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    say(&format!("making the debug keystore {}", ks.display()));
    run_checked(
        Command::new(keytool)
            .args(["-genkeypair", "-noprompt", "-keystore"])
            .arg(&ks)
            .args(["-storepass", DEBUG_KEY.0, "-keypass", DEBUG_KEY.0])
            .args(["-alias", DEBUG_KEY.1])
            .args(["-keyalg", "RSA", "-keysize", "2048", "-validity", "10000"])
            .args(["-dname", "CN=Android Debug,O=Android,C=US"]),
    )?;
    Ok(ks)
}

/// adb: the SDK's platform-tools, else PATH.
fn adb() -> Result<PathBuf> {
    let exe = if cfg!(windows) { "adb.exe" } else { "adb" };
    if let Some(p) = env_dir(&["ANDROID_HOME", "ANDROID_SDK_ROOT"])
        .map(|sdk| sdk.join("platform-tools").join(exe))
        .filter(|p| p.is_file())
    {
        return Ok(p);
    }
    which(exe).ok_or_else(|| {
        Failure::Msg(missing_tools_message(
            &[MissingTool {
                what: "adb".into(),
                from: "the SDK's platform-tools (sdkmanager \"platform-tools\", with \
                       ANDROID_HOME set) or Debian's adb package"
                    .into(),
            }],
            "installing and launching",
        ))
    })
}

/// `cargo xtask install`: `adb install -r` of the APK `cargo xtask apk` made.
pub fn cmd_install(release: bool) -> Result<()> {
    let apk = apk_path(&target_dir()?, release, false);
    if !apk.is_file() {
        return Err(Failure::Msg(format!(
            "{} does not exist: run `cargo xtask apk{}` first",
            apk.display(),
            if release { " --release" } else { "" }
        )));
    }
    run_checked(Command::new(adb()?).arg("install").arg("-r").arg(&apk))
}

/// `cargo xtask launch`: starts the activity, then follows logcat for the app's tag (and
/// `DEBUG`, where Android writes native crash dumps) until Ctrl-C.
pub fn cmd_launch() -> Result<()> {
    let adb = adb()?;
    run_checked(
        Command::new(&adb)
            .args(["shell", "am", "start", "-S", "-n"])
            .arg(format!("{PACKAGE}/{ACTIVITY}")),
    )?;
    say(&format!(
        "following logcat (tags {LOG_TAG}, DEBUG); Ctrl-C stops following, not the app"
    ));
    run_checked(
        Command::new(&adb)
            .args(["logcat", "-T", "1", "-v", "time", "-s"])
            .arg(format!("{LOG_TAG}:V"))
            .arg("DEBUG:V"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn apk_flags() {
        assert_eq!(parse_apk_args(&[]), Ok(ApkOpts::default()));
        assert_eq!(
            parse_apk_args(&strings(&[
                "--release",
                "--verify-without-ndk",
                "--openxr-loader",
                "x.aar"
            ])),
            Ok(ApkOpts {
                release: true,
                verify_without_ndk: true,
                openxr_loader: Some("x.aar".into())
            })
        );
        assert_eq!(
            parse_apk_args(&strings(&["--openxr-loader=y.so"]))
                .unwrap()
                .openxr_loader,
            Some(PathBuf::from("y.so"))
        );
        for bad in [
            &["--openxr-loader"][..],
            &["--openxr-loader", "--release"],
            &["--x"],
        ] {
            assert!(matches!(
                parse_apk_args(&strings(bad)),
                Err(Failure::Usage(_))
            ));
        }
        assert_eq!(
            parse_release_flag("install", &strings(&["--release"])),
            Ok(true)
        );
        assert!(parse_release_flag("launch", &strings(&["-x"])).is_err());
    }

    #[test]
    fn json_field() {
        let json = r#"{"packages":[],"target_directory":"/a \"b\"/t","version":1}"#;
        assert_eq!(
            json_string_field(json, "target_directory").as_deref(),
            Some("/a \"b\"/t")
        );
        assert_eq!(json_string_field(json, "workspace_root"), None);
    }

    #[test]
    fn versions_sort_numerically() {
        let mut v = vec!["9.0.0", "34.0.0", "30.0.3", "android-32", "android-4"];
        v.sort_by_key(|s| version_key(s));
        assert_eq!(v, ["android-4", "9.0.0", "30.0.3", "android-32", "34.0.0"]);
    }

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

    #[test]
    fn missing_tools_are_listed_each_with_its_source() {
        let msg = missing_tools_message(
            &[
                MissingTool {
                    what: "a".into(),
                    from: "b".into(),
                },
                MissingTool {
                    what: "c".into(),
                    from: "d".into(),
                },
            ],
            "x",
        );
        assert_eq!(
            msg,
            "x needs tools that are missing:\n  - a: from b\n  - c: from d"
        );
    }
}
