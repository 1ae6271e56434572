//! The sea as the ears need it, read from the simulation each frame: the water's height and
//! rise speed round the deck (the cascades' surface plus the interaction layer's waves), and
//! the whitecaps being made round the listener, by sector. Reads `sim` only; the app hands
//! over the pose, the deck and the wind.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use super::scene::{BreakingSector, Listener, SoundFrame, WashPoint, BREAK_SECTORS, WASH_POINTS};
use crate::sim::interaction::InteractionLayer;
use crate::sim::query::height_at;
use crate::sim::Surfaces;

/// Ring radii (m) sampled for whitecaps: geometric, so each ring weighs the same per unit of
/// foam density once weighted by area/r².
pub const RINGS: [f32; 4] = [3.0, 6.0, 12.0, 24.0];

/// Samples per sector per ring.
const PER_RING: usize = 2;

/// Samples per sector.
const PER_SECTOR: usize = RINGS.len() * PER_RING;

/// Lattice step (m) by which a whitecap sample is keyed: the finest whitecap level's.
const KEY_STEP: f32 = 0.5;

/// One step of the published coverage (R8).
const COVERAGE_CODE: f32 = 1.5 / 255.0;

/// Distance (m) from the listener's feet of the wash points when there is no deck.
pub const OPEN_WATER_WASH: f32 = 1.5;

/// The deck as the wash needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeckOutline {
    /// Centre (world x, z).
    pub centre: Vec2,
    /// Half its size along x and z (m).
    pub half: Vec2,
    /// Height of its underside (m).
    pub underside: f32,
}

/// What a frame tells the probe besides the surfaces.
#[derive(Clone, Copy)]
pub struct ProbeInput<'a> {
    /// The frame's display time (s).
    pub time: f64,
    /// The head.
    pub listener: Listener,
    /// The surfaces shown this frame.
    pub surfaces: &'a Surfaces,
    /// The interaction layer's waves, when on.
    pub layer: Option<&'a InteractionLayer>,
    /// Wind speed (m/s) and the direction it blows toward (degrees from +x toward +z).
    pub wind_speed: f32,
    /// See `wind_speed`.
    pub wind_toward_deg: f32,
    /// The deck, if any.
    pub deck: Option<DeckOutline>,
}

/// Reads sound frames from the simulation, keeping what the rates need from the last frame.
pub struct SeaProbe {
    last_time: Option<f64>,
    heights: [f32; WASH_POINTS],
    rises: [f32; WASH_POINTS],
    /// Per whitecap sample: its lattice key and coverage last frame.
    foam: [[((i32, i32), f32); PER_SECTOR]; BREAK_SECTORS],
}

impl Default for SeaProbe {
    fn default() -> Self {
        Self::new()
    }
}

impl SeaProbe {
    /// A probe with no history (the first frame's rates are zero).
    pub fn new() -> Self {
        Self {
            last_time: None,
            heights: [0.0; WASH_POINTS],
            rises: [0.0; WASH_POINTS],
            foam: [[((i32::MIN, i32::MIN), 0.0); PER_SECTOR]; BREAK_SECTORS],
        }
    }

    /// This frame's sound frame.
    pub fn probe(&mut self, input: &ProbeInput<'_>) -> SoundFrame {
        let dt = self
            .last_time
            .map(|t| (input.time - t) as f32)
            .filter(|dt| *dt > 1e-4 && dt.is_finite());
        self.last_time = Some(input.time);
        let head = input.listener.position;
        let surface = |x: f32, z: f32| {
            height_at(&input.surfaces.cascades, x, z)
                + input.layer.map_or(0.0, |l| l.height_at(x, z))
        };

        let mut wash = [WashPoint::default(); WASH_POINTS];
        for (k, w) in wash.iter_mut().enumerate() {
            let (dx, dz) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][k];
            let (centre, half, underside) = match input.deck {
                Some(d) => (d.centre, d.half + Vec2::splat(0.1), d.underside),
                None => (
                    Vec2::new(head.x, head.z),
                    Vec2::splat(OPEN_WATER_WASH),
                    f32::INFINITY,
                ),
            };
            let (x, z) = (centre.x + dx * half.x, centre.y + dz * half.y);
            let h = surface(x, z);
            if let Some(dt) = dt {
                self.rises[k] = (h - self.heights[k]) / dt;
            }
            self.heights[k] = h;
            *w = WashPoint {
                position: Vec3::new(x, h, z),
                rise: self.rises[k],
                clearance: underside - h,
            };
        }

        let mut breaking = [BreakingSector::default(); BREAK_SECTORS];
        let whitecaps = &input.surfaces.whitecaps;
        let sector_width = TAU / BREAK_SECTORS as f32;
        for (s, sector) in breaking.iter_mut().enumerate() {
            let mut weight_sum = 0.0;
            let mut centroid = Vec3::ZERO;
            for (ring, &r) in RINGS.iter().enumerate() {
                // The ring's share of the radius: from halfway to the last ring to halfway
                // to the next (geometric rings: 0.75·r wide).
                let dr = 0.75 * r;
                for j in 0..PER_RING {
                    let theta = (s as f32 + (j as f32 + 0.5) / PER_RING as f32) * sector_width;
                    let (x, z) = (head.x + r * theta.cos(), head.z + r * theta.sin());
                    let c = whitecaps.coverage_at(x, z).unwrap_or(0.0);
                    let key = ((x / KEY_STEP).round() as i32, (z / KEY_STEP).round() as i32);
                    let slot = &mut self.foam[s][ring * PER_RING + j];
                    // Coverage is published in 1/255 steps: a step of one code is not foam
                    // being made.
                    let made = match dt {
                        Some(dt) if slot.0 == key => (c - slot.1 - COVERAGE_CODE).max(0.0) / dt,
                        _ => 0.0,
                    };
                    *slot = (key, c);
                    // Area over r²: the sample's share of loudness at the listener.
                    let w = (sector_width / PER_RING as f32) * dr / r;
                    sector.production += made * w;
                    sector.foam += c * w;
                    let loud = (made + 0.1 * c) * w;
                    weight_sum += loud;
                    centroid += loud * Vec3::new(x, 0.0, z);
                }
            }
            let mid = 0.5 * (RINGS[1] + RINGS[2]);
            let theta = (s as f32 + 0.5) * sector_width;
            let fallback = Vec3::new(head.x + mid * theta.cos(), 0.0, head.z + mid * theta.sin());
            sector.position = if weight_sum > 0.0 {
                centroid / weight_sum
            } else {
                fallback
            };
        }

        let toward = input.wind_toward_deg.to_radians();
        SoundFrame {
            time: input.time,
            listener: input.listener,
            wind_speed: input.wind_speed,
            wind_toward: Vec2::new(toward.cos(), toward.sin()),
            significant_height: input.surfaces.significant_height,
            wash,
            breaking,
            submersion: surface(head.x, head.z) - head.y,
        }
    }
}
