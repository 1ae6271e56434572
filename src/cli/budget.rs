//! `vr-ocean gpu-budget`: renders the standard views at each modelled headset's eye size and
//! default settings with the counting variant of the ocean pass, and prints what the GPU cost
//! model ([`vr_ocean::render::budget`]) makes of the counts: per headset and view, invocations
//! and work per pixel, the estimated GPU time and the frame budget. A model, not a headset
//! measurement: the counts and instruction counts are measured, the throughput is published
//! figures and stated assumptions (`docs/notes/gpu-cost-model.md`).

use std::path::PathBuf;

use clap::Args;

use super::args::default_threads;
use super::report::ValidationWatch;
use super::CmdResult;
use vr_ocean::android::options::run_options;
use vr_ocean::app::{self, NoHooks};
use vr_ocean::render::budget::{self, HeadsetModel, PathCosts, StandardView, ViewEstimate};
use vr_ocean::render::ocean::Anisotropy;
use vr_ocean::render::{ContextOptions, Msaa, StereoMode, Validation};
use vr_ocean::xr::desktop::{CameraPath, EyeSize, HeadlessXr};
use vr_ocean::xr::openxr::quest::Headset;
use vr_ocean::xr::FrameLoop;

#[derive(Args)]
pub struct GpuBudgetArgs {
    /// Print a JSON array (one object per headset and view: headset, view, estimated_ms,
    /// budget_ms, share, the counts, ...) instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also write the JSON array to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Only these views (comma-separated names: horizon, glitter, down, high).
    #[arg(long, value_delimiter = ',')]
    pub views: Vec<String>,
    /// Scale of the eye size the counting renders at (1 = the headset's; smaller is faster and
    /// scales the counts back up by the pixel ratio, for quick looks).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub scale: f32,
    /// Turn the specular anti-aliasing off (to see what it costs).
    #[arg(long)]
    pub no_specular_aa: bool,
    /// Anisotropic filtering's most taps (1 = off; the apps' default on a headset is 4), to
    /// see what it costs. The counting pass reads the trilinear sampler and tallies the taps.
    /// Default: 4; with --calibrate, the app's default on the device in use (4 on a GPU, off
    /// on a CPU device, whose lavapipe filters every tap in software).
    #[arg(long)]
    pub anisotropy: Option<u32>,
    /// Calibrate the model on the device in use instead: time the calibration passes (known
    /// work per fragment, small triangles) at the Quest 2 eye size with its settings, fit the
    /// device's costs, predict the ocean pass of every standard view from its counts, and
    /// measure the plain pass's own GPU time (its timestamps, as `headless` reports them).
    /// Prints one object per view: device, view, predicted_ms, measured_ms, error, the
    /// prediction's terms and the counts.
    #[arg(long)]
    pub calibrate: bool,
    /// Where Mesa's turnip and its no-op kernel shim are (`cargo xtask turnip`; default
    /// `$VR_OCEAN_TURNIP`, else /var/cache/vr-ocean/turnip): each row carries what the
    /// Adreno's own compiler makes of the water's paths.
    #[arg(long)]
    pub turnip: Option<PathBuf>,
    /// Leave out the Adreno compiler's statistics (no turnip needed).
    #[arg(long)]
    pub no_adreno: bool,
    /// With --calibrate: the headset whose eye size and default settings the calibration
    /// and the views are rendered at.
    #[arg(long, value_enum, default_value_t = HeadsetArg::Quest2)]
    pub headset: HeadsetArg,
    /// With --calibrate: also write the whole calibration (every pass's times, the fitted
    /// costs, the views) to this JSON file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// With --calibrate: render nothing; fit the model again to the calibration passes of an
    /// earlier report (--report, of any device) and predict its views from their recorded
    /// counts and the shader costs recorded with them. To check the model against devices
    /// that are not here.
    #[arg(long)]
    pub from: Option<PathBuf>,
    /// With --calibrate: how often each calibration pass is timed (the median is used).
    #[arg(long, default_value_t = 5)]
    pub repeats: usize,
    /// With --calibrate: frames of each view's plain pass (the first two are warm-up; the
    /// median of the rest's timestamps is the measured time).
    #[arg(long, default_value_t = 8)]
    pub frames: u64,
    /// Count the cost variants in this folder (`cost_*.spv`, as `cargo xtask shaders` makes
    /// them) instead of the built-in ones: to compare another version of the shaders on the
    /// same counts.
    #[arg(long)]
    pub costs_from: Option<PathBuf>,
    /// Require the Khronos validation layer and fail on any error.
    #[arg(long)]
    pub validation: bool,
    /// Simulation threads.
    #[arg(long, default_value_t = default_threads())]
    pub threads: usize,
}

/// A modelled headset, as the command line names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum HeadsetArg {
    /// Quest 2 (Adreno 650).
    Quest2,
    /// Quest 3 (Adreno 740).
    Quest3,
}

impl HeadsetArg {
    /// Its model.
    pub fn model(self) -> &'static HeadsetModel {
        match self {
            HeadsetArg::Quest2 => &budget::QUEST_2,
            HeadsetArg::Quest3 => &budget::QUEST_3,
        }
    }
}

/// The headset a model stands for (its defaults in this app).
fn headset_of(model: &HeadsetModel) -> Headset {
    match model.name {
        "Quest 2" => Headset::Quest2,
        _ => Headset::Quest3,
    }
}

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

/// How a standard view is rendered for the model.
pub struct ViewRun<'a> {
    /// The headset whose eye size and defaults are used.
    pub model: &'a HeadsetModel,
    /// Where the eyes are.
    pub view: &'a StandardView,
    /// The counting pass (tallies) or the plain one (its timestamps).
    pub counting: bool,
    /// Frames rendered; the first `warmup` are not timed.
    pub frames: u64,
    /// Frames not timed.
    pub warmup: u64,
    /// Anisotropic filtering's most taps.
    pub taps: u32,
}

/// Renders `run.view` at its headset's eye size and default settings (the GPU-time governor
/// off, no bodies); the report and the device's name.
pub fn render_view(
    a: &GpuBudgetArgs,
    run: &ViewRun<'_>,
) -> Result<(app::RunReport, bool), Box<dyn std::error::Error>> {
    let model = run.model;
    let defaults = headset_of(model).defaults();
    let preset = defaults.preset;
    if preset.name() != model.preset {
        return Err(format!(
            "the cost model's {} preset ({}) is not the app's default ({})",
            model.name,
            model.preset,
            preset.name()
        )
        .into());
    }
    let mut opts = run_options(&defaults, preset, &[], Some(a.threads))?;
    opts.threads = a.threads.max(1);
    opts.floating = None;
    opts.warmup = run.warmup;
    // The headset's defaults as they start, never adapted: a device slower than the headset
    // (lavapipe takes seconds a frame) would otherwise let the GPU-time governor step quality
    // down between the measured frames.
    opts.governor.enabled = false;
    opts.renderer.count_paths = run.counting;
    opts.renderer.specular_aa = !a.no_specular_aa;
    opts.renderer.anisotropy = Anisotropy::from_taps(run.taps)
        .ok_or_else(|| format!("--anisotropy {}: 1 (off), 2, 4, 8 or 16 taps", run.taps))?;
    opts.renderer.msaa = Msaa::from_samples(model.msaa)
        .ok_or_else(|| format!("{}: {} MSAA samples", model.name, model.msaa))?;
    let (width, height) = scaled_eye(a, model);
    let size = EyeSize::new(width, height)?;
    let view = run.view;
    let path = CameraPath::still(glam::Vec3::new(0.0, view.height, 0.0), view.yaw, view.pitch);
    let mut xr = HeadlessXr::new(&context_options(a), size, path, run.frames)?;
    // Mesa's lavapipe draws the second view's clipped triangles into the first view with
    // multiview; two passes count the same fragments.
    let cpu = xr.gpu().cpu_device;
    if cpu {
        opts.renderer.stereo = StereoMode::TwoPass;
    }
    let validation = ValidationWatch::of(xr.gpu());
    let report = app::run(&mut xr, &opts, &mut NoHooks)?;
    drop(xr);
    validation.check()?;
    Ok((report, cpu))
}

/// The eye size the views are rendered at: the headset's, scaled by `--scale`.
fn scaled_eye(a: &GpuBudgetArgs, model: &HeadsetModel) -> (u32, u32) {
    let width = ((model.eye.0 as f32 * a.scale).round() as u32).max(16);
    let height = ((model.eye.1 as f32 * a.scale).round() as u32).max(16);
    (width, height)
}

/// The Vulkan context every run of the command uses: the validation layer as asked.
pub fn context_options(a: &GpuBudgetArgs) -> ContextOptions {
    ContextOptions {
        validation: if a.validation {
            Validation::Required
        } else {
            Validation::Off
        },
        ..ContextOptions::default()
    }
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
    let ratio = (model.eye.0 as f64 * model.eye.1 as f64) / (width as f64 * height as f64);
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
