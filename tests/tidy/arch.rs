//! Architecture: code chosen per CPU architecture (`target_arch`) lives in `sim` alone. CI's
//! aarch64 step (`xtask/src/ci/steps.rs`, under qemu) runs the unit tests of `sim`, `lod` and
//! `physics` and skips the other layers', which the host runs: a `target_arch` elsewhere would
//! go untested on the headset's architecture, so it fails here until that step runs its layer.

use crate::{rust_files, src};

/// The layers whose unit tests the aarch64 step runs, where `target_arch` may appear.
const ARCH_LAYERS: [&str; 3] = ["sim", "lod", "physics"];

#[test]
fn architecture_specific_code_stays_where_the_aarch64_step_tests_it() {
    let root = src();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    assert!(
        files.iter().any(|f| f.ends_with("sim/simd.rs")),
        "the walk missed src/sim/simd.rs: is the file walk broken?"
    );
    let mut found_in_sim = false;
    let mut outside = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap();
        let text = std::fs::read_to_string(file).unwrap();
        if !text.contains("target_arch") {
            continue;
        }
        let layer = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        if layer == "sim" {
            found_in_sim = true;
        }
        if !ARCH_LAYERS.iter().any(|l| *l == layer) {
            outside.push(rel.display().to_string());
        }
    }
    assert!(
        found_in_sim,
        "no target_arch in src/sim: is the search broken?"
    );
    assert!(
        outside.is_empty(),
        "target_arch outside {ARCH_LAYERS:?} (the aarch64 step skips their unit tests: run them \
         there too): {outside:?}"
    );
}
