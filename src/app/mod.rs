//! The frame loop that ties the layers together: sim → lod → render, driven by any
//! [`FrameLoop`]. The simulation step for the next frame runs on its own Rayon pool while this
//! frame's LOD is updated and its commands are recorded and submitted.

pub mod live;
pub mod timing;

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::base::ParamError;
use crate::lod::{
    self, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset, StereoFrustum,
};
use crate::render::readback::Readback;
use crate::render::{self, OceanRenderer, RenderError, RendererSettings};
use crate::sim::{OceanConfig, SimError, Simulation};
use crate::xr::{FrameLoop, FrameState, Tweak, XrError};
pub use timing::{FrameTimes, Percentiles, Timing};

/// Why a run stopped.
#[derive(Debug)]
pub enum AppError {
    /// The XR backend or the renderer failed.
    Xr(XrError),
    /// The simulation could not start.
    Sim(SimError),
    /// A parameter (pose, displacement) is out of range.
    Param(ParamError),
    /// A file could not be written.
    Io(String),
}

impl std::fmt::Display for AppError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AppError::Xr(e) => e.fmt(f),
            AppError::Sim(e) => e.fmt(f),
            AppError::Param(e) => e.fmt(f),
            AppError::Io(e) => f.write_str(e),
        }
    }
}

impl std::error::Error for AppError {}

impl From<XrError> for AppError {
    fn from(e: XrError) -> Self {
        AppError::Xr(e)
    }
}

impl From<RenderError> for AppError {
    fn from(e: RenderError) -> Self {
        AppError::Xr(XrError::Render(e))
    }
}

impl From<SimError> for AppError {
    fn from(e: SimError) -> Self {
        AppError::Sim(e)
    }
}

impl From<ParamError> for AppError {
    fn from(e: ParamError) -> Self {
        AppError::Param(e)
    }
}

/// What a run draws and how.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Simulation grid, cascades and waves.
    pub ocean: OceanConfig,
    /// Simulation threads.
    pub threads: usize,
    /// LOD preset and ocean size.
    pub lod: LodSettings,
    /// Renderer settings.
    pub renderer: RendererSettings,
    /// Frames whose images are handed to the capture callback (sorted or not).
    pub capture: Vec<u64>,
    /// Frames at the start left out of the timing statistics (pipeline warm-up).
    pub warmup: u64,
}

/// One captured frame: both eyes as tightly packed sRGB RGBA8 rows.
pub struct Capture<'a> {
    /// Frame number.
    pub frame: u64,
    /// The frame's state (poses, time).
    pub state: &'a FrameState,
    /// Per-eye width.
    pub width: u32,
    /// Per-eye height.
    pub height: u32,
    /// Left and right eye pixels.
    pub eyes: [&'a [u8]; 2],
}

/// What a run measured.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Frames rendered.
    pub frames: u64,
    /// Per-frame timings (warm-up frames excluded).
    pub times: FrameTimes,
    /// Most draws recorded in one frame.
    pub max_draws: u32,
    /// Validation errors reported during the run (0 without the layer).
    pub validation_errors: u32,
    /// The device's name.
    pub device: String,
}

/// What a caller of [`run`] hears about while frames go by.
pub trait RunHooks {
    /// A frame listed in [`RunOptions::capture`] finished rendering.
    fn capture(&mut self, _capture: &Capture<'_>) -> Result<(), AppError> {
        Ok(())
    }

    /// A frame ended (after [`FrameLoop::end_frame`]). Tests count allocations here.
    fn frame_done(&mut self, _frame: &FrameState) {}
}

/// Hooks that do nothing.
pub struct NoHooks;

impl RunHooks for NoHooks {}

/// Runs the frame loop until the backend ends the session, telling `hooks` about captures
/// (frames in `opts.capture`, after their rendering finished) and every finished frame.
pub fn run(
    xr: &mut dyn FrameLoop,
    opts: &RunOptions,
    hooks: &mut dyn RunHooks,
) -> Result<RunReport, AppError> {
    let mut lod = OceanLod::new(opts.lod);
    let mut sim = Simulation::new(opts.ocean.clone(), opts.threads)?;
    let mut renderer =
        OceanRenderer::new(xr.gpu(), &opts.ocean, &lod, xr.targets(), opts.renderer)?;
    let mut readback = if opts.capture.is_empty() {
        None
    } else {
        Some(Readback::new(xr.gpu(), xr.targets().extent)?)
    };
    let errors_before = xr.gpu().validation_errors();
    let result = frames(
        xr,
        opts,
        &mut lod,
        &mut sim,
        &mut renderer,
        &mut readback,
        hooks,
    );
    xr.gpu().wait_idle();
    renderer.destroy(xr.gpu());
    if let Some(r) = readback.as_mut() {
        r.destroy(xr.gpu());
    }
    let mut report = result?;
    report.validation_errors = xr.gpu().validation_errors() - errors_before;
    Ok(report)
}

#[allow(clippy::too_many_arguments)]
fn frames(
    xr: &mut dyn FrameLoop,
    opts: &RunOptions,
    lod: &mut OceanLod,
    sim: &mut Simulation,
    renderer: &mut OceanRenderer,
    readback: &mut Option<Readback>,
    hooks: &mut dyn RunHooks,
) -> Result<RunReport, AppError> {
    let mut times = FrameTimes::with_capacity(16_384);
    let mut max_draws = 0;
    let mut count = 0u64;
    let mut started = false;
    let mut recent = live::RecentFrames::default();
    let mut stats_text = String::with_capacity(256);
    let mut stats_at = Instant::now();
    loop {
        let start = Instant::now();
        let Some(frame) = xr.begin_frame()? else {
            break;
        };
        if !started {
            sim.begin_step(frame.predicted_display_time);
            started = true;
        }
        // The step for this frame's display time was started a frame ago.
        let wait = Instant::now();
        sim.end_step();
        let sim_wait = wait.elapsed();
        let sim_step = sim.last_step_time();
        // Live changes (window keys) apply from the step started next.
        for &tweak in frame.tweaks.iter().flatten() {
            match tweak {
                Tweak::Preset(p) => switch_preset(xr, sim, lod, renderer, p)?,
                t => live::apply_wave_tweak(sim, t),
            }
        }
        sim.begin_step(frame.predicted_display_time + frame.period);
        let surfaces = sim.surfaces();

        let t_lod = Instant::now();
        let stereo = StereoFrustum::new(frame.views[0], frame.views[1])?;
        lod.update(&lod::FrameInput {
            viewer: stereo.centre(),
            culling: Some(&stereo),
            max_displacement: MaxDisplacement::new(surfaces.max_displacement())?,
        })?;
        let lod_time = t_lod.elapsed();

        // A frame the runtime does not want shown is not drawn, nor are its images taken.
        let mut report = None;
        let mut drawn = None;
        if frame.should_render {
            let image = xr.acquire_image()?;
            report = Some(renderer.render(
                xr.gpu(),
                &render::FrameInput {
                    image: image.colour,
                    depth: image.depth,
                    eyes: &frame.views,
                    lod,
                    surfaces,
                },
            )?);
            xr.release_image()?;
            drawn = Some(image.colour);
        }
        if let (Some(rb), Some(image)) = (readback.as_mut(), drawn) {
            if opts.capture.contains(&frame.index) {
                let extent = xr.targets().extent;
                let image_handle = xr.targets().images[image as usize];
                let eyes = rb.read(xr.gpu(), image_handle)?;
                hooks.capture(&Capture {
                    frame: frame.index,
                    state: &frame,
                    width: extent.width,
                    height: extent.height,
                    eyes,
                })?;
            }
        }
        xr.end_frame(&frame)?;
        hooks.frame_done(&frame);
        count += 1;
        if let Some(r) = report {
            if let Some(g) = r.gpu_pass {
                xr.report_gpu_time(g);
            }
            max_draws = max_draws.max(r.draws);
            if frame.index >= opts.warmup {
                times.push(Timing::FrameTotal, start.elapsed());
                times.push(Timing::SimStep, sim_step);
                times.push(Timing::SimWait, sim_wait);
                times.push(Timing::Lod, lod_time);
                times.push(Timing::Record, r.record);
                times.push(Timing::Submit, r.submit);
                if let Some(g) = r.gpu_pass {
                    times.push(Timing::GpuPass, g);
                }
            }
            recent.push(start.elapsed(), sim_step, r.gpu_pass, r.draws);
        }
        if stats_at.elapsed().as_secs_f64() >= 0.5 {
            stats_at = Instant::now();
            recent.summarise(
                &mut stats_text,
                lod.settings().preset(),
                &sim.config().waves,
            );
            xr.show_stats(&stats_text);
        }
    }
    Ok(RunReport {
        frames: count,
        times,
        max_draws,
        validation_errors: 0,
        device: xr.gpu().device_name.clone(),
    })
}

/// Rebuilds the LOD and the renderer for `preset` (same ocean size). Waits for the GPU first:
/// a user's switch, not the steady state.
fn switch_preset(
    xr: &mut dyn FrameLoop,
    sim: &Simulation,
    lod: &mut OceanLod,
    renderer: &mut OceanRenderer,
    preset: QualityPreset,
) -> Result<(), AppError> {
    if lod.settings().preset() == preset {
        log::info!("quality preset is already {}", preset.name());
        return Ok(());
    }
    let size = OceanSize::new(lod.settings().size())?;
    let new_lod = OceanLod::new(LodSettings::new(preset, size));
    xr.gpu().wait_idle();
    let new_renderer = OceanRenderer::new(
        xr.gpu(),
        sim.config(),
        &new_lod,
        xr.targets(),
        *renderer.settings(),
    )?;
    let mut old = std::mem::replace(renderer, new_renderer);
    old.destroy(xr.gpu());
    *lod = new_lod;
    log::info!("quality preset: {}", preset.name());
    Ok(())
}

/// Checks `dir` can hold output files: creates it and writes and removes a probe file, so an
/// unwritable path fails before any work is done.
pub fn ensure_writable_dir(dir: &Path) -> Result<(), AppError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        AppError::Io(format!(
            "cannot create output directory {}: {e}",
            dir.display()
        ))
    })?;
    let probe = dir.join(".vr-ocean-write-test");
    std::fs::write(&probe, b"").map_err(|e| {
        AppError::Io(format!(
            "output directory {} is not writable: {e}",
            dir.display()
        ))
    })?;
    let _ = std::fs::remove_file(probe);
    Ok(())
}

/// Writes `bytes` to `path` atomically (a temporary file renamed into place).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), AppError> {
    let tmp = tmp_path(path);
    std::fs::write(&tmp, bytes)
        .and_then(|_| std::fs::rename(&tmp, path))
        .map_err(|e| AppError::Io(format!("cannot write {}: {e}", path.display())))
}

/// Saves one eye as an sRGB PNG, atomically.
pub fn save_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), AppError> {
    let tmp = tmp_path(path);
    image::save_buffer_with_format(
        &tmp,
        rgba,
        width,
        height,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .map_err(|e| AppError::Io(format!("cannot write {}: {e}", path.display())))?;
    std::fs::rename(&tmp, path)
        .map_err(|e| AppError::Io(format!("cannot write {}: {e}", path.display())))
}

fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}
