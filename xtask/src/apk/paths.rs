//! Where things are: cargo's target directory (from `cargo metadata`) and the APK of each
//! build kind in it.

use std::path::{Path, PathBuf};

use crate::process::{capture, cargo, workspace_root};
use crate::{Failure, Result};

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

/// The APK path of a build kind.
pub fn apk_path(target: &Path, release: bool, verify: bool) -> PathBuf {
    let name = match (verify, release) {
        (true, _) => "vr-ocean-verify-without-ndk.apk",
        (false, true) => "vr-ocean-release.apk",
        (false, false) => "vr-ocean-debug.apk",
    };
    target.join("apk").join(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_field() {
        let json = r#"{"packages":[],"target_directory":"/a \"b\"/t","version":1}"#;
        assert_eq!(
            json_string_field(json, "target_directory").as_deref(),
            Some("/a \"b\"/t")
        );
        assert_eq!(json_string_field(json, "workspace_root"), None);
    }
}
