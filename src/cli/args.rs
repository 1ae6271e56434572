//! Arguments shared by several commands: the ocean (every command that simulates), the view
//! (window, headless, xr) and the quality preset.

use clap::{Args, ValueEnum};

use super::given::Given;

use vr_ocean::app::{self as app, GovernorOptions, GpuFault, RunOptions, SoundOptions, SoundSink};
use vr_ocean::base::ParamError;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::physics::{BodyCount, PhysicsError};
use vr_ocean::render::ocean::{default_sun, Anisotropy};
use vr_ocean::render::sky::SunSky;
use vr_ocean::render::{
    ContextOptions, GpuContext, Msaa, RendererSettings, StereoMode, Validation,
};
use vr_ocean::sim::interaction::InteractionConfig;
use vr_ocean::sim::{
    Derivatives, FoamParams, GridSize, OceanConfig, PatchFit, SpectrumKind, WaveParams,
    DEFAULT_DERIVATIVES, DEFAULT_FETCH_KM, DEFAULT_GAMMA, DEFAULT_PATCH_SIZES,
};

#[derive(Clone, Copy, ValueEnum)]
pub enum PresetArg {
    Low,
    Medium,
    High,
    Ultra,
}

impl From<QualityPreset> for PresetArg {
    fn from(p: QualityPreset) -> Self {
        match p {
            QualityPreset::Low => PresetArg::Low,
            QualityPreset::Medium => PresetArg::Medium,
            QualityPreset::High => PresetArg::High,
            QualityPreset::Ultra => PresetArg::Ultra,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum SpectrumArg {
    Phillips,
    Jonswap,
}

/// How the surface's slopes and Jacobian are taken (`vr_ocean::sim::Derivatives`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DerivativesArg {
    /// In the spectrum: exact, four FFTs per cascade.
    Spectral,
    /// Central differences of the displacement: two FFTs per cascade.
    Finite,
}

impl DerivativesArg {
    /// The CLI default: the simulation's ([`DEFAULT_DERIVATIVES`]).
    fn default_arg() -> DerivativesArg {
        match DEFAULT_DERIVATIVES {
            Derivatives::Spectral => DerivativesArg::Spectral,
            Derivatives::Finite => DerivativesArg::Finite,
        }
    }
}

impl From<DerivativesArg> for Derivatives {
    fn from(d: DerivativesArg) -> Derivatives {
        match d {
            DerivativesArg::Spectral => Derivatives::Spectral,
            DerivativesArg::Finite => Derivatives::Finite,
        }
    }
}

/// Ocean parameters shared by every command.
#[derive(Args, Clone)]
pub struct OceanArgs {
    /// FFT grid side: a power of two from 16 to 1024.
    #[arg(long, allow_negative_numbers = true, default_value_t = 256)]
    pub grid: u32,
    /// Slopes and Jacobian from spectral derivatives (4 FFTs per cascade) or central
    /// differences of the displacement (2 FFTs; slightly flatter finest waves).
    #[arg(long, value_enum, default_value_t = DerivativesArg::default_arg())]
    pub derivatives: DerivativesArg,
    /// Patch size of each cascade in metres, coarsest first (1 to 4, comma-separated). Default:
    /// 257,69.5,16.1 with the coarsest growing to 2.5 peak wavelengths in strong wind.
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',')]
    pub patch: Vec<f32>,
    /// Wind speed at 10 m (m/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 10.0)]
    pub wind: f32,
    /// Wind direction (degrees from +x toward +z).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub wind_dir: f32,
    /// Directional alignment α in [0, 1] of the Phillips spectrum (the thesis's spread; the
    /// JONSWAP sea spreads by frequency, narrow at its peak and wide above, after Hasselmann).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.8)]
    pub alignment: f32,
    /// Choppiness λ in [0, 2].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.9)]
    pub choppiness: f32,
    /// Water depth (m); deep water when omitted.
    #[arg(long, allow_negative_numbers = true)]
    pub depth: Option<f32>,
    /// Wave spectrum.
    #[arg(long, value_enum, default_value_t = SpectrumArg::Jonswap)]
    pub spectrum: SpectrumArg,
    /// Phillips amplitude multiplier.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub amplitude: f32,
    /// JONSWAP peak enhancement γ.
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_GAMMA)]
    pub gamma: f32,
    /// JONSWAP fetch (km): how far the wind has blown over open water.
    #[arg(long, allow_negative_numbers = true, default_value_t = DEFAULT_FETCH_KM)]
    pub fetch: f32,
    /// Small-wave suppression β in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.2)]
    pub suppression: f32,
    /// Loop period T (s): the animation repeats exactly after T.
    #[arg(long, allow_negative_numbers = true, default_value_t = 200.0)]
    pub loop_period: f32,
    /// Material roughness in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.1)]
    pub roughness: f32,
    /// Random seed.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Jacobian below which foam forms.
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().threshold)]
    pub foam_threshold: f32,
    /// Foam growth rate (1/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().growth)]
    pub foam_growth: f32,
    /// Foam decay rate (1/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = FoamParams::default().decay)]
    pub foam_decay: f32,
}

impl OceanArgs {
    pub fn config(&self) -> Result<OceanConfig, ParamError> {
        let spectrum = match self.spectrum {
            SpectrumArg::Phillips => SpectrumKind::Phillips {
                amplitude: self.amplitude,
            },
            SpectrumArg::Jonswap => SpectrumKind::Jonswap {
                gamma: self.gamma,
                fetch_km: self.fetch,
            },
        };
        let (patch_sizes, patch_fit) = if self.patch.is_empty() {
            (
                DEFAULT_PATCH_SIZES.to_vec(),
                PatchFit::GrowWithWind {
                    min_coarsest: DEFAULT_PATCH_SIZES[0],
                },
            )
        } else {
            (self.patch.clone(), PatchFit::Fixed)
        };
        let mut cfg = OceanConfig {
            grid: GridSize::new(self.grid)?,
            patch_sizes,
            patch_fit,
            whitecaps: true,
            derivatives: self.derivatives.into(),
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
        cfg.fit_patches();
        Ok(cfg)
    }
}

/// Settings of the renderer and LOD shared by the headless and window modes.
#[derive(Args, Clone)]
pub struct ViewArgs {
    #[command(flatten)]
    pub ocean: OceanArgs,
    /// Which of this command's flags the command line gave ([`Given`]); filled in by
    /// [`super::parse`].
    #[arg(skip)]
    pub given: Given,
    /// Quality preset (thesis Table 2).
    #[arg(long, value_enum, default_value_t = PresetArg::High)]
    pub preset: PresetArg,
    /// Ocean size S (m) the quadtree covers, 256 to 8192; the skirt reaches 10 S.
    #[arg(long, allow_negative_numbers = true, default_value_t = 2048.0)]
    pub ocean_size: f32,
    /// How both eyes are drawn [default: multiview; in the window and headless on a CPU Vulkan
    /// device (lavapipe), two-pass: Mesa 22.3's lavapipe writes the second view's clipped
    /// triangles, such as the deck under you, into the first view's image].
    #[arg(long, value_enum)]
    pub stereo: Option<StereoArg>,
    /// Simulation worker threads.
    #[arg(long, default_value_t = default_threads())]
    pub threads: usize,
    /// Load the Khronos validation layer (fails if it is not installed).
    #[arg(long)]
    pub validation: bool,
    /// Multisample anti-aliasing: samples per pixel (1, 2 or 4) [default: 4 on a GPU, 1 on a
    /// CPU Vulkan device (lavapipe), which rasterizes every sample].
    #[arg(long)]
    pub msaa: Option<u32>,
    /// Specular anti-aliasing: slopes a pixel cannot show widen the sun's highlight instead of
    /// sparkling.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub specular_aa: OnOff,
    /// The specular AA's supersampling of the highlight where the waves' finest cascade is
    /// minified (four shading positions per pixel there, 1.3-1.5x the pass): a quality option
    /// for a desktop GPU with headroom; the headsets filter the lobe instead (off).
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub supersampling: OnOff,
    /// Anisotropic filtering of the waves' normal maps: most taps along a pixel's footprint
    /// (1 = off, 2, 4, 8 or 16; at most what the device has) [default: 4 on a GPU, 1 on a CPU
    /// Vulkan device (lavapipe), which filters every tap in software].
    #[arg(long)]
    pub anisotropy: Option<u32>,
    /// Floating bodies (buoys, crates, a small boat) spawned on the water around the deck,
    /// 0 to 64 (0 = none).
    #[arg(long, default_value_t = DEFAULT_BODIES)]
    pub bodies: usize,
    /// The interaction layer: splashes, rings and wakes from the bodies and hands, sized by
    /// the preset (256² cells of 0.16 m from high up, 128² at medium and low).
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub interaction: OnOff,
    /// Sun elevation above the horizon (degrees, -10 to 90; below 0 is twilight) [default:
    /// 17.5, a late-afternoon sun].
    #[arg(long, allow_negative_numbers = true)]
    pub sun_elevation: Option<f32>,
    /// Sun azimuth (degrees from +x toward +z; the view starts looking along -z, i.e. -90)
    /// [default: -61.8, ahead and to the right].
    #[arg(long, allow_negative_numbers = true)]
    pub sun_azimuth: Option<f32>,
    /// Atmospheric turbidity (1.7 very clear to 10 hazy; 2-3 clear maritime air) [default: 2.5].
    #[arg(long, allow_negative_numbers = true)]
    pub turbidity: Option<f32>,
    /// Share of the sky covered by cloud (0 clear to 1 overcast; baked into the sky the sea
    /// reflects) [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub clouds: Option<f32>,
    /// GPU-time governor: steps quality down (supersampling, foveation, render scale, LOD
    /// preset) when the GPU pass exceeds 0.8 of the budget, back up with headroom [default:
    /// on for xr; off for window and headless, where a CPU Vulkan device is over any budget].
    #[arg(long, value_enum)]
    pub gpu_governor: Option<OnOff>,
    /// The governor's GPU budget per frame (ms, 0.1 to 1000) [default: the frame period].
    #[arg(long, allow_negative_numbers = true)]
    pub gpu_budget_ms: Option<f64>,
    /// Test fault MS@FROM-TO: adds MS ms to the measured GPU pass time of frames shown from
    /// FROM to TO s (an injected measurement, not GPU work), so the governor steps down and,
    /// once it ends, back up.
    #[arg(long, value_name = "MS@FROM-TO", value_parser = GpuFault::parse)]
    pub fault_gpu_ms: Option<GpuFault>,
    /// Sound from the sea (wind, swell, wash, whitecaps, splashes) on the audio device; with
    /// no device, one warning and a silent run [default: on for window and xr, off for
    /// headless, which writes it with --audio-out].
    #[arg(long, value_enum)]
    pub audio: Option<OnOff>,
    /// Master volume of the sound, 0 (silent) to 1 (full).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub volume: f32,
    /// Forget the kept settings (wind, preset, sun, sound) before starting; window and xr
    /// start from them otherwise, where no flag says otherwise, and keep what the run ended
    /// with (in $XDG_CONFIG_HOME/vr-ocean/settings.json).
    #[arg(long)]
    pub reset_settings: bool,
}

/// `--bodies` when not given.
pub const DEFAULT_BODIES: usize = BodyCount::DEFAULT.get();

/// A switch on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum StereoArg {
    Multiview,
    TwoPass,
}

impl ViewArgs {
    pub fn run_options(&self, capture: Vec<u64>, warmup: u64) -> Result<RunOptions, ParamError> {
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
                    None | Some(StereoArg::Multiview) => StereoMode::Multiview,
                    Some(StereoArg::TwoPass) => StereoMode::TwoPass,
                },
                msaa: match self.msaa {
                    None => Msaa::X4,
                    Some(n) => Msaa::from_samples(n).ok_or(ParamError::new(
                        "msaa",
                        n as f64,
                        "1, 2 or 4 samples per pixel",
                    ))?,
                },
                specular_aa: self.specular_aa == OnOff::On,
                supersampling: self.supersampling == OnOff::On,
                anisotropy: match self.anisotropy {
                    None => Anisotropy::X4,
                    Some(n) => Anisotropy::from_taps(n).ok_or(ParamError::new(
                        "anisotropy",
                        n as f64,
                        "1 (off), 2, 4, 8 or 16 taps",
                    ))?,
                },
                sun: self.sun()?,
                ..RendererSettings::default()
            },
            capture,
            warmup,
            floating: None,
            governor: self.governor(false)?,
            audio: self.sound(false)?,
            panel_open: false,
            comfort: Default::default(),
        })
    }

    /// The sound's options: on the audio device unless `--audio off` when `default_on`, else
    /// only with `--audio on`.
    pub fn sound(&self, default_on: bool) -> Result<SoundOptions, ParamError> {
        if !(0.0..=1.0).contains(&self.volume) {
            return Err(ParamError::new(
                "volume",
                self.volume as f64,
                "0 (silent) to 1 (full)",
            ));
        }
        let on = self.audio.map_or(default_on, |a| a == OnOff::On);
        Ok(SoundOptions {
            sink: if on {
                SoundSink::Device
            } else {
                SoundSink::Off
            },
            volume: self.volume,
            seed: self.ocean.seed,
        })
    }

    /// The GPU-time governor's options; on unless `--gpu-governor off` when `default_on`,
    /// else only with `--gpu-governor on`. A fault needs the governor on (only it reads the
    /// faulted time).
    pub fn governor(&self, default_on: bool) -> Result<GovernorOptions, ParamError> {
        let enabled = self.gpu_governor.map_or(default_on, |g| g == OnOff::On);
        let budget = match self.gpu_budget_ms {
            None => None,
            Some(ms) if ms.is_finite() && (0.1..=1000.0).contains(&ms) => {
                Some(std::time::Duration::from_secs_f64(ms * 1e-3))
            }
            Some(ms) => {
                return Err(ParamError::new(
                    "gpu-budget-ms",
                    ms,
                    "milliseconds in [0.1, 1000]",
                ))
            }
        };
        if let (false, Some(f)) = (enabled, self.fault_gpu_ms) {
            return Err(ParamError::new(
                "fault-gpu-ms",
                f.extra.as_secs_f64() * 1e3,
                "a fault only with the GPU-time governor on (--gpu-governor on)",
            ));
        }
        Ok(GovernorOptions {
            enabled,
            budget,
            fault: self.fault_gpu_ms,
        })
    }

    /// The sun and the air the options ask for, validated (the error names the flag).
    pub fn sun(&self) -> Result<SunSky, ParamError> {
        let d = default_sun();
        let sun = SunSky {
            elevation_deg: self.sun_elevation.unwrap_or(d.elevation_deg),
            azimuth_deg: self.sun_azimuth.unwrap_or(d.azimuth_deg),
            turbidity: self.turbidity.unwrap_or(d.turbidity),
            clouds: self.clouds.unwrap_or(d.clouds),
        };
        sun.validate()?;
        Ok(sun)
    }

    /// The desktop views' stereo mode on `gpu`: as asked, else multiview, or two passes on a
    /// CPU Vulkan device, whose multiview (Mesa 22.3's lavapipe) draws the second eye's clipped
    /// triangles into the first eye's layer (the deck under the viewer shows twice).
    pub fn resolve_desktop_stereo(&self, opts: &mut RunOptions, gpu: &GpuContext) {
        if self.stereo.is_none() && gpu.cpu_device {
            opts.renderer.stereo = StereoMode::TwoPass;
        }
    }

    /// The MSAA to use on `gpu`: as asked, else 4, or 1 on a CPU Vulkan device (lavapipe
    /// rasterizes every sample, so 4 cost it about 4×; a tile-based GPU resolves on chip);
    /// likewise the anisotropy (as asked, else 4, or off on a CPU device).
    pub fn resolve_msaa(&self, opts: &mut RunOptions, gpu: &GpuContext) {
        if self.msaa.is_none() && gpu.cpu_device {
            opts.renderer.msaa = Msaa::X1;
        }
        if self.anisotropy.is_none() && gpu.cpu_device {
            opts.renderer.anisotropy = Anisotropy::Off;
        }
    }

    /// `--bodies` checked against the physics' limit: "--bodies 65: at most 64 floating
    /// bodies (0 = none)".
    pub fn bodies(&self) -> Result<BodyCount, PhysicsError> {
        BodyCount::new(self.bodies)
    }

    /// The interaction layer `--interaction` and `--preset` ask for.
    pub fn interaction(&self) -> Option<InteractionConfig> {
        (self.interaction == OnOff::On).then(|| app::interaction_for(preset(self.preset)))
    }

    pub fn context(&self) -> ContextOptions {
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

pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The library's preset for a `--preset` value.
pub fn preset(p: PresetArg) -> QualityPreset {
    match p {
        PresetArg::Low => QualityPreset::Low,
        PresetArg::Medium => QualityPreset::Medium,
        PresetArg::High => QualityPreset::High,
        PresetArg::Ultra => QualityPreset::Ultra,
    }
}
