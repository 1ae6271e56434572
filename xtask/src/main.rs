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

mod android_stubs;
mod apk;
mod apk_check;
mod cache;
mod fuzz;
mod monado;
mod openxr_loader;
mod turnip;

/// The shader table and the sources fingerprint, shared with `build.rs`.
mod shader_table {
    include!("../../shaders/shader_table.rs");
}

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Debian/Ubuntu packages `cargo xtask test` needs. Add new requirements here (one list, so a
/// fresh machine gets everything in a single `apt-get install`).
const APT_PACKAGES: &[&str] = &[
    // The sound's output device (cpal links ALSA; its build finds it with pkg-config).
    "libasound2-dev",
    "pkg-config",
    // Cross-compiling and running the aarch64 (NEON) tests.
    "gcc-aarch64-linux-gnu",
    "libc6-dev-arm64-cross",
    "qemu-user-static",
    // The renderer: GLSL → SPIR-V at build time, SPIR-V validation in a test, the Vulkan
    // loader, Mesa's lavapipe (CPU Vulkan) to run on, and the Khronos validation layer the
    // Vulkan tests require.
    "glslang-tools",
    "spirv-tools",
    "libvulkan1",
    "mesa-vulkan-drivers",
    "vulkan-validationlayers",
    // The window-mode test runs a real window on a virtual X server (`xvfb-run`, which needs
    // `xauth`); winit loads libxkbcommon-x11 at run time.
    "xvfb",
    "xauth",
    "libxkbcommon-x11-0",
    // The OpenXR tests run Monado in a Debian trixie chroot (Monado is not in bookworm):
    // debootstrap builds it, zstd packs and unpacks its cached tarball.
    "debootstrap",
    "zstd",
    // The Adreno's compiler (`cargo xtask turnip`): Mesa's turnip and its no-op kernel shim,
    // built from Debian's Mesa source (TURNIP_APT_PACKAGES).
    "ninja-build",
    "python3-mako",
    "python3-yaml",
    "python3-packaging",
    "python3-venv",
    "bison",
    "flex",
    "libdrm-dev",
    "libexpat1-dev",
    "zlib1g-dev",
    "libzstd-dev",
    "patch",
    "xz-utils",
    "dpkg-dev",
    // The APK checked without the NDK: aapt and aapt2 (package `aapt`), zipalign, apksigner
    // (its Java runtime brings keytool), framework-res.apk of API 29 as aapt2's `-I`, clang and
    // lld for the stub system libraries, llvm for llvm-readelf, zip/unzip for the loader AAR.
    "aapt",
    "zipalign",
    "apksigner",
    "android-framework-res",
    "clang",
    "lld",
    "llvm",
    "zip",
    "unzip",
];

/// What building and running the ocean needs on a fresh machine (`cargo xtask run`): the Vulkan
/// loader and a driver (Mesa's, with lavapipe for machines without a GPU), libxkbcommon-x11,
/// which winit loads for a window on X11, and ALSA's headers and pkg-config, which the sound's
/// output (cpal) builds against. The SPIR-V is committed (`shaders/spirv/`).
const RUN_APT_PACKAGES: &[&str] = &[
    "libvulkan1",
    "mesa-vulkan-drivers",
    "libxkbcommon-x11-0",
    "libasound2-dev",
    "pkg-config",
];

/// What `cargo xtask shaders` needs: glslang's compiler, and spirv-opt for the cost variants.
const SHADER_APT_PACKAGES: &[&str] = &["glslang-tools", "spirv-tools"];

/// Extra packages for `cargo xtask bench` (the `fftw` feature links libfftw3f).
const BENCH_APT_PACKAGES: &[&str] = &["libfftw3-dev"];

/// rustup components the checks use.
const RUSTUP_COMPONENTS: &[&str] = &["rustfmt", "clippy"];

/// The cross target: Quest-class hardware is aarch64, so the NEON kernels are tested there.
const CROSS_TARGET: &str = "aarch64-unknown-linux-gnu";

/// rustup targets the checks use (the Quest's for clippy and the APK).
const RUSTUP_TARGETS: &[&str] = &[CROSS_TARGET, apk::ANDROID_TARGET];

/// One check of `cargo xtask test`. Adding a check is adding one entry to [`STEPS`].
struct Step {
    /// Short name for logs and the summary table.
    name: &'static str,
    /// Banner printed before the step, so CI logs show clearly what runs.
    header: &'static str,
    /// What it runs.
    run: Run,
    /// Skipped by `--quick` (slow steps).
    slow: bool,
    /// Runs before cargo (a failure fails the step); returns environment variables for it.
    prepare: Option<Prepare>,
}

/// What a step runs.
enum Run {
    /// `cargo` with these arguments (the toolchain running xtask).
    Cargo(&'static [&'static str]),
    /// The fuzz targets, each for a bounded time ([`fuzz::run_all`]).
    Fuzz,
}

/// A step's preparation: returns `(name, value)` environment variables for its cargo command.
type Prepare = fn() -> Result<Vec<(String, String)>>;

/// The doc step's environment: rustdoc's warnings (links that lead nowhere) are errors.
fn deny_doc_warnings() -> Result<Vec<(String, String)>> {
    Ok(vec![("RUSTDOCFLAGS".into(), "-D warnings".into())])
}

const STEPS: &[Step] = &[
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
        ]),
        slow: false,
        prepare: Some(turnip::prepare_step),
    },
    Step {
        name: "frame times",
        header: "frame-time tests on lavapipe: table below, target/frame-times.json",
        run: Run::Cargo(&[
            "test",
            "--test",
            "frame_times",
            "--",
            "--nocapture",
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
        header: "CROSS: sim unit tests and the sim target (its laws, both derivative modes) for aarch64-unknown-linux-gnu (NEON path, both derivative modes) under qemu-aarch64-static",
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
          cargo test --test openxr_monado --test openxr_no_alloc -- --ignored --nocapture
              --test-threads=1 (needs root: first makes sure the Monado root exists, see monado-root,
              and passes its path in VR_OCEAN_MONADO_ROOT)
          cargo test --no-default-features --lib --test sim_physics --test sim_derivatives
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
          cargo test --test openxr_monado --test openxr_no_alloc -- --ignored --nocapture --test-threads=1
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

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((cmd, rest)) = args.split_first() else {
        eprint!("{USAGE}");
        return ExitCode::from(2);
    };
    let result = match cmd.as_str() {
        "test" => parse_test_args(rest).and_then(|opts| cmd_test(&opts)),
        "run" => cmd_run(rest),
        "shaders" if rest.is_empty() => cmd_shaders(),
        "shaders" => Err(Failure::Usage("shaders takes no arguments".into())),
        "bench" => parse_bench_args(rest).and_then(|opts| cmd_bench(&opts)),
        "soak" => cmd_soak(rest),
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

#[derive(Debug, PartialEq)]
enum Failure {
    /// Bad command line: usage text, exit 2.
    Usage(String),
    /// Something went wrong: message, exit 1.
    Msg(String),
    /// A child command failed and already reported why: exit with this code.
    Exit(u8),
}

type Result<T> = std::result::Result<T, Failure>;

// ---------------------------------------------------------------------------------------------
// Argument parsing

#[derive(Debug, Default, PartialEq)]
struct TestOpts {
    quick: bool,
    no_setup: bool,
}

fn parse_test_args(args: &[String]) -> Result<TestOpts> {
    let mut opts = TestOpts::default();
    for arg in args {
        match arg.as_str() {
            "--quick" => opts.quick = true,
            "--no-setup" => opts.no_setup = true,
            other => return Err(Failure::Usage(format!("test: unknown option `{other}`"))),
        }
    }
    Ok(opts)
}

#[derive(Debug, Default, PartialEq)]
struct BenchOpts {
    criterion: bool,
    no_setup: bool,
    /// Passed to `vr-ocean bench`.
    passthrough: Vec<String>,
}

fn parse_bench_args(args: &[String]) -> Result<BenchOpts> {
    let mut opts = BenchOpts::default();
    let mut iter = args.iter();
    while let Some(arg) = iter.next() {
        match arg.as_str() {
            "--criterion" => opts.criterion = true,
            "--no-setup" => opts.no_setup = true,
            "--" => {
                opts.passthrough.extend(iter.by_ref().cloned());
                break;
            }
            _ => opts.passthrough.push(arg.clone()),
        }
    }
    Ok(opts)
}

// ---------------------------------------------------------------------------------------------
// Commands

fn cmd_test(opts: &TestOpts) -> Result<()> {
    let root = workspace_root();
    let mut rows: Vec<(String, Outcome)> = Vec::new();

    if opts.no_setup {
        say("set-up skipped (--no-setup)");
        rows.push(("set-up".into(), Outcome::Skipped("--no-setup")));
    } else {
        let start = Instant::now();
        let setup = ensure_apt_packages(APT_PACKAGES).and_then(|()| ensure_rustup());
        let took = start.elapsed();
        if let Err(err) = setup {
            // Report the cause before the summary so it is not lost below the table.
            let code = match err {
                Failure::Msg(msg) => {
                    eprintln!("xtask: error: {msg}");
                    1
                }
                Failure::Exit(code) => code,
                Failure::Usage(msg) => return Err(Failure::Usage(msg)),
            };
            rows.push(("set-up".into(), Outcome::Failed(took)));
            for step in STEPS {
                rows.push((step.name.into(), Outcome::NotRun));
            }
            print_summary(&rows);
            say("FAILED at step `set-up`");
            return Err(Failure::Exit(code));
        }
        rows.push(("set-up".into(), Outcome::Ok(took)));
    }

    // The failed step and what failed in it.
    let mut failed: Option<(&Step, String)> = None;
    for step in STEPS {
        if failed.is_some() {
            rows.push((step.name.into(), Outcome::NotRun));
            continue;
        }
        if opts.quick && step.slow {
            say(&format!("skipping `{}` (--quick)", step.name));
            rows.push((step.name.into(), Outcome::Skipped("--quick")));
            continue;
        }
        banner(&format!("step `{}`: {}", step.name, step.header));
        let start = Instant::now();
        let outcome = match step.prepare.map_or(Ok(Vec::new()), |prepare| prepare()) {
            Ok(envs) => {
                for (key, value) in &envs {
                    say(&format!("with {key}={value}"));
                }
                match step.run {
                    Run::Cargo(args) => {
                        let mut cmd = cargo();
                        cmd.args(args).envs(envs).current_dir(&root);
                        let ok = run_status(&mut cmd)?.success();
                        ok.then_some(())
                            .ok_or_else(|| format!("cargo {}", args.join(" ")))
                    }
                    Run::Fuzz => fuzz::run_all(&root, fuzz::CI_SECONDS),
                }
            }
            Err(err) => {
                if let Failure::Msg(msg) = err {
                    eprintln!("xtask: error: {msg}");
                }
                Err("its preparation (see the error above)".into())
            }
        };
        let took = start.elapsed();
        match outcome {
            Ok(()) => rows.push((step.name.into(), Outcome::Ok(took))),
            Err(what) => {
                rows.push((step.name.into(), Outcome::Failed(took)));
                failed = Some((step, what));
            }
        }
    }

    print_summary(&rows);
    match failed {
        Some((step, what)) => {
            say(&format!("FAILED at step `{}`: {what}", step.name));
            Err(Failure::Exit(1))
        }
        None => {
            say("all steps passed");
            Ok(())
        }
    }
}

fn cmd_run(args: &[String]) -> Result<()> {
    let (no_setup, args) = match args.split_first() {
        Some((first, rest)) if first == "--no-setup" => (true, rest),
        _ => (false, args),
    };
    if !no_setup {
        ensure_apt_packages(RUN_APT_PACKAGES)?;
    }
    if args.is_empty() {
        say("opening the ocean window (WASD/QE to move, mouse button held to look, Esc quits; headless PNGs if there is no display)");
    }
    let mut cmd = cargo();
    cmd.args(["run", "--release", "--bin", "vr-ocean"]);
    if !args.is_empty() {
        cmd.arg("--").args(args);
    }
    run_checked(cmd.current_dir(workspace_root()))
}

/// Compiles every shader of the table into `shaders/spirv/` and records the fingerprint of
/// the sources they came from.
fn cmd_shaders() -> Result<()> {
    ensure_apt_packages(SHADER_APT_PACKAGES)?;
    let src = workspace_root().join("shaders");
    let dir = src.join("spirv");
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", dir.display())))?;
    let tool = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    for (file, stem, defines) in shader_table::SHADERS {
        let out = dir.join(format!("{stem}.spv"));
        let mut cmd = Command::new(&tool);
        cmd.args(shader_table::glslang_args(
            &src.join(file),
            &out,
            &src,
            defines,
        ));
        let text = capture(&mut cmd)?;
        say(&format!(
            "{stem}.spv: {}",
            text.lines().last().unwrap_or("ok").trim()
        ));
    }
    // The cost variants of `vr-ocean gpu-budget`: compiled, then optimized (spirv-opt).
    let scratch = std::env::temp_dir().join(format!("vr-ocean-shaders-{}", std::process::id()));
    std::fs::create_dir_all(&scratch)
        .map_err(|e| Failure::Msg(format!("cannot create {}: {e}", scratch.display())))?;
    for (file, stem, defines) in shader_table::COST_SHADERS {
        let raw = scratch.join(format!("{stem}.spv"));
        let out = dir.join(format!("{stem}.spv"));
        let mut cmd = Command::new(&tool);
        cmd.args(shader_table::glslang_args(
            &src.join(file),
            &raw,
            &src,
            defines,
        ));
        capture(&mut cmd)?;
        let mut opt = Command::new("spirv-opt");
        opt.args(shader_table::optimizer_args(&raw, &out));
        capture(&mut opt)?;
        say(&format!("{stem}.spv: optimized"));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let fingerprint = shader_table::sources_fingerprint(&src)
        .map_err(|e| Failure::Msg(format!("cannot read {}: {e}", src.display())))?;
    let file = dir.join(shader_table::SOURCES_FINGERPRINT_FILE);
    std::fs::write(&file, format!("{fingerprint}\n"))
        .map_err(|e| Failure::Msg(format!("cannot write {}: {e}", file.display())))?;
    say(&format!(
        "wrote {} ({} modules, sources {fingerprint})",
        dir.display(),
        shader_table::SHADERS.len() + shader_table::COST_SHADERS.len()
    ));
    Ok(())
}

fn cmd_bench(opts: &BenchOpts) -> Result<()> {
    let root = workspace_root();
    if opts.no_setup {
        say("set-up skipped (--no-setup)");
    } else {
        ensure_apt_packages(BENCH_APT_PACKAGES)?;
    }
    // Without arguments: the baseline comparison on one thread, then thread scaling without
    // the baselines (their buffers crowd the shared cache and distort the scaling rounds).
    let default_runs: [&[&str]; 2] = [
        &["--threads", "1"],
        &["--threads", "1,2", "--skip-baselines"],
    ];
    // Other arguments are added to both runs; choosing `--threads` yourself makes it one run.
    let runs: Vec<Vec<String>> = if opts.passthrough.iter().any(|a| a.starts_with("--threads")) {
        vec![opts.passthrough.clone()]
    } else {
        default_runs
            .iter()
            .map(|r| {
                r.iter()
                    .map(|a| a.to_string())
                    .chain(opts.passthrough.iter().cloned())
                    .collect()
            })
            .collect()
    };
    for args in runs {
        let mut cmd = cargo();
        cmd.args([
            "run",
            "--release",
            "--features",
            "fftw",
            "--bin",
            "vr-ocean",
            "--",
            "bench",
        ])
        .args(&args)
        .current_dir(&root);
        run_checked(&mut cmd)?;
    }
    if opts.criterion {
        let mut cmd = cargo();
        cmd.args(["bench", "--features", "fftw", "--bench", "fft"])
            .current_dir(&root);
        run_checked(&mut cmd)?;
    }
    Ok(())
}

/// `cargo xtask soak [MINUTES]`: the soak test on Monado for MINUTES (default 20).
fn cmd_soak(rest: &[String]) -> Result<()> {
    let minutes = match rest {
        [] => 20.0,
        [m] => match m.parse::<f64>() {
            Ok(v) if v > 0.0 && v <= 24.0 * 60.0 => v,
            _ => {
                return Err(Failure::Usage(format!(
                    "soak: {m:?} is not a number of minutes in (0, 1440]"
                )))
            }
        },
        _ => {
            return Err(Failure::Usage(
                "soak takes at most one argument, MINUTES".into(),
            ))
        }
    };
    let env = monado::prepare_step()?;
    let mut cmd = cargo();
    cmd.args(["test", "--test", "soak", "--", "--ignored", "--nocapture"])
        .envs(env)
        .env("VR_OCEAN_SOAK_MINUTES", minutes.to_string())
        .current_dir(workspace_root());
    run_checked(&mut cmd)
}

// ---------------------------------------------------------------------------------------------
// Set-up

static APT_UPDATED: AtomicBool = AtomicBool::new(false);

/// Installs the Debian packages in `wanted` that are not installed yet (one `apt-get update`
/// per xtask run at most). Needs root or sudo; otherwise fails naming the packages.
fn ensure_apt_packages(wanted: &[&str]) -> Result<()> {
    say(&format!("checking apt packages: {}", wanted.join(" ")));
    let mut missing = Vec::new();
    for pkg in wanted {
        if !dpkg_installed(pkg)? {
            missing.push(*pkg);
        }
    }
    if missing.is_empty() {
        say("apt packages already installed, skipping");
        return Ok(());
    }
    let list = missing.join(" ");
    // Runs apt-get directly as root, through `sudo env ...` otherwise (sudo resets the env).
    let prefix: Vec<&str> = if is_root() {
        vec![]
    } else if on_path("sudo") {
        say("not root: using sudo for apt-get");
        vec!["sudo", "env", "DEBIAN_FRONTEND=noninteractive"]
    } else {
        return Err(Failure::Msg(format!(
            "missing apt packages: {list}\n  installing them needs root and sudo is not available; \
             run as root: apt-get install -y {list}\n  (or install them yourself and pass --no-setup)"
        )));
    };
    let apt = |args: &[&str]| -> Result<()> {
        let mut all: Vec<&str> = prefix.clone();
        all.push("apt-get");
        all.extend_from_slice(args);
        let mut cmd = Command::new(all[0]);
        cmd.args(&all[1..])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .stdin(std::process::Stdio::null());
        run_checked(&mut cmd).map_err(|_| {
            Failure::Msg(format!(
                "`{}` failed (needed packages: {list})",
                all.join(" ")
            ))
        })
    };
    // Wait for a concurrent dpkg (e.g. unattended-upgrades) instead of failing at once.
    const LOCK_WAIT: &str = "-oDPkg::Lock::Timeout=600";
    if !APT_UPDATED.swap(true, Ordering::SeqCst) {
        say("apt-get update");
        apt(&["-q", LOCK_WAIT, "update"])?;
    }
    say(&format!("installing apt packages: {list}"));
    let mut args = vec!["-q", LOCK_WAIT, "install", "-y", "--no-install-recommends"];
    args.extend_from_slice(&missing);
    apt(&args)
}

fn dpkg_installed(pkg: &str) -> Result<bool> {
    let out = Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", pkg])
        .output()
        .map_err(|e| {
            Failure::Msg(format!(
                "cannot run dpkg-query ({e}); automatic set-up supports Debian/Ubuntu only. \
                 Install the equivalents of: {} and pass --no-setup",
                APT_PACKAGES.join(" ")
            ))
        })?;
    // Exit status 1 and "no packages found" on stderr when the package is unknown.
    Ok(out.status.success() && is_installed_status(&String::from_utf8_lossy(&out.stdout)))
}

/// `${Status}` is "want flag status", e.g. `install ok installed`; `deinstall ok config-files`
/// (removed, config kept) does not count.
fn is_installed_status(status: &str) -> bool {
    status.split_whitespace().nth(2) == Some("installed")
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
        .unwrap_or(false)
}

/// Adds the rustup components and targets the checks need to the active toolchain (the
/// rustup proxy exports RUSTUP_TOOLCHAIN, so this is the toolchain cargo runs with).
fn ensure_rustup() -> Result<()> {
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

// ---------------------------------------------------------------------------------------------
// Process helpers

/// The cargo that runs us (same toolchain), or `cargo` from PATH.
fn cargo() -> Command {
    Command::new(std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo")))
}

/// The workspace root: the parent of xtask's manifest dir (cargo sets it at run time; the
/// compile-time value is the fallback for running the binary directly).
fn workspace_root() -> PathBuf {
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")));
    manifest.parent().map(Path::to_path_buf).unwrap_or(manifest)
}

fn show(cmd: &Command) -> String {
    std::iter::once(cmd.get_program())
        .chain(cmd.get_args())
        .map(|s| s.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

fn run_status(cmd: &mut Command) -> Result<std::process::ExitStatus> {
    say(&format!("running: {}", show(cmd)));
    cmd.status()
        .map_err(|e| Failure::Msg(format!("cannot start `{}`: {e}", show(cmd))))
}

/// Runs `cmd`; on failure exits with its code (128 + signal when killed).
fn run_checked(cmd: &mut Command) -> Result<()> {
    let status = run_status(cmd)?;
    if status.success() {
        return Ok(());
    }
    say(&format!("`{}` failed: {status}", show(cmd)));
    Err(Failure::Exit(exit_code(status)))
}

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

fn capture(cmd: &mut Command) -> Result<String> {
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

// ---------------------------------------------------------------------------------------------
// Output

fn say(msg: &str) {
    println!("xtask: {msg}");
}

fn banner(title: &str) {
    let rule = "=".repeat(78);
    println!("\n{rule}\nxtask: {title}\n{rule}");
}

enum Outcome {
    Ok(Duration),
    Failed(Duration),
    Skipped(&'static str),
    NotRun,
}

fn print_summary(rows: &[(String, Outcome)]) {
    let width = rows.iter().map(|(n, _)| n.len()).max().unwrap_or(4).max(4);
    let total: Duration = rows
        .iter()
        .map(|(_, o)| match o {
            Outcome::Ok(d) | Outcome::Failed(d) => *d,
            _ => Duration::ZERO,
        })
        .sum();
    banner("summary");
    println!("  {:<width$}  {:<18}  {:>9}", "step", "result", "time");
    for (name, outcome) in rows {
        let (result, time) = match outcome {
            Outcome::Ok(d) => ("ok".to_string(), fmt_duration(*d)),
            Outcome::Failed(d) => ("FAILED".to_string(), fmt_duration(*d)),
            Outcome::Skipped(why) => (format!("skipped ({why})"), "-".into()),
            Outcome::NotRun => ("not run".to_string(), "-".into()),
        };
        println!("  {name:<width$}  {result:<18}  {time:>9}");
    }
    println!(
        "  {:<width$}  {:<18}  {:>9}",
        "total",
        "",
        fmt_duration(total)
    );
}

fn fmt_duration(d: Duration) -> String {
    let secs = d.as_secs_f64();
    if secs < 60.0 {
        format!("{secs:.1}s")
    } else {
        format!("{}m{:02}s", d.as_secs() / 60, d.as_secs() % 60)
    }
}

// ---------------------------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn test_flags() {
        assert_eq!(parse_test_args(&[]), Ok(TestOpts::default()));
        assert_eq!(
            parse_test_args(&strings(&["--quick", "--no-setup"])),
            Ok(TestOpts {
                quick: true,
                no_setup: true
            })
        );
        assert!(matches!(
            parse_test_args(&strings(&["--bogus"])),
            Err(Failure::Usage(_))
        ));
    }

    #[test]
    fn bench_flags_are_stripped_and_rest_passes_through() {
        let opts = parse_bench_args(&strings(&[
            "--criterion",
            "--size",
            "512",
            "--",
            "--no-setup",
        ]))
        .unwrap();
        assert!(opts.criterion);
        assert!(!opts.no_setup);
        assert_eq!(opts.passthrough, strings(&["--size", "512", "--no-setup"]));
    }

    #[test]
    fn dpkg_status() {
        assert!(is_installed_status("install ok installed"));
        assert!(!is_installed_status("deinstall ok config-files"));
        assert!(!is_installed_status(""));
    }

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
