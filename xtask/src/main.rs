//! `cargo xtask`: project automation for vr-ocean (std only, no dependencies).
//!
//! * `cargo xtask test [--quick] [--no-setup]`: the single test command. Installs what is
//!   missing (apt packages, rustup components/targets), then runs fmt, clippy, rustdoc, host
//!   tests, the frame-time tests, the OpenXR tests against Monado in a Debian trixie chroot (as
//!   root; see [`monado`]) and the aarch64 (NEON) tests under qemu, stopping at the first
//!   failure.
//! * `cargo xtask run [ARGS]`: `cargo run --release --bin vr-ocean -- ARGS`; without ARGS the
//!   ocean window (headless PNGs in `./vr-ocean-headless/` when there is no display).
//! * `cargo xtask bench [--criterion] [--no-setup] [ARGS]`: FFT benchmarks against FFTW.
//! * `cargo xtask monado-root`: makes sure the Monado chroot exists and prints its path.
//! * `cargo xtask turnip`: makes sure Mesa's Adreno driver on its no-op kernel shim is built
//!   ([`turnip`]) and prints its path.
//! * `cargo xtask apk [--release] [--openxr-loader PATH] [--verify-without-ndk]`,
//!   `install [--release]`, `launch`: the Quest APK ([`apk`]); `apk-check`: CI's checks of
//!   the APK built without the NDK ([`apk_check`], [`android_stubs`], [`openxr_loader`]).
//!
//! The target directory is never chosen here: nested cargo calls inherit `CARGO_TARGET_DIR`
//! when the user set it and otherwise use the workspace default.

//!
//! Where things are: [`ci`] (`test`: its steps and summary), [`setup`] (apt packages, rustup),
//! [`process`] (running programs, xtask's output), [`commands`] (`run`, `shaders`, `bench`,
//! `soak`), [`apk`] and [`apk_check`] (the Quest APK), [`monado`], [`turnip`] and [`cache`]
//! (trees built once and kept), [`fuzz`].

mod android_stubs;
mod apk;
mod apk_check;
mod cache;
mod ci;
mod commands;
mod fuzz;
mod monado;
mod openxr_loader;
mod process;
mod setup;
mod turnip;

use std::process::ExitCode;

/// What `cargo xtask help` (and a bad command line) prints.
const USAGE: &str = "\
usage: cargo xtask <command> [options]

commands:
  test [--quick] [--no-setup]
        The project's test command. Installs what is missing (apt packages via
        apt-get, using sudo when not root; rustup components and targets), then runs
        in order, stopping at the first failure:
          cargo fmt --all -- --check
          cargo clippy --workspace --all-targets -- -D warnings
          cargo clippy --target aarch64-linux-android --lib -- -D warnings
          cargo test --workspace
          cargo test --test frame_times -- --nocapture
          cargo test --test openxr_monado --test openxr_no_alloc --test render --test soak
              -- --ignored --nocapture
              --test-threads=1 (needs root: first makes sure the Monado root exists, see monado-root,
              and passes its path in VR_OCEAN_MONADO_ROOT)
          cargo test --no-default-features --lib --test sim
              --target aarch64-unknown-linux-gnu   (qemu)
          cargo xtask apk-check
        --quick      skip the slow steps (frame times, Monado, APK, aarch64)
        --no-setup   install nothing; only run the checks
  run [--no-setup] [ARGS...]
        Installs what running needs when it is missing (the Vulkan loader and Mesa's
        drivers, and the keyboard library the window needs: libvulkan1
        mesa-vulkan-drivers libxkbcommon-x11-0 libasound2-dev pkg-config, via apt-get, using sudo when not root),
        then cargo run --release --bin vr-ocean -- ARGS...
        Without ARGS: the ocean in a window (keys in the README); with no display it
        renders 144 frames headless into ./vr-ocean-headless/ and says where.
        --no-setup   install nothing
  shaders
        Installs glslang-tools if missing, compiles shaders/*.vert|frag to
        shaders/spirv/*.spv (Vulkan 1.1) and records the sources' fingerprint there.
        Run it after editing a shader and commit the result: builds on machines
        without glslang use those files.
  bench [--criterion] [--no-setup] [--] [ARGS...]
        Installs libfftw3-dev if missing, then
          cargo run --release --features fftw --bin vr-ocean -- bench ARGS...
        --criterion  afterwards also run: cargo bench --features fftw --bench fft
        Arguments after `--` go to `vr-ocean bench` untouched.
  turnip
        As root: makes sure Mesa's Adreno Vulkan driver (turnip, with its compiler
        ir3) and its no-op kernel shim are built, then prints their folder (alone on
        stdout): $VR_OCEAN_CACHE/turnip (default /var/cache/vr-ocean/turnip), built
        once from Debian trixie's Mesa source (about 3 minutes) and restored from
        turnip.tar.zst there afterwards. `vr-ocean gpu-budget` reads the Adreno 650's
        and 740's shader statistics through it (VR_OCEAN_TURNIP or --turnip).
  soak [MINUTES]
        As root: the soak of issue 44 on Monado (default 20 minutes): `vr-ocean xr
        --soak-minutes` played by its scripted user while the test takes the focus
        away twice and kills the runtime once; prints the memory, open files,
        validation and under-run numbers and fails when they grow. Runs
          VR_OCEAN_SOAK_MINUTES=MINUTES cargo test --test soak -- --ignored --nocapture
        with the Monado root (see monado-root).
  monado-root
        As root: makes sure the Debian trixie chroot with Monado exists, then prints its
        path (alone on stdout). It is $VR_OCEAN_CACHE/monado-trixie (default cache dir
        /var/cache/vr-ocean), restored from monado-trixie.tar.zst there or built with
        debootstrap (about 100 s) when missing or when its package list changed. Run the
        OpenXR tests by hand with:
          export VR_OCEAN_MONADO_ROOT=$(cargo xtask monado-root)
          cargo test --test openxr_monado --test openxr_no_alloc --test render --test soak
              -- --ignored --nocapture --test-threads=1
  apk [--release] [--openxr-loader PATH] [--verify-without-ndk]
        The Quest APK: needs ANDROID_NDK_HOME (NDK r23+) and ANDROID_HOME or
        ANDROID_SDK_ROOT (build-tools, a platform >= 29), and the Khronos OpenXR loader:
        --openxr-loader takes its AAR (openxr_loader_for_android) or an arm64
        libopenxr_loader.so; without it the AAR is downloaded from Maven Central.
        Prints the APK path (<target dir>/apk/vr-ocean-debug.apk or -release.apk).
        --verify-without-ndk  CI only: links with rust-lld against API 29 stubs and
                     packages with Debian's tools; no download, and without
                     --openxr-loader the APK has no loader and cannot run.
  install [--release]
        adb install -r of the APK `apk` made.
  launch
        adb shell am start of the app, then logcat for its tag (vr-ocean) and DEBUG.
  apk-check
        Builds the APK with --verify-without-ndk and checks it (signature, badging,
        manifest, ELF exports and dependencies, alignment, loader packaging).
  help
        This text.

The cargo target directory is the workspace default unless CARGO_TARGET_DIR is set.
";

/// Runs the command named by the first argument; exits 2 on a bad command line.
fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((cmd, rest)) = args.split_first() else {
        eprint!("{USAGE}");
        return ExitCode::from(2);
    };
    let result = match cmd.as_str() {
        "test" => ci::parse_test_args(rest).and_then(|opts| ci::cmd_test(&opts)),
        "run" => commands::cmd_run(rest),
        "shaders" if rest.is_empty() => commands::cmd_shaders(),
        "shaders" => Err(Failure::Usage("shaders takes no arguments".into())),
        "bench" => commands::parse_bench_args(rest).and_then(|opts| commands::cmd_bench(&opts)),
        "soak" => commands::cmd_soak(rest),
        "monado-root" if rest.is_empty() => monado::ensure_root().map(|root| {
            println!("{}", root.display());
        }),
        "monado-root" => Err(Failure::Usage("monado-root takes no arguments".into())),
        "turnip" if rest.is_empty() => turnip::ensure_turnip().map(|root| {
            println!("{}", root.display());
        }),
        "turnip" => Err(Failure::Usage("turnip takes no arguments".into())),
        "apk" => apk::parse_apk_args(rest).and_then(|opts| apk::cmd_apk(&opts)),
        "install" => apk::parse_release_flag("install", rest).and_then(apk::cmd_install),
        "launch" => apk::parse_release_flag("launch", rest).and_then(|_| apk::cmd_launch()),
        "apk-check" => {
            if rest.is_empty() {
                apk_check::cmd_apk_check()
            } else {
                Err(Failure::Usage("apk-check takes no options".into()))
            }
        }
        "help" | "-h" | "--help" => {
            print!("{USAGE}");
            Ok(())
        }
        other => Err(Failure::Usage(format!("unknown command `{other}`"))),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(msg)) => {
            eprintln!("xtask: {msg}\n");
            eprint!("{USAGE}");
            ExitCode::from(2)
        }
        Err(Failure::Msg(msg)) => {
            eprintln!("xtask: error: {msg}");
            ExitCode::FAILURE
        }
        Err(Failure::Exit(code)) => ExitCode::from(code),
    }
}

/// Why a command failed, and so how xtask exits.
#[derive(Debug, PartialEq)]
enum Failure {
    /// Bad command line: usage text, exit 2.
    Usage(String),
    /// Something went wrong: message, exit 1.
    Msg(String),
    /// A child command failed and already reported why: exit with this code.
    Exit(u8),
}

/// xtask's result: a [`Failure`] says how to exit.
type Result<T> = std::result::Result<T, Failure>;
