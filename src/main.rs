//! The `vr-ocean` command line: the ocean window (the default, falling back to headless without a
//! display), headless rendering, the headset through OpenXR (`xr`), simulate, export, bench and
//! lod-svg.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, Parser, Subcommand, ValueEnum};

use vr_ocean::app::{self, FrameTimes, RunOptions};
use vr_ocean::base::ParamError;
use vr_ocean::bench::{self, BenchOptions};
use vr_ocean::export;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::render::{ContextOptions, RendererSettings, StereoMode, Validation};
use vr_ocean::sim::{
    FoamParams, GridSize, OceanConfig, SimCore, SimError, Simulation, SpectrumKind, Surfaces,
    WaveParams,
};
use vr_ocean::xr::desktop::window::{OpenError, WindowOptions, WindowSize, WindowXr, KEYS_HELP};
use vr_ocean::xr::desktop::{self, CameraPath, EyeSize, HeadlessXr};
use vr_ocean::xr::openxr::quest::{Foveation, PerfLevel};
use vr_ocean::xr::openxr::{OpenXr, OpenXrOptions};
use vr_ocean::xr::FrameLoop;

#[derive(Parser)]
#[command(
    name = "vr-ocean",
    version,
    about = "An endless FFT ocean for OpenXR headsets"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run the simulation without graphics and print its statistics once a second.
    Simulate(SimulateArgs),
    /// Write height, Dx, Dz, normals and Jacobian at given times as float32 EXR and .npy.
    Export(ExportArgs),
    /// Time every pipeline stage next to rustfft and (with --features fftw) FFTW.
    Bench(BenchArgs),
    /// Open the ocean in a window (the default): both eyes side by side, fly with keyboard and
    /// mouse, live wave and quality keys, frame times in the title.
    Window(WindowArgs),
    /// Render without a window along a camera path: both eyes as PNG and frame_times.json.
    Headless(HeadlessArgs),
    /// Run in a headset through the active OpenXR runtime (Monado, SteamVR, WiVRn): left stick
    /// glides, right stick snap-turns, A (or menu) cycles the preset, triggers change the wind.
    Xr(XrArgs),
    /// Draw one frame of the quadtree LOD (patches by level, stitched edges, both eye frusta) as SVG.
    LodSvg(LodSvgArgs),
}

#[derive(Clone, Copy, ValueEnum)]
enum PresetArg {
    Low,
    Medium,
    High,
    Ultra,
}

#[derive(Args)]
struct LodSvgArgs {
    /// Head position x,y,z (m; y is the height above the water).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        required = true
    )]
    camera: Vec<f32>,
    /// Heading (degrees; 0 looks along -z, positive turns left toward -x).
    #[arg(long, allow_negative_numbers = true, required = true)]
    yaw: f32,
    /// Pitch (degrees; negative looks down).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pitch: f32,
    /// Quality preset (thesis Table 2).
    #[arg(long, value_enum, default_value_t = PresetArg::Ultra)]
    preset: PresetArg,
    /// Ocean size S (m), 256 to 8192.
    #[arg(long, allow_negative_numbers = true, default_value_t = 8192.0)]
    size: f32,
    /// Maximum displacement max|Dx|,max|h|,max|Dz| (m) padding the culling boxes.
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',', default_values_t = [1.0, 1.5, 1.0])]
    max_displacement: Vec<f32>,
    /// Output SVG file.
    #[arg(long)]
    out: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum SpectrumArg {
    Phillips,
    Jonswap,
}

/// Ocean parameters shared by every command.
#[derive(Args, Clone)]
struct OceanArgs {
    /// FFT grid side: a power of two from 16 to 1024.
    #[arg(long, allow_negative_numbers = true, default_value_t = 256)]
    grid: u32,
    /// Patch size of each cascade in metres, coarsest first (1 to 4, comma-separated).
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',', default_values_t = [257.0, 69.5, 16.1])]
    patch: Vec<f32>,
    /// Wind speed at 10 m (m/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    wind: f32,
    /// Wind direction (degrees from +x toward +z).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    wind_dir: f32,
    /// Directional alignment α in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.8)]
    alignment: f32,
    /// Choppiness λ in [0, 2].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.9)]
    choppiness: f32,
    /// Water depth (m); deep water when omitted.
    #[arg(long, allow_negative_numbers = true)]
    depth: Option<f32>,
    /// Wave spectrum.
    #[arg(long, value_enum, default_value_t = SpectrumArg::Phillips)]
    spectrum: SpectrumArg,
    /// Phillips amplitude multiplier.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    amplitude: f32,
    /// JONSWAP peak enhancement γ.
    #[arg(long, allow_negative_numbers = true, default_value_t = 3.3)]
    gamma: f32,
    /// JONSWAP fetch (km).
    #[arg(long, allow_negative_numbers = true, default_value_t = 100.0)]
    fetch: f32,
    /// Small-wave suppression β in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.2)]
    suppression: f32,
    /// Loop period T (s): the animation repeats exactly after T.
    #[arg(long, allow_negative_numbers = true, default_value_t = 200.0)]
    loop_period: f32,
    /// Material roughness in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.1)]
    roughness: f32,
    /// Random seed.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Jacobian below which foam forms.
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().threshold)]
    foam_threshold: f32,
    /// Foam growth rate (1/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().growth)]
    foam_growth: f32,
    /// Foam decay rate (1/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().decay)]
    foam_decay: f32,
}

impl OceanArgs {
    fn config(&self) -> Result<OceanConfig, ParamError> {
        let spectrum = match self.spectrum {
            SpectrumArg::Phillips => SpectrumKind::Phillips {
                amplitude: self.amplitude,
            },
            SpectrumArg::Jonswap => SpectrumKind::Jonswap {
                gamma: self.gamma,
                fetch_km: self.fetch,
            },
        };
        let cfg = OceanConfig {
            grid: GridSize::new(self.grid)?,
            patch_sizes: self.patch.clone(),
            waves: WaveParams {
                spectrum,
                wind_speed: self.wind,
                wind_direction_deg: self.wind_dir,
                alignment: self.alignment,
                depth: self.depth,
                small_wave_suppression: self.suppression,
                choppiness: self.choppiness,
                loop_period: self.loop_period,
                roughness: self.roughness,
                foam: FoamParams {
                    threshold: self.foam_threshold,
                    growth: self.foam_growth,
                    decay: self.foam_decay,
                },
                seed: self.seed,
            },
        };
        cfg.validate()?;
        Ok(cfg)
    }
}

#[derive(Args)]
struct SimulateArgs {
    #[command(flatten)]
    ocean: OceanArgs,
    /// Simulated seconds to run.
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    seconds: f64,
    /// Steps per simulated second (the headset's refresh rate).
    #[arg(long, default_value_t = 72.0)]
    rate: f64,
    /// Simulation worker threads.
    #[arg(long, default_value_t = default_threads())]
    threads: usize,
}

/// What `vr-ocean` with no subcommand runs: `window` with its defaults (headless without a
/// display).
#[derive(Parser)]
struct DefaultRun {
    #[command(flatten)]
    args: WindowArgs,
}

#[derive(Args)]
struct ExportArgs {
    #[command(flatten)]
    ocean: OceanArgs,
    /// Times (s) to export, comma-separated.
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        required = true
    )]
    time: Vec<f64>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

/// Settings of the renderer and LOD shared by the headless and window modes.
#[derive(Args, Clone)]
struct ViewArgs {
    #[command(flatten)]
    ocean: OceanArgs,
    /// Quality preset (thesis Table 2).
    #[arg(long, value_enum, default_value_t = PresetArg::High)]
    preset: PresetArg,
    /// Ocean size S (m) the quadtree covers, 256 to 8192; the skirt reaches 10 S.
    #[arg(long, allow_negative_numbers = true, default_value_t = 2048.0)]
    ocean_size: f32,
    /// How both eyes are drawn.
    #[arg(long, value_enum, default_value_t = StereoArg::Multiview)]
    stereo: StereoArg,
    /// Simulation worker threads.
    #[arg(long, default_value_t = default_threads())]
    threads: usize,
    /// Load the Khronos validation layer (fails if it is not installed).
    #[arg(long)]
    validation: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum StereoArg {
    Multiview,
    TwoPass,
}

impl ViewArgs {
    fn run_options(&self, capture: Vec<u64>, warmup: u64) -> Result<RunOptions, ParamError> {
        let ocean = self.ocean.config()?;
        let size = OceanSize::new(self.ocean_size)?;
        if self.threads == 0 {
            return Err(ParamError::new("threads", 0.0, "at least 1 thread"));
        }
        Ok(RunOptions {
            ocean,
            threads: self.threads,
            lod: LodSettings::new(preset(self.preset), size),
            renderer: RendererSettings {
                stereo: match self.stereo {
                    StereoArg::Multiview => StereoMode::Multiview,
                    StereoArg::TwoPass => StereoMode::TwoPass,
                },
                ..RendererSettings::default()
            },
            capture,
            warmup,
        })
    }

    fn context(&self) -> ContextOptions {
        ContextOptions {
            validation: if self.validation {
                Validation::Required
            } else {
                Validation::Off
            },
            ..ContextOptions::default()
        }
    }
}

#[derive(Args)]
struct HeadlessArgs {
    #[command(flatten)]
    view: ViewArgs,
    /// Frames to render (on a fixed 72 Hz clock).
    #[arg(long, default_value_t = 144)]
    frames: u64,
    /// Per-eye image size WIDTHxHEIGHT.
    #[arg(long, allow_hyphen_values = true, default_value = "640x640")]
    size: String,
    /// Camera path file (format in `src/xr/desktop/path.rs` and the README); default: standing
    /// on a deck 4.5 m above the mean sea level, looking slightly down at the horizon.
    #[arg(long)]
    path: Option<PathBuf>,
    /// Frames to save as PNG (comma-separated); default: the last one.
    #[arg(long, value_delimiter = ',')]
    capture: Vec<u64>,
    /// Frames at the start left out of frame_times.json.
    #[arg(long, default_value_t = 10)]
    warmup: u64,
    /// Output directory for PNGs and frame_times.json (created if missing).
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct WindowArgs {
    #[command(flatten)]
    view: ViewArgs,
    /// Window size WIDTHxHEIGHT; each eye is rendered at half the width by the full height.
    #[arg(long, default_value = "1600x800")]
    size: String,
    /// Camera path file: poses from the path (on the real clock) instead of keyboard and mouse.
    #[arg(long)]
    path: Option<PathBuf>,
    /// Quit after this many frames (unattended runs and tests); default: until Esc.
    #[arg(long)]
    frames: Option<u64>,
    /// Save the window's last frame as PNG (needs --frames).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
}

#[derive(Args)]
struct XrArgs {
    #[command(flatten)]
    view: ViewArgs,
    /// End the session after this many submitted frames (tests, CI); default: until the
    /// runtime ends it or Ctrl-C.
    #[arg(long)]
    frames: Option<u64>,
    /// Factor on the runtime's recommended per-eye size, 0.1 to 4 [default: the headset's, 1].
    #[arg(long, allow_negative_numbers = true)]
    resolution_scale: Option<f32>,
    /// Fixed foveation level (with XR_FB_foveation) [default: the headset's: high on Quest 2,
    /// medium elsewhere].
    #[arg(long, value_enum)]
    foveation: Option<FoveationArg>,
    /// Highest display refresh rate to ask for (Hz, with XR_FB_display_refresh_rate); lower
    /// rates are taken when frames do not fit the budget [default: the headset's: 72 on
    /// Quest 2, 90 on Quest Pro/3/3S, 120 elsewhere].
    #[arg(long, allow_negative_numbers = true)]
    max_refresh_rate: Option<f32>,
    /// CPU performance level (with XR_EXT_performance_settings).
    #[arg(long, value_enum, default_value_t = PerfArg::SustainedHigh)]
    cpu_level: PerfArg,
    /// GPU performance level (with XR_EXT_performance_settings).
    #[arg(long, value_enum, default_value_t = PerfArg::SustainedHigh)]
    gpu_level: PerfArg,
    /// Height of the floor you stand on above the mean sea level (m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 2.9)]
    deck_height: f32,
}

#[derive(Clone, Copy, ValueEnum)]
enum FoveationArg {
    Off,
    Low,
    Medium,
    High,
}

#[derive(Clone, Copy, ValueEnum)]
enum PerfArg {
    PowerSavings,
    SustainedLow,
    SustainedHigh,
    Boost,
}

/// Where the default run writes when there is no display.
const FALLBACK_DIR: &str = "vr-ocean-headless";

#[derive(Args)]
struct BenchArgs {
    /// Grid sides to measure.
    #[arg(long, value_delimiter = ',', default_values_t = [128, 256, 512])]
    sizes: Vec<u32>,
    /// Thread counts to measure.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 2])]
    threads: Vec<usize>,
    /// Timed repetitions per measurement.
    #[arg(long, default_value_t = 40)]
    iterations: usize,
    /// Patch size of each cascade (m); one cascade = four FFTs per step.
    #[arg(long, value_delimiter = ',', default_values_t = [250.0])]
    patch: Vec<f32>,
    /// Skip the rustfft/FFTW baselines (for thread-scaling runs: their buffers crowd the cache).
    #[arg(long)]
    skip_baselines: bool,
}

fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        None => window_cmd(DefaultRun::parse_from(["vr-ocean"]).args, true),
        Some(Command::Window(a)) => window_cmd(a, false),
        Some(Command::Simulate(a)) => simulate(a),
        Some(Command::Export(a)) => export_cmd(a),
        Some(Command::Bench(a)) => bench_cmd(a),
        Some(Command::LodSvg(a)) => lod_svg_cmd(a),
        Some(Command::Headless(a)) => headless_cmd(a),
        Some(Command::Xr(a)) => xr_cmd(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

type CmdResult = Result<(), Box<dyn std::error::Error>>;

fn preset(p: PresetArg) -> QualityPreset {
    match p {
        PresetArg::Low => QualityPreset::Low,
        PresetArg::Medium => QualityPreset::Medium,
        PresetArg::High => QualityPreset::High,
        PresetArg::Ultra => QualityPreset::Ultra,
    }
}

fn headless_cmd(a: HeadlessArgs) -> CmdResult {
    let size = EyeSize::parse(&a.size)?;
    if a.frames == 0 {
        return Err(ParamError::new("frames", 0.0, "at least 1 frame").into());
    }
    let path = match &a.path {
        Some(p) => CameraPath::load(p)?,
        None => CameraPath::still(desktop::START_POSITION, 0.0, desktop::START_PITCH),
    };
    let capture = if a.capture.is_empty() {
        vec![a.frames - 1]
    } else {
        a.capture.clone()
    };
    if let Some(bad) = capture.iter().find(|&&f| f >= a.frames) {
        return Err(ParamError::new("capture", *bad as f64, "frame numbers below --frames").into());
    }
    let opts = a.view.run_options(capture, a.warmup.min(a.frames - 1))?;
    app::ensure_writable_dir(&a.out)?;
    let mut xr = HeadlessXr::new(&a.view.context(), size, path, a.frames)?;
    println!(
        "rendering {} frames of {}x{} per eye ({}) on {}",
        a.frames,
        size.extent().width,
        size.extent().height,
        opts.renderer.stereo.name(),
        xr.gpu().device_name
    );
    let mut pngs = PngWriter {
        dir: a.out.clone(),
        saved: Vec::new(),
    };
    let report = app::run(&mut xr, &opts, &mut pngs)?;
    let saved = pngs.saved;
    let json = format!(
        "{{\n\"device\": \"{}\",\n\"frames\": {},\n\"stereo\": \"{}\",\n\"max_draws\": {},\n\"timings_ms\": {}}}\n",
        report.device.replace('"', "'"),
        report.frames,
        opts.renderer.stereo.name(),
        report.max_draws,
        report.times.to_json()
    );
    let json_path = a.out.join("frame_times.json");
    app::write_atomic(&json_path, json.as_bytes())?;
    print_times(&report.times);
    for f in &saved {
        println!("wrote {}", f.display());
    }
    println!("wrote {}", json_path.display());
    if report.validation_errors > 0 {
        return Err(format!("{} Vulkan validation errors", report.validation_errors).into());
    }
    Ok(())
}

/// Saves captured frames as `frame_NNNNN_{left,right}.png`.
struct PngWriter {
    dir: PathBuf,
    saved: Vec<PathBuf>,
}

impl app::RunHooks for PngWriter {
    fn capture(&mut self, c: &app::Capture<'_>) -> Result<(), app::AppError> {
        for (eye, pixels) in ["left", "right"].iter().zip(c.eyes) {
            let file = self.dir.join(format!("frame_{:05}_{eye}.png", c.frame));
            app::save_png(&file, c.width, c.height, pixels)?;
            self.saved.push(file);
        }
        Ok(())
    }
}

/// The window mode; with `fallback`, no display means a headless run into [`FALLBACK_DIR`].
fn window_cmd(a: WindowArgs, fallback: bool) -> CmdResult {
    let size = WindowSize::parse(&a.size)?;
    if a.frames == Some(0) {
        return Err(ParamError::new("frames", 0.0, "at least 1 frame").into());
    }
    let path = a.path.as_deref().map(CameraPath::load).transpose()?;
    let warmup = a.frames.map_or(10, |n| n.saturating_sub(1).min(10));
    let opts = a.view.run_options(Vec::new(), warmup)?;
    if let Some(shot) = &a.screenshot {
        let dir = shot.parent().filter(|d| !d.as_os_str().is_empty());
        app::ensure_writable_dir(dir.unwrap_or(std::path::Path::new(".")))?;
    }
    let options = WindowOptions {
        size,
        path,
        frames: a.frames,
        screenshot: a.screenshot.is_some(),
    };
    let mut xr = match WindowXr::new(&a.view.context(), options) {
        Ok(xr) => xr,
        Err(OpenError::Unavailable(why)) if fallback => return headless_fallback(&why, a.view),
        Err(e) => return Err(e.into()),
    };
    let eye = size.eye().extent();
    println!(
        "window {}x{}: both eyes at {}x{} ({}) on {}",
        size.extent().width,
        size.extent().height,
        eye.width,
        eye.height,
        opts.renderer.stereo.name(),
        xr.gpu().device_name
    );
    if a.path.is_none() {
        println!("{KEYS_HELP}");
    }
    // Counts validation errors over the whole window lifetime, shutdown included.
    let validation = xr.gpu().validation.clone();
    let report = app::run(&mut xr, &opts, &mut app::NoHooks)?;
    let screenshot = xr.take_screenshot();
    drop(xr);
    println!("{} frames", report.frames);
    print_times(&report.times);
    if let Some(file) = &a.screenshot {
        let shot = screenshot.ok_or(
            "no screenshot: the last frame was not shown (window minimised), or the window's \
             images cannot be copied",
        )?;
        app::save_png(file, shot.width, shot.height, &shot.rgba)?;
        println!("wrote {}", file.display());
    }
    let errors = validation.map_or(0, |v| v.errors());
    if errors > 0 {
        return Err(format!("{errors} Vulkan validation errors").into());
    }
    Ok(())
}

fn xr_cmd(a: XrArgs) -> CmdResult {
    if a.frames == Some(0) {
        return Err(ParamError::new("frames", 0.0, "at least 1 frame").into());
    }
    let opts = a.view.run_options(Vec::new(), 10)?;
    let perf = |p: PerfArg| match p {
        PerfArg::PowerSavings => PerfLevel::PowerSavings,
        PerfArg::SustainedLow => PerfLevel::SustainedLow,
        PerfArg::SustainedHigh => PerfLevel::SustainedHigh,
        PerfArg::Boost => PerfLevel::Boost,
    };
    let mut xr = OpenXr::new(OpenXrOptions {
        frames: a.frames,
        resolution_scale: a.resolution_scale,
        validation: a.view.context().validation,
        foveation: a.foveation.map(|f| match f {
            FoveationArg::Off => Foveation::Off,
            FoveationArg::Low => Foveation::Low,
            FoveationArg::Medium => Foveation::Medium,
            FoveationArg::High => Foveation::High,
        }),
        max_refresh_rate: a.max_refresh_rate,
        perf_levels: (perf(a.cpu_level), perf(a.gpu_level)),
        deck_height: a.deck_height,
        preset: Some(preset(a.view.preset)),
    })?;
    exit_signal::install();
    let extent = xr.targets().extent;
    println!(
        "OpenXR session: {}x{} per eye ({}) on {}",
        extent.width,
        extent.height,
        opts.renderer.stereo.name(),
        xr.gpu().device_name
    );
    // Counts validation errors over the whole session, shutdown included.
    let validation = xr.gpu().validation.clone();
    let result = app::run(&mut xr, &opts, &mut app::NoHooks);
    let summary = xr.summary();
    drop(xr);
    println!("openxr summary: {}", summary.line());
    let report = result?;
    println!("{} frames rendered", report.frames);
    print_times(&report.times);
    let errors = validation.map_or(0, |v| v.errors());
    if errors > 0 {
        return Err(format!("{errors} Vulkan validation errors").into());
    }
    Ok(())
}

/// Ctrl-C (SIGINT) and SIGTERM ask the runtime to end the session instead of killing the
/// process mid-frame.
mod exit_signal {
    #[cfg(unix)]
    pub fn install() {
        use std::ffi::c_int;
        extern "C" fn on_signal(_: c_int) {
            vr_ocean::xr::openxr::EXIT_SIGNAL.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        extern "C" {
            fn signal(signum: c_int, handler: extern "C" fn(c_int)) -> usize;
        }
        const SIGINT: c_int = 2;
        const SIGTERM: c_int = 15;
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
        unsafe {
            signal(SIGINT, on_signal);
            signal(SIGTERM, on_signal);
        }
    }

    #[cfg(not(unix))]
    pub fn install() {}
}

/// The default run without a display: 144 headless frames into [`FALLBACK_DIR`].
fn headless_fallback(why: &str, view: ViewArgs) -> CmdResult {
    println!("{why}; rendering 144 frames headless into ./{FALLBACK_DIR}/ instead");
    let out = PathBuf::from(FALLBACK_DIR);
    headless_cmd(HeadlessArgs {
        view,
        frames: 144,
        size: "640x640".into(),
        path: None,
        capture: Vec::new(),
        warmup: 10,
        out: out.clone(),
    })?;
    let shown = std::fs::canonicalize(&out).unwrap_or(out);
    println!(
        "no display, so no window: the images are in {}",
        shown.display()
    );
    Ok(())
}

fn print_times(t: &FrameTimes) {
    println!("{:<12} {:>9} {:>9} {:>9}", "ms", "p50", "p95", "p99");
    for (name, p) in app::timing::TIMINGS.iter().zip(t.all()) {
        println!("{name:<12} {:>9.3} {:>9.3} {:>9.3}", p.p50, p.p95, p.p99);
    }
}

fn simulate(a: SimulateArgs) -> CmdResult {
    let cfg = a.ocean.config()?;
    if !(a.seconds.is_finite() && a.seconds > 0.0) {
        return Err(ParamError::new("seconds", a.seconds, "a finite duration > 0 (s)").into());
    }
    if !(a.rate.is_finite() && a.rate >= 1.0 && a.rate <= 1000.0) {
        return Err(ParamError::new("rate", a.rate, "a step rate in [1, 1000] (1/s)").into());
    }
    let mut sim = Simulation::new(cfg.clone(), a.threads)?;
    println!(
        "simulating {} cascade(s) of {}x{} on {} thread(s); patches {:?} m",
        cfg.patch_sizes.len(),
        cfg.grid,
        cfg.grid,
        sim.threads(),
        cfg.patch_sizes
    );
    let steps = (a.seconds * a.rate).ceil() as usize;
    let mut last_report = 0.0;
    let mut wall = std::time::Duration::ZERO;
    let mut count = 0u32;
    for i in 0..=steps {
        let t = i as f64 / a.rate;
        let start = Instant::now();
        let s = sim.step_blocking(t);
        wall += start.elapsed();
        count += 1;
        if t - last_report >= 1.0 || i == steps {
            last_report = t;
            let c0 = &s.cascades[0];
            let texels = c0.displacement_f16.len();
            let n = texels as f64;
            let var = c0
                .displacement_f16
                .iter()
                .map(|d| (d[1].to_f64()).powi(2))
                .sum::<f64>()
                / n;
            let foam = c0.normal_foam[..texels]
                .iter()
                .map(|p| ((p >> 16) & 0xff) as f64 / 255.0)
                .sum::<f64>()
                / n;
            let m = s.max_displacement();
            println!(
                "t={t:6.2}s  step {:6.2} ms  Hs(coarsest)={:5.2} m  max |D|=({:.2}, {:.2}, {:.2}) m  foam {:4.1}%  h(0,0)={:+.3} m",
                wall.as_secs_f64() * 1e3 / count as f64,
                4.0 * var.sqrt(),
                m[0],
                m[1],
                m[2],
                foam * 100.0,
                s.height_at(0.0, 0.0)
            );
            wall = std::time::Duration::ZERO;
            count = 0;
        }
    }
    Ok(())
}

fn export_cmd(a: ExportArgs) -> CmdResult {
    let cfg = a.ocean.config()?;
    for &t in &a.time {
        if !t.is_finite() {
            return Err(ParamError::new("time", t, "finite times (s)").into());
        }
    }
    export::prepare_dir(&a.out)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(default_threads())
        .build()
        .map_err(|e| SimError::Threads(e.to_string()))?;
    let mut core = pool.install(|| SimCore::new(cfg.clone()))?;
    let mut s = Surfaces::with_float_copies(&cfg);
    let mut written = 0;
    for &t in &a.time {
        pool.install(|| core.step(t, &mut s));
        for (i, c) in s.cascades.iter().enumerate() {
            let stem = if s.cascades.len() == 1 {
                format!("t{t:.3}")
            } else {
                format!("t{t:.3}_c{i}")
            };
            written += export::write_cascade(c, &a.out, &stem)?.len();
        }
    }
    println!("wrote {written} files to {}", a.out.display());
    Ok(())
}

fn bench_cmd(a: BenchArgs) -> CmdResult {
    let sizes = a
        .sizes
        .iter()
        .map(|&n| GridSize::new(n))
        .collect::<Result<Vec<_>, _>>()?;
    if a.threads.iter().any(|&t| t == 0 || t > 256) {
        return Err(ParamError::new("threads", 0.0, "thread counts in [1, 256]").into());
    }
    if a.iterations == 0 || a.iterations > 100_000 {
        return Err(
            ParamError::new("iterations", a.iterations as f64, "a count in [1, 100000]").into(),
        );
    }
    let mut config = OceanConfig::single(256, 250.0)?;
    config.patch_sizes = a.patch.clone();
    config.validate()?;
    let opts = BenchOptions {
        sizes,
        threads: a.threads,
        iterations: a.iterations,
        config,
        baselines: !a.skip_baselines,
    };
    println!(
        "vr-ocean bench: CPU {}, rustfft baseline {}, FFTW baseline {}",
        cpu_model(),
        if cfg!(feature = "baselines") {
            "on"
        } else {
            "off"
        },
        if cfg!(feature = "fftw") {
            "on (FFTW_PATIENT)"
        } else {
            "off (build with --features fftw)"
        }
    );
    let rows = bench::run(&opts)?;
    print!("{}", bench::format_table(&rows));
    Ok(())
}

fn lod_svg_cmd(a: LodSvgArgs) -> CmdResult {
    use vr_ocean::lod::{
        svg, FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset,
        StereoFrustum,
    };
    let &[x, y, z] = a.camera.as_slice() else {
        return Err(ParamError::new(
            "camera",
            a.camera.len() as f64,
            "three comma-separated coordinates x,y,z (m)",
        )
        .into());
    };
    if !a.yaw.is_finite() {
        return Err(ParamError::new("yaw", a.yaw as f64, "a finite angle (degrees)").into());
    }
    if !(a.pitch.is_finite() && a.pitch.abs() <= 89.0) {
        return Err(
            ParamError::new("pitch", a.pitch as f64, "an angle in [-89, 89] (degrees)").into(),
        );
    }
    let &[dx, h, dz] = a.max_displacement.as_slice() else {
        return Err(ParamError::new(
            "max-displacement",
            a.max_displacement.len() as f64,
            "three comma-separated values dx,h,dz (m)",
        )
        .into());
    };
    let pad = MaxDisplacement::new([dx, h, dz])?;
    let preset = match a.preset {
        PresetArg::Low => QualityPreset::Low,
        PresetArg::Medium => QualityPreset::Medium,
        PresetArg::High => QualityPreset::High,
        PresetArg::Ultra => QualityPreset::Ultra,
    };
    let settings = LodSettings::new(preset, OceanSize::new(a.size)?);
    // A Quest-like headset: 64 mm between the eyes, asymmetric per-eye FOVs.
    let (yaw, pitch) = (a.yaw.to_radians(), a.pitch.to_radians());
    let eyes = StereoFrustum::from_head(
        glam::Vec3::new(x, y, z),
        yaw,
        pitch,
        0.064,
        vr_ocean::base::Fov::QUEST_EYES,
    )?;
    let mut lod = OceanLod::new(settings);
    let stats = lod.update(&FrameInput {
        viewer: eyes.centre(),
        culling: Some(&eyes),
        max_displacement: pad,
    })?;
    std::fs::write(&a.out, svg::render(&lod, &eyes))
        .map_err(|e| format!("cannot write --out {}: {e}", a.out.display()))?;
    println!(
        "{}: {} patches, {} visible, {} draws + skirt, {} triangles -> {}",
        preset.name(),
        stats.patches,
        stats.visible,
        stats.draws,
        stats.triangles,
        a.out.display()
    );
    Ok(())
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}
