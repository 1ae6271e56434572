//! Signing: the debug keystore (made with keytool on first use) and `apksigner sign`.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::tools::Tools;
use crate::process::{run_checked, say};
use crate::{Failure, Result};

/// The debug keystore's password, alias and key password (Android's convention).
const DEBUG_KEY: (&str, &str) = ("android", "androiddebugkey");

/// Signs `unsigned` into `out` with the debug key (`~/.android/debug.keystore`).
pub fn sign_with_debug_key(tools: &Tools, unsigned: &Path, out: &Path) -> Result<()> {
    let keystore = debug_keystore(&tools.keytool)?;
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
            .arg(out)
            .arg(unsigned),
    )
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
