//! Things that float: rigid bodies (buoys, crates, a small boat) riding the simulated sea, a
//! deck to stand on, and the hands that grab and throw them (issue 15). Pure: no Vulkan, no XR;
//! reads the simulation's [`Surfaces`](crate::sim::Surfaces) only.
//!
//! # Who does what
//!
//! [rapier3d](https://rapier.rs) integrates the bodies and solves contacts (bodies with each
//! other and with the deck); the water forces are ours ([`buoyancy`]). Every fixed step
//! ([`PHYSICS_HZ`]):
//!
//! 1. [`water`]: the sample points of all bodies (the centres of their hull columns,
//!    [`body::Column`]) are queried in **one** batched pass into preallocated buffers: the
//!    heights of [`Surfaces::height_at`](crate::sim::Surfaces::height_at) (all cascades
//!    summed, the horizontal (choppy) displacement inverted to the same tolerance), each
//!    column's inversion warm-started from its last solution with quasi-Newton steps (in the
//!    15 m/s sea of `tests/physics/stability.rs`, 3.4 iterations a point where the plain
//!    fixed point, warm-started too, took 8), and the vertical speed of the water particle at
//!    each column.
//! 2. [`buoyancy`]: Archimedes per column on its submerged volume, Froude-Krylov along the
//!    local water slope, linear and quadratic drag relative to the water, a constant added mass.
//! 3. rapier steps once (`dt` = 1/[`PHYSICS_HZ`]) with those forces.
//!
//! [`Floaters::advance`] runs 0..=[`clock::MAX_CATCH_UP_STEPS`] fixed steps for a frame's
//! time ([`clock::FixedClock`]); [`Floaters::instances`] interpolates the last two poses by the
//! left-over fraction, so the drawn bodies move smoothly at any frame rate.
//!
//! # Guarantees
//!
//! - **No allocation per step** in steady state: buffers are sized for [`MAX_BODIES`] at
//!   creation; rapier's pipeline reuses its own (`tests/no_alloc/physics.rs` counts).
//! - **Deterministic**: a step is a pure function of the world and the heights it reads. It runs
//!   on the caller's thread (rapier without its `parallel` feature), and the simulation's
//!   surfaces are bit-identical for any thread count, so poses are too
//!   (`tests/physics/stability.rs` compares 1 and 2 simulation threads bit for bit). Across
//!   platforms rapier may differ in the last bits (its `enhanced-determinism` feature is off).
//! - **Bad input is a [`PhysicsError`]**, never a panic: too many bodies, a body that cannot
//!   be placed, a size or density out of range.
//!
//! # Sinking
//!
//! A body denser than water sinks (drag slows it to a few m/s). Once its centre is more than
//! [`PhysicsConfig::floor_depth`] below the mean sea level it is *sunk*: taken out of the
//! simulation (disabled in rapier, no longer drawn or queried), and its slot is the first
//! one [`Floaters::throw_from`] reuses.

pub mod body;
pub mod buoyancy;
pub mod clock;
mod convert;
pub mod error;
pub mod hands;
pub mod impacts;
pub mod interact;
pub mod kind;
pub mod motor;
mod slot;
pub mod spawn;
pub mod wakes;
pub mod water;
mod world;

use glam::{Mat4, Quat, Vec3};

pub use body::BodySpec;
pub use clock::{FixedClock, Ticks};
pub use error::PhysicsError;
pub use hands::{Hand, HandCommand, HandEvent, HandInput, HandState};
pub use impacts::Impact;
pub use kind::BodyKind;
pub use slot::{BodyId, BodyState};
pub use spawn::BodyCount;
pub use world::{BodyInstance, Energy, Floaters};

/// Fixed physics rate (Hz): a Quest's 90 Hz display, so at 90 Hz every frame gets one step.
pub const PHYSICS_HZ: f32 = 90.0;

/// Fixed physics step (s).
pub const PHYSICS_DT: f32 = 1.0 / PHYSICS_HZ;

/// Density of sea water (kg/m³).
pub const WATER_DENSITY: f32 = 1025.0;

/// Most bodies a world holds (`--bodies` and thrown ones together): bounds every buffer.
pub const MAX_BODIES: usize = 64;

/// Where the OpenXR app puts the user: the deck 2.9 m above the mean sea level
/// (`xr::openxr` defaults `deck_height` to this; `--deck-height` changes both).
pub const DEFAULT_DECK_HEIGHT: f32 = 2.9;

/// A rigid pose in the world (metres; y up, the mean sea level at y = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position (m).
    pub position: Vec3,
    /// Orientation (unit quaternion).
    pub rotation: Quat,
}

impl Pose {
    /// The pose at `position` with no rotation.
    pub fn at(position: Vec3) -> Self {
        Self {
            position,
            rotation: Quat::IDENTITY,
        }
    }

    /// Whether every component is finite (and the rotation not degenerate).
    pub fn is_finite(&self) -> bool {
        self.position.is_finite() && self.rotation.is_finite() && self.rotation.length() > 0.5
    }

    /// `self` followed by `local`: the world pose of something whose pose relative to `self`
    /// is `local`.
    pub fn mul(&self, local: &Pose) -> Pose {
        Pose {
            position: self.position + self.rotation * local.position,
            rotation: (self.rotation * local.rotation).normalize(),
        }
    }

    /// The inverse pose (`p.mul(&p.inverse())` is the identity).
    pub fn inverse(&self) -> Pose {
        let r = self.rotation.conjugate();
        Pose {
            position: r * -self.position,
            rotation: r,
        }
    }

    /// Interpolates from `self` (t = 0) to `to` (t = 1): lerp and slerp.
    pub fn lerp(&self, to: &Pose, t: f32) -> Pose {
        Pose {
            position: self.position.lerp(to.position, t),
            rotation: self.rotation.slerp(to.rotation, t),
        }
    }

    /// Model matrix: rotation then translation.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_rotation_translation(self.rotation, self.position)
    }
}

/// The deck the user stands on: a static box whose top is at `height`, centred at (x, z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeckSpec {
    /// Height of the deck's top surface above the mean sea level (m).
    pub height: f32,
    /// Centre of the deck in the horizontal plane (x, z) (m).
    pub centre: [f32; 2],
    /// Full extents along x and z (m).
    pub size: [f32; 2],
    /// Thickness of the slab (m): thick enough that a thrown body cannot pass through in one
    /// step ([`PHYSICS_DT`] × 20 m/s = 0.22 m).
    pub thickness: f32,
}

impl DeckSpec {
    /// The model matrix of a unit cube ([-0.5, 0.5]³) scaled and placed as the deck slab.
    pub fn model(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            Vec3::new(self.size[0], self.thickness, self.size[1]),
            Quat::IDENTITY,
            self.slab_centre(),
        )
    }

    /// Centre of the slab (its top is at `height`).
    pub fn slab_centre(&self) -> Vec3 {
        Vec3::new(
            self.centre[0],
            self.height - 0.5 * self.thickness,
            self.centre[1],
        )
    }
}

/// Deck default extents (m): a 4 m × 4 m platform, room-scale for a standing user.
pub const DEFAULT_DECK_SIZE: [f32; 2] = [4.0, 4.0];

/// Deck slab thickness (m).
pub const DEFAULT_DECK_THICKNESS: f32 = 0.4;

/// Default depth below the mean sea level where sinking bodies are taken out (m).
pub const DEFAULT_FLOOR_DEPTH: f32 = 20.0;

/// Everything a [`Floaters`] world is built with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsConfig {
    /// The deck, or `None` for open water (tests).
    pub deck: Option<DeckSpec>,
    /// Depth below the mean sea level (m, > 0) at which a sinking body is taken out.
    pub floor_depth: f32,
    /// Gravity (m/s², > 0), downward.
    pub gravity: f32,
    /// Water density (kg/m³).
    pub water_density: f32,
}

impl Default for PhysicsConfig {
    fn default() -> Self {
        Self {
            deck: Some(DeckSpec {
                height: DEFAULT_DECK_HEIGHT,
                centre: [0.0, 0.0],
                size: DEFAULT_DECK_SIZE,
                thickness: DEFAULT_DECK_THICKNESS,
            }),
            floor_depth: DEFAULT_FLOOR_DEPTH,
            gravity: crate::sim::dispersion::GRAVITY,
            water_density: WATER_DENSITY,
        }
    }
}

impl PhysicsConfig {
    /// The default world with the deck top at `height` (m above the mean sea level).
    pub fn with_deck_height(height: f32) -> Self {
        let mut c = Self::default();
        if let Some(d) = c.deck.as_mut() {
            d.height = height;
        }
        c
    }

    /// Checks every value; the first out of range is named.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        if let Some(d) = &self.deck {
            error::check("deck height", d.height, -1000.0, 1000.0, "within ±1000 m")?;
            for (what, v) in [
                ("deck centre x", d.centre[0]),
                ("deck centre z", d.centre[1]),
            ] {
                error::check(what, v, -1.0e5, 1.0e5, "within ±100 km")?;
            }
            for (what, v) in [("deck size x", d.size[0]), ("deck size z", d.size[1])] {
                error::check(what, v, 0.1, 1000.0, "0.1 to 1000 m")?;
            }
            error::check("deck thickness", d.thickness, 0.05, 100.0, "0.05 to 100 m")?;
        }
        error::check("floor depth", self.floor_depth, 1.0, 1.0e4, "1 to 10000 m")?;
        error::check("gravity", self.gravity, 0.1, 100.0, "0.1 to 100 m/s²")?;
        error::check(
            "water density",
            self.water_density,
            100.0,
            1.0e5,
            "100 to 100000 kg/m³",
        )
    }
}
