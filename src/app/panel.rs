//! The control panel in the frame loop (issue 31): the one [`Panel`] both front ends show.
//! Each frame the backend's pointer events go in, the panel runs (only when something it
//! shows changed), and what the user changed is applied: the wind through the simulation's
//! smooth sea-state change, the sun and clouds through the renderer's sky, comfort through the
//! backend (turning, seated) and the bodies' world (the deck's height), the buttons (spawn,
//! reset, quit) here. The panel is built from the running state every frame, so it always
//! shows what is, whoever changed it (a key, a controller).
//!
//! A slider dragged across many frames would restart the sea-state build, rebake the sky or
//! remake the bodies' world every frame: those changes go out at most every [`APPLY_EVERY`]
//! seconds, the last value always. The performance line moves every [`PERF_EVERY`] seconds,
//! so an open panel nobody touches is redrawn (and allocates, in egui) only then. Times are
//! the frames' display clock.

use super::{AppError, Frames};
use crate::render::sky::SunSky;
use crate::sim::SeaState;
use crate::ui::panel::{Comfort, Panel, PanelModel, PanelUpdate, Perf};
use crate::xr::{FrameLoop, FrameState};

/// Shortest time between two applications of a dragged wind, sky or deck height (s).
pub const APPLY_EVERY: f64 = 0.25;

/// How often the performance line takes the recent frames' medians (s).
pub const PERF_EVERY: f64 = 1.0;

/// The panel and the changes it has not applied yet.
pub(super) struct PanelHost {
    panel: Panel,
    comfort: Comfort,
    /// The performance line as last taken, and when (display time, s).
    perf: Perf,
    perf_at: f64,
    /// Waves, sky and deck height the user set that wait for [`APPLY_EVERY`].
    waves: Option<SeaState>,
    sun: Option<SunSky>,
    deck: Option<f32>,
    /// When waves, sky or deck were last applied (display time, s).
    applied_at: f64,
}

impl PanelHost {
    /// The panel for `xr`'s front end, open or closed, showing `comfort` as the run starts;
    /// `None` when it shows no panel.
    pub fn new(xr: &dyn FrameLoop, open: bool, comfort: Comfort) -> Option<Self> {
        let ppp = xr.panel_pixels_per_point()?;
        let mut panel = Panel::new(open, ppp);
        panel.set_draw_cursor(xr.panel_draws_cursor());
        Some(Self {
            panel,
            comfort,
            perf: Perf {
                frame_ms: 0.0,
                gpu_ms: None,
                level: None,
            },
            perf_at: f64::NEG_INFINITY,
            waves: None,
            sun: None,
            deck: None,
            applied_at: f64::NEG_INFINITY,
        })
    }

    /// The comfort options as the user left them.
    pub fn comfort(&self) -> Comfort {
        self.comfort
    }

    /// The waves and sky the user set that were not applied yet.
    pub fn pending(&self) -> (Option<SeaState>, Option<SunSky>) {
        (self.waves, self.sun)
    }
}

impl Frames<'_> {
    /// The panel's frame: `frame`'s pointer events, the UI, the user's changes applied, the
    /// panel handed to the backend to show. Returns false when the user asked to quit.
    pub(super) fn drive_panel(&mut self, frame: &FrameState) -> Result<bool, AppError> {
        let Some(mut host) = self.panel.take() else {
            return Ok(true);
        };
        let result = self.panel_frame(&mut host, frame);
        self.panel = Some(host);
        result
    }

    fn panel_frame(&mut self, host: &mut PanelHost, frame: &FrameState) -> Result<bool, AppError> {
        for &e in frame.pointer.iter().flatten() {
            host.panel.handle(e);
        }
        let now = frame.predicted_display_time;
        if now - host.perf_at >= PERF_EVERY {
            host.perf_at = now;
            let (frame_ms, gpu_ms) = self.stats.recent.medians();
            host.perf = Perf {
                frame_ms: frame_ms as f32,
                gpu_ms: gpu_ms.map(|g| g as f32),
                level: self.governed.as_ref().map(|g| g.level().name()),
            };
        }
        let live = self.panel_model(host, frame.in_water);
        let update: PanelUpdate = host.panel.update(&live, now);
        if update.redrawn {
            self.hooks.panel_drawn(frame);
        }
        if update.haptic {
            self.xr.panel_haptic();
        }
        if let Some(m) = update.edited {
            self.take_edits(host, &live, &m);
        }
        let waiting = host.waves.is_some() || host.sun.is_some() || host.deck.is_some();
        if now - host.applied_at >= APPLY_EVERY && waiting {
            host.applied_at = now;
            if let Some(sea) = host.waves.take() {
                let waves = sea.waves();
                match self.sim.set_waves(sea) {
                    Ok(()) => log::info!(
                        "panel: wind {:.1} m/s toward {:.0}°",
                        waves.wind_speed,
                        waves.wind_direction_deg
                    ),
                    Err(e) => log::warn!("panel: wind change refused: {e}"),
                }
            }
            if let Some(sun) = host.sun.take() {
                self.renderer.set_sun(self.xr.gpu(), sun)?;
            }
            let deck = host.deck.take();
            if let (Some(h), Some(afloat)) = (deck, self.afloat.as_mut()) {
                match afloat.move_deck(h) {
                    Ok(()) => log::info!("panel: deck {h:.1} m above the sea"),
                    Err(e) => log::warn!("panel: deck change refused: {e}"),
                }
            }
        }
        let r = update.requests;
        if r.water {
            self.xr.set_in_water(!frame.in_water);
        }
        if r.spawn_body {
            self.spawn_in_front(frame);
        }
        if r.reset_bodies {
            match self.afloat.as_mut() {
                Some(a) => a.reset(),
                None => log::info!("no floating bodies in this run: nothing to reset"),
            }
        }
        self.xr.show_panel(&mut host.panel)?;
        Ok(!r.quit)
    }

    /// What the panel shows now: the waves and sky as set (or waiting to be), the bodies, the
    /// comfort options, whether the user is `in_water`, and the performance line as last
    /// taken.
    fn panel_model(&self, host: &PanelHost, in_water: bool) -> PanelModel {
        let waves = host.waves.map_or(self.sim.config().waves, |s| *s.waves());
        let sun = host.sun.unwrap_or(self.renderer.settings().sun);
        PanelModel {
            wind_speed: waves.wind_speed,
            wind_direction_deg: waves.wind_direction_deg.rem_euclid(360.0),
            sun_elevation_deg: sun.elevation_deg,
            sun_azimuth_deg: sun.azimuth_deg.rem_euclid(360.0),
            clouds: sun.clouds,
            bodies: self
                .afloat
                .as_ref()
                .and_then(|a| a.world())
                .map_or(0, |w| w.live() as u32),
            comfort: host.comfort,
            in_water,
            perf: host.perf,
        }
    }

    /// Files what the user changed from `live` to `m`: waves and sky wait for their turn,
    /// comfort goes to the backend at once. Values the simulation or sky would refuse are
    /// logged and dropped (the panel's ranges keep them in range).
    fn take_edits(&mut self, host: &mut PanelHost, live: &PanelModel, m: &PanelModel) {
        if (m.wind_speed, m.wind_direction_deg) != (live.wind_speed, live.wind_direction_deg) {
            let mut waves = host.waves.map_or(self.sim.config().waves, |s| *s.waves());
            waves.wind_speed = m.wind_speed;
            waves.wind_direction_deg = m.wind_direction_deg.rem_euclid(360.0);
            match SeaState::new(waves) {
                Ok(sea) => host.waves = Some(sea),
                Err(e) => log::warn!("panel: wind change refused: {e}"),
            }
        }
        let sky = |p: &PanelModel| (p.sun_elevation_deg, p.sun_azimuth_deg, p.clouds);
        if sky(m) != sky(live) {
            let mut sun = host.sun.unwrap_or(self.renderer.settings().sun);
            sun.elevation_deg = m.sun_elevation_deg;
            sun.azimuth_deg = m.sun_azimuth_deg.rem_euclid(360.0);
            sun.clouds = m.clouds;
            match sun.validate() {
                Ok(()) => host.sun = Some(sun),
                Err(e) => log::warn!("panel: sky change refused: {e}"),
            }
        }
        if m.comfort != host.comfort {
            if m.comfort.deck_height_m != host.comfort.deck_height_m {
                host.deck = Some(m.comfort.deck_height_m);
            }
            host.comfort = m.comfort;
            self.xr.set_comfort(m.comfort);
        }
    }

    /// Drops a crate in front of the head of `frame` (the panel's spawn button).
    fn spawn_in_front(&mut self, frame: &FrameState) {
        match self.afloat.as_mut() {
            Some(a) => {
                if let Err(e) = a.drop_in_front(frame) {
                    log::warn!("spawn: {e}");
                }
            }
            None => log::info!("no floating bodies in this run: nothing to spawn"),
        }
    }
}
