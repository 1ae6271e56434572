//! Set-up: installs what a command needs on a fresh machine (Debian packages, rustup
//! components and targets) before it runs.

mod apt;
mod packages;
mod rustup;

pub use apt::ensure_apt_packages;
pub use packages::{APT_PACKAGES, BENCH_APT_PACKAGES, RUN_APT_PACKAGES, SHADER_APT_PACKAGES};
pub use rustup::ensure_rustup;
