//! The commands without graphics: `simulate`, `export`, `bench` and `lod-svg`.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::args::{default_threads, preset, DerivativesArg, OceanArgs, PresetArg};
use super::report::CmdResult;
use vr_ocean::base::ParamError;
use vr_ocean::bench::{self, BenchOptions};
use vr_ocean::export;
use vr_ocean::sim::fft::{Backend, UnavailableBackend};
use vr_ocean::sim::interaction::{InteractionConfig, Scenario, ScenarioRun};
use vr_ocean::sim::{GridSize, OceanConfig, SimCore, SimError, Simulation, Surfaces};

#[derive(Args)]
pub struct LodSvgArgs {
    /// Head position x,y,z (m; y is the height above the water).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        required = true
    )]
    pub camera: Vec<f32>,
    /// Heading (degrees; 0 looks along -z, positive turns left toward -x).
    #[arg(long, allow_negative_numbers = true, required = true)]
    pub yaw: f32,
    /// Pitch (degrees; negative looks down).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub pitch: f32,
    /// Quality preset (thesis Table 2).
    #[arg(long, value_enum, default_value_t = PresetArg::Ultra)]
    pub preset: PresetArg,
    /// Ocean size S (m), 256 to 8192.
    #[arg(long, allow_negative_numbers = true, default_value_t = 8192.0)]
    pub size: f32,
    /// Maximum displacement max|Dx|,max|h|,max|Dz| (m) padding the culling boxes.
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',', default_values_t = [1.0, 1.5, 1.0])]
    pub max_displacement: Vec<f32>,
    /// Output SVG file.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub ocean: OceanArgs,
    /// Simulated seconds to run.
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    pub seconds: f64,
    /// Steps per simulated second (the headset's refresh rate).
    #[arg(long, default_value_t = 72.0)]
    pub rate: f64,
    /// Simulation worker threads.
    #[arg(long, default_value_t = default_threads())]
    pub threads: usize,
}

#[derive(Args)]
pub struct ExportArgs {
    #[command(flatten)]
    pub ocean: OceanArgs,
    /// Times (s) to export, comma-separated.
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        required = true
    )]
    pub time: Vec<f64>,
    /// Output directory (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Also export the interaction layer after a 1 m sphere dropped at world X,Z (m) at t = 0:
    /// `t{time}_interaction_height.npy` and `t{time}_interaction.json` (times must be >= 0).
    #[arg(
        long,
        value_name = "X,Z",
        allow_negative_numbers = true,
        value_delimiter = ',',
        num_args = 1
    )]
    pub impulse: Option<Vec<f32>>,
    /// Also export the interaction layer with a 1 m float towed along +x from the origin at
    /// SPEED (m/s) from t = 0, the layer following it (times must be >= 0).
    #[arg(long, value_name = "SPEED", allow_negative_numbers = true)]
    pub tow: Option<f32>,
}

impl ExportArgs {
    /// The interaction scenario asked for, checked; `None` when neither option is given.
    fn scenario(&self) -> Result<Option<Scenario>, ParamError> {
        let impulse = match self.impulse.as_deref() {
            None => None,
            Some(&[x, z]) if x.is_finite() && z.is_finite() => Some([x, z]),
            Some(v) => {
                let bad = v
                    .iter()
                    .find(|x| !x.is_finite())
                    .copied()
                    .unwrap_or(v.len() as f32);
                return Err(ParamError::new(
                    "impulse",
                    bad as f64,
                    "two finite numbers X,Z (m), e.g. --impulse 3,-2",
                ));
            }
        };
        let tow = match self.tow {
            None => None,
            Some(v) if v.is_finite() && v > 0.0 && v <= 10.0 => Some(v),
            Some(v) => {
                return Err(ParamError::new(
                    "tow",
                    v as f64,
                    "a speed > 0 and <= 10 (m/s)",
                ));
            }
        };
        if impulse.is_none() && tow.is_none() {
            return Ok(None);
        }
        if let Some(&t) = self.time.iter().find(|&&t| t < 0.0) {
            return Err(ParamError::new(
                "time",
                t,
                "times >= 0 (s) with --impulse or --tow: the layer starts calm at t = 0",
            ));
        }
        Ok(Some(Scenario { impulse, tow }))
    }
}

#[derive(Args)]
pub struct BenchArgs {
    /// Grid sides to measure.
    #[arg(long, value_delimiter = ',', default_values_t = [128, 256, 512])]
    pub sizes: Vec<u32>,
    /// Thread counts to measure.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 2])]
    pub threads: Vec<usize>,
    /// Timed repetitions per measurement.
    #[arg(long, default_value_t = 40)]
    pub iterations: usize,
    /// Patch size of each cascade (m); one cascade = four FFTs per step.
    #[arg(long, value_delimiter = ',', default_values_t = [250.0])]
    pub patch: Vec<f32>,
    /// Skip the rustfft/FFTW baselines (for thread-scaling runs: their buffers crowd the cache).
    #[arg(long)]
    pub skip_baselines: bool,
    /// SIMD tiers to measure, comma-separated: avx512, avx2, sse2, scalar (x86-64), neon
    /// (aarch64), or `all` (every tier this CPU has, fastest first). Each runs our FFT on that
    /// backend and the element-wise kernels at the matching width; sse2 is the 128-bit path
    /// nearest the headset's NEON.
    #[arg(long, alias = "tier", value_delimiter = ',', default_value = "all")]
    pub tiers: Vec<String>,
    /// Derivative modes to measure, comma-separated: spectral (4 FFTs per cascade), finite
    /// (central differences, 2 FFTs).
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [DerivativesArg::Spectral, DerivativesArg::Finite])]
    pub derivatives: Vec<DerivativesArg>,
}

pub fn simulate(a: SimulateArgs) -> CmdResult {
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
            // The foam the renderer draws: the whole surface's whitecap coverage around the
            // viewer (the fine level's mean), or, with whitecaps off, each cascade's own foam.
            // With whitecaps, also how far the surface's drift has carried the foam so far.
            let drifted = s.whitecaps.drift[0].hypot(s.whitecaps.drift[1]);
            let drift = if cfg.whitecaps {
                format!("  foam drifted {drifted:.2} m")
            } else {
                String::new()
            };
            let (foam_label, foam) = if cfg.whitecaps {
                ("whitecaps", f64::from(s.whitecaps.levels[0].mean))
            } else {
                let f = c0.normal_foam[..texels]
                    .iter()
                    .map(|p| ((p >> 16) & 0xff) as f64 / 255.0)
                    .sum::<f64>()
                    / n;
                ("foam (cascade)", f)
            };
            let m = s.max_displacement();
            println!(
                "t={t:6.2}s  step {:6.2} ms  Hs(coarsest)={:5.2} m  max |D|=({:.2}, {:.2}, {:.2}) m  {foam_label} {:4.1}%{drift}  h(0,0)={:+.3} m",
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

pub fn export_cmd(a: ExportArgs) -> CmdResult {
    let cfg = a.ocean.config()?;
    for &t in &a.time {
        if !t.is_finite() {
            return Err(ParamError::new("time", t, "finite times (s)").into());
        }
    }
    let scenario = a.scenario()?;
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
        // The whitecap coverage the renderer draws (the cascades' own foam above is eq. 51's).
        if cfg.whitecaps {
            written += export::write_whitecaps(&s.whitecaps, &a.out, &format!("t{t:.3}"))?.len();
        }
    }
    if let Some(scenario) = scenario {
        // The layer only runs forward: its times in order, each file named as asked.
        let mut times = a.time.clone();
        times.sort_by(f64::total_cmp);
        let config = InteractionConfig::default_with_dt(vr_ocean::physics::PHYSICS_DT)?;
        let mut run = ScenarioRun::new(config, scenario);
        for t in times {
            pool.install(|| run.advance_to(t));
            let at = run.scenario().centre_at(run.layer().time());
            written +=
                export::write_interaction(run.layer(), at, &a.out, &format!("t{t:.3}"))?.len();
        }
    }
    println!("wrote {written} files to {}", a.out.display());
    Ok(())
}

pub fn bench_cmd(a: BenchArgs) -> CmdResult {
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
    let tiers = bench_tiers(&a.tiers)?;
    let opts = BenchOptions {
        sizes,
        threads: a.threads,
        tiers,
        derivatives: a.derivatives.iter().map(|&d| d.into()).collect(),
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

pub fn lod_svg_cmd(a: LodSvgArgs) -> CmdResult {
    use vr_ocean::lod::{
        svg, FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, StereoFrustum,
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
    let preset = preset(a.preset);
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

/// The tiers `--tiers` names (`all` or empty: every tier this CPU has, fastest first).
fn bench_tiers(names: &[String]) -> Result<Vec<Backend>, Box<dyn std::error::Error>> {
    if names.is_empty() || names.iter().any(|n| n.trim().eq_ignore_ascii_case("all")) {
        return Ok(bench::all_tiers());
    }
    let mut tiers = Vec::new();
    for name in names {
        let tier = Backend::from_name(name).ok_or_else(|| {
            format!(
                "unknown SIMD tier '{name}' for --tiers: expected all, avx512, avx2, sse2, scalar \
                 or neon"
            )
        })?;
        if !tier.is_available() {
            return Err(UnavailableBackend {
                wanted: tier,
                available: Backend::available(),
            }
            .into());
        }
        if !tiers.contains(&tier) {
            tiers.push(tier);
        }
    }
    Ok(tiers)
}

/// The CPU's model name with its family and model numbers (`lscpu`'s), e.g.
/// "AMD EPYC (family 25 model 1)": virtual machines often report only the brand.
fn cpu_model() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |key: &str| {
        info.lines()
            .find(|l| l.split(':').next().is_some_and(|k| k.trim() == key))
            .and_then(|l| l.split(':').nth(1))
            .map(|v| v.trim().to_string())
    };
    let name = cpu_name();
    match (field("cpu family"), field("model")) {
        (Some(family), Some(model)) => format!("{name} (family {family} model {model})"),
        _ => name,
    }
}

fn cpu_name() -> String {
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
