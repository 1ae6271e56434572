//! rustup: the components and targets the checks use, added to the active toolchain.

use std::process::Command;

use crate::apk::ANDROID_TARGET;
use crate::ci::CROSS_TARGET;
use crate::process::{capture, on_path, run_checked, say};
use crate::Result;

/// rustup components the checks use.
const RUSTUP_COMPONENTS: &[&str] = &["rustfmt", "clippy"];

/// rustup targets the checks use (the Quest's for clippy and the APK).
const RUSTUP_TARGETS: &[&str] = &[CROSS_TARGET, ANDROID_TARGET];

/// Adds the rustup components and targets the checks need to the active toolchain (the
/// rustup proxy exports RUSTUP_TOOLCHAIN, so this is the toolchain cargo runs with).
pub fn ensure_rustup() -> Result<()> {
    if !on_path("rustup") {
        say(&format!(
            "rustup not found: not installing components ({}) or targets ({}); \
             the checks will fail if they are missing",
            RUSTUP_COMPONENTS.join(" "),
            RUSTUP_TARGETS.join(" ")
        ));
        return Ok(());
    }

    say(&format!(
        "checking rustup components: {}",
        RUSTUP_COMPONENTS.join(" ")
    ));
    let installed = capture(Command::new("rustup").args(["component", "list", "--installed"]))?;
    let missing: Vec<&str> = RUSTUP_COMPONENTS
        .iter()
        .copied()
        .filter(|c| !has_component(&installed, c))
        .collect();
    if missing.is_empty() {
        say("rustup components already installed, skipping");
    } else {
        say(&format!(
            "installing rustup components: {}",
            missing.join(" ")
        ));
        run_checked(
            Command::new("rustup")
                .args(["component", "add"])
                .args(&missing),
        )?;
    }

    say(&format!(
        "checking rustup targets: {}",
        RUSTUP_TARGETS.join(" ")
    ));
    let installed = capture(Command::new("rustup").args(["target", "list", "--installed"]))?;
    let missing: Vec<&str> = RUSTUP_TARGETS
        .iter()
        .copied()
        .filter(|t| !installed.lines().any(|l| l.trim() == *t))
        .collect();
    if missing.is_empty() {
        say("rustup targets already installed, skipping");
    } else {
        say(&format!("installing rustup targets: {}", missing.join(" ")));
        run_checked(
            Command::new("rustup")
                .args(["target", "add"])
                .args(&missing),
        )?;
    }
    Ok(())
}

/// `rustup component list --installed` prints e.g. `clippy-x86_64-unknown-linux-gnu` (older
/// rustups: `rustfmt-preview-...`). Host triples never start with a component name.
fn has_component(list: &str, component: &str) -> bool {
    list.lines().map(str::trim).any(|line| {
        line.strip_prefix(component)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with('-'))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rustup_components() {
        let list = "cargo-x86_64-unknown-linux-gnu\nclippy-x86_64-unknown-linux-gnu\n\
                    rustfmt-preview-x86_64-unknown-linux-gnu\n";
        assert!(has_component(list, "clippy"));
        assert!(has_component(list, "rustfmt"));
        assert!(!has_component(list, "rust-src"));
        assert!(!has_component(
            "rustfmt-x86_64-unknown-linux-gnu\n",
            "clippy"
        ));
    }
}
