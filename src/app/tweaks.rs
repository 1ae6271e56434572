//! The user's live changes in the frame loop: the window's keys, the controllers' buttons and
//! a camera path's scripted events ([`Tweak`]s), applied at the frame start: waves (through
//! [`apply_wave_tweak`]), the sun, a thrown crate, a launched boat, a quality preset
//! (which rebuilds the LOD and the renderer; the GPU governor's LOD step uses the same).

use super::{AppError, Frames};
use crate::lod::{LodSettings, OceanLod, OceanSize, QualityPreset};
use crate::render::OceanRenderer;
use crate::sim::{SeaState, Simulation, WaveParams};
use crate::ui::Beaufort;
use crate::xr::{FrameState, Tweak};

impl Frames<'_> {
    /// Applies `frame`'s tweaks, first to last.
    pub(super) fn apply_tweaks(&mut self, frame: &FrameState) -> Result<(), AppError> {
        for &tweak in frame.tweaks.iter().flatten() {
            match tweak {
                Tweak::Preset(p) => self.user_preset(p)?,
                Tweak::NextPreset => {
                    // The user's preset, not the governor's step: cycling starts from what the
                    // user chose.
                    let current = self
                        .governed
                        .as_ref()
                        .map_or(self.lod.settings().preset(), |g| g.preset);
                    self.user_preset(current.next())?;
                }
                Tweak::Throw => self.throw(frame),
                Tweak::LaunchBoat(speed) => self.launch_boat(frame, speed),
                Tweak::Sun { elevation, azimuth } => self.move_sun(elevation, azimuth)?,
                t => apply_wave_tweak(&mut self.sim, t),
            }
        }
        Ok(())
    }

    /// Moves the sun by the given degrees (the window's time-of-day keys); a sun out of range
    /// (below −10° or above 90°) is refused with a log line and the sky stays.
    fn move_sun(&mut self, elevation: f32, azimuth: f32) -> Result<(), AppError> {
        let mut sun = self.renderer.settings().sun;
        sun.elevation_deg += elevation;
        sun.azimuth_deg = (sun.azimuth_deg + azimuth).rem_euclid(360.0);
        if let Err(e) = sun.validate() {
            log::warn!("sun change refused: {e}");
            return Ok(());
        }
        self.renderer.set_sun(self.xr.gpu(), sun)?;
        log::info!(
            "sun: {:.0}° high, azimuth {:.0}°",
            sun.elevation_deg,
            sun.azimuth_deg
        );
        Ok(())
    }

    /// Throws a crate along the view (the window's throw key); a throw that cannot be placed
    /// (a body in the way) is only logged.
    fn throw(&mut self, frame: &FrameState) {
        match self.afloat.as_mut() {
            Some(afloat) => {
                if let Err(e) = afloat.throw(frame) {
                    log::warn!("throw: {e}");
                }
            }
            None => log::info!("no floating bodies in this run: nothing to throw"),
        }
    }

    /// Launches a boat ahead along the view (a camera path's `boat`); one that cannot be
    /// placed is only logged.
    fn launch_boat(&mut self, frame: &FrameState, speed: f32) {
        let launched = self.afloat.as_mut().and_then(|a| a.world_mut()).map(|w| {
            let head = (frame.views[0].position + frame.views[1].position) * 0.5;
            w.launch_boat(head, frame.views[0].orientation * glam::Vec3::NEG_Z, speed)
        });
        match launched {
            Some(Err(e)) => log::warn!("boat: {e}"),
            None => log::info!("no floating bodies in this run yet: no boat launched"),
            Some(Ok(_)) => {}
        }
    }

    /// Rebuilds the LOD and the renderer for `preset` (same ocean size). Waits for the GPU first:
    /// a user's switch, not the steady state.
    pub(super) fn switch_preset(&mut self, preset: QualityPreset) -> Result<(), AppError> {
        let (xr, sim, lod, renderer) =
            (&mut *self.xr, &self.sim, &mut self.lod, &mut self.renderer);
        if lod.settings().preset() == preset {
            log::info!("quality preset is already {}", preset.name());
            return Ok(());
        }
        let size = OceanSize::new(lod.settings().size())?;
        let new_lod = OceanLod::new(LodSettings::new(preset, size));
        xr.gpu().wait_idle();
        let new_renderer = OceanRenderer::new(
            xr.gpu(),
            sim.config(),
            &new_lod,
            xr.targets(),
            *renderer.settings(),
        )?;
        let mut old = std::mem::replace(renderer, new_renderer);
        old.destroy(xr.gpu());
        *lod = new_lod;
        log::info!("quality preset: {}", preset.name());
        // The new renderer draws the whole image with the user's settings: the part the
        // backend shows, and the governor's level, go back on.
        renderer.set_render_area(xr.render_rect())?;
        if let Some(g) = self.governed.as_ref() {
            g.apply(g.level(), &mut self.renderer, &mut *self.xr)?;
        }
        Ok(())
    }

    /// The user chose `preset` (window key, controller): the governor's LOD step, if taken,
    /// applies below it.
    fn user_preset(&mut self, preset: QualityPreset) -> Result<(), AppError> {
        match self.governed.as_mut() {
            Some(g) => {
                g.preset = preset;
                let p = g.preset_for(g.level());
                self.switch_preset(p)
            }
            None => self.switch_preset(preset),
        }
    }
}

/// Applies a wave tweak (wind speed, direction, choppiness) through
/// [`Simulation::set_waves`]; logs the new value, or why it was refused. Preset tweaks are
/// the caller's (they rebuild the LOD and renderer) and are ignored here.
pub fn apply_wave_tweak(sim: &mut Simulation, tweak: Tweak) {
    let mut waves: WaveParams = sim.config().waves;
    let what = match tweak {
        Tweak::WindSpeed(d) => {
            waves.wind_speed += d;
            "wind speed"
        }
        Tweak::WindDirection(d) => {
            waves.wind_direction_deg = (waves.wind_direction_deg + d).rem_euclid(360.0);
            "wind direction"
        }
        Tweak::SeaState(d) => {
            let now = Beaufort::of_wind(waves.wind_speed).map_or(0, Beaufort::number);
            let to = (now as i32 + d as i32).clamp(0, crate::ui::beaufort::MAX_PRESET as i32);
            let force = Beaufort::new(to as u8).expect("clamped to the scale");
            waves.wind_speed = force.wind_speed();
            log::info!("sea state: Beaufort {to}, {}", force.force().name);
            "sea state"
        }
        Tweak::Choppiness(d) => {
            // Rounded to the step so repeated presses land on 0 and 2 exactly.
            waves.choppiness = ((waves.choppiness + d) * 100.0).round() / 100.0;
            "choppiness"
        }
        Tweak::Preset(_)
        | Tweak::NextPreset
        | Tweak::Throw
        | Tweak::LaunchBoat(_)
        | Tweak::Sun { .. } => return,
    };
    match SeaState::new(waves).and_then(|sea| sim.set_waves(sea)) {
        Ok(()) => log::info!(
            "{what}: wind {:.1} m/s from {:.0} deg, choppiness {:.2}",
            waves.wind_speed,
            waves.wind_direction_deg,
            waves.choppiness
        ),
        Err(e) => log::warn!("{what} change refused: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wave_tweaks_apply_and_out_of_range_values_are_refused() {
        let cfg = crate::sim::OceanConfig::single(16, 50.0).unwrap();
        let mut sim = Simulation::new(cfg, 1).unwrap();
        let w0 = sim.config().waves;
        apply_wave_tweak(&mut sim, Tweak::WindSpeed(2.0));
        assert_eq!(sim.config().waves.wind_speed, w0.wind_speed + 2.0);
        apply_wave_tweak(&mut sim, Tweak::WindSpeed(-1000.0));
        assert_eq!(sim.config().waves.wind_speed, w0.wind_speed + 2.0);
        apply_wave_tweak(&mut sim, Tweak::WindDirection(-15.0));
        assert_eq!(
            sim.config().waves.wind_direction_deg,
            (w0.wind_direction_deg - 15.0).rem_euclid(360.0)
        );
        for _ in 0..40 {
            apply_wave_tweak(&mut sim, Tweak::Choppiness(0.1));
        }
        assert_eq!(sim.config().waves.choppiness, 2.0);
        // Sea states by Beaufort force: 12 m/s is force 6; up two is a gale's middle.
        apply_wave_tweak(&mut sim, Tweak::SeaState(2));
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(8).unwrap().wind_speed()
        );
        for _ in 0..20 {
            apply_wave_tweak(&mut sim, Tweak::SeaState(-1));
        }
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(0).unwrap().wind_speed()
        );
        apply_wave_tweak(&mut sim, Tweak::SeaState(4));
        assert_eq!(
            sim.config().waves.wind_speed,
            Beaufort::new(4).unwrap().wind_speed()
        );
        apply_wave_tweak(&mut sim, Tweak::Preset(QualityPreset::Low));
        assert_eq!(sim.config().waves.choppiness, 2.0);
        // The simulation still steps with the new waves.
        assert!(sim.step_blocking(0.5).max_displacement()[1] > 0.0);
    }
}
