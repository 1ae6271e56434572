//! What the panel shows and changes: the front end fills a [`PanelModel`] from the running app,
//! the panel's UI edits a copy, and the front end applies what differs and the one-shot
//! [`PanelRequests`].

use crate::ui::Beaufort;

/// Comfort options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comfort {
    /// One snap turn (degrees).
    pub snap_turn_deg: f32,
    /// Turn smoothly with the stick instead of in snaps.
    pub smooth_turn: bool,
    /// Height of the deck above the mean sea level (m).
    pub deck_height_m: f32,
    /// Seated: the floor is raised to a standing eye height.
    pub seated: bool,
    /// In the water, the head rides the waves (false: it stays at a fixed height over the
    /// mean level and the water moves around it).
    pub ride_waves: bool,
    /// Narrow the view with a vignette while it is moved for the user (gliding, swimming,
    /// smooth turns, riding the waves).
    pub vignette: bool,
}

impl Default for Comfort {
    fn default() -> Self {
        Self {
            snap_turn_deg: 30.0,
            smooth_turn: false,
            deck_height_m: crate::physics::DEFAULT_DECK_HEIGHT,
            seated: false,
            ride_waves: true,
            vignette: true,
        }
    }
}

/// The performance line: shown, never edited.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perf {
    /// Median frame time (ms).
    pub frame_ms: f32,
    /// Median GPU time of the pass (ms), when timed.
    pub gpu_ms: Option<f32>,
    /// The GPU-time governor's level, when it runs.
    pub level: Option<&'static str>,
}

impl Perf {
    /// Rounded to what the line shows (0.1 ms), so a redraw happens only when the text would
    /// change.
    pub fn shown(self) -> Self {
        let r = |x: f32| (x * 10.0).round() / 10.0;
        Self {
            frame_ms: r(self.frame_ms),
            gpu_ms: self.gpu_ms.map(r),
            level: self.level,
        }
    }
}

/// Everything the panel shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelModel {
    /// Wind speed at 10 m (m/s); the sea state follows it.
    pub wind_speed: f32,
    /// Direction the wind blows toward (degrees).
    pub wind_direction_deg: f32,
    /// Sun elevation (degrees above the horizon).
    pub sun_elevation_deg: f32,
    /// Sun azimuth (degrees).
    pub sun_azimuth_deg: f32,
    /// Share of the sky under cloud, 0 to 1.
    pub clouds: f32,
    /// Floating bodies in the scene.
    pub bodies: u32,
    /// Comfort options.
    pub comfort: Comfort,
    /// The user floats in the water (the button then reads "Back on the deck").
    pub in_water: bool,
    /// The performance line.
    pub perf: Perf,
}

impl PanelModel {
    /// The Beaufort force of the current wind, if within the panel's presets.
    pub fn beaufort(&self) -> Option<Beaufort> {
        Beaufort::of_wind(self.wind_speed)
    }
}

/// One-shot requests from the panel's buttons.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PanelRequests {
    /// Put every body back where it started.
    pub reset_bodies: bool,
    /// Drop a body in front of the user.
    pub spawn_body: bool,
    /// End the session.
    pub quit: bool,
    /// Into the water from the deck, or back onto it (whichever the user is not).
    pub water: bool,
}

impl PanelRequests {
    /// Whether any was made.
    pub fn any(&self) -> bool {
        self.reset_bodies || self.spawn_body || self.quit || self.water
    }
}
