//! Installs the fault-injection OpenXR API layer (`tests/fixtures/xr-fault-layer`) into a
//! chroot root, for tests that run a client against Monado with `VR_OCEAN_XR_FAULT` set.
//!
//! ```text
//! let mut env = fault_layer::install(root, &fault_layer::built_library());
//! env.push(fault_layer::fault("swapchain-fail"));
//! fault_layer::enable_core_validation(&mut env); // optional
//! // chroot root env K=V... /xr/app
//! ```
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};

/// The layer's name (its manifest's `api_layer.name`).
pub const LAYER_NAME: &str = "XR_APILAYER_VROCEAN_fault";

/// The environment variable that selects the fault (`no-vulkan-enable2`, `no-srgb`,
/// `swapchain-fail`; unset or empty for none).
pub const FAULT_ENV: &str = "VR_OCEAN_XR_FAULT";

/// The file name cargo gives the layer library.
pub const LIBRARY_FILE: &str = "libxr_fault_layer.so";

/// The Khronos core validation layer (trixie's `openxr-layer-corevalidation`).
pub const CORE_VALIDATION_LAYER: &str = "XR_APILAYER_LUNARG_core_validation";

/// Where distribution packages put explicit layer manifests. `XR_API_LAYER_PATH` replaces the
/// loader's standard explicit-layer search paths, so this has to be listed in it again for
/// the core validation layer to be found.
pub const SYSTEM_EXPLICIT_LAYER_DIR: &str = "/usr/share/openxr/1/api_layers/explicit.d";

/// The environment variable listing explicit-layer manifest directories (':'-separated).
pub const LAYER_PATH_ENV: &str = "XR_API_LAYER_PATH";

/// The environment variable listing the layers to enable (':'-separated on Linux).
pub const ENABLE_LAYERS_ENV: &str = "XR_ENABLE_API_LAYERS";

/// Directory of the library inside the chroot.
const CHROOT_DIR: &str = "/xr";

/// Directory of the manifest inside the chroot.
const CHROOT_LAYER_DIR: &str = "/xr/layers";

/// The built layer library: `libxr_fault_layer.so` in the profile directory of the running
/// test binary (`<target>/<profile>/deps/<test>` -> `<target>/<profile>/`), that is, where
/// `cargo build -p xr-fault-layer` puts it for the same target dir and profile (`cargo test`
/// and `cargo build` both use `debug/`; with `--release` both use `release/`).
///
/// Panics, saying how to build it, when it is missing.
pub fn built_library() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let profile_dir = exe
        .parent()
        .filter(|deps| deps.file_name().is_some_and(|n| n == "deps"))
        .and_then(Path::parent)
        .unwrap_or_else(|| {
            panic!(
                "{} is not in <target>/<profile>/deps/; cannot find {LIBRARY_FILE}",
                exe.display()
            )
        });
    let lib = profile_dir.join(LIBRARY_FILE);
    if !lib.is_file() {
        let release = if profile_dir.file_name().is_some_and(|n| n == "release") {
            " --release"
        } else {
            ""
        };
        panic!(
            "{} is missing: run `cargo build -p xr-fault-layer{release}` (with the same \
             CARGO_TARGET_DIR) before this test",
            lib.display()
        );
    }
    lib
}

/// Copies the layer library `lib` to `<root>/xr/libxr_fault_layer.so`, writes its manifest to
/// `<root>/xr/layers/XR_APILAYER_VROCEAN_fault.json` (`library_path` is the absolute path
/// inside the chroot, `/xr/libxr_fault_layer.so`) and returns the environment a client in the
/// chroot needs to load the layer: `XR_API_LAYER_PATH=/xr/layers` and
/// `XR_ENABLE_API_LAYERS=XR_APILAYER_VROCEAN_fault`. Add the fault with [`fault`].
///
/// The library is written under a temporary name and renamed, so a process that still has the
/// old copy mapped is not disturbed. Panics on I/O errors.
pub fn install(root: &Path, lib: &Path) -> Vec<(String, String)> {
    let dir = root.join(CHROOT_DIR.trim_start_matches('/'));
    let layer_dir = root.join(CHROOT_LAYER_DIR.trim_start_matches('/'));
    fs::create_dir_all(&layer_dir)
        .unwrap_or_else(|e| panic!("creating {}: {e}", layer_dir.display()));

    let dest = dir.join(LIBRARY_FILE);
    let tmp = dir.join(format!(".{LIBRARY_FILE}.{}", std::process::id()));
    fs::copy(lib, &tmp)
        .unwrap_or_else(|e| panic!("copying {} to {}: {e}", lib.display(), tmp.display()));
    fs::rename(&tmp, &dest)
        .unwrap_or_else(|e| panic!("renaming {} to {}: {e}", tmp.display(), dest.display()));

    let manifest = layer_dir.join(format!("{LAYER_NAME}.json"));
    let text = manifest_json(&format!("{CHROOT_DIR}/{LIBRARY_FILE}"));
    fs::write(&manifest, text).unwrap_or_else(|e| panic!("writing {}: {e}", manifest.display()));

    vec![
        (LAYER_PATH_ENV.to_string(), CHROOT_LAYER_DIR.to_string()),
        (ENABLE_LAYERS_ENV.to_string(), LAYER_NAME.to_string()),
    ]
}

/// The explicit-layer manifest (file format 1.0.0) for a library at `library_path`. An
/// explicit layer needs no `disable_environment` (only implicit layers must have one).
pub fn manifest_json(library_path: &str) -> String {
    format!(
        r#"{{
    "file_format_version": "1.0.0",
    "api_layer": {{
        "name": "{name}",
        "library_path": "{path}",
        "api_version": "1.0",
        "implementation_version": "1",
        "description": "vr-ocean test fixture: injects runtime faults chosen by {env}"
    }}
}}
"#,
        name = LAYER_NAME,
        path = json_escape(library_path),
        env = FAULT_ENV,
    )
}

/// `(VR_OCEAN_XR_FAULT, fault)`.
pub fn fault(fault: &str) -> (String, String) {
    (FAULT_ENV.to_string(), fault.to_string())
}

/// Adds `value` to the ':'-separated list in variable `key` of `env` (a new entry if `env`
/// has none). Empty items and items already listed are not added twice.
pub fn merge_list(env: &mut Vec<(String, String)>, key: &str, value: &str) {
    match env.iter_mut().find(|(k, _)| k == key) {
        Some((_, list)) => *list = join_lists(list, value),
        None => env.push((key.to_string(), join_lists("", value))),
    }
}

/// Joins two ':'-separated lists, dropping empty and repeated items.
pub fn join_lists(a: &str, b: &str) -> String {
    let mut items: Vec<&str> = Vec::new();
    for item in a.split(':').chain(b.split(':')) {
        if !item.is_empty() && !items.contains(&item) {
            items.push(item);
        }
    }
    items.join(":")
}

/// Also enables the core validation layer: appends it to `XR_ENABLE_API_LAYERS` and adds the
/// directory of its manifest to `XR_API_LAYER_PATH` (which otherwise hides it, see
/// [`SYSTEM_EXPLICIT_LAYER_DIR`]).
///
/// The loader (1.1.47) chains the layers in the order of `XR_ENABLE_API_LAYERS`, the first
/// nearest the application. The fault layer stays first so the application sees exactly the
/// injected `XrResult`: with the fault layer below it, the core validation layer turns the
/// failed instance creation of `no-vulkan-enable2` into `XR_ERROR_INITIALIZATION_FAILED`
/// (seen with trixie's 1.1.47; the other faults' results pass through it unchanged).
pub fn enable_core_validation(env: &mut Vec<(String, String)>) {
    merge_list(env, ENABLE_LAYERS_ENV, CORE_VALIDATION_LAYER);
    merge_list(env, LAYER_PATH_ENV, SYSTEM_EXPLICIT_LAYER_DIR);
}

/// `s` as the inside of a JSON string.
fn json_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out
}
