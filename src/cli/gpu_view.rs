//! What `vr-ocean gpu-budget` is given and how it renders one standard view with the counting
//! ocean pass: the arguments, the modelled headsets as the command line names them, and the
//! counted render itself. The budget table ([`super::budget`]), the calibration against a
//! device's timestamps ([`super::calibrate`]) and the Adreno compiler's report
//! ([`super::adreno`]) all build on it.

use std::path::PathBuf;

use clap::Args;

use super::args::default_threads;
use super::report::ValidationWatch;
use vr_ocean::android::options::run_options;
use vr_ocean::app::{self, NoHooks};
use vr_ocean::render::budget::{self, HeadsetModel, StandardView};
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
    /// work per fragment, small triangles) at the Quest 2's recommended eye size (at render
    /// scale one) with its settings, fit the
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
    /// With --calibrate: the headset whose recommended eye size and default settings the
    /// calibration and the views are rendered at.
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
pub fn headset_of(model: &HeadsetModel) -> Headset {
    match model.name {
        "Quest 2" => Headset::Quest2,
        _ => Headset::Quest3,
    }
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
    // The headset's surface at any `--scale`: its far mesh collapsed for the headset's pixels.
    opts.renderer.mesh_eye_width = Some(model.eye().0);
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
pub fn scaled_eye(a: &GpuBudgetArgs, model: &HeadsetModel) -> (u32, u32) {
    let (eye_width, eye_height) = model.eye();
    let width = ((eye_width as f32 * a.scale).round() as u32).max(16);
    let height = ((eye_height as f32 * a.scale).round() as u32).max(16);
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
