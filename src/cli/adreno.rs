//! `vr-ocean shader-stats`: what the device's own shader compiler makes of every pipeline a
//! headset draws (and of each water path as a pipeline of its own); and how `gpu-budget` reads
//! it for the Adreno 650 and 740: this binary run again on Mesa's turnip with its no-op kernel
//! shim (`cargo xtask turnip`), as that GPU (`FD_GPU_ID`).

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;

use super::gpu_view::HeadsetArg;
use super::report::CmdResult;
use vr_ocean::render::budget::adreno::{self, AdrenoPath};
use vr_ocean::render::budget::paths::headset_pipelines;
use vr_ocean::render::budget::HeadsetModel;
use vr_ocean::render::render_pass::PassLayout;
use vr_ocean::render::statistics::PipelineStatistics;
use vr_ocean::render::{ContextOptions, GpuContext, Msaa, StereoMode, Validation};

#[derive(Args)]
pub struct ShaderStatsArgs {
    /// Print a JSON array (one object per pipeline: label, executables with their stage and
    /// statistics) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// The headset whose pass (multiview, its MSAA, fixed foveation where the device has it)
    /// the pipelines are built for.
    #[arg(long, value_enum, default_value_t = HeadsetArg::Quest2)]
    pub headset: HeadsetArg,
}

/// What `shader-stats --json` prints.
#[derive(serde::Serialize, serde::Deserialize)]
struct StatsReport {
    /// The device whose compiler made the pipelines.
    device: String,
    /// Every pipeline, in the order made.
    pipelines: Vec<PipelineStatistics>,
}

/// The eye images' format on the headsets (the runtimes' sRGB swapchains).
const EYE_FORMAT: ash::vk::Format = ash::vk::Format::R8G8B8A8_SRGB;

pub fn shader_stats_cmd(a: ShaderStatsArgs) -> CmdResult {
    let model = a.headset.model();
    let ctx = GpuContext::new(&ContextOptions {
        validation: Validation::Off,
        capture_statistics: true,
        fragment_density_map: true,
        ..ContextOptions::default()
    })?;
    let pass = PassLayout {
        mode: StereoMode::Multiview,
        colour_format: EYE_FORMAT,
        msaa: Msaa::from_samples(model.msaa).ok_or("the model's MSAA")?,
        store_depth: false,
        density_map: ctx.fragment_density_map,
    };
    let stats = headset_pipelines(&ctx, pass)?;
    if a.json {
        let report = StatsReport {
            device: ctx.device_name.clone(),
            pipelines: stats,
        };
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!(
        "{} compiled by {} ({}'s pass: multiview, MSAA {}{})",
        stats.len(),
        ctx.device_name,
        model.name,
        model.msaa,
        if pass.density_map {
            ", fixed foveation"
        } else {
            ""
        }
    );
    for p in &stats {
        for e in &p.executables {
            let line: Vec<String> = e
                .statistics
                .iter()
                .map(|s| format!("{} {}", s.name, s.value.as_f64()))
                .collect();
            println!("{} / {}: {}", p.label, e.stage, line.join(", "));
        }
    }
    Ok(())
}

/// Where turnip is: `dir` (`--turnip`), else `$VR_OCEAN_TURNIP`, else the cache folder
/// `cargo xtask turnip` builds it in.
pub fn turnip_dir(dir: Option<&Path>) -> PathBuf {
    dir.map(Path::to_path_buf)
        .or_else(|| std::env::var_os("VR_OCEAN_TURNIP").map(PathBuf::from))
        .unwrap_or_else(|| {
            std::env::var_os("VR_OCEAN_CACHE")
                .map(PathBuf::from)
                .unwrap_or_else(|| PathBuf::from("/var/cache/vr-ocean"))
                .join("turnip")
        })
}

/// The water paths as ir3 compiles them for `model`'s Adreno: this binary's `shader-stats`
/// run on turnip in `turnip` as that GPU.
pub fn adreno_paths(
    turnip: &Path,
    model: &HeadsetModel,
) -> Result<Vec<AdrenoPath>, Box<dyn std::error::Error>> {
    let icd = turnip.join("share/vulkan/icd.d/freedreno_icd.x86_64.json");
    let shim = turnip.join("lib/x86_64-linux-gnu/libfreedreno_noop_drm_shim.so");
    if !icd.is_file() || !shim.is_file() {
        return Err(format!(
            "the Adreno compiler is not in {} (no {} or {}): build it with `cargo xtask \
             turnip` (as root: Mesa's turnip from Debian's source, about 3 minutes once), or \
             name its folder with --turnip or VR_OCEAN_TURNIP; --no-adreno leaves it out",
            turnip.display(),
            icd.display(),
            shim.display()
        )
        .into());
    }
    let headset = match model.adreno {
        650 => "quest2",
        _ => "quest3",
    };
    let me = std::env::current_exe()?;
    let out = Command::new(&me)
        .args(["shader-stats", "--json", "--headset", headset])
        .env("VK_ICD_FILENAMES", &icd)
        .env("VK_DRIVER_FILES", &icd)
        .env("LD_PRELOAD", &shim)
        .env("FD_GPU_ID", model.adreno.to_string())
        // Every shader compiled afresh, nothing kept between runs.
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .env("RUST_BACKTRACE", "0")
        .output()
        .map_err(|e| format!("cannot run {} shader-stats: {e}", me.display()))?;
    if !out.status.success() {
        return Err(format!(
            "shader-stats on turnip as an Adreno {} failed ({}): {}",
            model.adreno,
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )
        .into());
    }
    let report: StatsReport = serde_json::from_slice(&out.stdout)
        .map_err(|e| format!("shader-stats on turnip printed no statistics: {e}"))?;
    if !report
        .device
        .contains(&format!("Adreno (TM) {}", model.adreno))
    {
        return Err(format!(
            "shader-stats ran on {} instead of turnip's Adreno {}",
            report.device, model.adreno
        )
        .into());
    }
    Ok(adreno::water_paths(&report.pipelines)?)
}
