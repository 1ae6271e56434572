//! Ocean parameters in physical units, validated once into types the pipeline trusts.

use crate::base::ParamError;
use crate::sim::dispersion::GRAVITY;

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

/// The derivative mode [`OceanConfig`](crate::sim::OceanConfig)'s constructors pick: central
/// differences on the headset (Android), where the CPU is the budget (the step costs 0.76x the
/// spectral one at N = 256 on the 128-bit SSE2 path, and the finest cascade's lost slope
/// returns as roughness), spectral derivatives on desktops (exact, and cheap enough there).
/// Measured in `docs/notes/fft-128bit.md`.
#[cfg(target_os = "android")]
pub const DEFAULT_DERIVATIVES: Derivatives = Derivatives::Finite;
/// See the Android definition above.
#[cfg(not(target_os = "android"))]
pub const DEFAULT_DERIVATIVES: Derivatives = Derivatives::Spectral;

/// A sea state that passed [`WaveParams::validate`]: made once where a value enters (a flag,
/// the panel, the kept settings, a key), and the only thing a running simulation takes, so no
/// layer below checks it again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeaState(WaveParams);

impl SeaState {
    /// Checks `waves`; the error names the first parameter out of range.
    pub fn new(waves: WaveParams) -> Result<Self, ParamError> {
        waves.validate()?;
        Ok(Self(waves))
    }

    /// The waves.
    pub fn waves(&self) -> &WaveParams {
        &self.0
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

    /// Checks every field; see [`OceanConfig::validate`](crate::sim::OceanConfig::validate).
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

pub(crate) fn finite(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ParamError::new(name, v as f64, valid))
    }
}

pub(crate) fn positive(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(name, v as f64, valid))
    }
}

pub(crate) fn in_range(
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

pub(crate) fn unit(name: &'static str, v: f32, valid: &'static str) -> Result<(), ParamError> {
    in_range(name, v, 0.0, 1.0, valid)
}
