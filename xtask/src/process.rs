//! Process helpers: finding programs, running them (cargo included) and what xtask prints.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{Failure, Result};

/// The cargo that runs us (same toolchain), or `cargo` from PATH.
pub fn cargo() -> Command {
    Command::new(std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo")))
}

/// The workspace root: the parent of xtask's manifest dir (cargo sets it at run time; the
/// compile-time value is the fallback for running the binary directly).
pub fn workspace_root() -> PathBuf {
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")));
    manifest.parent().map(Path::to_path_buf).unwrap_or(manifest)
}

/// Finds `name` on PATH.
pub fn which(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join(name))
            .find(|p| p.is_file())
    })
}

/// Whether `program` is on PATH.
pub fn on_path(program: &str) -> bool {
    which(program).is_some()
}

/// Whether xtask runs as root (`id -u` is 0).
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// The command line of `cmd`, for logs and errors.
pub fn show(cmd: &Command) -> String {
    std::iter::once(cmd.get_program())
        .chain(cmd.get_args())
        .map(|s| s.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `cmd` (saying so) and returns its exit status; fails only when it cannot start.
pub fn run_status(cmd: &mut Command) -> Result<std::process::ExitStatus> {
    say(&format!("running: {}", show(cmd)));
    cmd.status()
        .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(cmd))))
}

/// Runs `cmd`; on failure exits with its code (128 + signal when killed).
pub fn run_checked(cmd: &mut Command) -> Result<()> {
    let status = run_status(cmd)?;
    if status.success() {
        return Ok(());
    }
    say(&format!("`{}` failed: {status}", show(cmd)));
    Err(Failure::Exit(exit_code(status)))
}

/// The exit code xtask passes on for a failed child: its own, or 128 + signal when killed.
fn exit_code(status: std::process::ExitStatus) -> u8 {
    if let Some(code) = status.code() {
        return u8::try_from(code).ok().filter(|&c| c != 0).unwrap_or(1);
    }
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = status.signal() {
            return u8::try_from(128 + sig).unwrap_or(1);
        }
    }
    1
}

/// Runs `cmd` quietly and returns its stdout; a failure carries its stderr.
pub fn capture(cmd: &mut Command) -> Result<String> {
    let out = cmd
        .output()
        .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(cmd))))?;
    if !out.status.success() {
        return Err(Failure::Msg(format!(
            "`{}` failed: {}\n{}",
            show(cmd),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// One line of xtask's own output.
pub fn say(msg: &str) {
    println!("xtask: {msg}");
}

/// A ruled title, so CI logs show clearly what runs.
pub fn banner(title: &str) {
    let rule = "=".repeat(78);
    println!("\n{rule}\nxtask: {title}\n{rule}");
}
