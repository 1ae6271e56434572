//! Anisotropic filtering of the cascades' normal maps (issue 29, item 5).
//!
//! Toward the horizon a pixel's footprint on the sea is long across the view and narrow along
//! it; trilinear filtering picks the mip of the long axis, so the distant water is blurred to
//! its mean (and its highlight widened by the Toksvig variance of that whole mip). An
//! anisotropic sampler reads the mip of the short axis and averages up to N taps along the long
//! one: the same footprint's average, so the filtered normal's length still carries the
//! variance the specular AA needs, without the blur across the view.
//!
//! It is drawn only where the device has `samplerAnisotropy`, through a second sampler of the
//! same normal maps (binding 8), so it switches per frame with a uniform (`Globals::filtering`):
//! the GPU-time governor's first step turns it off with the supersampling.

/// The most taps a pixel's normal-map samples take along its footprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anisotropy {
    /// Trilinear only.
    Off,
    /// Up to 2 taps.
    X2,
    /// Up to 4 taps.
    X4,
    /// Up to 8 taps.
    X8,
    /// Up to 16 taps.
    X16,
}

impl Anisotropy {
    /// From a tap count (1, 2, 4, 8 or 16; 1 is off).
    pub fn from_taps(n: u32) -> Option<Self> {
        match n {
            1 => Some(Self::Off),
            2 => Some(Self::X2),
            4 => Some(Self::X4),
            8 => Some(Self::X8),
            16 => Some(Self::X16),
            _ => None,
        }
    }

    /// The most taps (1 when off).
    pub fn taps(self) -> u32 {
        match self {
            Self::Off => 1,
            Self::X2 => 2,
            Self::X4 => 4,
            Self::X8 => 8,
            Self::X16 => 16,
        }
    }

    /// The taps a device filtering up to `max` (`GpuContext::max_anisotropy`; `None`: no
    /// anisotropic filtering) gives this setting: at most its limit, 1 without the feature.
    pub fn on_device(self, max: Option<f32>) -> u32 {
        max.map_or(1, |m| self.taps().min(m.max(1.0) as u32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn taps_round_trip_and_stay_within_the_device() {
        for n in [1, 2, 4, 8, 16] {
            assert_eq!(Anisotropy::from_taps(n).unwrap().taps(), n);
        }
        for n in [0, 3, 32] {
            assert_eq!(Anisotropy::from_taps(n), None);
        }
        assert_eq!(Anisotropy::X8.on_device(None), 1);
        assert_eq!(Anisotropy::X8.on_device(Some(4.0)), 4);
        assert_eq!(Anisotropy::X4.on_device(Some(16.0)), 4);
        assert_eq!(Anisotropy::Off.on_device(Some(16.0)), 1);
    }
}
