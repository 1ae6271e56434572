//! What the soundscape hears: plain data a frame hands over (no simulation, physics or
//! renderer types), so the synthesis is testable from made-up scenes and the real-time path
//! can copy it across threads as one value.

use glam::{Quat, Vec2, Vec3};

/// Points round the listener where the water's wash against the deck is heard.
pub const WASH_POINTS: usize = 4;

/// Directions round the listener whose whitecaps are heard breaking (each a sector of
/// 360°/8).
pub const BREAK_SECTORS: usize = 8;

/// The listener's head: world position and orientation (OpenXR's: −Z ahead, +X right, +Y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Listener {
    /// Between the ears (m).
    pub position: Vec3,
    /// The head's rotation.
    pub orientation: Quat,
}

impl Default for Listener {
    fn default() -> Self {
        Self {
            position: Vec3::new(0.0, 1.7, 0.0),
            orientation: Quat::IDENTITY,
        }
    }
}

/// The water at one wash point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WashPoint {
    /// Where the water is (its surface, m).
    pub position: Vec3,
    /// The surface's vertical speed there (m/s, + rising).
    pub rise: f32,
    /// Height of the deck's underside above the water there (m); infinite without a deck.
    pub clearance: f32,
}

impl Default for WashPoint {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            rise: 0.0,
            clearance: f32::INFINITY,
        }
    }
}

/// The whitecaps of one sector round the listener.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BreakingSector {
    /// Where they are on average (weighted by loudness, m).
    pub position: Vec3,
    /// Foam being made: coverage gained per second, summed over the sector's samples, each
    /// weighted by the area it stands for over its distance squared (what reaches the ear).
    pub production: f32,
    /// Foam lying there (coverage, same weighting): its bubbles fizz.
    pub foam: f32,
}

/// One frame's sea as the ears need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoundFrame {
    /// The frame's display time (s): events and frames share this clock.
    pub time: f64,
    /// The head.
    pub listener: Listener,
    /// Wind speed at 10 m (m/s).
    pub wind_speed: f32,
    /// Unit vector (world x, z) the wind blows toward.
    pub wind_toward: Vec2,
    /// Significant wave height Hs (m): the swell's rumble.
    pub significant_height: f32,
    /// The water round the deck.
    pub wash: [WashPoint; WASH_POINTS],
    /// Whitecaps round the listener.
    pub breaking: [BreakingSector; BREAK_SECTORS],
    /// How deep (m) the head is under the water's surface (negative above it): under it the
    /// soundscape is a diver's ([`super::submerged`]).
    pub submersion: f32,
}

impl Default for SoundFrame {
    fn default() -> Self {
        Self {
            time: 0.0,
            listener: Listener::default(),
            wind_speed: 0.0,
            wind_toward: Vec2::X,
            significant_height: 0.0,
            wash: [WashPoint::default(); WASH_POINTS],
            breaking: [BreakingSector::default(); BREAK_SECTORS],
            submersion: -1.0,
        }
    }
}

/// Farthest a position may be from the origin (m): beyond it, a frame's position is taken as
/// broken (a far body is silent long before).
pub const MAX_POSITION: f32 = 1.0e6;

/// `v` when finite, else `fallback`.
fn finite_or(v: f32, fallback: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        fallback
    }
}

/// `p` when finite and within [`MAX_POSITION`], else `fallback`.
fn position_or(p: Vec3, fallback: Vec3) -> Vec3 {
    if p.is_finite() && p.abs().max_element() <= MAX_POSITION {
        p
    } else {
        fallback
    }
}

impl SoundFrame {
    /// The frame with every value the voices cannot use made harmless: a non-finite or absurd
    /// number becomes its quiet default (no wind, still water, no foam, no deck), a position
    /// out of [`MAX_POSITION`] the listener's. The probe never makes such values, but a bad
    /// frame must never make noise or NaN.
    pub fn sanitized(&self) -> Self {
        let mut f = *self;
        let head = position_or(f.listener.position, Listener::default().position);
        f.listener.position = head;
        let q = f.listener.orientation;
        f.listener.orientation = if q.is_finite() && q.length() > 1e-3 {
            q.normalize()
        } else {
            Quat::IDENTITY
        };
        f.wind_speed = finite_or(f.wind_speed, 0.0).clamp(0.0, 60.0);
        f.wind_toward = f.wind_toward.try_normalize().unwrap_or(Vec2::X);
        f.significant_height = finite_or(f.significant_height, 0.0).clamp(0.0, 30.0);
        f.submersion = finite_or(f.submersion, -1.0);
        for w in &mut f.wash {
            w.position = position_or(w.position, head);
            w.rise = finite_or(w.rise, 0.0).clamp(-20.0, 20.0);
            w.clearance = if w.clearance.is_nan() {
                f32::INFINITY
            } else {
                w.clearance.max(-100.0)
            };
        }
        for b in &mut f.breaking {
            b.position = position_or(b.position, head);
            b.production = finite_or(b.production, 0.0).clamp(0.0, 100.0);
            b.foam = finite_or(b.foam, 0.0).clamp(0.0, 100.0);
        }
        f
    }
}

/// Something hit the water: a body's entry, a hand plunging in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splash {
    /// When (s, the frames' clock); one in the past of the rendered block sounds at once.
    pub time: f64,
    /// Where (m).
    pub position: Vec3,
    /// Speed into the water (m/s).
    pub speed: f32,
    /// Mass of what hit (kg).
    pub mass: f32,
    /// Its radius (m): bigger bodies sound lower.
    pub radius: f32,
}

impl Splash {
    /// Kinetic energy at impact, ½·m·v² (J).
    pub fn energy(&self) -> f32 {
        0.5 * self.mass * self.speed * self.speed
    }

    /// Whether every field is finite and within reason (speed up to 1000 m/s, mass up to
    /// 10⁶ kg, radius up to 100 m, position within [`MAX_POSITION`]): anything else is
    /// dropped.
    pub fn is_valid(&self) -> bool {
        self.time.is_finite()
            && self.position.is_finite()
            && self.position.abs().max_element() <= MAX_POSITION
            && (0.0..=1000.0).contains(&self.speed)
            && self.mass > 0.0
            && self.mass <= 1.0e6
            && self.radius > 0.0
            && self.radius <= 100.0
    }
}
