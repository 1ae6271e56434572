//! The whole simulation's configuration ([`OceanConfig`]): the grid, the cascades' patches and
//! how the coarsest follows the wind, and the waves ([`crate::sim::params`]), validated once.
//! It sits above the spectrum: it asks it for each cascade's band.

use crate::base::ParamError;
use crate::sim::grid::GridSize;
use crate::sim::params::{positive, Derivatives, SeaState, WaveParams, DEFAULT_DERIVATIVES};
use crate::sim::spectrum::{cascade_bands, CascadeSpec, MAX_OCTAVE};

/// Most cascades a simulation may run (issue: 1 to 4).
pub const MAX_CASCADES: usize = 4;

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

    /// This configuration with the waves of `sea`, the coarsest patch refitted to them
    /// ([`OceanConfig::fit_patches`]) and checked; the flag says whether the patch changed.
    pub fn with_sea(&self, sea: SeaState) -> Result<(Self, bool), ParamError> {
        let mut config = Self {
            waves: *sea.waves(),
            ..self.clone()
        };
        let refit = config.fit_patches();
        config.validate()?;
        Ok((config, refit))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::SpectrumKind;

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
