//! Batched height queries: every sample point of every body in one call per step, into
//! buffers sized at creation, plus how fast the water rises under each point.
//!
//! The heights come from [`Surfaces::heights_at`] (all cascades summed, the horizontal
//! displacement inverted). The water's vertical speed under a column is the change of its
//! height between two surface updates divided by their time apart: the rate at which the
//! water climbs the column as both move (∂η/∂t + v·∇η), which is what drag should oppose.
//! Between updates (the simulation may run slower than the physics) it is held.

use crate::physics::body::MAX_COLUMNS;
use crate::physics::MAX_BODIES;
use crate::sim::Surfaces;

/// Largest vertical water speed believed (m/s): steeper changes are a reset, not a wave.
pub const MAX_WATER_RATE: f32 = 10.0;

/// Surface updates further apart than this (s) restart the rates instead of differencing.
pub const MAX_SURFACE_GAP_S: f64 = 0.5;

/// Every column's sample point, height and water speed.
pub struct WaterSamples {
    /// This step's query points [x, z] (m), body after body.
    points: Vec<[f32; 2]>,
    /// Heights at `points` (m).
    heights: Vec<f32>,
    /// Per slot and column ([`key`]): the height when the surfaces last changed.
    reference: Vec<f32>,
    /// Per slot and column: the water's vertical speed (m/s).
    rate: Vec<f32>,
    /// Per slot and column: whether `reference` belongs to this body's column.
    valid: Vec<bool>,
    /// Time of the surfaces last read, and the gap to the ones before when they changed.
    surface_time: Option<f64>,
    advanced_by: Option<f64>,
}

/// Index of (slot, column) in the per-column arrays.
#[inline]
pub fn key(slot: usize, column: usize) -> usize {
    slot * MAX_COLUMNS + column
}

impl Default for WaterSamples {
    fn default() -> Self {
        Self::new()
    }
}

impl WaterSamples {
    /// Buffers for [`MAX_BODIES`] bodies of [`MAX_COLUMNS`] columns.
    pub fn new() -> Self {
        let n = MAX_BODIES * MAX_COLUMNS;
        Self {
            points: Vec::with_capacity(n),
            heights: Vec::with_capacity(n),
            reference: vec![0.0; n],
            rate: vec![0.0; n],
            valid: vec![false; n],
            surface_time: None,
            advanced_by: None,
        }
    }

    /// Starts a step's list of points.
    pub fn begin(&mut self) {
        self.points.clear();
    }

    /// Adds a point; returns its index in this step's heights.
    #[inline]
    pub fn push(&mut self, x: f32, z: f32) -> usize {
        debug_assert!(
            self.points.len() < self.points.capacity(),
            "sized at creation"
        );
        self.points.push([x, z]);
        self.points.len() - 1
    }

    /// Points queued this step.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether no point is queued.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Heights at every queued point, in one call; notes whether the surfaces moved on.
    pub fn query(&mut self, surfaces: &Surfaces) {
        self.heights.clear();
        self.heights.extend(surfaces.heights_at(&self.points));
        let t = surfaces.time();
        self.advanced_by = match self.surface_time {
            Some(before) if t != before => Some(t - before),
            _ => None,
        };
        self.surface_time = Some(t);
    }

    /// Height at this step's point `i` (m).
    #[inline]
    pub fn height(&self, i: usize) -> f32 {
        self.heights[i]
    }

    /// The water's vertical speed at column `k` ([`key`]) whose height this step is `h`.
    #[inline]
    pub fn rate(&mut self, k: usize, h: f32) -> f32 {
        match (self.valid[k], self.advanced_by) {
            (false, _) => {
                self.valid[k] = true;
                self.reference[k] = h;
                self.rate[k] = 0.0;
            }
            (true, Some(gap)) if gap > 0.0 && gap <= MAX_SURFACE_GAP_S => {
                let r = (h - self.reference[k]) / gap as f32;
                self.rate[k] = r.clamp(-MAX_WATER_RATE, MAX_WATER_RATE);
                self.reference[k] = h;
            }
            (true, Some(_)) => {
                self.rate[k] = 0.0;
                self.reference[k] = h;
            }
            (true, None) => {}
        }
        self.rate[k]
    }

    /// Forgets a slot's history (a body spawned, respawned or released there).
    pub fn forget(&mut self, slot: usize) {
        self.valid[key(slot, 0)..key(slot + 1, 0)].fill(false);
    }
}
