//! `vr-ocean gpu-budget --json` on lavapipe with the validation layer: every standard view of
//! both headsets is counted at its eye size and default settings, and the model's estimate is
//! gated against the headset's frame budget (issue 28). The counts are measured here; the
//! estimate is a model (`docs/notes/gpu-cost-model.md`). The report goes to
//! `target/gpu-budget.json`.

mod common;

use common::{assert_rejected, scratch_path};
use vr_ocean::render::budget::{self, QUEST_2, QUEST_3};
use vr_ocean::xr::openxr::quest::Headset;

/// The share of the frame budget every standard view's estimate must stay under: the issue's
/// goal, [`budget::GATE_SHARE`] (75 %).
const GATE: f64 = budget::GATE_SHARE;

/// The views whose estimate does not meet the goal yet (issue 28 is open on them), each with a
/// ceiling: its latest estimate plus 5 points, so that it can only get better. Measured with
/// `vr-ocean gpu-budget` after the special-function savings (lavapipe, Zen 5): Quest 2 25 m up
/// 98 %, 99 % with the detail near the viewer (every other view of both headsets 73 % or less).
/// Remove a line once its view meets the goal.
const NOT_YET: [(&str, &str, f64); 1] = [("Quest 2", "high", 1.03)];

#[test]
fn every_standard_view_fits_its_headsets_budget() {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .join("gpu-budget.json");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_vr-ocean"))
        .args([
            "gpu-budget",
            "--json",
            "--validation",
            "--threads",
            "2",
            "--out",
        ])
        .arg(&out)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "gpu-budget failed: {stderr}");
    let rows: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON on stdout");
    let rows = rows.as_array().expect("an array");
    assert_eq!(rows.len(), budget::HEADSETS.len() * budget::VIEWS.len());
    let saved: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(&saved, &serde_json::Value::Array(rows.clone()));
    let mut over = Vec::new();
    for r in rows {
        let (headset, view) = (r["headset"].as_str().unwrap(), r["view"].as_str().unwrap());
        let estimated = r["estimated_ms"].as_f64().unwrap();
        let budget_ms = r["budget_ms"].as_f64().unwrap();
        let c = &r["counts"];
        let n = |k: &str| c[k].as_u64().unwrap();
        println!(
            "{headset:<8} {view:<8} {estimated:6.2} ms of {budget_ms:5.2} ({:3.0} %), {:.2} \
             fragments/px, {:.0} % supersampled, counts {c}",
            100.0 * estimated / budget_ms,
            r["invocations_per_pixel"].as_f64().unwrap(),
            100.0 * r["supersampled_share"].as_f64().unwrap(),
        );
        assert!(estimated.is_finite() && estimated > 0.0);
        // Every pixel is shaded at least once (sky or water) and, with near-to-far order and
        // early depth tests, not many times more.
        let ipp = r["invocations_per_pixel"].as_f64().unwrap();
        assert!(
            (0.95..2.0).contains(&ipp),
            "{headset} {view}: {ipp} fragments per pixel"
        );
        // The views see what they are named for.
        match view {
            "horizon" | "glitter" => {
                assert!(
                    n("sky") > 0 && n("supersampled") > 0,
                    "{headset} {view}: {c}"
                );
                assert!(n("resamples") > 0);
            }
            "down" => assert_eq!(n("sky"), 0, "{headset} looking down sees no sky"),
            _ => {}
        }
        assert_eq!(n("plain"), 0, "the headsets' defaults have specular AA on");
        assert!(n("vertex_invocations") > 0);
        let gate = NOT_YET
            .iter()
            .find(|(h, v, _)| *h == headset && *v == view)
            .map_or(GATE, |&(_, _, ceiling)| ceiling);
        if estimated > gate * budget_ms {
            over.push(format!(
                "{headset} {view}: {estimated:.2} ms > {:.0} % of {budget_ms:.2} ms",
                100.0 * gate
            ));
        }
    }
    assert!(over.is_empty(), "over the GPU budget gate: {over:?}");
}

#[test]
fn the_model_follows_the_apps_headset_defaults() {
    for (model, headset) in [(QUEST_2, Headset::Quest2), (QUEST_3, Headset::Quest3)] {
        let d = headset.defaults();
        assert_eq!(model.preset, d.preset.name(), "{}", model.name);
        assert!((model.refresh_hz - d.max_refresh_rate as f64).abs() < 1e-6);
        let foveation = format!("{:?}", d.foveation);
        assert_eq!(
            format!("{:?}", model.foveation),
            foveation,
            "{}",
            model.name
        );
    }
}

#[test]
fn bad_arguments_are_refused() {
    let out = scratch_path("budget.json");
    let out = out.to_str().unwrap();
    assert_rejected(&["gpu-budget", "--scale", "0", "--out", out], &["scale"]);
    assert_rejected(&["gpu-budget", "--scale", "nan"], &["scale"]);
    assert_rejected(
        &["gpu-budget", "--views", "sideways"],
        &["sideways", "horizon"],
    );
    assert_rejected(
        &["gpu-budget", "--costs-from", "/nonexistent/vr-ocean-costs"],
        &["costs-from", "/nonexistent/vr-ocean-costs"],
    );
}
