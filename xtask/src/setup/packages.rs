//! The Debian packages each command needs: the one place to add a new requirement.

/// Debian/Ubuntu packages `cargo xtask test` needs. Add new requirements here (one list, so a
/// fresh machine gets everything in a single `apt-get install`).
pub const APT_PACKAGES: &[&str] = &[
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
    // built from Debian's Mesa source (its build dependencies, down to dpkg-dev).
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
pub const RUN_APT_PACKAGES: &[&str] = &[
    "libvulkan1",
    "mesa-vulkan-drivers",
    "libxkbcommon-x11-0",
    "libasound2-dev",
    "pkg-config",
];

/// What `cargo xtask shaders` needs: glslang's compiler, and spirv-opt for the cost variants.
pub const SHADER_APT_PACKAGES: &[&str] = &["glslang-tools", "spirv-tools"];

/// Extra packages for `cargo xtask bench` (the `fftw` feature links libfftw3f).
pub const BENCH_APT_PACKAGES: &[&str] = &["libfftw3-dev"];
