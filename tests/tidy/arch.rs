//! Architecture: code chosen per CPU architecture (`target_arch`) lives in `sim`, `lod` and
//! `physics` alone. CI's aarch64 step (`xtask/src/ci/steps.rs`, under qemu) runs those layers'
//! unit tests and skips the others', which the host runs: a `target_arch` elsewhere would go
//! untested on the headset's architecture, so it fails here until that step runs its layer.

use std::path::Path;

use crate::{rust_files, src};

/// The layers whose unit tests the aarch64 step runs, where `target_arch` may appear.
const ARCH_LAYERS: [&str; 3] = ["sim", "lod", "physics"];

/// The files under `root` (a crate's `src/`) that name `target_arch`, as (layer, path from
/// `root`).
fn arch_files(root: &Path) -> Vec<(String, String)> {
    let mut files = Vec::new();
    rust_files(root, &mut files);
    files
        .iter()
        .filter(|f| std::fs::read_to_string(f).unwrap().contains("target_arch"))
        .map(|f| {
            let rel = f.strip_prefix(root).unwrap();
            let layer = rel.components().next().unwrap().as_os_str();
            (
                layer.to_string_lossy().into_owned(),
                rel.display().to_string(),
            )
        })
        .collect()
}

/// The files of `found` outside [`ARCH_LAYERS`].
fn outside(found: &[(String, String)]) -> Vec<String> {
    found
        .iter()
        .filter(|(layer, _)| !ARCH_LAYERS.contains(&layer.as_str()))
        .map(|(_, path)| path.clone())
        .collect()
}

#[test]
fn architecture_specific_code_stays_where_the_aarch64_step_tests_it() {
    let found = arch_files(&src());
    assert!(
        found.iter().any(|(_, p)| p.ends_with("simd.rs")),
        "no target_arch in src/sim/simd.rs: is the search broken?"
    );
    let outside = outside(&found);
    assert!(
        outside.is_empty(),
        "target_arch outside {ARCH_LAYERS:?} (the aarch64 step skips their unit tests: run them \
         there too): {outside:?}"
    );
}

#[test]
fn the_arch_rule_sees_a_target_arch_outside_its_layers() {
    let root = std::env::temp_dir().join(format!("vr-ocean-tidy-arch-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for (file, text) in [
        (
            "sim/simd.rs",
            "#[cfg(target_arch = \"aarch64\")]\nfn f() {}\n",
        ),
        (
            "render/probe.rs",
            "#[cfg(target_arch = \"x86_64\")]\nfn g() {}\n",
        ),
        ("render/plain.rs", "fn h() {}\n"),
    ] {
        let path = root.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    let found = arch_files(&root);
    std::fs::remove_dir_all(&root).unwrap();
    assert_eq!(found.len(), 2, "{found:?}");
    assert_eq!(
        outside(&found),
        vec![format!("render{}probe.rs", std::path::MAIN_SEPARATOR)]
    );
}
