//! `cargo xtask install` and `launch`: the APK on a headset over adb.

use std::path::PathBuf;
use std::process::Command;

use super::paths::{apk_path, target_dir};
use super::tools::{env_dir, missing_tools_message, MissingTool};
use super::{ACTIVITY, LOG_TAG, PACKAGE};
use crate::process::{run_checked, say, which};
use crate::{Failure, Result};

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
