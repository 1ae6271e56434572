//! Finding the tools an APK build uses ([`Tools`]), and naming each one that is missing with
//! where it comes from ([`MissingTool`]): one message for all of them. The two builds find them
//! in different places: [`verify`] (Debian's packages and rust-lld, for CI) and [`ndk`] (the
//! user's NDK and SDK).

mod ndk;
mod verify;

use std::path::PathBuf;
use std::process::Command;

use super::ANDROID_TARGET;
use crate::process::{capture, which};
use crate::{Failure, Result};

pub use ndk::ndk_tools;
pub use verify::verify_tools;

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
pub struct Tools {
    /// For `aapt add` (build-tools still ship aapt).
    pub aapt: PathBuf,
    /// Compiles the resources and links them with the manifest.
    pub aapt2: PathBuf,
    /// Aligns the APK (`-p 4`: native libraries page-aligned).
    pub zipalign: PathBuf,
    /// Signs the APK.
    pub apksigner: PathBuf,
    /// Makes the debug keystore on first use.
    pub keytool: PathBuf,
    /// `-I` of `aapt2 link`.
    pub android_jar: PathBuf,
    /// Strips debug info from the packaged copy of the library (rustc's `rust-objcopy`, or
    /// the NDK's `llvm-objcopy`).
    pub objcopy: PathBuf,
    /// Environment for the cargo build (linker, flags). The flags go in
    /// `CARGO_ENCODED_RUSTFLAGS`, which replaces the user's `RUSTFLAGS` for this build.
    pub cargo_env: Vec<(String, String)>,
}

/// An environment variable naming an existing directory.
pub fn env_dir(names: &[&str]) -> Option<PathBuf> {
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

/// The host triple rustc reports (`rustc -vV`), for rust-lld's directory.
pub fn host_triple() -> Result<String> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = capture(Command::new(rustc).arg("-vV"))?;
    out.lines()
        .find_map(|l| l.strip_prefix("host: "))
        .map(str::to_string)
        .ok_or_else(|| Failure::Msg("rustc -vV printed no host triple".into()))
}

/// Checks the Rust side both builds need.
pub fn rust_tools(missing: &mut Vec<MissingTool>) -> Result<PathBuf> {
    let sysroot = sysroot()?;
    if !sysroot.join("lib/rustlib").join(ANDROID_TARGET).is_dir() {
        missing.push(MissingTool {
            what: format!("Rust target {ANDROID_TARGET}"),
            from: format!("rustup target add {ANDROID_TARGET}"),
        });
    }
    Ok(sysroot)
}

/// keytool from PATH or `$JAVA_HOME/bin` (a Java runtime), else noted as missing.
pub fn keytool(missing: &mut Vec<MissingTool>) -> PathBuf {
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

/// `CARGO_TARGET_AARCH64_LINUX_ANDROID_LINKER`.
pub fn linker_var() -> String {
    format!(
        "CARGO_TARGET_{}_LINKER",
        ANDROID_TARGET.to_uppercase().replace('-', "_")
    )
}

/// One error naming every missing tool and where it comes from.
pub fn missing_tools_message(missing: &[MissingTool], what: &str) -> String {
    let mut msg = format!("{what} needs tools that are missing:");
    for m in missing {
        msg.push_str(&format!("\n  - {}: from {}", m.what, m.from));
    }
    msg
}

/// Fails with [`missing_tools_message`] when anything is missing.
pub fn report_missing(missing: &[MissingTool], what: &str) -> Result<()> {
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Failure::Msg(missing_tools_message(missing, what)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
