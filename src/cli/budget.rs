//! `vr-ocean gpu-budget`: renders the standard views at each modelled headset's eye size and
//! default settings with the counting variant of the ocean pass, and prints what the GPU cost
//! model ([`vr_ocean::render::budget`]) makes of the counts: per headset and view, invocations
//! and work per pixel, the estimated GPU time and the frame budget. A model, not a headset
//! measurement: the counts and instruction counts are measured, the throughput is published
//! figures and stated assumptions (`docs/notes/gpu-cost-model.md`).

use super::gpu_view::{render_view, scaled_eye, GpuBudgetArgs, ViewRun};
use super::report::CmdResult;
use vr_ocean::app;
use vr_ocean::render::budget::{self, HeadsetModel, PathCosts, StandardView, ViewEstimate};

pub fn gpu_budget_cmd(a: GpuBudgetArgs) -> CmdResult {
    if !(a.scale.is_finite() && (0.05..=1.0).contains(&a.scale)) {
        return Err(format!("--scale {}: must be in [0.05, 1]", a.scale).into());
    }
    // The calibration times the standard views; the budget prices the highest eye as well.
    let all: Vec<&StandardView> = if a.calibrate {
        budget::VIEWS.iter().collect()
    } else {
        budget::budget_views().to_vec()
    };
    let views: Vec<&StandardView> = if a.views.is_empty() {
        all
    } else {
        a.views
            .iter()
            .map(|name| {
                all.iter().copied().find(|v| v.name == name).ok_or_else(|| {
                    let names: Vec<&str> = all.iter().map(|v| v.name).collect();
                    format!("--views: no view {name:?} ({})", names.join(", "))
                })
            })
            .collect::<Result<_, _>>()?
    };
    let costs = match &a.costs_from {
        None => PathCosts::of_shaders()?,
        Some(dir) => costs_from(dir)?,
    };
    if a.calibrate {
        return super::calibrate::calibrate_cmd(&a, &costs, &views);
    }
    let mut rows: Vec<ViewEstimate> = Vec::new();
    for model in &budget::HEADSETS {
        let adreno = if a.no_adreno {
            None
        } else {
            let turnip = super::adreno::turnip_dir(a.turnip.as_deref());
            Some(super::adreno::adreno_paths(&turnip, model)?)
        };
        let mut measured = Vec::with_capacity(views.len());
        for view in &views {
            let mut row = measure(&a, model, view, &costs)?;
            if let Some(paths) = &adreno {
                row.with_adreno(model, paths);
            }
            if !a.json {
                eprintln!(
                    "{} / {}: {:.2} ms of {:.1}",
                    row.headset, row.view, row.estimated_ms, row.budget_ms
                );
            }
            measured.push((*view, row.counts));
            rows.push(row);
        }
        // The same frames at another refresh rate: priced again, not rendered again.
        for (variant, base) in &budget::RATE_VARIANTS {
            if *base != model.name {
                continue;
            }
            for (view, counts) in &measured {
                let mut row = budget::estimate(variant, view, &costs, counts);
                if let Some(paths) = &adreno {
                    row.with_adreno(variant, paths);
                }
                rows.push(row);
            }
        }
    }
    let json = serde_json::to_string_pretty(&rows)?;
    if let Some(out) = &a.out {
        vr_ocean::export::write_bytes(out, json.as_bytes())?;
    }
    if a.json {
        println!("{json}");
    } else {
        println!(
            "GPU cost model (a model: invocation and instruction counts measured, throughput \
             from published figures; docs/notes/gpu-cost-model.md)"
        );
        println!("per invocation: {costs:?}");
        print!("{}", budget::table(&rows));
    }
    Ok(())
}

/// Reads and counts the cost variants in `dir`.
fn costs_from(dir: &std::path::Path) -> Result<PathCosts, Box<dyn std::error::Error>> {
    let mut words: Vec<Vec<u32>> = Vec::new();
    for name in budget::COST_MODULES {
        let file = dir.join(format!("{name}.spv"));
        let bytes = std::fs::read(&file)
            .map_err(|e| format!("--costs-from: cannot read {}: {e}", file.display()))?;
        if bytes.len() % 4 != 0 {
            return Err(format!("--costs-from: {} is not SPIR-V (length)", file.display()).into());
        }
        words.push(
            bytes
                .chunks_exact(4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
        );
    }
    let m: [&[u32]; 12] = std::array::from_fn(|i| words[i].as_slice());
    PathCosts::of_modules(m).map_err(|e| format!("--costs-from {}: {e}", dir.display()).into())
}

/// Renders `view` at `model`'s eye size and default settings with the counting pass and
/// estimates its cost.
fn measure(
    a: &GpuBudgetArgs,
    model: &HeadsetModel,
    view: &StandardView,
    costs: &PathCosts,
) -> Result<ViewEstimate, Box<dyn std::error::Error>> {
    // Four frames: the tallies are averaged over all of them, and the pass's timestamps (read a
    // frame or two late) reach the report for the last ones.
    let run = ViewRun {
        model,
        view,
        counting: true,
        frames: 4,
        warmup: 1,
        taps: a.anisotropy.unwrap_or(4),
    };
    let (report, _) = render_view(a, &run)?;
    let mut counts = report
        .paths
        .ok_or("the renderer returned no counts (the device lacks pipeline statistics)")?;
    // Counted at a smaller size: scale back to the headset's pixels.
    let (width, height) = scaled_eye(a, model);
    let (eye_width, eye_height) = model.eye();
    let ratio = (eye_width as f64 * eye_height as f64) / (width as f64 * height as f64);
    if ratio != 1.0 {
        for c in [
            &mut counts.sky,
            &mut counts.single,
            &mut counts.supersampled,
            &mut counts.resamples,
            &mut counts.foam,
            &mut counts.plain,
            &mut counts.detail,
            &mut counts.knee,
            &mut counts.below,
            &mut counts.depths,
            &mut counts.aniso_taps,
            &mut counts.fragment_invocations,
        ] {
            *c = (*c as f64 * ratio).round() as u64;
        }
        for c in counts
            .by_area
            .iter_mut()
            .chain(&mut counts.quarter_lanes)
            .chain(&mut counts.by_thickness)
        {
            *c = (*c as f64 * ratio).round() as u64;
        }
    }
    let mut row = budget::estimate(model, view, costs, &counts);
    let gpu = report.times.percentiles(app::Timing::GpuPass);
    row.measured_gpu_ms = (gpu.samples > 0).then_some(gpu.p50);
    Ok(row)
}
