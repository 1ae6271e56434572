//! Frame-time tests on lavapipe (validation layer on): per scenario p50/p95/p99 of frame
//! total, sim step, sim wait, LOD, record, submit and GPU pass, printed as a table and written
//! to `target/frame-times.json`.
//!
//! The machines CI and developers get differ (Zen 1 without AVX-512 to Zen 5 with it) and so
//! does the balance between their CPU work and lavapipe's, so every gate is made of quantities
//! that hold on every kind:
//! - counts that do not depend on the machine: multiview records half the draws of two-pass;
//!   the LOD's triangles grow with log(size), not size: over the same path at 1024, 2048, 4096
//!   and 8192 m, each doubling adds about the same number of triangles (the largest increment
//!   at most [`TRIANGLE_STEP_SPREAD`] × the smallest), so 8192 m costs a bounded multiple of
//!   1024 m, not 64×;
//! - time ratios measured in this run with margins that hold on the slowest kind, scenarios
//!   interleaved round by round so the host's drift hits them alike (a ratio is the median over
//!   rounds of the ratio within each round): multiview ≤ [`MULTIVIEW_TIME`] × two-pass, 8192 m
//!   ≤ [`SIZE_TIME`] × 1024 m;
//! - a ceiling on the frame time that scales with a calibration measured in the same rounds
//!   (a fixed scalar FFT workload: [`CALIBRATION_CEILING`]), not with a file measured elsewhere;
//! - what anti-aliasing costs on lavapipe, reported with generous ceilings ([`MSAA_COST`],
//!   [`SPECULAR_AA_COST`]): a CPU rasterizer shades and stores every sample, a tiler does not;
//! - the render thread's wait for simulation results has p95 < 0.5 ms when the sim step is
//!   shorter than the frame.

mod common;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use common::gpu;
use vr_ocean::app::{FrameTimes, NoHooks, RunReport, Timing};
use vr_ocean::lod::{
    FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset, StereoFrustum,
};
use vr_ocean::render::{Msaa, StereoMode};
use vr_ocean::sim::fft::{Backend, Fft2d};
use vr_ocean::sim::{GridSize, OceanConfig, SplitField};
use vr_ocean::xr::desktop::{eye_views, CameraPath};

/// Largest over smallest triangle increment per doubling of the ocean size (1.0 would be exactly
/// linear in log(size); quadratic growth in size would give 4).
const TRIANGLE_STEP_SPREAD: f64 = 1.5;
/// Multiview frame time over two-pass (measured 0.85-0.94 on Zen 3 and Zen 5 until 2026-11-23;
/// on 2026-11-24 the same Zen 3 host gave medians 0.98, 1.16, 1.12 and 1.02 in four runs, with
/// or without the whitecaps, the per-round ratio rising in every run from 0.6-0.8 in the first
/// round to 1.0-1.4 in the last: not yet explained, see issue 12's note). On lavapipe multiview
/// replays the pass per view, so no gain is expected; the gate catches a multiview path a
/// quarter slower than two passes.
const MULTIVIEW_TIME: f64 = 1.25;
/// Frame time at 8192 m over 1024 m. Measured 0.84-1.01 on Zen 3/Zen 5 and 1.31 on Zen 1
/// (where lavapipe's vertex work weighs more: AVX2 runs as two 128-bit halves there) until the
/// far mesh collapsed by its thickness on the screen (`lod::ScreenCollapse`). That cut the
/// 1024 m frame far more than the 8192 m one (Zen 4, GPU pass p50: 73 -> 41 ms and 73 -> 67
/// ms): the larger ocean's extra rings lie beyond the coarsest lattice the collapse reaches,
/// sub-pixel triangles lavapipe still sets up one by one at this 256-pixel eye. The ratio now
/// reads 1.59 and 1.68 on Zen 4 (1.01 on the same host just before the collapse); with Zen 1's
/// factor of about 1.4 over the others, 2.5 holds there and still fails a far field that costs
/// half as much again. A far field coarser than the quadtree's coarsest lattice is the lever
/// that would bring it back down (issue 43's notes).
const SIZE_TIME: f64 = 2.5;
/// What MSAA 4 may cost over MSAA 1 on lavapipe (a CPU rasterizer shades and stores every
/// sample in memory; a tiler resolves on chip): a generous ceiling, the ratio is reported.
const MSAA_COST: f64 = 4.0;
/// What specular anti-aliasing (supersampled shading of minified water) may cost: generous.
const SPECULAR_AA_COST: f64 = 3.0;
/// Multiview-1024 frame time in units of the calibration workload (measured 7.6-11.7 per round
/// on Zen 3): 3× that, room for machines whose lavapipe/scalar balance differs, while a
/// regression that makes the frame 3× slower fails.
const CALIBRATION_CEILING: f64 = 30.0;

struct Scenario {
    name: &'static str,
    stereo: StereoMode,
    size: f32,
    msaa: Msaa,
    specular_aa: bool,
    attachment_bytes: u64,
    times: FrameTimes,
    draws: u32,
    triangles: f64,
    /// p50 frame time of each round, for paired per-round ratios.
    round_p50: Vec<f64>,
}

const ROUNDS: usize = 4;
const FRAMES: u64 = 30;
const WARMUP: u64 = 6;

fn options(s: &Scenario) -> vr_ocean::app::RunOptions {
    let mut o = gpu::small_options(s.stereo, Vec::new());
    o.ocean = OceanConfig::default_cascades(128).unwrap();
    o.threads = 1;
    o.lod = LodSettings::new(QualityPreset::Medium, OceanSize::new(s.size).unwrap());
    o.renderer.msaa = s.msaa;
    o.renderer.specular_aa = s.specular_aa;
    o.warmup = WARMUP;
    o
}

fn path() -> CameraPath {
    // Standing, looking around at the horizon and down at the water.
    CameraPath::parse(
        "0    0  1.7  0   0    -8
         0.25 1  1.7  -1  40   -20
         0.5  2  1.7  -2  80   -5",
    )
    .unwrap()
}

/// Mean triangles the LOD draws per frame along [`path`] (the headless clock's frame times) at
/// ocean size `size`, with a fixed displacement padding: the geometry cost, machine-free.
fn lod_triangles(size: f32) -> f64 {
    let mut lod = OceanLod::new(LodSettings::new(
        QualityPreset::Medium,
        OceanSize::new(size).unwrap(),
    ));
    let path = path();
    let pad = MaxDisplacement::new([1.0, 1.5, 1.0]).unwrap();
    let mut sum = 0u64;
    for frame in 0..FRAMES {
        let (position, orientation) = path.pose(frame as f64 / 72.0);
        let views = eye_views(position, orientation);
        let eyes = StereoFrustum::new(views[0], views[1]).unwrap();
        let stats = lod
            .update(&FrameInput {
                viewer: eyes.centre(),
                culling: Some(&eyes),
                max_displacement: pad,
            })
            .unwrap();
        sum += u64::from(stats.triangles);
    }
    sum as f64 / FRAMES as f64
}

/// The calibration workload: four inverse FFTs of 256² on the portable scalar backend, the
/// same instructions on every x86-64 machine. Returns the median of 5 timings (ms).
struct Calibration {
    fft: Fft2d,
    fields: Vec<SplitField>,
    scratch: Vec<SplitField>,
}

impl Calibration {
    fn new() -> Self {
        let grid = GridSize::new(256).unwrap();
        let mut fields: Vec<SplitField> = (0..4).map(|_| SplitField::zeros(grid)).collect();
        for (i, f) in fields.iter_mut().enumerate() {
            let (re, im) = f.planes_mut();
            for (j, (r, m)) in re.iter_mut().zip(im.iter_mut()).enumerate() {
                *r = ((i * 31 + j * 7) % 97) as f32 * 0.01;
                *m = ((i * 17 + j * 13) % 89) as f32 * 0.01;
            }
        }
        Self {
            fft: Fft2d::with_backend(grid, Backend::Scalar).unwrap(),
            fields,
            scratch: (0..4).map(|_| SplitField::zeros(grid)).collect(),
        }
    }

    fn measure(&mut self) -> f64 {
        let mut t: Vec<Duration> = (0..5)
            .map(|_| {
                let start = Instant::now();
                self.fft.inverse_batch(&mut self.fields, &mut self.scratch);
                start.elapsed()
            })
            .collect();
        t.sort();
        t[2].as_secs_f64() * 1e3
    }
}

/// The median over rounds of the per-round ratios a/b (scenarios run back to back there): a
/// burst of host load spoils one round, not the result.
fn median_ratio(a: &[f64], b: &[f64]) -> (f64, Vec<f64>) {
    let mut v: Vec<f64> = a.iter().zip(b).map(|(x, y)| x / y).collect();
    v.sort_by(f64::total_cmp);
    ((v[(v.len() - 1) / 2] + v[v.len() / 2]) / 2.0, v)
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            let l = s.lines().find(|l| l.starts_with("model name"))?.to_string();
            let family = s.lines().find(|l| l.starts_with("cpu family"))?.to_string();
            let pick = |l: &str| l.split(':').nth(1).unwrap_or("").trim().to_string();
            Some(format!("{} (family {})", pick(&l), pick(&family)))
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// The timed tests take turns: one timed while the other renders on the same cores would time
/// both.
static TIMING: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn frame_times_on_lavapipe() {
    let _turn = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    // Geometry and stereo are compared without anti-aliasing (MSAA 1, no specular AA), so
    // those ratios do not depend on how a machine rasterizes samples; the last two add MSAA 4,
    // then specular AA (the defaults), for what anti-aliasing costs.
    let mut scenarios = [
        (
            "multiview-1024",
            StereoMode::Multiview,
            1024.0,
            Msaa::X1,
            false,
        ),
        (
            "two-pass-1024",
            StereoMode::TwoPass,
            1024.0,
            Msaa::X1,
            false,
        ),
        (
            "multiview-8192",
            StereoMode::Multiview,
            8192.0,
            Msaa::X1,
            false,
        ),
        ("msaa4-1024", StereoMode::Multiview, 1024.0, Msaa::X4, false),
        (
            "defaults-1024",
            StereoMode::Multiview,
            1024.0,
            Msaa::X4,
            true,
        ),
    ]
    .map(|(name, stereo, size, msaa, specular_aa)| Scenario {
        name,
        stereo,
        size,
        msaa,
        specular_aa,
        attachment_bytes: 0,
        times: FrameTimes::with_capacity(ROUNDS * FRAMES as usize),
        draws: 0,
        triangles: 0.0,
        round_p50: Vec::with_capacity(ROUNDS),
    });
    let mut calibration = Calibration::new();
    let mut round_calibration = Vec::with_capacity(ROUNDS);
    for round in 0..ROUNDS {
        // Alternate the order (ABC, CBA, ...) so a drift within a round cancels out; the
        // calibration runs at the round's middle.
        let order: [usize; 5] = if round % 2 == 0 {
            [0, 1, 2, 3, 4]
        } else {
            [4, 3, 2, 1, 0]
        };
        for (k, i) in order.into_iter().enumerate() {
            if k == 2 {
                round_calibration.push(calibration.measure());
            }
            let s = &mut scenarios[i];
            let r: RunReport =
                gpu::render_with(&options(s), path(), FRAMES, 256, 256, &mut NoHooks);
            s.times.merge(&r.times);
            s.draws = s.draws.max(r.max_draws);
            s.triangles = r.mean_triangles;
            s.attachment_bytes = r.attachment_bytes;
            s.round_p50
                .push(r.times.percentiles(Timing::FrameTotal).p50);
        }
    }

    let cpu = cpu_model();
    let mut table = String::new();
    let _ = writeln!(table, "CPU: {cpu}");
    let _ = writeln!(
        table,
        "{:<16} {:<11} {:>8} {:>8} {:>8}   (ms; draws, triangles)",
        "scenario", "timing", "p50", "p95", "p99"
    );
    for s in &scenarios {
        for (name, p) in vr_ocean::app::timing::TIMINGS.iter().zip(s.times.all()) {
            let _ = writeln!(
                table,
                "{:<16} {:<11} {:>8.3} {:>8.3} {:>8.3}",
                s.name, name, p.p50, p.p95, p.p99
            );
        }
        let _ = writeln!(
            table,
            "{:<16} draws {}, triangles {:.0}",
            s.name, s.draws, s.triangles
        );
    }
    let [mv, tp, big, msaa4, defaults] = &scenarios;
    let (r_stereo, v_stereo) = median_ratio(&mv.round_p50, &tp.round_p50);
    let (r_size, v_size) = median_ratio(&big.round_p50, &mv.round_p50);
    let (r_cal, v_cal) = median_ratio(&mv.round_p50, &round_calibration);
    let (r_msaa, v_msaa) = median_ratio(&msaa4.round_p50, &mv.round_p50);
    let (r_spec, v_spec) = median_ratio(&defaults.round_p50, &msaa4.round_p50);
    let gpu_p50 = |s: &Scenario| s.times.percentiles(Timing::GpuPass).p50;
    let sweep: Vec<(f32, f64)> = [1024.0, 2048.0, 4096.0, 8192.0]
        .into_iter()
        .map(|size| (size, lod_triangles(size)))
        .collect();
    let steps: Vec<f64> = sweep.windows(2).map(|w| w[1].1 - w[0].1).collect();
    let spread = steps.iter().copied().fold(f64::MIN, f64::max)
        / steps.iter().copied().fold(f64::MAX, f64::min);
    let mut calib_sorted = round_calibration.clone();
    calib_sorted.sort_by(f64::total_cmp);
    let _ = writeln!(
        table,
        "calibration (4 scalar FFTs of 256^2): {:.3} ms median over rounds",
        calib_sorted[ROUNDS / 2]
    );
    let _ = writeln!(
        table,
        "LOD triangles per frame at 1024/2048/4096/8192 m: {:.0?}; increments per doubling \
         {steps:.0?}, largest / smallest {spread:.3} (gate <= {TRIANGLE_STEP_SPREAD}); \
         rendered 8192 m / 1024 m {:.3}",
        sweep.iter().map(|s| s.1).collect::<Vec<_>>(),
        big.triangles / mv.triangles
    );
    let _ = writeln!(
        table,
        "multiview / two-pass frame time: {r_stereo:.3} (gate <= {MULTIVIEW_TIME}), per round {v_stereo:.3?}"
    );
    let _ = writeln!(
        table,
        "8192 m / 1024 m frame time: {r_size:.3} (gate <= {SIZE_TIME}), per round {v_size:.3?}"
    );
    let _ = writeln!(
        table,
        "multiview-1024 frame / calibration: {r_cal:.1} (gate <= {CALIBRATION_CEILING}), per round {v_cal:.1?}"
    );
    let _ = writeln!(
        table,
        "cost of MSAA 4 over 1 (frame time): {r_msaa:.3} (gate <= {MSAA_COST}), per round \
         {v_msaa:.3?}; GPU pass p50 {:.1} vs {:.1} ms; transient attachments {:.2} vs {:.2} MiB",
        gpu_p50(msaa4),
        gpu_p50(mv),
        msaa4.attachment_bytes as f64 / 1048576.0,
        mv.attachment_bytes as f64 / 1048576.0
    );
    let _ = writeln!(
        table,
        "cost of specular AA (frame time): {r_spec:.3} (gate <= {SPECULAR_AA_COST}), per round \
         {v_spec:.3?}; GPU pass p50 {:.1} vs {:.1} ms",
        gpu_p50(defaults),
        gpu_p50(msaa4)
    );
    println!("{table}");

    let json = serde_json::json!({
        "cpu": cpu,
        "calibration_ms": calib_sorted[ROUNDS / 2],
        "ratios": {
            "lod_triangles_by_size": sweep,
            "triangle_step_spread": spread,
            "multiview_over_two_pass": r_stereo,
            "size_8192_over_1024": r_size,
            "frame_over_calibration": r_cal,
            "msaa4_over_msaa1": r_msaa,
            "specular_aa_on_over_off": r_spec,
        },
        "scenarios": scenarios.iter().map(|s| serde_json::json!({
            "name": s.name,
            "draws": s.draws,
            "mean_triangles": s.triangles,
            "attachment_bytes": s.attachment_bytes,
            "timings_ms": &s.times,
        })).collect::<Vec<_>>(),
    });
    let target: PathBuf = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .to_path_buf();
    let out = target.join("frame-times.json");
    std::fs::write(&out, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    println!("wrote {}", out.display());

    assert_eq!(
        2 * mv.draws,
        tp.draws,
        "multiview must record half the draws"
    );
    assert!(
        steps.iter().all(|&d| d > 0.0) && spread <= TRIANGLE_STEP_SPREAD,
        "triangles per doubling of the ocean size {steps:.0?}: not linear in log(size)"
    );
    assert!(
        r_stereo <= MULTIVIEW_TIME,
        "multiview frame time {r_stereo:.3}x two-pass"
    );
    assert!(
        r_size <= SIZE_TIME,
        "frame time at 8192 m is {r_size:.3}x that at 1024 m"
    );
    assert!(
        r_msaa <= MSAA_COST,
        "MSAA 4 costs {r_msaa:.3}x the frame time of MSAA 1"
    );
    assert!(
        r_spec <= SPECULAR_AA_COST,
        "specular AA costs {r_spec:.3}x the frame time without it"
    );
    assert!(
        r_cal <= CALIBRATION_CEILING,
        "multiview-1024 frame time is {r_cal:.1}x the calibration workload ({cpu})"
    );
    for s in &scenarios {
        let step = s.times.percentiles(Timing::SimStep).p95;
        let frame = s.times.percentiles(Timing::FrameTotal).p50;
        let wait = s.times.percentiles(Timing::SimWait).p95;
        if step < frame {
            assert!(
                wait < 0.5,
                "{}: sim wait p95 {wait:.3} ms (step {step:.2}, frame {frame:.2})",
                s.name
            );
        }
    }
}

/// What the headsets' specular AA may cost at the Quest 2 eye size (issue 43): the filtered lobe
/// alone, no supersampling, on the pass's own timestamps.
const HEADSET_SPECULAR_AA_COST: f64 = 1.25;

/// The p50 of the GPU pass (ms) of `vr-ocean headless` with `args`, from its timing table.
fn headless_gpu_pass(args: &[&str]) -> f64 {
    let out = common::scratch_path("aa-cost");
    let mut all = vec!["headless"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", out.to_str().unwrap()]);
    let run = common::vr_ocean(&all);
    let _ = std::fs::remove_dir_all(&out);
    let text =
        String::from_utf8_lossy(&run.stdout).into_owned() + &String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "headless {args:?} failed: {text}");
    text.lines()
        .find_map(|l| l.strip_prefix("gpu_pass"))
        .and_then(|l| l.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no gpu_pass line in: {text}"))
}

/// On lavapipe at the Quest 2 eye size (1440x1584, MSAA 4, standing at 1.7 m facing the
/// horizon, the medium preset) the pass with the headsets' specular AA (the filtered lobe,
/// supersampling off) costs at most [`HEADSET_SPECULAR_AA_COST`] the pass without it; the
/// ratio is the median over rounds of on over off within a round (the runs alternate).
/// Anisotropic filtering is left off: Mesa 22.3's lavapipe filters its taps ~50x slower than
/// a GPU's texture unit (`tests/render/anisotropy.rs`).
#[test]
fn frame_times_on_lavapipe_headset_specular_aa_at_the_quest_2_eye_size() {
    let _turn = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    let path = common::scratch_path("aa-cost-path");
    std::fs::write(&path, "0 0 1.7 0 0 0\n").unwrap();
    let path_arg = path.to_str().unwrap().to_string();
    let run = |aa: &str| {
        headless_gpu_pass(&[
            "--size",
            "1440x1584",
            "--msaa",
            "4",
            "--specular-aa",
            aa,
            "--supersampling",
            "off",
            "--anisotropy",
            "1",
            "--preset",
            "medium",
            "--bodies",
            "0",
            "--frames",
            "4",
            "--warmup",
            "1",
            "--validation",
            "--path",
            &path_arg,
        ])
    };
    let mut ratios = Vec::new();
    for _ in 0..3 {
        let on = run("on");
        let off = run("off");
        println!("GPU pass p50 at 1440x1584, MSAA 4: specular AA on {on:.0} ms, off {off:.0} ms");
        ratios.push(on / off);
    }
    let _ = std::fs::remove_file(&path);
    ratios.sort_by(f64::total_cmp);
    let ratio = ratios[ratios.len() / 2];
    println!(
        "the headsets' specular AA at the Quest 2 eye size on lavapipe ({}): {ratio:.3}x the \
         pass without it (rounds {ratios:.3?}; gate {HEADSET_SPECULAR_AA_COST})",
        cpu_model()
    );
    assert!(
        ratio <= HEADSET_SPECULAR_AA_COST,
        "the headsets' specular AA costs {ratio:.3}x the pass without it at the Quest 2 eye size"
    );
}
