//! The float mode through the OpenXR path: the eyes ride the sea.

use std::path::Path;
use std::time::Duration;

use crate::common::monado::{self, Monado};
use crate::{summary_value, EXE};

/// Issue 45: the float mode through the OpenXR path. `--in-water` starts the user in the
/// water off the deck's edge (the Y button and the panel's button do it in a session); with
/// Monado's simulated headset and controllers, the eyes ride the sea under the head: they stay
/// near their float height over it while the sea lifts and lowers them. Zero OpenXR core
/// validation and Vulkan validation messages.
#[test]
#[ignore = "needs root and the Monado root (the `openxr (Monado)` step of cargo xtask test)"]
fn floating_in_the_water_rides_the_sea_through_monado() {
    const NAME: &str = "float";
    let root = monado::root_from_env();
    let service = Monado::start(&root, NAME);
    let mut env = monado::xr_validation_env(NAME);
    env.push(("RUST_LOG".into(), "info".into()));
    let run = service.client(
        Path::new(EXE),
        &[
            "xr",
            "--grid",
            "64",
            "--preset",
            "low",
            "--wind",
            "14",
            "--frames",
            "200",
            "--in-water",
            "--validation",
        ],
        &monado::env_refs(&env),
        Duration::from_secs(600),
    );
    let _ = service.finish();
    assert!(run.success(), "{run}");
    assert!(run.stderr.contains("into the water"), "{run}");
    let afloat: u64 = summary_value(&run, "afloat_frames").parse().unwrap();
    let submitted: u64 = summary_value(&run, "frames_submitted").parse().unwrap();
    let range = |key: &str| -> (f32, f32) {
        let v = summary_value(&run, key);
        let (lo, hi) = v
            .split_once("..")
            .unwrap_or_else(|| panic!("{key}={v}\n{run}"));
        (lo.parse().unwrap(), hi.parse().unwrap())
    };
    let (over_lo, over_hi) = range("eyes_over_water_cm");
    let (low, high) = range("eye_height_cm");
    println!(
        "{afloat} of {submitted} frames afloat; eyes {over_lo}..{over_hi} cm over the sea \
         under the head, {low}..{high} cm over the mean level"
    );
    assert!(
        afloat + 2 >= submitted,
        "{afloat} frames afloat of {submitted}"
    );
    // Eyes 15 cm over the water, give or take the ride's lag (about 8 cm per metre of wave).
    assert!(over_lo > -10.0 && over_hi < 45.0, "{over_lo}..{over_hi}");
    // A 14 m/s sea (Hs about 3.5 m) lifts and lowers the head.
    assert!(
        high - low > 30.0,
        "the head did not ride the sea: {low}..{high} cm"
    );
    let xr_problems = monado::xr_validation_errors(&root, NAME);
    assert!(
        xr_problems.is_empty(),
        "OpenXR core validation: {xr_problems:#?}"
    );
    assert!(!run.stderr.contains("Vulkan validation"), "{run}");
}
