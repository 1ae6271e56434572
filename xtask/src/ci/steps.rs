//! The checks of `cargo xtask test`, in order: adding a check is adding one entry to [`STEPS`].

use crate::{apk, fuzz, monado, turnip, Result};

/// The cross target: Quest-class hardware is aarch64, so the NEON kernels are tested there.
pub const CROSS_TARGET: &str = "aarch64-unknown-linux-gnu";

/// One check of `cargo xtask test`. Adding a check is adding one entry to [`STEPS`].
pub struct Step {
    /// Short name for logs and the summary table.
    pub name: &'static str,
    /// Banner printed before the step, so CI logs show clearly what runs.
    pub header: &'static str,
    /// What it runs.
    pub run: Run,
    /// Skipped by `--quick` (slow steps).
    pub slow: bool,
    /// Runs before cargo (a failure fails the step); returns environment variables for it.
    pub prepare: Option<Prepare>,
}

/// What a step runs.
pub enum Run {
    /// `cargo` with these arguments (the toolchain running xtask).
    Cargo(&'static [&'static str]),
    /// The fuzz targets, each for a bounded time ([`fuzz::run_all`]).
    Fuzz,
}

/// A step's preparation: returns `(name, value)` environment variables for its cargo command.
pub type Prepare = fn() -> Result<Vec<(String, String)>>;

/// The doc step's environment: rustdoc's warnings (links that lead nowhere) are errors.
fn deny_doc_warnings() -> Result<Vec<(String, String)>> {
    Ok(vec![("RUSTDOCFLAGS".into(), "-D warnings".into())])
}

/// The checks, in the order they run (the first failure stops the rest).
pub const STEPS: &[Step] = &[
    Step {
        name: "fmt",
        header: "rustfmt check",
        run: Run::Cargo(&["fmt", "--all", "--", "--check"]),
        slow: false,
        prepare: None,
    },
    Step {
        name: "clippy",
        header: "clippy (all targets, warnings are errors)",
        run: Run::Cargo(&[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ]),
        slow: false,
        prepare: None,
    },
    Step {
        name: "clippy (android)",
        header: "clippy for aarch64-linux-android (the Quest library; no C compiler needed)",
        run: Run::Cargo(&[
            "clippy",
            "--target",
            apk::ANDROID_TARGET,
            "--lib",
            "--",
            "-D",
            "warnings",
        ]),
        slow: false,
        prepare: None,
    },
    Step {
        name: "doc",
        header: "rustdoc of the library (broken, ambiguous or private intra-doc links are errors)",
        run: Run::Cargo(&["doc", "--no-deps", "--lib"]),
        slow: false,
        prepare: Some(deny_doc_warnings),
    },
    Step {
        name: "test (host)",
        header: "tests on the host (Vulkan tests on lavapipe with the Khronos validation layer; the Adreno statistics on turnip, cargo xtask turnip)",
        run: Run::Cargo(&[
            "test",
            "--workspace",
            "--",
            "--skip",
            "frame_times_on_lavapipe",
            "--skip",
            "sea_state_blend::",
        ]),
        slow: false,
        prepare: Some(turnip::prepare_step),
    },
    Step {
        name: "frame times",
        header: "frame-time tests on lavapipe (table below, target/frame-times.json) and the sea state's blend, each alone on the CPU",
        run: Run::Cargo(&[
            "test",
            "--test",
            "frame_times",
            "--test",
            "app",
            "--",
            "--nocapture",
            "--test-threads=1",
            "frame_times_on_lavapipe",
            "sea_state_blend::",
        ]),
        slow: true,
        prepare: None,
    },
    Step {
        name: "openxr (Monado)",
        header: "OpenXR tests against Monado (trixie chroot, null compositor, simulated HMD; needs root), a 5-minute soak, and anisotropic filtering and the headsets' specular AA on its Mesa 25 lavapipe",
        run: Run::Cargo(&[
            "test",
            "--test",
            "openxr_monado",
            "--test",
            "openxr_no_alloc",
            "--test",
            "render",
            "--test",
            "soak",
            "--",
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ]),
        slow: true,
        prepare: Some(monado::prepare_step),
    },
    Step {
        name: "test (aarch64/qemu)",
        header: "CROSS: the unit tests of sim, lod and physics and the sim target (its laws, both derivative modes) for aarch64-unknown-linux-gnu (NEON path) under qemu-aarch64-static",
        run: Run::Cargo(&[
            "test",
            // No audio device: cpal's ALSA would need an arm64 libasound to link against.
            "--no-default-features",
            "--lib",
            "--test",
            "sim",
            "--target",
            CROSS_TARGET,
            "--",
            // The interaction layer's longest runs (minutes under qemu): they test its
            // physics, which the host runs; its NEON arithmetic is in the shorter tests.
            "--skip",
            "sim::interaction::tests::towed_sphere_leaves_a_kelvin_wake",
            "--skip",
            "sim::interaction::tests::the_edges_absorb_rings",
            // 90 s of the layer's decay (5400 steps): 150 of the 396 s the library's tests took
            // under qemu on Zen 4; the same steps run in the layer's shorter tests.
            "--skip",
            "sim::interaction::tests::energy_falls_after_the_sources_stop",
            // The layers with no code of their own per architecture (every `target_arch` is in
            // `sim`, `tests/tidy/arch.rs`): the host runs their tests.
            "--skip",
            "render::",
            "--skip",
            "xr::",
            "--skip",
            "app::",
            "--skip",
            "audio::",
            "--skip",
            "ui::",
            "--skip",
            "android::",
        ]),
        slow: true,
        prepare: None,
    },
    Step {
        name: "apk (verify without NDK)",
        header: "the Quest APK linked without the NDK (rust-lld, API 29 stubs, -z defs), packaged with Debian's aapt2, signed, then checked (cargo xtask apk-check)",
        run: Run::Cargo(&["run", "--quiet", "--package", "xtask", "--", "apk-check"]),
        slow: true,
        prepare: None,
    },
    Step {
        name: "fuzz",
        header: "cargo-fuzz (nightly, libFuzzer): the settings file, camera paths, parameter validation and the sound's input, 60 s each",
        run: Run::Fuzz,
        slow: true,
        prepare: Some(fuzz::prepare_step),
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_well_formed() {
        let mut names: Vec<_> = STEPS.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), STEPS.len(), "step names must be unique");
        assert!(
            STEPS.iter().any(|s| s.slow),
            "--quick must have something to skip"
        );
    }
}
