//! The shapes a body can have: the vocabulary the bodies, their errors and their users share.

/// The shapes a body can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyKind {
    /// A ballasted cylindrical buoy, axis along the body's y (size: diameter, height,
    /// diameter).
    Buoy,
    /// A box (size: x, y, z extents).
    Crate,
    /// A small boat: a hull tapering to a narrower, shorter flat bottom (size: beam, depth,
    /// length; the bow and stern along z). [`boat_unit_hull`](crate::physics::body::boat_unit_hull) gives its corners.
    Boat,
}

impl BodyKind {
    /// The kind's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Buoy => "buoy",
            Self::Crate => "crate",
            Self::Boat => "boat",
        }
    }
}
