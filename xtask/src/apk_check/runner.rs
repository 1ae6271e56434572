//! Running this xtask binary and the Android tools for apk-check, echoing what they print.

use std::path::Path;
use std::process::Command;

use crate::process::{capture, say};
use crate::{Failure, Result};

/// Output and status of one `xtask apk` run.
pub struct Run {
    /// It exited with success.
    pub ok: bool,
    /// Its stdout, then its stderr.
    pub text: String,
}

/// Runs this xtask binary with `args` (and `env_remove`), echoing its output.
pub fn xtask(args: &[&str], env_remove: &[&str]) -> Result<Run> {
    let exe = std::env::current_exe()
        .map_err(|e| Failure::Msg(format!("cannot find the xtask binary: {e}")))?;
    let mut cmd = Command::new(exe);
    cmd.args(args);
    for var in env_remove {
        cmd.env_remove(var);
    }
    say(&format!("running: xtask {}", args.join(" ")));
    let out = cmd
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run xtask {}: {e}", args.join(" "))))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    for line in text.lines() {
        println!("    | {line}");
    }
    Ok(Run {
        ok: out.status.success(),
        text,
    })
}

/// Output of a tool that must succeed.
pub fn tool_output(cmd: &mut Command) -> Result<String> {
    capture(cmd)
}

/// Output of a tool as bytes.
pub fn tool_bytes(cmd: &mut Command) -> Result<Vec<u8>> {
    let out = cmd
        .output()
        .map_err(|e| Failure::Msg(format!("cannot run {:?}: {e}", cmd.get_program())))?;
    if !out.status.success() {
        return Err(Failure::Msg(format!(
            "{:?} failed: {}",
            cmd.get_program(),
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    Ok(out.stdout)
}

/// Prints `text` indented under a bar, as the output of a tool apk-check ran.
pub fn print_indented(text: &str) {
    for line in text.lines() {
        println!("    | {line}");
    }
}

/// Writes `bytes` to `path`, naming it on failure.
pub fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes)
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", path.display())))
}
