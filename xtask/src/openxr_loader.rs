//! The Khronos OpenXR loader for Android that the APK ships as
//! `lib/arm64-v8a/libopenxr_loader.so` (vr-ocean loads it at run time, like the desktop loads
//! `libopenxr_loader.so.1`).
//!
//! Where it comes from, in order:
//! 1. `--openxr-loader PATH`: the `openxr_loader_for_android-<version>.aar` (a zip), or a
//!    `libopenxr_loader.so` for arm64 (e.g. built from the OpenXR-SDK-Source with the NDK,
//!    see the README's Quest section).
//! 2. The AAR cached by an earlier download in `<target dir>/openxr-loader/`.
//! 3. Downloaded from Maven Central ([`AAR_URL`], with `curl`).
//!
//! From an AAR the library is [`AAR_MEMBER`] (older AARs: [`AAR_MEMBER_JNI`]), taken out with
//! `unzip`. Whatever the source, the file must be an ELF shared object for AArch64, or the
//! build stops saying so.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::process::say;
use crate::{Failure, Result};

/// The loader version downloaded when no path is given: at least 1.0.34 (older loaders break
/// on Quest OS v62 and later).
pub const LOADER_VERSION: &str = "1.1.49";

/// Maven Central's copy of the Khronos loader AAR of [`LOADER_VERSION`].
pub const AAR_URL: &str = "https://repo1.maven.org/maven2/org/khronos/openxr/openxr_loader_for_android/1.1.49/openxr_loader_for_android-1.1.49.aar";

/// The arm64 loader inside the AAR (prefab layout).
pub const AAR_MEMBER: &str =
    "prefab/modules/openxr_loader/libs/android.arm64-v8a/libopenxr_loader.so";

/// The same in the classic AAR layout.
pub const AAR_MEMBER_JNI: &str = "jni/arm64-v8a/libopenxr_loader.so";

/// Where the loader is found or how it failed to be.
#[derive(Debug, PartialEq, Eq)]
pub enum Loader {
    /// A checked arm64 `libopenxr_loader.so`.
    Found(PathBuf),
    /// None given and none could be had; the text says why and what to do.
    Missing(String),
}

/// What to do when no loader is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fallback {
    /// Use the cached AAR, or download it.
    Download,
    /// Neither (the verification build stays offline and reproducible).
    None,
}

/// The message shown when the loader is missing, after `why`.
pub fn missing_message(why: &str) -> String {
    format!(
        "the OpenXR loader for Android is missing ({why}). The APK needs the Khronos loader \
         (>= 1.0.34) as lib/arm64-v8a/libopenxr_loader.so, or it cannot start OpenXR on the \
         headset. Give it with --openxr-loader PATH, PATH being either\n  \
         - the AAR from Maven Central: {AAR_URL}\n  \
         - or libopenxr_loader.so for arm64 built from source with the NDK (README, section \
         Quest)"
    )
}

/// Finds the loader: `given` (AAR or .so), else per `fallback`. `work` is a scratch
/// directory (`<target dir>/openxr-loader`).
pub fn resolve(given: Option<&Path>, fallback: Fallback, work: &Path) -> Result<Loader> {
    if let Some(path) = given {
        if !path.is_file() {
            return Err(Failure::Msg(format!(
                "--openxr-loader {}: no such file",
                path.display()
            )));
        }
        let so = if is_zip(path)? {
            extract(path, &work.join("given"))?
        } else {
            path.to_path_buf()
        };
        check_arm64_so(&so)?;
        return Ok(Loader::Found(so));
    }
    if fallback == Fallback::None {
        return Ok(Loader::Missing(
            "no --openxr-loader given; the verification build does not download".into(),
        ));
    }
    let aar = work.join(format!("openxr_loader_for_android-{LOADER_VERSION}.aar"));
    if !aar.is_file() {
        if let Err(why) = download(&aar) {
            return Ok(Loader::Missing(why));
        }
    } else {
        say(&format!("OpenXR loader: cached {}", aar.display()));
    }
    let so = extract(&aar, &work.join(LOADER_VERSION))?;
    check_arm64_so(&so)?;
    Ok(Loader::Found(so))
}

/// Downloads the AAR to `to` (via a temporary name); `Err` says why it could not.
fn download(to: &Path) -> std::result::Result<(), String> {
    if !crate::process::on_path("curl") {
        return Err(
            "no --openxr-loader given, and curl (Debian: apt install curl) is not \
                    installed to download it"
                .into(),
        );
    }
    if let Some(dir) = to.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let part = to.with_extension("aar.part");
    say(&format!("OpenXR loader: downloading {AAR_URL}"));
    let status = Command::new("curl")
        .args(["--fail", "--location", "--silent", "--show-error"])
        .args(["--connect-timeout", "20", "--max-time", "300", "--output"])
        .arg(&part)
        .arg(AAR_URL)
        .status()
        .map_err(|e| format!("cannot run curl: {e}"))?;
    if !status.success() {
        let _ = std::fs::remove_file(&part);
        return Err(format!(
            "no --openxr-loader given, and downloading {AAR_URL} failed ({status})"
        ));
    }
    std::fs::rename(&part, to).map_err(|e| format!("cannot rename {}: {e}", part.display()))
}

/// Whether `path` starts like a zip archive (an AAR).
fn is_zip(path: &Path) -> Result<bool> {
    let mut head = [0u8; 4];
    let mut f = std::fs::File::open(path)
        .map_err(|e| Failure::Msg(format!("cannot open {}: {e}", path.display())))?;
    use std::io::Read as _;
    let n = f
        .read(&mut head)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", path.display())))?;
    Ok(n == 4 && head == *b"PK\x03\x04")
}

/// Takes the arm64 loader out of an AAR into `dir`; returns its path.
fn extract(aar: &Path, dir: &Path) -> Result<PathBuf> {
    if !crate::process::on_path("unzip") {
        return Err(Failure::Msg(format!(
            "{} is an AAR (zip); taking the loader out of it needs unzip (Debian: apt install \
             unzip)",
            aar.display()
        )));
    }
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    for member in [AAR_MEMBER, AAR_MEMBER_JNI] {
        let out = Command::new("unzip")
            .args(["-o", "-j", "-q"])
            .arg(aar)
            .arg(member)
            .arg("-d")
            .arg(dir)
            .output()
            .map_err(|e| Failure::Msg(format!("cannot run unzip: {e}")))?;
        let so = dir.join("libopenxr_loader.so");
        if out.status.success() && so.is_file() {
            say(&format!("OpenXR loader: {member} from {}", aar.display()));
            return Ok(so);
        }
    }
    Err(Failure::Msg(format!(
        "{} has neither {AAR_MEMBER} nor {AAR_MEMBER_JNI}: not the Khronos \
         openxr_loader_for_android AAR?",
        aar.display()
    )))
}

/// Checks that `path` is an ELF64 little-endian shared object for AArch64.
pub fn check_arm64_so(path: &Path) -> Result<()> {
    let bytes = std::fs::read(path)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", path.display())))?;
    elf_arm64_so(&bytes).map_err(|why| {
        Failure::Msg(format!(
            "{} is not an arm64 shared library ({why}); the OpenXR loader must be \
             libopenxr_loader.so for arm64-v8a",
            path.display()
        ))
    })
}

/// `Ok` for an ELF64 LSB `ET_DYN` for `EM_AARCH64`; else what is wrong.
pub fn elf_arm64_so(b: &[u8]) -> std::result::Result<(), &'static str> {
    if b.len() < 64 || &b[..4] != b"\x7fELF" {
        return Err("not an ELF file");
    }
    if b[4] != 2 || b[5] != 1 {
        return Err("not 64-bit little-endian ELF");
    }
    let e_type = u16::from_le_bytes([b[16], b[17]]);
    let e_machine = u16::from_le_bytes([b[18], b[19]]);
    if e_machine != 183 {
        return Err("not for AArch64");
    }
    if e_type != 3 {
        return Err("not a shared object");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn elf(class: u8, e_type: u16, machine: u16) -> Vec<u8> {
        let mut b = vec![0u8; 64];
        b[..4].copy_from_slice(b"\x7fELF");
        b[4] = class;
        b[5] = 1;
        b[16..18].copy_from_slice(&e_type.to_le_bytes());
        b[18..20].copy_from_slice(&machine.to_le_bytes());
        b
    }

    #[test]
    fn elf_header_check() {
        assert_eq!(elf_arm64_so(&elf(2, 3, 183)), Ok(()));
        assert_eq!(elf_arm64_so(&elf(2, 3, 62)), Err("not for AArch64"));
        assert_eq!(elf_arm64_so(&elf(2, 2, 183)), Err("not a shared object"));
        assert_eq!(
            elf_arm64_so(&elf(1, 3, 183)),
            Err("not 64-bit little-endian ELF")
        );
        assert_eq!(elf_arm64_so(b"PK\x03\x04"), Err("not an ELF file"));
    }

    #[test]
    fn missing_without_fallback_and_bad_paths_are_errors() {
        let work = std::env::temp_dir().join(format!("xtask-loader-{}", std::process::id()));
        assert!(matches!(
            resolve(None, Fallback::None, &work),
            Ok(Loader::Missing(_))
        ));
        let err = resolve(Some(Path::new("/nonexistent/x.aar")), Fallback::None, &work);
        assert!(matches!(err, Err(Failure::Msg(m)) if m.contains("no such file")));
        std::fs::create_dir_all(&work).unwrap();
        let fake = work.join("libopenxr_loader.so");
        std::fs::write(&fake, elf(2, 3, 62)).unwrap();
        let err = resolve(Some(&fake), Fallback::None, &work);
        assert!(matches!(err, Err(Failure::Msg(m)) if m.contains("not for AArch64")));
        std::fs::write(&fake, elf(2, 3, 183)).unwrap();
        assert_eq!(
            resolve(Some(&fake), Fallback::None, &work),
            Ok(Loader::Found(fake.clone()))
        );
        let _ = std::fs::remove_dir_all(&work);
        let msg = missing_message("test");
        assert!(msg.contains(AAR_URL) && msg.contains("--openxr-loader"));
    }
}
