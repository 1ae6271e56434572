//! `cargo xtask apk-check`: CI's proof of the APK without the NDK or a headset.
//!
//! Runs `cargo xtask apk` itself (this binary) in the ways that matter and checks what comes
//! out:
//! 1. the user build with no NDK/SDK fails, naming each missing tool and where it comes from;
//! 2. `--verify-without-ndk` with no loader builds an APK without `libopenxr_loader.so` and
//!    says loudly that it cannot run;
//! 3. a missing or non-arm64 `--openxr-loader` fails clearly;
//! 4. a placeholder arm64 loader, given as a `.so` and inside an AAR, is packaged byte for
//!    byte as `lib/arm64-v8a/libopenxr_loader.so`;
//! 5. that APK: `apksigner verify` (v2 or v3 scheme, one signer), `aapt dump badging` (launchable NativeActivity,
//!    native-code arm64-v8a only, SDK 29/34, the features and permissions), `aapt dump
//!    xmltree` of the manifest (the intent categories, meta-data, `<queries>`,
//!    `<uses-native-library>`, launch mode, orientation), `llvm-readelf` of the packaged
//!    `libvr_ocean.so` (AArch64 shared object with SONAME, exports `ANativeActivity_onCreate`,
//!    NEEDs only system libraries, no text relocations), native libraries stored uncompressed,
//!    and `zipalign -c -p 4`.
//!
//! The checks of tool output are pure functions, one file each with unit tests that feed them
//! wrong output: [`listing`] (the archive's members), [`signature`] (apksigner), [`badging`]
//! and [`manifest`] (what aapt reads of the manifest; [`xmltree`] parses its dump), [`elf`]
//! (the packaged library). [`runner`] runs xtask and the tools, [`placeholder`] makes the
//! stand-in loader, [`verdict`] counts what passed.

mod badging;
mod elf;
mod listing;
mod manifest;
mod placeholder;
mod runner;
mod signature;
mod verdict;
mod xmltree;

use std::process::Command;

use badging::check_badging;
use elf::check_elf;
use listing::{check_listing, LIB, LOADER};
use manifest::check_manifest;
use placeholder::{fake_aar, fake_loader};
use runner::{print_indented, tool_bytes, tool_output, write, xtask};
use signature::check_apksigner;
use verdict::Verdict;

use crate::apk::{apk_path, target_dir};
use crate::process::{banner, say};
use crate::{Failure, Result};

/// `cargo xtask apk-check`.
pub fn cmd_apk_check() -> Result<()> {
    let start = std::time::Instant::now();
    let target = target_dir()?;
    let work = target.join("apk-check");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", work.display())))?;
    let apk = apk_path(&target, false, true);
    let mut v = Verdict::default();

    banner("apk-check 1/5: the user build without NDK and SDK names what is missing");
    let r = xtask(
        &["apk"],
        &[
            "ANDROID_NDK_HOME",
            "ANDROID_NDK_ROOT",
            "ANDROID_HOME",
            "ANDROID_SDK_ROOT",
        ],
    )?;
    v.expect(!r.ok, "`xtask apk` without NDK/SDK fails");
    v.expect(
        r.text.contains("needs tools that are missing")
            && r.text.contains("ANDROID_NDK_HOME (the Android NDK")
            && r.text.contains("ANDROID_HOME or ANDROID_SDK_ROOT")
            && r.text.contains("developer.android.com/ndk")
            && r.text.contains("sdkmanager"),
        "its message names the NDK and the SDK and where they come from",
    );

    banner("apk-check 2/5: --verify-without-ndk without a loader");
    let r = xtask(&["apk", "--verify-without-ndk"], &[])?;
    v.expect(r.ok, "`xtask apk --verify-without-ndk` builds an APK");
    v.expect(
        r.text.contains("WARNING: this APK has NO OpenXR loader")
            && r.text.contains("cannot run on a headset")
            && r.text.contains("--openxr-loader")
            && r.text.contains("openxr_loader_for_android"),
        "it says loudly that the APK has no OpenXR loader, and how to give one",
    );
    if r.ok {
        let listing = tool_output(Command::new("aapt").args(["list", "-v"]).arg(&apk))?;
        v.all(
            "APK without loader: members",
            check_listing(&listing, false),
        );
    }

    banner("apk-check 3/5: a bad --openxr-loader is refused");
    let nowhere = work.join("nowhere/openxr_loader_for_android.aar");
    let r = xtask(
        &[
            "apk",
            "--verify-without-ndk",
            "--openxr-loader",
            &nowhere.display().to_string(),
        ],
        &[],
    )?;
    v.expect(
        !r.ok
            && r.text
                .contains(&format!("{}: no such file", nowhere.display())),
        "a missing loader file fails, naming it",
    );
    let text_file = work.join("libopenxr_loader.so.txt");
    write(&text_file, b"not a library")?;
    let r = xtask(
        &[
            "apk",
            "--verify-without-ndk",
            "--openxr-loader",
            &text_file.display().to_string(),
        ],
        &[],
    )?;
    v.expect(
        !r.ok && r.text.contains("is not an arm64 shared library"),
        "a loader that is not an arm64 .so fails, saying so",
    );

    banner("apk-check 4/5: a placeholder loader (.so, then inside an AAR) is packaged");
    let fake = fake_loader(&work)?;
    let fake_bytes = std::fs::read(&fake)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", fake.display())))?;
    let aar = fake_aar(&work, &fake)?;
    for given in [&fake, &aar] {
        let r = xtask(
            &[
                "apk",
                "--verify-without-ndk",
                "--openxr-loader",
                &given.display().to_string(),
            ],
            &[],
        )?;
        let name = given.file_name().unwrap_or_default().to_string_lossy();
        v.expect(
            r.ok && !r.text.contains("WARNING: this APK has NO OpenXR loader"),
            &format!("--openxr-loader {name}: builds, without the warning"),
        );
        if r.ok {
            let packaged = tool_bytes(Command::new("unzip").arg("-p").arg(&apk).arg(LOADER))?;
            v.expect(
                packaged == fake_bytes,
                &format!("--openxr-loader {name}: {LOADER} is the given loader, byte for byte"),
            );
        }
    }

    banner("apk-check 5/5: the APK (with the placeholder loader)");
    let signed = Command::new("apksigner")
        .args(["verify", "--verbose"])
        .arg(&apk)
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run apksigner: {e}")))?;
    let signed_text = String::from_utf8_lossy(&signed.stdout);
    print_indented(&signed_text);
    v.expect(signed.status.success(), "apksigner verify succeeds");
    v.all("apksigner verify --verbose", check_apksigner(&signed_text));
    let listing = tool_output(Command::new("aapt").args(["list", "-v"]).arg(&apk))?;
    v.all("APK members", check_listing(&listing, true));
    let badging = tool_output(Command::new("aapt").args(["dump", "badging"]).arg(&apk))?;
    print_indented(&badging);
    v.all("aapt dump badging", check_badging(&badging));
    let tree = tool_output(
        Command::new("aapt")
            .args(["dump", "xmltree"])
            .arg(&apk)
            .arg("AndroidManifest.xml"),
    )?;
    v.all(
        "aapt dump xmltree AndroidManifest.xml",
        check_manifest(&tree),
    );
    let so = work.join("libvr_ocean.so");
    write(
        &so,
        &tool_bytes(Command::new("unzip").arg("-p").arg(&apk).arg(LIB))?,
    )?;
    let elf = tool_output(
        Command::new("llvm-readelf")
            .args(["--file-header", "--dynamic-table", "--dyn-syms", "--wide"])
            .arg(&so),
    )?;
    let needed = elf
        .lines()
        .filter(|l| l.contains("(NEEDED)") || l.contains("(SONAME)"))
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("\n");
    print_indented(&needed);
    v.all("llvm-readelf libvr_ocean.so", check_elf(&elf));
    let aligned = Command::new("zipalign")
        .args(["-c", "-p", "4"])
        .arg(&apk)
        .status()
        .map_err(|e| Failure::Msg(format!("cannot run zipalign: {e}")))?;
    v.expect(aligned.success(), "zipalign -c -p 4");

    say(&format!(
        "apk-check: {} checks passed, {} failed, in {:.1}s; APK {} ({:.1} MiB)",
        v.passed,
        v.problems.len(),
        start.elapsed().as_secs_f64(),
        apk.display(),
        std::fs::metadata(&apk).map(|m| m.len()).unwrap_or(0) as f64 / (1 << 20) as f64
    ));
    if v.problems.is_empty() {
        Ok(())
    } else {
        Err(Failure::Msg(format!(
            "apk-check failed:\n  - {}",
            v.problems.join("\n  - ")
        )))
    }
}
