//! Commands and files in the root: `chroot` with a clean environment, a service's runtime
//! directory, a client's executable copied in.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The service's socket in its runtime directory.
pub(super) const SOCKET: &str = "monado_comp_ipc";

/// `PATH` inside the root (also used to find `chroot` on the host).
const PATH: &str = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin";

/// The runtime directory of the service called `name`, as seen inside the root.
pub fn runtime_dir_in_root(name: &str) -> String {
    format!("/run/xrt-{name}")
}

/// `chroot <root>` with a cleared environment plus `PATH` and `HOME`.
pub(super) fn chroot_command(root: &Path) -> Command {
    let mut cmd = Command::new("chroot");
    cmd.env_clear()
        .env("PATH", PATH)
        .env("HOME", "/root")
        .arg(root);
    cmd
}

/// Creates `<root>/run/xrt-<name>` (mode 700) and deletes a stale socket in it; returns it.
pub(super) fn prepare_runtime_dir(root: &Path, name: &str) -> PathBuf {
    assert!(
        !name.is_empty()
            && name.len() <= 40
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'),
        "service name {name:?}: use 1 to 40 letters, digits, `-` or `_` (it is part of the \
         socket path, which must fit in 108 bytes)"
    );
    let dir = root.join(runtime_dir_in_root(name).trim_start_matches('/'));
    fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    fs::set_permissions(&dir, fs::Permissions::from_mode(0o700))
        .unwrap_or_else(|e| panic!("cannot chmod {}: {e}", dir.display()));
    let socket = dir.join(SOCKET);
    if fs::symlink_metadata(&socket).is_ok() {
        fs::remove_file(&socket)
            .unwrap_or_else(|e| panic!("cannot remove {}: {e}", socket.display()));
    }
    dir
}

/// Copies `exe` to `<root>/xr/<file name>` (through a temporary name and a rename, so a copy
/// still running elsewhere keeps its file); returns its path inside the root.
pub(super) fn install_client(root: &Path, exe: &Path) -> String {
    let file = exe
        .file_name()
        .unwrap_or_else(|| panic!("{} has no file name", exe.display()))
        .to_string_lossy()
        .into_owned();
    let dir = root.join("xr");
    fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    // Unique per call: clients may be installed from several threads at once.
    static COPIES: AtomicUsize = AtomicUsize::new(0);
    let copy = COPIES.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!(".{file}.{}.{copy}", std::process::id()));
    fs::copy(exe, &tmp)
        .unwrap_or_else(|e| panic!("cannot copy {} to {}: {e}", exe.display(), tmp.display()));
    fs::rename(&tmp, dir.join(&file)).expect("rename the client into place");
    format!("/xr/{file}")
}
