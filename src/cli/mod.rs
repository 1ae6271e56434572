//! The `vr-ocean` command line: argument structs ([`args`] shared, one file per command
//! family: [`view`] for window/headless/xr, [`tools`] for simulate/export/bench/lod-svg,
//! [`budget`] for gpu-budget) and the
//! run report ([`report`]: validation errors, `frame_times.json`).

pub mod adreno;
pub mod args;
pub mod budget;
pub mod calibrate;
pub mod given;
pub mod gpu_view;
pub mod report;
pub mod settings;
pub mod soak;
pub mod tools;
pub mod view;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

use self::adreno::ShaderStatsArgs;
use self::gpu_view::GpuBudgetArgs;
use self::tools::{BenchArgs, ExportArgs, LodSvgArgs, SimulateArgs};
use self::view::{DefaultRun, HeadlessArgs, WindowArgs, XrArgs};

pub use self::report::CmdResult;

#[derive(Parser)]
#[command(
    name = "vr-ocean",
    version,
    about = "An endless FFT ocean for OpenXR headsets"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
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
    /// Estimate the ocean pass's GPU time on Quest 2 and Quest 3 at their default settings: the
    /// standard views rendered with the counting pass, shader paths and instructions counted,
    /// combined with the GPUs' published throughput (a model, not a headset measurement).
    GpuBudget(GpuBudgetArgs),
    /// Print what the Vulkan device's own shader compiler makes of every pipeline a headset
    /// draws, and of each water path as a pipeline of its own (instructions, registers, waves,
    /// from VK_KHR_pipeline_executable_properties; Mesa's turnip reports the Adreno's ir3).
    ShaderStats(ShaderStatsArgs),
    /// Draw one frame of the quadtree LOD (patches by level, stitched edges, both eye frusta) as SVG.
    LodSvg(LodSvgArgs),
}

/// Parses the command line (exiting with clap's message on bad input, or after `--help`),
/// recording in each view command which of its flags were given ([`given::Given`]).
pub fn parse() -> Cli {
    parse_from(std::env::args_os())
}

/// [`parse`] from `args` (the program name first).
pub fn parse_from<I, T>(args: I) -> Cli
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = Cli::command().get_matches_from(args);
    let mut cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let (Some(command), Some((_, sub))) = (cli.command.as_mut(), matches.subcommand()) {
        let given = given::Given::of(sub);
        match command {
            Command::Window(a) => a.view.given = given,
            Command::Headless(a) => a.view.given = given,
            Command::Xr(a) => a.view.given = given,
            _ => {}
        }
    }
    cli
}

/// Runs the command (the window, or headless without a display, when none is given).
pub fn run(cli: Cli) -> CmdResult {
    match cli.command {
        None => view::window_cmd(DefaultRun::parse_from(["vr-ocean"]).args, true),
        Some(Command::Window(a)) => view::window_cmd(a, false),
        Some(Command::Simulate(a)) => tools::simulate(a),
        Some(Command::Export(a)) => tools::export_cmd(a),
        Some(Command::Bench(a)) => tools::bench_cmd(a),
        Some(Command::LodSvg(a)) => tools::lod_svg_cmd(a),
        Some(Command::Headless(a)) => view::headless_cmd(a),
        Some(Command::Xr(a)) => view::xr_cmd(a),
        Some(Command::GpuBudget(a)) => budget::gpu_budget_cmd(a),
        Some(Command::ShaderStats(a)) => adreno::shader_stats_cmd(a),
    }
}
