//! `vr-ocean gpu-budget --calibrate`: asks the cost model to predict the device it runs on.
//! The calibration passes (`render::calibration`) are timed at a headset's recommended eye size with its
//! settings (Quest 2's by default), the device's costs fitted from them (`render::budget::calibration`), and every
//! standard view's ocean pass predicted from its counts (the counting pass) and compared with
//! the plain pass's own GPU time (its timestamps, as `headless` reports them).

use std::time::Duration;

use serde::Serialize;

use super::gpu_view::{context_options, render_view, GpuBudgetArgs, ViewRun};
use super::report::CmdResult;
use super::report::ValidationWatch;
use vr_ocean::app;
use vr_ocean::render::budget::calibration::{
    fragments_per_pixel, predict, DeviceRates, KernelKind, KernelMeasurement, Prediction,
};
use vr_ocean::render::budget::{self, spirv, PathCosts, PathCounts, StandardView};
use vr_ocean::render::calibration::kernels::{self, Geometry, Kernel, Shader};
use vr_ocean::render::calibration::{CalibrationSettings, Calibrator};
use vr_ocean::render::render_pass::PassLayout;
use vr_ocean::render::{GpuContext, Msaa, StereoMode};
use vr_ocean::xr::desktop::COLOUR_FORMAT;

/// One standard view: what the model predicts of the ocean pass, and what it took.
#[derive(Clone, Debug, Serialize)]
pub struct CalibrationRow {
    /// The device that rendered it.
    pub device: String,
    /// The view.
    pub view: &'static str,
    /// The model's prediction (ms).
    pub predicted_ms: f64,
    /// The plain pass's GPU time (median of its timestamps, ms).
    pub measured_ms: f64,
    /// `predicted / measured - 1`.
    pub error: f64,
    /// How fast the device ran while the view was measured: its reference pass's time then
    /// over at calibration (the prediction is scaled by it).
    pub drift: f64,
    /// The prediction's terms.
    pub prediction: Prediction,
    /// What the counting pass measured.
    pub counts: PathCounts,
}

/// What `--from` reads back of a report: the passes, the costs and the views as recorded.
#[derive(serde::Deserialize)]
struct Earlier {
    device: String,
    kernels: Vec<KernelMeasurement>,
    costs: PathCosts,
    views: Vec<EarlierView>,
}

/// A view of an earlier report.
#[derive(serde::Deserialize)]
struct EarlierView {
    view: String,
    measured_ms: f64,
    #[serde(default = "no_drift")]
    drift: f64,
    counts: PathCounts,
}

fn no_drift() -> f64 {
    1.0
}

/// `--from`: the model fitted again to a report's passes, its views predicted again.
fn refit(a: &GpuBudgetArgs, path: &std::path::Path) -> CmdResult {
    let text = std::fs::read(path).map_err(|e| format!("--from {}: {e}", path.display()))?;
    let earlier: Earlier = serde_json::from_slice(&text)
        .map_err(|e| format!("--from {}: not a calibration report: {e}", path.display()))?;
    let rates = DeviceRates::fit(&earlier.device, &earlier.kernels)?;
    let rows: Vec<CalibrationRow> = earlier
        .views
        .iter()
        .map(|v| {
            let view = budget::VIEWS
                .iter()
                .find(|s| s.name == v.view)
                .map_or("?", |s| s.name);
            CalibrationRow::new(
                &earlier.device,
                view,
                &rates,
                &earlier.costs,
                v.counts,
                v.measured_ms,
                v.drift,
            )
        })
        .collect();
    print_rows(a, &earlier.device, &rates, &rows)
}

impl CalibrationRow {
    /// The row of `view`: its prediction from `rates`, `costs` and `counts`, scaled by
    /// `drift`, against `measured_ms`.
    fn new(
        device: &str,
        view: &'static str,
        rates: &DeviceRates,
        costs: &PathCosts,
        counts: PathCounts,
        measured_ms: f64,
        drift: f64,
    ) -> Self {
        let prediction = predict(rates, costs, &counts);
        let predicted_ms = prediction.ms * drift;
        Self {
            device: device.to_string(),
            view,
            predicted_ms,
            measured_ms,
            error: predicted_ms / measured_ms - 1.0,
            drift,
            prediction,
            counts,
        }
    }
}

/// The whole calibration (`--report`): every pass as timed, the fitted costs, the views.
#[derive(Serialize)]
struct Report<'a> {
    device: &'a str,
    headset: &'static str,
    eye: [u32; 2],
    stereo: &'static str,
    msaa: u32,
    anisotropy_taps: u32,
    kernels: &'a [KernelMeasurement],
    rates: &'a DeviceRates,
    costs: &'a PathCosts,
    views: &'a [CalibrationRow],
}

pub fn calibrate_cmd(a: &GpuBudgetArgs, costs: &PathCosts, views: &[&StandardView]) -> CmdResult {
    if a.scale != 1.0 {
        return Err(
            "--calibrate renders at the headset's recommended eye size: leave out --scale".into(),
        );
    }
    if !(1..=100).contains(&a.repeats) {
        return Err(format!("--repeats {}: 1 to 100", a.repeats).into());
    }
    if !(3..=1000).contains(&a.frames) {
        return Err(format!("--frames {}: 3 to 1000 (two are warm-up)", a.frames).into());
    }
    if let Some(path) = &a.from {
        return refit(a, path);
    }
    // At the runtime's recommended eye size (render scale 1), whatever the headset's default
    // scale: the calibration predicts the device it runs on, and its recorded runs and
    // ceilings were measured at that size.
    let model = &budget::HeadsetModel {
        resolution_scale: 1.0,
        ..*a.headset.model()
    };
    // The calibration's device stays open while the views render (in devices of their own):
    // its reference pass is timed again around each view, so that a host whose speed drifts
    // (shared machines: 1.5x within minutes) is measured at the speed the view met.
    let gpu = GpuContext::new(&context_options(a))?;
    let watch = ValidationWatch::of(&gpu);
    let cpu = gpu.cpu_device;
    let device = gpu.device_name.clone();
    // The app's default on this device: anisotropic filtering on a GPU, not on lavapipe.
    let wanted = a.anisotropy.unwrap_or(if cpu { 1 } else { 4 });
    let taps = match gpu.max_anisotropy {
        Some(max) => wanted.min(max as u32).max(1),
        None => 1,
    };
    let (width, height) = model.eye();
    let settings = CalibrationSettings {
        pass: PassLayout {
            mode: stereo_of(cpu),
            colour_format: COLOUR_FORMAT,
            msaa: Msaa::from_samples(model.msaa).ok_or("the model's MSAA")?,
            store_depth: false,
            density_map: false,
        },
        eye: ash::vk::Extent2D { width, height },
        anisotropy_taps: taps,
    };
    let mut cal = Calibrator::new(&gpu, settings)?;
    let result = Measuring {
        a,
        gpu: &gpu,
        model,
        costs,
        taps,
        device: &device,
    }
    .run(&mut cal, views);
    cal.destroy(&gpu);
    drop(gpu);
    watch.check()?;
    let Calibration {
        kernels,
        rates,
        rows,
    } = result?;
    if let Some(path) = &a.report {
        let report = Report {
            device: &device,
            headset: model.name,
            eye: [width, height],
            stereo: stereo_of(cpu).name(),
            msaa: model.msaa,
            anisotropy_taps: taps,
            kernels: &kernels,
            rates: &rates,
            costs,
            views: &rows,
        };
        let text = serde_json::to_string_pretty(&report)?;
        vr_ocean::export::write_bytes(path, text.as_bytes())?;
    }
    print_rows(a, &device, &rates, &rows)
}

/// The pass timed again around each view to follow the device's speed: the arithmetic kernel.
const REFERENCE: Kernel = Kernel {
    shader: Shader::Alu,
    geometry: Geometry::FullScreen,
};

/// What a calibration found: the passes as timed, the costs fitted to them, the views.
struct Calibration {
    kernels: Vec<KernelMeasurement>,
    rates: DeviceRates,
    rows: Vec<CalibrationRow>,
}

/// The calibration's procedure and what it runs with.
struct Measuring<'a> {
    a: &'a GpuBudgetArgs,
    gpu: &'a GpuContext,
    model: &'a budget::HeadsetModel,
    costs: &'a PathCosts,
    taps: u32,
    device: &'a str,
}

impl Measuring<'_> {
    /// Times the calibration passes, fits the device's costs, then renders each view
    /// (counting pass, then the plain pass between two timings of the reference pass) and
    /// predicts it.
    fn run(
        &self,
        cal: &mut Calibrator,
        views: &[&StandardView],
    ) -> Result<Calibration, Box<dyn std::error::Error>> {
        let Self {
            a,
            gpu,
            model,
            costs,
            taps,
            device,
        } = *self;
        settle(gpu, cal)?;
        let kernels = run_kernels(a, gpu, cal, taps, model.eye())?;
        let rates = DeviceRates::fit(device, &kernels)?;
        if !a.json {
            eprintln!("{device}: {rates:?}");
        }
        let reference_ms = kernels
            .iter()
            .find(|k| k.kind == KernelKind::Alu)
            .map(|k| k.ms)
            .ok_or("no arithmetic pass")?;
        let mut rows = Vec::new();
        for view in views {
            let counted = ViewRun {
                model,
                view,
                counting: true,
                frames: 4,
                warmup: 1,
                taps,
            };
            let counts = render_view(a, &counted)?
                .0
                .paths
                .ok_or("the renderer returned no counts (the device lacks pipeline statistics)")?;
            let plain = ViewRun {
                counting: false,
                frames: a.frames,
                warmup: 2,
                ..counted
            };
            let before = median_ms(&cal.time(gpu, REFERENCE, 3)?);
            let (report, _) = render_view(a, &plain)?;
            let after = median_ms(&cal.time(gpu, REFERENCE, 3)?);
            let gpu_pass = report.times.percentiles(app::Timing::GpuPass);
            if gpu_pass.samples == 0 {
                return Err(format!(
                    "{}: the plain pass reported no GPU times (the device has no timestamps)",
                    view.name
                )
                .into());
            }
            let drift = 0.5 * (before + after) / reference_ms;
            let row = CalibrationRow::new(
                device,
                view.name,
                &rates,
                costs,
                counts,
                gpu_pass.p50,
                drift,
            );
            if !a.json {
                eprintln!(
                    "{} / {}: predicted {:.2} ms, measured {:.2} ms ({:+.0} %; the device ran at \
                 {:.2}x its calibration's time)",
                    row.device,
                    row.view,
                    row.predicted_ms,
                    row.measured_ms,
                    100.0 * row.error,
                    row.drift
                );
            }
            rows.push(row);
        }
        Ok(Calibration {
            kernels,
            rates,
            rows,
        })
    }
}

/// The median of `runs` (ms).
fn median_ms(runs: &[Duration]) -> f64 {
    let mut ms: Vec<f64> = runs.iter().map(|d| d.as_secs_f64() * 1e3).collect();
    ms.sort_by(f64::total_cmp);
    ms[ms.len() / 2]
}

/// The rows as JSON (stdout with --json, and --out) or a table.
fn print_rows(
    a: &GpuBudgetArgs,
    device: &str,
    rates: &DeviceRates,
    rows: &[CalibrationRow],
) -> CmdResult {
    let json = serde_json::to_string_pretty(rows)?;
    if let Some(out) = &a.out {
        vr_ocean::export::write_bytes(out, json.as_bytes())?;
    }
    if a.json {
        println!("{json}");
    } else {
        println!(
            "cost model calibrated on {device} at {}'s recommended eye size (docs/notes/gpu-cost-model.md)",
            a.headset.model().name
        );
        println!(
            "fitted: per fragment {:.2} ns, ALU {:.4} ns, special {:.3} ns, sample {:.2} ns, \
             overlap {:.2}, branches paid {:.2}",
            rates.fragment_ns,
            rates.alu_ns,
            rates.special_ns,
            rates.sample_ns,
            rates.overlap,
            rates.branch_share
        );
        println!("view      predicted ms  measured ms   error");
        for r in rows {
            println!(
                "{:<9} {:>12.2} {:>12.2} {:>+6.0} %",
                r.view,
                r.predicted_ms,
                r.measured_ms,
                100.0 * r.error
            );
        }
    }
    Ok(())
}

/// The stereo mode the views are drawn in on this kind of device (as `render_view` chooses).
fn stereo_of(cpu: bool) -> StereoMode {
    if cpu {
        StereoMode::TwoPass
    } else {
        StereoMode::Multiview
    }
}

/// Times the reference pass until two rounds in a row agree within 5 % (at most
/// [`SETTLE_ROUNDS`]): a host that has just run something large (on this project's VMs, the
/// budget's views before the calibration in `tests/gpu_budget.rs`) ran the first passes up to
/// 40 % slow for ten seconds or more, which shrank every rate fitted after them and put the
/// views 40-60 % over their prediction; alone, the same build predicted them within 10-25 %.
fn settle(gpu: &GpuContext, cal: &mut Calibrator) -> Result<(), Box<dyn std::error::Error>> {
    let mut last = median_ms(&cal.time(gpu, REFERENCE, 3)?);
    for _ in 1..SETTLE_ROUNDS {
        let now = median_ms(&cal.time(gpu, REFERENCE, 3)?);
        if (now / last - 1.0).abs() < 0.05 {
            break;
        }
        last = now;
    }
    Ok(())
}

/// The most rounds [`settle`] waits for the device's speed to hold.
const SETTLE_ROUNDS: usize = 8;

/// Times each pass `a.repeats` times (after one untimed run, which compiles and warms).
fn run_kernels(
    a: &GpuBudgetArgs,
    gpu: &GpuContext,
    cal: &mut Calibrator,
    taps: u32,
    (width, height): (u32, u32),
) -> Result<Vec<KernelMeasurement>, Box<dyn std::error::Error>> {
    let pixels = 2.0 * f64::from(width) * f64::from(height);
    let mut out = Vec::new();
    for kernel in kernels::all() {
        if kernel.shader == Shader::Anisotropic && taps <= 1 {
            continue;
        }
        // One untimed run compiles and warms; then `repeats` runs, fewer (at least 3) where
        // each takes seconds (lavapipe's smallest grids).
        let first = cal.time(gpu, kernel, 1)?[0];
        let repeats = if first.as_secs_f64() > 1.0 {
            a.repeats.min(3)
        } else {
            a.repeats
        };
        let runs = cal.time(gpu, kernel, repeats)?;
        let mut ms: Vec<f64> = runs
            .iter()
            .map(|d| Duration::as_secs_f64(d) * 1e3)
            .collect();
        let runs_ms = ms.clone();
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let counts = spirv::count(kernel.shader.spirv())?;
        let (triangles, fragments, cell) = match kernel.geometry {
            Geometry::Grid(cell) => (
                2.0 * f64::from(kernel.vertices(width, height) / 3),
                pixels * fragments_per_pixel(cell),
                cell,
            ),
            Geometry::FullScreen => (2.0, pixels, 0),
            Geometry::Empty => (0.0, 0.0, 0),
        };
        let m = KernelMeasurement {
            name: kernel.name(),
            kind: kind_of(&kernel),
            ms: median,
            runs_ms,
            fragments,
            triangles,
            cell,
            taps: if kernel.shader == Shader::Anisotropic {
                f64::from(taps)
            } else {
                1.0
            },
            counts,
        };
        if !a.json {
            eprintln!("calibration pass {:<24} {:9.3} ms", m.name, m.ms);
        }
        out.push(m);
    }
    Ok(out)
}

/// What a pass measures, for the fit.
fn kind_of(k: &Kernel) -> KernelKind {
    match (k.geometry, k.shader) {
        (Geometry::Empty, _) => KernelKind::Empty,
        (Geometry::Grid(_), Shader::Lod) => KernelKind::GridShaded,
        (Geometry::Grid(_), _) => KernelKind::GridBase,
        (Geometry::FullScreen, Shader::Base) => KernelKind::Base,
        (Geometry::FullScreen, Shader::Alu) => KernelKind::Alu,
        (Geometry::FullScreen, Shader::Relaxed) => KernelKind::Relaxed,
        (Geometry::FullScreen, Shader::Special) => KernelKind::Special,
        (Geometry::FullScreen, Shader::Trilinear) => KernelKind::Trilinear,
        (Geometry::FullScreen, Shader::Anisotropic) => KernelKind::Anisotropic,
        (Geometry::FullScreen, Shader::Mixed) => KernelKind::Mixed,
        (Geometry::FullScreen, Shader::Lod) => KernelKind::Lod,
        (Geometry::FullScreen, Shader::Grad) => KernelKind::Grad,
        (Geometry::FullScreen, Shader::Query) => KernelKind::Query,
        (Geometry::FullScreen, Shader::Branch) => KernelKind::Branch,
    }
}
