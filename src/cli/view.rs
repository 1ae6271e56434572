//! The commands that show the ocean: `window` (the default), `headless` and `xr`.

use std::path::PathBuf;

use clap::{Args, Parser, ValueEnum};

use super::args::{preset, OnOff, ViewArgs};
use super::report::CmdResult;
use super::report::{self, ValidationWatch};
use super::settings;
use super::soak;
use vr_ocean::app::{self, DeckPlacement, FloatOptions, FrameTimes};
use vr_ocean::base::ParamError;
use vr_ocean::export;
use vr_ocean::physics::DEFAULT_DECK_HEIGHT;
use vr_ocean::render::Msaa;
use vr_ocean::xr::desktop::window::{OpenError, WindowOptions, WindowSize, WindowXr, KEYS_HELP};
use vr_ocean::xr::desktop::{self, CameraPath, EyeSize, HeadlessXr};
use vr_ocean::xr::openxr::quest::{Foveation, PerfLevel};
use vr_ocean::xr::openxr::{self, OpenXr, OpenXrOptions};
use vr_ocean::xr::FrameLoop;

/// What `vr-ocean` with no subcommand runs: `window` with its defaults (headless without a
/// display).
#[derive(Parser)]
pub struct DefaultRun {
    #[command(flatten)]
    pub args: WindowArgs,
}

#[derive(Args)]
pub struct HeadlessArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// Frames to render (on a fixed 72 Hz clock).
    #[arg(long, default_value_t = 144)]
    pub frames: u64,
    /// Per-eye image size WIDTHxHEIGHT.
    #[arg(long, allow_hyphen_values = true, default_value = "640x640")]
    pub size: String,
    /// Camera path file (format in `src/xr/desktop/path.rs` and the README); default: standing
    /// on a deck 4.5 m above the mean sea level, looking slightly down at the horizon.
    #[arg(long)]
    pub path: Option<PathBuf>,
    /// Frames to save as PNG (comma-separated); default: the last one.
    #[arg(long, value_delimiter = ',')]
    pub capture: Vec<u64>,
    /// Frames at the start left out of frame_times.json.
    #[arg(long, default_value_t = 10)]
    pub warmup: u64,
    /// Seconds of simulated time before the first frame, stepped at 10 Hz without drawing: foam
    /// and floating bodies start settled (whitecaps need ~5 s to build up). Frame numbers
    /// (--capture, --warmup, file names) count drawn frames only.
    #[arg(long, default_value_t = 0.0)]
    pub settle: f64,
    /// Output directory for the images and frame_times.json (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Image format of the saved frames: png (lossless) or jpeg (quality 90, small files).
    #[arg(long, value_enum, default_value_t = ImageFormat::Png)]
    pub format: ImageFormat,
    /// Writes the run's sound to this WAV file (16-bit stereo, 48 kHz), rendered in step with
    /// the drawn frames: the same path and seed make the same file.
    #[arg(long)]
    pub audio_out: Option<PathBuf>,
}

/// How captured frames are saved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ImageFormat {
    /// Lossless PNG.
    Png,
    /// JPEG, quality 90.
    Jpeg,
}

#[derive(Args)]
pub struct WindowArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// Window size WIDTHxHEIGHT; each eye is rendered at half the width by the full height.
    #[arg(long, default_value = "1600x800")]
    pub size: String,
    /// Camera path file: poses from the path (on the real clock) instead of keyboard and mouse.
    #[arg(long)]
    pub path: Option<PathBuf>,
    /// Quit after this many frames (unattended runs and tests); default: until Esc.
    #[arg(long)]
    pub frames: Option<u64>,
    /// Quit after this many seconds of wall-clock time (timed runs, 0.1 to 86400).
    #[arg(long, allow_negative_numbers = true)]
    pub seconds: Option<f64>,
    /// Save the window's last frame as PNG (needs --frames).
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// The control panel at start: open or closed (Tab opens and closes it).
    #[arg(long, value_enum, default_value_t = PanelArg::Closed)]
    pub panel: PanelArg,
}

/// Whether the control panel starts open.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PanelArg {
    /// Shown from the first frame (tests, screenshots).
    Open,
    /// Hidden until the user opens it.
    Closed,
}

#[derive(Args)]
pub struct XrArgs {
    #[command(flatten)]
    pub view: ViewArgs,
    /// End the session after this many submitted frames (tests, CI); default: until the
    /// runtime ends it or Ctrl-C.
    #[arg(long)]
    pub frames: Option<u64>,
    /// Factor on the runtime's recommended per-eye size, 0.1 to 4 [default: the headset's: 0.9
    /// on Quest 2, 1 elsewhere].
    #[arg(long, allow_negative_numbers = true)]
    pub resolution_scale: Option<f32>,
    /// Fixed foveation level (with XR_FB_foveation) [default: the headset's: high on Quest 2,
    /// medium elsewhere].
    #[arg(long, value_enum)]
    pub foveation: Option<FoveationArg>,
    /// Highest display refresh rate to ask for (Hz, with XR_FB_display_refresh_rate); lower
    /// rates are taken when frames do not fit the budget [default: the headset's: 72 on
    /// Quest 2, 90 on Quest Pro/3/3S, 120 elsewhere].
    #[arg(long, allow_negative_numbers = true)]
    pub max_refresh_rate: Option<f32>,
    /// The control panel at start: open or closed (the left controller's menu button opens
    /// and closes it).
    #[arg(long, value_enum, default_value_t = PanelArg::Closed)]
    pub panel: PanelArg,
    /// CPU performance level (with XR_EXT_performance_settings).
    #[arg(long, value_enum, default_value_t = PerfArg::SustainedHigh)]
    pub cpu_level: PerfArg,
    /// GPU performance level (with XR_EXT_performance_settings).
    #[arg(long, value_enum, default_value_t = PerfArg::SustainedHigh)]
    pub gpu_level: PerfArg,
    /// Height of the floor you stand on above the mean sea level (m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 2.9)]
    pub deck_height: f32,
    /// Submit depth to the compositor (XR_KHR_composition_layer_depth), for runtimes whose
    /// reprojection uses it (PC runtimes); off: depth stays transient.
    #[arg(long)]
    pub submit_depth: bool,
    /// Start in the water, floating off the deck's edge (the left controller's Y goes in and
    /// out; X held ducks under).
    #[arg(long)]
    pub in_water: bool,
    /// A soak: this many minutes played by a scripted user (sea state, throws, the panel,
    /// presets), through new sessions when one is lost; prints memory and open files once a
    /// minute (`cargo xtask soak`).
    #[arg(long)]
    pub soak_minutes: Option<f64>,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum FoveationArg {
    Off,
    Low,
    Medium,
    High,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum PerfArg {
    PowerSavings,
    SustainedLow,
    SustainedHigh,
    Boost,
}

/// The longest `--settle` (s): 6000 CPU steps.
const MAX_SETTLE_S: f64 = 600.0;

/// Where the default run writes when there is no display.
pub const FALLBACK_DIR: &str = "vr-ocean-headless";

pub fn headless_cmd(a: HeadlessArgs) -> CmdResult {
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
    if !(0.0..=MAX_SETTLE_S).contains(&a.settle) {
        return Err(ParamError::new("settle", a.settle, "seconds in [0, 600]").into());
    }
    let settle = (a.settle / desktop::SETTLE_DT).round() as u64;
    // The app numbers settling frames too: drawn frame k is frame settle + k.
    let capture = capture.into_iter().map(|f| f + settle).collect();
    // Checked before any window or device opens.
    let bodies = a.view.bodies()?;
    let mut opts = a
        .view
        .run_options(capture, settle + a.warmup.min(a.frames - 1))?;
    opts.floating = Some(FloatOptions {
        bodies,
        deck: DeckPlacement::UnderViewer,
        interaction: a.view.interaction(),
    });
    if let Some(wav) = &a.audio_out {
        if a.view.audio == Some(OnOff::On) {
            return Err("--audio on plays the sound and --audio-out writes it: choose one".into());
        }
        let dir = wav.parent().filter(|d| !d.as_os_str().is_empty());
        export::prepare_dir(dir.unwrap_or(std::path::Path::new(".")))?;
        if wav.is_dir() {
            return Err(format!("--audio-out {}: a directory, not a file", wav.display()).into());
        }
        opts.audio.sink = app::SoundSink::File(wav.clone());
    }
    export::prepare_dir(&a.out)?;
    let mut xr = HeadlessXr::new(&a.view.context(), size, path, a.frames)?.settle(settle);
    a.view.resolve_msaa(&mut opts, xr.gpu());
    a.view.resolve_desktop_stereo(&mut opts, xr.gpu());
    println!(
        "rendering {} frames of {}x{} per eye ({}, MSAA {}) on {}",
        a.frames,
        size.extent().width,
        size.extent().height,
        opts.renderer.stereo.name(),
        opts.renderer.msaa.samples(),
        xr.gpu().device_name
    );
    let mut pngs = FrameWriter {
        dir: a.out.clone(),
        format: a.format,
        first_drawn: settle,
        saved: Vec::new(),
    };
    // Counts validation errors over the whole run, shutdown included.
    let validation = ValidationWatch::of(xr.gpu());
    let report = app::run(&mut xr, &opts, &mut pngs)?;
    drop(xr);
    print_governor(&report.governor);
    let json_path = a.out.join("frame_times.json");
    report::write_frame_times(&json_path, &report, opts.renderer.stereo.name())?;
    print_times(&report.times);
    print_sound(&report);
    for f in &pngs.saved {
        println!("wrote {}", f.display());
    }
    println!("wrote {}", json_path.display());
    validation.check()
}

/// The sound's line, when the run had sound.
fn print_sound(report: &app::RunReport) {
    if let Some(a) = &report.audio {
        println!("{a}");
    }
}

/// Saves captured frames as `frame_NNNNN_{left,right}.{png,jpg}`, numbered from the first
/// drawn frame.
struct FrameWriter {
    dir: PathBuf,
    format: ImageFormat,
    first_drawn: u64,
    saved: Vec<PathBuf>,
}

impl app::RunHooks for FrameWriter {
    fn capture(&mut self, c: &app::Capture<'_>) -> Result<(), app::AppError> {
        for (eye, pixels) in ["left", "right"].iter().zip(c.eyes) {
            let ext = match self.format {
                ImageFormat::Png => "png",
                ImageFormat::Jpeg => "jpg",
            };
            let drawn = c.frame - self.first_drawn;
            let file = self.dir.join(format!("frame_{drawn:05}_{eye}.{ext}"));
            let saved = match self.format {
                ImageFormat::Png => export::save_png(&file, c.width, c.height, pixels),
                ImageFormat::Jpeg => export::save_jpeg(&file, c.width, c.height, pixels),
            };
            saved.map_err(|e| app::AppError::Io(e.to_string()))?;
            self.saved.push(file);
        }
        Ok(())
    }
}

/// The window mode; with `fallback`, no display means a headless run into [`FALLBACK_DIR`].
pub fn window_cmd(mut a: WindowArgs, fallback: bool) -> CmdResult {
    let size = WindowSize::parse(&a.size)?;
    let kept = settings::open(&a.view)?;
    let saved = kept
        .as_ref()
        .map(|file| settings::apply_saved(file, &mut a.view));
    if a.frames == Some(0) {
        return Err(ParamError::new("frames", 0.0, "at least 1 frame").into());
    }
    let path = a.path.as_deref().map(CameraPath::load).transpose()?;
    let warmup = a.frames.map_or(10, |n| n.saturating_sub(1).min(10));
    // Checked before any window or device opens.
    let bodies = a.view.bodies()?;
    let mut opts = a.view.run_options(Vec::new(), warmup)?;
    opts.audio = a.view.sound(true)?;
    opts.panel_open = a.panel == PanelArg::Open;
    // Kept as they were (the window has no use for them; the headset does).
    if let Some(s) = &saved {
        opts.comfort = s.comfort(DEFAULT_DECK_HEIGHT);
    }
    opts.floating = Some(FloatOptions {
        bodies,
        deck: DeckPlacement::UnderViewer,
        interaction: a.view.interaction(),
    });
    if let Some(shot) = &a.screenshot {
        let dir = shot.parent().filter(|d| !d.as_os_str().is_empty());
        export::prepare_dir(dir.unwrap_or(std::path::Path::new(".")))?;
    }
    let duration = match a.seconds {
        None => None,
        Some(s) if s.is_finite() && (0.1..=86_400.0).contains(&s) => {
            Some(std::time::Duration::from_secs_f64(s))
        }
        Some(s) => return Err(ParamError::new("seconds", s, "seconds in [0.1, 86400]").into()),
    };
    let options = WindowOptions {
        size,
        path,
        frames: a.frames,
        duration,
        screenshot: a.screenshot.is_some(),
    };
    let mut xr = match WindowXr::new(&a.view.context(), options) {
        Ok(xr) => xr,
        Err(OpenError::Unavailable(why)) if fallback => return headless_fallback(&why, a.view),
        Err(e) => return Err(e.into()),
    };
    a.view.resolve_msaa(&mut opts, xr.gpu());
    a.view.resolve_desktop_stereo(&mut opts, xr.gpu());
    let eye = size.eye().extent();
    println!(
        "window {}x{}: both eyes at {}x{} ({}, MSAA {}) on {}",
        size.extent().width,
        size.extent().height,
        eye.width,
        eye.height,
        opts.renderer.stereo.name(),
        opts.renderer.msaa.samples(),
        xr.gpu().device_name
    );
    if a.path.is_none() {
        println!("{KEYS_HELP}");
    }
    // Counts validation errors over the whole window lifetime, shutdown included.
    let validation = ValidationWatch::of(xr.gpu());
    let mut keeper = settings::keeper(kept.as_ref(), &a.view);
    let report = app::run(&mut xr, &opts, &mut keeper)?;
    let screenshot = xr.take_screenshot();
    drop(xr);
    println!("{} frames", report.frames);
    print_governor(&report.governor);
    print_times(&report.times);
    print_sound(&report);
    if let Some(file) = &a.screenshot {
        let shot = screenshot.ok_or(
            "no screenshot: the last frame was not shown (window minimised), or the window's \
             images cannot be copied",
        )?;
        export::save_png(file, shot.width, shot.height, &shot.rgba)?;
        println!("wrote {}", file.display());
    }
    validation.check()
}

pub fn xr_cmd(mut a: XrArgs) -> CmdResult {
    if a.frames == Some(0) {
        return Err(ParamError::new("frames", 0.0, "at least 1 frame").into());
    }
    let kept = settings::open(&a.view)?;
    let saved = kept
        .as_ref()
        .map(|file| settings::apply_saved(file, &mut a.view));
    if let Some(h) = saved.as_ref().and_then(|s| s.deck_height_m) {
        if !a.view.given.has("deck_height") {
            a.deck_height = h;
        }
    }
    // Checked before any window or device opens.
    let bodies = a.view.bodies()?;
    let mut opts = a.view.run_options(Vec::new(), 10)?;
    opts.audio = a.view.sound(true)?;
    opts.panel_open = a.panel == PanelArg::Open;
    if let Some(s) = &saved {
        opts.comfort = s.comfort(a.deck_height);
    }
    opts.floating = Some(FloatOptions {
        bodies,
        deck: DeckPlacement::At(a.deck_height),
        interaction: a.view.interaction(),
    });
    // The headset path governs GPU time unless told not to.
    opts.governor = a.view.governor(true)?;
    if a.submit_depth && a.view.msaa.is_none() {
        // Submitted depth is single-sample.
        opts.renderer.msaa = Msaa::X1;
    }
    if a.submit_depth && opts.renderer.msaa != Msaa::X1 {
        return Err(
            "--submit-depth needs --msaa 1: the multisampled depth is not resolved, so there \
             is no single-sample depth to hand the compositor"
                .into(),
        );
    }
    let perf = |p: PerfArg| match p {
        PerfArg::PowerSavings => PerfLevel::PowerSavings,
        PerfArg::SustainedLow => PerfLevel::SustainedLow,
        PerfArg::SustainedHigh => PerfLevel::SustainedHigh,
        PerfArg::Boost => PerfLevel::Boost,
    };
    let xr_options = OpenXrOptions {
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
        submit_depth: a.submit_depth,
        in_water: a.in_water,
    };
    if let Some(minutes) = a.soak_minutes {
        let mut keeper = settings::keeper(kept.as_ref(), &a.view);
        let view = &a.view;
        let mut open = |opts: &mut app::RunOptions| {
            let xr = OpenXr::new(xr_options.clone())?;
            view.resolve_msaa(opts, xr.gpu());
            Ok(xr)
        };
        openxr::install_exit_signal_handler();
        return soak::soak(minutes, &mut open, &mut opts, &mut keeper);
    }
    let mut xr = OpenXr::new(xr_options)?;
    openxr::install_exit_signal_handler();
    a.view.resolve_msaa(&mut opts, xr.gpu());
    let extent = xr.targets().extent;
    println!(
        "OpenXR session: {}x{} per eye ({}, MSAA {}) on {}",
        extent.width,
        extent.height,
        opts.renderer.stereo.name(),
        opts.renderer.msaa.samples(),
        xr.gpu().device_name
    );
    // Counts validation errors over the whole session, shutdown included.
    let validation = ValidationWatch::of(xr.gpu());
    // The choices are kept as they settle and at the end, a lost runtime's end included.
    let mut keeper = settings::keeper(kept.as_ref(), &a.view);
    let result = app::run(&mut xr, &opts, &mut keeper);
    let summary = xr.summary();
    drop(xr);
    println!("openxr summary: {}", summary.line());
    let report = result?;
    println!("{} frames rendered", report.frames);
    print_times(&report.times);
    print_sound(&report);
    validation.check()
}

/// The default run without a display: 144 headless frames into [`FALLBACK_DIR`].
fn headless_fallback(why: &str, view: ViewArgs) -> CmdResult {
    println!("{why}; rendering 144 frames headless into ./{FALLBACK_DIR}/ instead");
    let out = PathBuf::from(FALLBACK_DIR);
    // The sound goes with the images unless asked for (on the device) or off.
    let audio_out = view.audio.is_none().then(|| out.join("sound.wav"));
    headless_cmd(HeadlessArgs {
        view,
        audio_out,
        frames: 144,
        size: "640x640".into(),
        path: None,
        capture: Vec::new(),
        warmup: 10,
        // Foam and floating bodies in their steady state from the first image.
        settle: 10.0,
        out: out.clone(),
        format: ImageFormat::Png,
    })?;
    let shown = std::fs::canonicalize(&out).unwrap_or(out);
    println!(
        "no display, so no window: the images are in {}",
        shown.display()
    );
    Ok(())
}

/// The GPU-time governor's changes, one line each (nothing when it is off or never changed).
fn print_governor(changes: &[app::GovernorChange]) {
    for c in changes {
        println!(
            "GPU governor: {} at {:.3} s (frame {})",
            c.level.name(),
            c.time,
            c.frame
        );
    }
}

pub fn print_times(t: &FrameTimes) {
    println!("{:<12} {:>9} {:>9} {:>9}", "ms", "p50", "p95", "p99");
    for (name, p) in app::timing::TIMINGS.iter().zip(t.all()) {
        println!("{name:<12} {:>9.3} {:>9.3} {:>9.3}", p.p50, p.p95, p.p99);
    }
}
