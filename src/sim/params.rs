//! Ocean parameters in physical units, validated once into types the pipeline trusts.

use crate::base::ParamError;
use crate::sim::grid::GridSize;
use crate::sim::spectrum::{cascade_bands, CascadeSpec, MAX_OCTAVE};

/// Standard gravity (m/s²).
pub const GRAVITY: f32 = 9.81;

/// Most cascades a simulation may run (issue: 1 to 4).
pub const MAX_CASCADES: usize = 4;

/// Which directional wave spectrum seeds the amplitudes (thesis 3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpectrumKind {
    /// Phillips spectrum with the thesis's normalization (eq. 3-5); `amplitude` scales it.
    Phillips {
        /// Dimensionless multiplier on A of eq. 4 (1 = the thesis's value).
        amplitude: f32,
    },
    /// JONSWAP fetch-limited spectrum in physical units: variance in m², Hs = 4σ.
    Jonswap {
        /// Peak enhancement factor γ (3.3 for a typical North Sea sea state).
        gamma: f32,
        /// Fetch, the distance over which the wind has blown (km).
        fetch_km: f32,
    },
}

/// Persistent foam: accumulates where the Jacobian J falls below `threshold`, decays over time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoamParams {
    /// Jacobian below which the surface is breaking (eq. 48; 0 = exact fold; up to 1).
    pub threshold: f32,
    /// Foam added per second per unit of (threshold − J).
    pub growth: f32,
    /// Exponential decay rate (1/s): foam halves every ln2/decay seconds.
    pub decay: f32,
}

impl Default for FoamParams {
    fn default() -> Self {
        Self {
            threshold: 0.3,
            growth: 4.0,
            decay: 0.6,
        }
    }
}

/// Everything that shapes the waves; shared by all cascades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveParams {
    /// Spectrum model.
    pub spectrum: SpectrumKind,
    /// Wind speed at 10 m (m/s), V of eq. 3.
    pub wind_speed: f32,
    /// Direction the wind blows toward, degrees from +x toward +z.
    pub wind_direction_deg: f32,
    /// Directional alignment α ∈ [0, 1] (eq. 6, 8) of the Phillips spectrum: 0 spreads widely,
    /// 1 follows the wind. The JONSWAP sea's spread depends on the frequency instead
    /// ([`crate::sim::spectrum::spreading`]).
    pub alignment: f32,
    /// Water depth (m) for the finite-depth dispersion ω² = gk·tanh(kd); `None` = deep water.
    pub depth: Option<f32>,
    /// Small-wave suppression strength β ∈ [0, 1] (eq. 10-11).
    pub small_wave_suppression: f32,
    /// Choppiness λ ∈ [0, 2] (eq. 25, 44).
    pub choppiness: f32,
    /// Loop period T (s) of the quantized dispersion (eq. 16).
    pub loop_period: f32,
    /// Material roughness r ∈ [0, 1] mapped to normal length (eq. 49).
    pub roughness: f32,
    /// Foam dynamics.
    pub foam: FoamParams,
    /// Random seed: equal seeds give bit-identical spectra on every platform and thread count.
    pub seed: u64,
}

/// The default fetch (km): open ocean, where a 10 m/s wind is fully developed and a gale still
/// grows (issue 14: the sea a sailor would see).
pub const DEFAULT_FETCH_KM: f32 = 300.0;

/// The default JONSWAP peak enhancement (the JONSWAP mean).
pub const DEFAULT_GAMMA: f32 = 3.3;

impl Default for WaveParams {
    fn default() -> Self {
        Self {
            spectrum: SpectrumKind::Jonswap {
                gamma: DEFAULT_GAMMA,
                fetch_km: DEFAULT_FETCH_KM,
            },
            wind_speed: 10.0,
            wind_direction_deg: 0.0,
            alignment: 0.8,
            depth: None,
            small_wave_suppression: 0.2,
            choppiness: 0.9,
            loop_period: 200.0,
            roughness: 0.1,
            foam: FoamParams::default(),
            seed: 1,
        }
    }
}

/// Peak wavelengths the coarsest patch holds when it grows with the wind: at two, its
/// fundamental sits at half the peak wave number (ω ≈ 0.7 ω_p, where JONSWAP has e⁻⁵ of its
/// peak density) and the energetic range is sampled by several modes.
pub const PEAK_WAVELENGTHS_PER_PATCH: f32 = 2.5;

/// How the coarsest cascade's patch follows the waves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PatchFit {
    /// The patch sizes exactly as given.
    Fixed,
    /// The coarsest patch holds at least [`PEAK_WAVELENGTHS_PER_PATCH`] peak wavelengths of
    /// the wind sea, `min_coarsest` (m) doubled as often as that needs (at most
    /// [`MAX_OCTAVE`] times): a gale's 200 m waves fit in it, a breeze keeps the default tiling.
    GrowWithWind {
        /// The coarsest patch for light winds (m).
        min_coarsest: f32,
    },
}

/// How the surface stage gets the slopes and the Jacobian of the displaced surface.
///
/// Spectral derivatives are exact for every wave the grid holds but cost eight real fields,
/// four complex FFTs per cascade (thesis eq. 47-48 taken in the spectrum); central differences
/// of the displacement (eq. 45-46) need only h, Dx and Dz, two FFTs, and respond to a wave of
/// wave number k with sin(kΔ)/(kΔ) of its slope (Δ = L/N): the finest waves of each cascade
/// come out flatter. `docs/notes/fft-128bit.md` measures both.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Derivatives {
    /// ∂/∂x = i·kₓ in the spectrum: 8 real fields, 4 complex FFTs per cascade.
    Spectral,
    /// Central differences of h, Dx, Dz on the grid: 3 real fields, 2 complex FFTs.
    Finite,
}

impl std::fmt::Display for Derivatives {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Derivatives::Spectral => "spectral",
            Derivatives::Finite => "finite",
        })
    }
}

/// The derivative mode [`OceanConfig`]'s constructors pick: central differences on the
/// headset (Android), where the CPU is the budget (the step costs 0.76x the spectral one at
/// N = 256 on the 128-bit SSE2 path, and the finest cascade's lost slope returns as
/// roughness), spectral derivatives on desktops (exact, and cheap enough there). Measured in
/// `docs/notes/fft-128bit.md`.
#[cfg(target_os = "android")]
pub const DEFAULT_DERIVATIVES: Derivatives = Derivatives::Finite;
/// See the Android definition above.
#[cfg(not(target_os = "android"))]
pub const DEFAULT_DERIVATIVES: Derivatives = Derivatives::Spectral;

/// A complete simulation configuration: grid, cascade patch sizes, waves.
#[derive(Clone, Debug, PartialEq)]
pub struct OceanConfig {
    /// FFT grid side shared by every cascade.
    pub grid: GridSize,
    /// Patch size L (m) of each cascade, coarsest first; 1 to 4 entries, strictly decreasing.
    pub patch_sizes: Vec<f32>,
    /// Whether the coarsest patch follows the wind ([`OceanConfig::fit_patches`]).
    pub patch_fit: PatchFit,
    /// Wave conditions.
    pub waves: WaveParams,
    /// Whether each step computes the whitecaps of the whole surface
    /// ([`crate::sim::whitecaps`], a few ms of one core a step); off, they stay empty.
    pub whitecaps: bool,
    /// How slopes and the Jacobian are taken ([`Derivatives`]).
    pub derivatives: Derivatives,
}

/// The default cascades' patch sizes (m), coarsest first: non-integer ratios (≈3.7, ≈4.3) so
/// their tilings never align.
pub const DEFAULT_PATCH_SIZES: [f32; 3] = [257.0, 69.5, 16.1];

impl OceanConfig {
    /// One cascade of side `patch` metres on an `n`-grid with default waves.
    pub fn single(n: u32, patch: f32) -> Result<Self, ParamError> {
        let cfg = Self {
            grid: GridSize::new(n)?,
            patch_sizes: vec![patch],
            patch_fit: PatchFit::Fixed,
            waves: WaveParams::default(),
            whitecaps: true,
            derivatives: DEFAULT_DERIVATIVES,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    /// The default three cascades ([`DEFAULT_PATCH_SIZES`]), the coarsest growing with the
    /// wind ([`PatchFit::GrowWithWind`]).
    pub fn default_cascades(n: u32) -> Result<Self, ParamError> {
        let mut cfg = Self {
            grid: GridSize::new(n)?,
            patch_sizes: DEFAULT_PATCH_SIZES.to_vec(),
            patch_fit: PatchFit::GrowWithWind {
                min_coarsest: DEFAULT_PATCH_SIZES[0],
            },
            waves: WaveParams::default(),
            whitecaps: true,
            derivatives: DEFAULT_DERIVATIVES,
        };
        cfg.fit_patches();
        cfg.validate()?;
        Ok(cfg)
    }

    /// Applies [`OceanConfig::patch_fit`] to the current waves: sets the coarsest patch and
    /// returns true if it changed. The coarsest patch grows by whole octaves (`min_coarsest`
    /// times 2, 4, ...; at most [`MAX_OCTAVE`]): every wave a patch holds is then a wave of
    /// the next octave's grid too, so a sea-state change can hand it over without a pop
    /// ([`crate::sim::spectrum::modes`]).
    pub fn fit_patches(&mut self) -> bool {
        let PatchFit::GrowWithWind { min_coarsest } = self.patch_fit else {
            return false;
        };
        let fitted = PEAK_WAVELENGTHS_PER_PATCH * self.waves.peak_wavelength() as f32;
        let mut wanted = min_coarsest;
        for _ in 0..MAX_OCTAVE {
            if wanted >= fitted {
                break;
            }
            wanted *= 2.0;
        }
        let changed = self.patch_sizes.first() != Some(&wanted);
        if let Some(first) = self.patch_sizes.first_mut() {
            *first = wanted;
        }
        changed
    }

    /// Every cascade's [`CascadeSpec`]: patch, band ([`cascade_bands`]) and octave (how often
    /// a growing coarsest patch has doubled; 0 for every fixed patch).
    pub fn cascade_specs(&self) -> Vec<CascadeSpec> {
        let bands = cascade_bands(&self.patch_sizes, self.grid);
        self.patch_sizes
            .iter()
            .zip(bands)
            .enumerate()
            .map(|(i, (&patch, band))| {
                let octave = match self.patch_fit {
                    PatchFit::GrowWithWind { min_coarsest } if i == 0 => (patch / min_coarsest)
                        .log2()
                        .round()
                        .clamp(0.0, MAX_OCTAVE as f32)
                        as u32,
                    _ => 0,
                };
                CascadeSpec {
                    index: i as u32,
                    patch,
                    band,
                    grid: self.grid,
                    octave,
                }
            })
            .collect()
    }

    /// Checks every parameter; the first violation is returned naming it and its valid range.
    pub fn validate(&self) -> Result<(), ParamError> {
        if self.patch_sizes.is_empty() || self.patch_sizes.len() > MAX_CASCADES {
            return Err(ParamError::new(
                "cascades",
                self.patch_sizes.len() as f64,
                "1 to 4 cascades",
            ));
        }
        for &l in &self.patch_sizes {
            positive("patch", l, "a finite patch size > 0 and <= 100000 (m)")?;
            if l > 100_000.0 {
                return Err(ParamError::new(
                    "patch",
                    l as f64,
                    "a finite patch size > 0 and <= 100000 (m)",
                ));
            }
        }
        for w in self.patch_sizes.windows(2) {
            if w[1] >= w[0] {
                return Err(ParamError::new(
                    "patch",
                    w[1] as f64,
                    "cascade patch sizes strictly decreasing (coarsest first)",
                ));
            }
        }
        self.waves.validate()
    }
}

impl OceanConfig {
    /// Pairs of cascades whose patch ratio is within 2% of an integer: their tilings line up
    /// every few repeats, which the non-integer ratios are there to avoid (valid, but worth a
    /// warning).
    pub fn aligned_cascades(&self) -> impl Iterator<Item = (usize, f32)> + '_ {
        self.patch_sizes
            .windows(2)
            .enumerate()
            .filter_map(|(i, w)| {
                let ratio = w[0] / w[1];
                ((ratio - ratio.round()).abs() < 0.02 * ratio).then_some((i, ratio))
            })
    }
}

impl WaveParams {
    /// Deep-water wavelength (m) of the spectrum's energy peak: JONSWAP's 2πg/ω_p² (of the
    /// normalised sea, [`crate::sim::spectrum::jonswap::JonswapSea`]), or for Phillips the
    /// maximum of its k·P(k), k = √(2/3)·g/V².
    pub fn peak_wavelength(&self) -> f64 {
        let g = GRAVITY as f64;
        let u = self.wind_speed as f64;
        match self.spectrum {
            SpectrumKind::Jonswap { fetch_km, .. } => {
                crate::sim::spectrum::jonswap::peak_wavelength(
                    self.wind_speed,
                    fetch_km as f64 * 1000.0,
                )
            }
            SpectrumKind::Phillips { .. } => {
                std::f64::consts::TAU / ((2.0f64 / 3.0).sqrt() * g / (u * u))
            }
        }
    }

    /// The unit direction (x, z) the wind blows toward.
    pub fn toward(&self) -> [f32; 2] {
        let a = self.wind_direction_deg.to_radians();
        [a.cos(), a.sin()]
    }

    /// Checks every field; see [`OceanConfig::validate`].
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("wind", self.wind_speed, "a finite wind speed > 0 (m/s)")?;
        if self.wind_speed > 60.0 {
            return Err(ParamError::new(
                "wind",
                self.wind_speed as f64,
                "a finite wind speed > 0 and <= 60 (m/s)",
            ));
        }
        finite(
            "wind-direction",
            self.wind_direction_deg,
            "a finite angle (degrees)",
        )?;
        unit("alignment", self.alignment, "a number in [0, 1]")?;
        if let Some(d) = self.depth {
            positive("depth", d, "a finite depth > 0 (m), or deep water")?;
        }
        unit(
            "suppression",
            self.small_wave_suppression,
            "a number in [0, 1]",
        )?;
        in_range(
            "choppiness",
            self.choppiness,
            0.0,
            2.0,
            "a number in [0, 2]",
        )?;
        positive("loop-period", self.loop_period, "a finite period > 0 (s)")?;
        unit("roughness", self.roughness, "a number in [0, 1]")?;
        unit("foam-threshold", self.foam.threshold, "a number in [0, 1]")?;
        in_range(
            "foam-growth",
            self.foam.growth,
            0.0,
            1000.0,
            "a number in [0, 1000] (1/s)",
        )?;
        in_range(
            "foam-decay",
            self.foam.decay,
            0.0,
            1000.0,
            "a number in [0, 1000] (1/s)",
        )?;
        match self.spectrum {
            SpectrumKind::Phillips { amplitude } => {
                positive("amplitude", amplitude, "a finite amplitude > 0")?;
            }
            SpectrumKind::Jonswap { gamma, fetch_km } => {
                in_range("gamma", gamma, 1.0, 10.0, "a number in [1, 10]")?;
                positive("fetch", fetch_km, "a finite fetch > 0 (km)")?;
                if fetch_km > 10_000.0 {
                    return Err(ParamError::new(
                        "fetch",
                        fetch_km as f64,
                        "a finite fetch > 0 and <= 10000 (km)",
                    ));
                }
            }
        }
        Ok(())
    }
}

fn finite(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ParamError::new(name, v as f64, valid))
    }
}

fn positive(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(name, v as f64, valid))
    }
}

fn in_range(
    name: &'static str,
    v: f32,
    lo: f32,
    hi: f32,
    valid: &'static str,
) -> Result<(), ParamError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(ParamError::new(name, v as f64, valid))
    }
}

fn unit(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    in_range(name, v, 0.0, 1.0, valid)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rejects(mut f: impl FnMut(&mut OceanConfig), name: &str) {
        let mut c = OceanConfig::default_cascades(64).unwrap();
        f(&mut c);
        let e = c.validate().expect_err(name);
        assert_eq!(e.parameter, name, "{e}");
        assert!(e.to_string().contains(name));
    }

    #[test]
    fn defaults_are_valid() {
        let c = OceanConfig::default_cascades(256).unwrap();
        assert_eq!(c.aligned_cascades().count(), 0);
        OceanConfig::single(16, 10.0).unwrap();
    }

    #[test]
    fn integer_cascade_ratios_are_flagged() {
        let mut c = OceanConfig::default_cascades(64).unwrap();
        c.patch_sizes = vec![400.0, 100.0, 35.0];
        let flagged: Vec<usize> = c.aligned_cascades().map(|(i, _)| i).collect();
        assert_eq!(flagged, vec![0]);
    }

    #[test]
    fn bad_values_name_the_parameter() {
        rejects(|c| c.waves.wind_speed = 0.0, "wind");
        rejects(|c| c.waves.wind_speed = -3.0, "wind");
        rejects(|c| c.waves.wind_speed = f32::NAN, "wind");
        rejects(|c| c.waves.depth = Some(0.0), "depth");
        rejects(|c| c.waves.depth = Some(-5.0), "depth");
        rejects(|c| c.waves.depth = Some(f32::NAN), "depth");
        rejects(|c| c.waves.choppiness = -0.1, "choppiness");
        rejects(|c| c.waves.choppiness = f32::NAN, "choppiness");
        rejects(|c| c.patch_sizes[0] = -1.0, "patch");
        rejects(|c| c.patch_sizes[1] = f32::INFINITY, "patch");
        rejects(|c| c.patch_sizes = vec![10.0, 20.0], "patch");
        rejects(|c| c.patch_sizes = vec![], "cascades");
        rejects(
            |c| c.patch_sizes = vec![50.0, 40.0, 30.0, 20.0, 10.0],
            "cascades",
        );
        rejects(|c| c.waves.alignment = 1.5, "alignment");
        rejects(|c| c.waves.loop_period = 0.0, "loop-period");
        rejects(|c| c.waves.wind_direction_deg = f32::NAN, "wind-direction");
        rejects(
            |c| {
                c.waves.spectrum = SpectrumKind::Jonswap {
                    gamma: 3.3,
                    fetch_km: f32::NAN,
                }
            },
            "fetch",
        );
        rejects(
            |c| c.waves.spectrum = SpectrumKind::Phillips { amplitude: 0.0 },
            "amplitude",
        );
    }
}
