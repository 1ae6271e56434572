//! The one error of the physics layer: what was wrong and what to change.

use std::fmt;

use crate::physics::kind::BodyKind;

/// Why a world, a body or an interaction was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum PhysicsError {
    /// More bodies were asked for than the world holds (`--bodies`).
    TooManyBodies {
        /// What was asked.
        requested: usize,
        /// The most allowed ([`crate::physics::MAX_BODIES`]).
        limit: usize,
    },
    /// A number out of its range (a size, a density, a deck height, a speed).
    OutOfRange {
        /// What the number is, as the user or caller names it.
        what: &'static str,
        /// The value given.
        value: f32,
        /// The valid range, in words with units.
        range: &'static str,
    },
    /// A body cannot be put where it was asked to go.
    CannotPlace {
        /// The kind of body.
        kind: BodyKind,
        /// The requested centre (m).
        position: [f32; 3],
        /// Why: what it would overlap, or that the position is not finite.
        reason: &'static str,
    },
    /// A pose, direction or velocity with a NaN or infinite component.
    NotFinite {
        /// What it was.
        what: &'static str,
    },
    /// A body id that does not name a live body of this world.
    NoSuchBody {
        /// The id given.
        id: usize,
    },
}

impl fmt::Display for PhysicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooManyBodies { requested, limit } => write!(
                f,
                "--bodies {requested}: at most {limit} floating bodies (0 = none)"
            ),
            Self::OutOfRange { what, value, range } => {
                write!(f, "{what} {value}: must be {range}")
            }
            Self::CannotPlace {
                kind,
                position: [x, y, z],
                reason,
            } => write!(
                f,
                "cannot place a {} at ({x}, {y}, {z}) m: {reason}",
                kind.name()
            ),
            Self::NotFinite { what } => {
                write!(f, "{what} is not finite: every component must be a number")
            }
            Self::NoSuchBody { id } => write!(
                f,
                "body {id} does not exist or has sunk: pick one from Floaters::instances or \
                 nearest_body"
            ),
        }
    }
}

impl std::error::Error for PhysicsError {}

/// `Ok` when `value` is finite and within [lo, hi], else [`PhysicsError::OutOfRange`].
pub(crate) fn check(
    what: &'static str,
    value: f32,
    lo: f32,
    hi: f32,
    range: &'static str,
) -> Result<(), PhysicsError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(PhysicsError::OutOfRange { what, value, range })
    }
}
