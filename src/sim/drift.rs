//! The surface's mean drift: what carries foam (and anything else in the top centimetres)
//! downwind, beside the waves' orbital motion that the displacement already draws.
//!
//! Two parts (Wu 1975, 1983):
//! - the **Stokes drift** of the waves, from the simulated spectrum itself
//!   ([`crate::sim::spectrum::modes::Moments::stokes_drift`]), swell included;
//! - the **wind-driven current** of the water's top layer, proportional to the wind's friction
//!   velocity u* = √C_d·U₁₀ (Wu 1975 measured about 0.55·u* at the interface), with Wu's
//!   (1982) drag coefficient C_d = (0.8 + 0.065·U₁₀)·10⁻³.
//!
//! Together they make the observed rule of thumb: surface drift 2.5-3.5 % of the wind speed
//! (AMS Glossary, "surface current"; Wu 1975: 3.5 % at long fetch). `tests` hold the sum to
//! 2-4.5 % at 5-20 m/s.

/// Wind-driven surface current per unit of the wind's friction velocity (Wu 1975).
pub const WIND_DRIFT_PER_FRICTION_VELOCITY: f64 = 0.55;

/// Wu's (1982) drag coefficient of the sea surface at wind speed `wind` (m/s at 10 m).
pub fn drag_coefficient(wind: f32) -> f64 {
    (0.8 + 0.065 * wind as f64) * 1e-3
}

/// The wind-driven current at the surface (m/s, along the wind) for wind speed `wind`.
pub fn wind_drift(wind: f32) -> f64 {
    WIND_DRIFT_PER_FRICTION_VELOCITY * drag_coefficient(wind).sqrt() * wind as f64
}

/// The surface's mean drift (x, z) (m/s): the Stokes drift (m/s) of the waves of each part of
/// the spectrum in `stokes` (the cascades') plus the wind-driven current for wind `wind` (m/s)
/// blowing toward the unit direction `toward`.
pub fn surface_drift(
    stokes: impl IntoIterator<Item = [f64; 2]>,
    wind: f32,
    toward: [f32; 2],
) -> [f32; 2] {
    let stokes = stokes
        .into_iter()
        .fold([0.0; 2], |s, d| [s[0] + d[0], s[1] + d[1]]);
    let w = wind_drift(wind);
    [
        (stokes[0] + w * toward[0] as f64) as f32,
        (stokes[1] + w * toward[1] as f64) as f32,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::config::OceanConfig;
    use crate::sim::spectrum::PackedSpectrum;

    /// The drift of the default cascades' sea at `wind` blowing toward 30°.
    fn drift_at(wind: f32) -> ([f32; 2], [f64; 2]) {
        let mut cfg = OceanConfig::default_cascades(64).unwrap();
        cfg.waves.wind_speed = wind;
        cfg.waves.wind_direction_deg = 30.0;
        let parts: Vec<[f64; 2]> = cfg
            .cascade_specs()
            .iter()
            .map(|spec| PackedSpectrum::generate(&cfg.waves, spec).stokes_drift)
            .collect();
        let stokes = surface_drift(parts.iter().copied(), 0.0, [1.0, 0.0]);
        let stokes = [stokes[0] as f64, stokes[1] as f64];
        (surface_drift(parts, wind, cfg.waves.toward()), stokes)
    }

    #[test]
    fn the_surface_drifts_downwind_at_a_few_percent_of_the_wind() {
        for wind in [5.0f32, 10.0, 15.0, 20.0] {
            let (d, stokes) = drift_at(wind);
            let speed = d[0].hypot(d[1]);
            let share = speed / wind;
            let angle = d[1].atan2(d[0]).to_degrees();
            let s = stokes[0].hypot(stokes[1]);
            println!(
                "{wind} m/s: drift {speed:.3} m/s ({:.2} %), Stokes {s:.3}, wind {:.3}, at {angle:.1}°",
                100.0 * share,
                wind_drift(wind)
            );
            assert!((0.02..0.045).contains(&share), "{wind} m/s: {share}");
            assert!((angle - 30.0).abs() < 10.0, "{wind} m/s: toward {angle}°");
            // Both parts matter: the waves' share was 20-26 % at 5-20 m/s (the Stokes drift of
            // the resolved sea: 0.65 % of U at 10 m/s; the same at N = 256, being carried by
            // the waves near the peak).
            assert!(
                (0.15..0.5).contains(&(s / speed as f64)),
                "{wind} m/s: Stokes {s}"
            );
        }
    }
}
