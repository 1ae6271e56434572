//! The Beaufort scale of wind force, as the World Meteorological Organization tabulates it
//! (wind speed at 10 m, m/s), with the names sailors give each force. Sea states are offered
//! by force, 0 (calm) to 10 (storm); a force's representative wind is the middle of its range.

use crate::base::ParamError;

/// One force of the scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Force {
    /// Its number, 0 to 12.
    pub number: u8,
    /// Its name.
    pub name: &'static str,
    /// Lowest wind speed (m/s at 10 m).
    pub min: f32,
    /// Highest wind speed (m/s at 10 m; the last force has no top).
    pub max: f32,
}

/// The scale (WMO), forces 0 to 12.
pub const BEAUFORT: [Force; 13] = [
    Force {
        number: 0,
        name: "calm",
        min: 0.0,
        max: 0.2,
    },
    Force {
        number: 1,
        name: "light air",
        min: 0.3,
        max: 1.5,
    },
    Force {
        number: 2,
        name: "light breeze",
        min: 1.6,
        max: 3.3,
    },
    Force {
        number: 3,
        name: "gentle breeze",
        min: 3.4,
        max: 5.4,
    },
    Force {
        number: 4,
        name: "moderate breeze",
        min: 5.5,
        max: 7.9,
    },
    Force {
        number: 5,
        name: "fresh breeze",
        min: 8.0,
        max: 10.7,
    },
    Force {
        number: 6,
        name: "strong breeze",
        min: 10.8,
        max: 13.8,
    },
    Force {
        number: 7,
        name: "near gale",
        min: 13.9,
        max: 17.1,
    },
    Force {
        number: 8,
        name: "gale",
        min: 17.2,
        max: 20.7,
    },
    Force {
        number: 9,
        name: "strong gale",
        min: 20.8,
        max: 24.4,
    },
    Force {
        number: 10,
        name: "storm",
        min: 24.5,
        max: 28.4,
    },
    Force {
        number: 11,
        name: "violent storm",
        min: 28.5,
        max: 32.6,
    },
    Force {
        number: 12,
        name: "hurricane",
        min: 32.7,
        max: f32::INFINITY,
    },
];

/// The strongest force offered as a sea state.
pub const MAX_PRESET: u8 = 10;

/// A sea state by Beaufort force, 0 to [`MAX_PRESET`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Beaufort(u8);

impl Beaufort {
    /// Force `number`, 0 to 10.
    pub fn new(number: u8) -> Result<Self, ParamError> {
        if number > MAX_PRESET {
            return Err(ParamError::new(
                "beaufort",
                number as f64,
                "a Beaufort force from 0 (calm) to 10 (storm)",
            ));
        }
        Ok(Self(number))
    }

    /// The force a wind of `speed` m/s is (forces above 10 are given as 10); `None` for a
    /// speed that is not a finite number ≥ 0.
    pub fn of_wind(speed: f32) -> Option<Self> {
        if !(speed.is_finite() && speed >= 0.0) {
            return None;
        }
        let n = BEAUFORT
            .iter()
            .rposition(|f| speed >= f.min - 0.05)
            .unwrap_or(0);
        Some(Self((n as u8).min(MAX_PRESET)))
    }

    /// Its number.
    pub fn number(self) -> u8 {
        self.0
    }

    /// Its row of the scale.
    pub fn force(self) -> &'static Force {
        &BEAUFORT[self.0 as usize]
    }

    /// The wind it stands for: the middle of its range (m/s; 0.2 for calm, the simulation
    /// needs some wind).
    pub fn wind_speed(self) -> f32 {
        let f = self.force();
        if self.0 == 0 {
            f.max
        } else {
            0.5 * (f.min + f.max)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_is_contiguous_and_each_preset_is_its_own_force() {
        for w in BEAUFORT.windows(2) {
            assert!((w[1].min - w[0].max - 0.1).abs() < 1e-4, "{w:?}");
        }
        for n in 0..=MAX_PRESET {
            let b = Beaufort::new(n).unwrap();
            assert_eq!(Beaufort::of_wind(b.wind_speed()), Some(b), "force {n}");
        }
        assert_eq!(
            Beaufort::of_wind(10.0).unwrap().force().name,
            "fresh breeze"
        );
        assert_eq!(Beaufort::of_wind(45.0).unwrap().number(), 10);
        assert_eq!(Beaufort::of_wind(f32::NAN), None);
        assert!(Beaufort::new(11)
            .unwrap_err()
            .to_string()
            .contains("0 (calm) to 10"));
    }
}
