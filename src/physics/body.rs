//! What a floating body is: its kind, size and density ([`BodySpec`]), the rapier collider
//! that gives it mass and inertia, and the columns the water pushes on ([`Hull`]).
//!
//! Every body has a frame with its geometric centre at the origin and y up; `size` is its full
//! extent along the frame's x, y and z. A renderer draws a unit mesh (spanning [-0.5, 0.5]³:
//! a cube, a cylinder of diameter 1 along y, or [`boat_unit_hull`]) scaled by `size`.
//!
//! # Hull columns
//!
//! The water sees a body as vertical prisms ([`Column`]) standing on a grid over its
//! footprint, each from the hull's bottom to its top at that point. A prism cut by a plane
//! has the volume `area × (submerged length along its axis)`, so in calm water the columns
//! give the exact submerged volume of a box at any tilt that keeps the water off its end
//! faces, and of the boat's hull up to how its sloped bottom varies across one column.

use glam::Vec3;
use rapier3d::prelude::{ColliderBuilder, MassProperties};

use crate::physics::convert::to_rapier;
use crate::physics::error::{check, PhysicsError};
use crate::physics::kind::BodyKind;

/// Smallest and largest extent of a body along any axis (m).
pub const SIZE_RANGE_M: (f32, f32) = (0.05, 10.0);

/// Lightest and densest body (kg/m³): from foam to lead.
pub const DENSITY_RANGE: (f32, f32) = (10.0, 20_000.0);

/// A buoy's centre of mass sits this fraction of its height below its centre (ballast at
/// the bottom), so a buoy taller than wide floats upright.
pub const BUOY_BALLAST: f32 = 0.35;

/// The boat's flat bottom spans this fraction of its beam...
pub const BOAT_BOTTOM_BEAM: f32 = 0.6;

/// ...and this fraction of its length.
pub const BOAT_BOTTOM_LENGTH: f32 = 0.7;

/// Friction coefficient of every body and the deck.
pub const FRICTION: f32 = 0.6;

/// Restitution (bounciness) of every body.
pub const RESTITUTION: f32 = 0.2;

/// The shape, size and mass of one body, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodySpec {
    kind: BodyKind,
    size: Vec3,
    density: f32,
}

impl BodySpec {
    /// A body of `kind` with full extents `size` (m, each within [`SIZE_RANGE_M`]) and
    /// uniform `density` (kg/m³, within [`DENSITY_RANGE`]; the buoy's is ballasted, see
    /// [`BUOY_BALLAST`]). A buoy's x and z extents must be equal (its diameter).
    pub fn new(kind: BodyKind, size: Vec3, density: f32) -> Result<Self, PhysicsError> {
        let range = "finite and 0.05 to 10 m";
        check("body size x", size.x, SIZE_RANGE_M.0, SIZE_RANGE_M.1, range)?;
        check("body size y", size.y, SIZE_RANGE_M.0, SIZE_RANGE_M.1, range)?;
        check("body size z", size.z, SIZE_RANGE_M.0, SIZE_RANGE_M.1, range)?;
        check(
            "body density",
            density,
            DENSITY_RANGE.0,
            DENSITY_RANGE.1,
            "10 to 20000 kg/m³ (water is 1000-1025)",
        )?;
        if kind == BodyKind::Buoy && size.x != size.z {
            return Err(PhysicsError::OutOfRange {
                what: "buoy depth (size z)",
                value: size.z,
                range: "equal to its diameter (size x)",
            });
        }
        Ok(Self {
            kind,
            size,
            density,
        })
    }

    /// A buoy of `diameter` and `height` (m).
    pub fn buoy(diameter: f32, height: f32, density: f32) -> Result<Self, PhysicsError> {
        Self::new(
            BodyKind::Buoy,
            Vec3::new(diameter, height, diameter),
            density,
        )
    }

    /// A box crate of extents `size` (m).
    pub fn crate_box(size: Vec3, density: f32) -> Result<Self, PhysicsError> {
        Self::new(BodyKind::Crate, size, density)
    }

    /// A boat of `beam` (x), `depth` (y) and `length` (z) (m).
    pub fn boat(beam: f32, depth: f32, length: f32, density: f32) -> Result<Self, PhysicsError> {
        Self::new(BodyKind::Boat, Vec3::new(beam, depth, length), density)
    }

    /// The kind.
    pub fn kind(&self) -> BodyKind {
        self.kind
    }

    /// Full extents along the body's x, y, z (m): the scale of the unit mesh.
    pub fn size(&self) -> Vec3 {
        self.size
    }

    /// Density (kg/m³).
    pub fn density(&self) -> f32 {
        self.density
    }

    /// Volume of the solid (m³).
    pub fn volume(&self) -> f32 {
        let s = self.size;
        match self.kind {
            BodyKind::Crate => s.x * s.y * s.z,
            BodyKind::Buoy => std::f32::consts::PI * 0.25 * s.x * s.x * s.y,
            // A prismatoid: h/6 · (top + 4·middle + bottom).
            BodyKind::Boat => {
                let (bb, bl) = (BOAT_BOTTOM_BEAM, BOAT_BOTTOM_LENGTH);
                let mid = 0.25 * (1.0 + bb) * (1.0 + bl);
                s.x * s.z * s.y / 6.0 * (1.0 + 4.0 * mid + bb * bl)
            }
        }
    }

    /// Mass (kg).
    pub fn mass(&self) -> f32 {
        self.volume() * self.density
    }

    /// Radius of the sphere around the centre that holds the body (m).
    pub fn bounding_radius(&self) -> f32 {
        0.5 * self.size.length()
    }

    /// The rapier collider: the shape with this density, the buoy's centre of mass moved
    /// down by its ballast.
    pub(crate) fn collider(&self) -> ColliderBuilder {
        let h = 0.5 * self.size;
        let builder = match self.kind {
            BodyKind::Crate => ColliderBuilder::cuboid(h.x, h.y, h.z),
            BodyKind::Buoy => ColliderBuilder::cylinder(h.y, h.x),
            BodyKind::Boat => {
                let corners = boat_unit_hull().map(|c| to_rapier(c * self.size));
                // Eight corners of two nested rectangles: never degenerate.
                ColliderBuilder::convex_hull(&corners)
                    .unwrap_or_else(|| ColliderBuilder::cuboid(h.x, h.y, h.z))
            }
        };
        let builder = builder
            .density(self.density)
            .friction(FRICTION)
            .restitution(RESTITUTION);
        if self.kind != BodyKind::Buoy {
            return builder;
        }
        let solid = builder.build().mass_properties();
        let com = rapier3d::math::Vector::new(0.0, -BUOY_BALLAST * self.size.y, 0.0);
        builder.mass_properties(MassProperties::new(
            com,
            solid.mass(),
            solid.principal_inertia(),
        ))
    }
}

/// The boat's eight corners in its unit box ([-0.5, 0.5]³): the deck rectangle at y = 0.5,
/// the narrower, shorter flat bottom at y = -0.5. A renderer's boat mesh is their convex hull.
pub fn boat_unit_hull() -> [Vec3; 8] {
    let (bx, bz) = (0.5 * BOAT_BOTTOM_BEAM, 0.5 * BOAT_BOTTOM_LENGTH);
    [
        Vec3::new(-0.5, 0.5, -0.5),
        Vec3::new(0.5, 0.5, -0.5),
        Vec3::new(0.5, 0.5, 0.5),
        Vec3::new(-0.5, 0.5, 0.5),
        Vec3::new(-bx, -0.5, -bz),
        Vec3::new(bx, -0.5, -bz),
        Vec3::new(bx, -0.5, bz),
        Vec3::new(-bx, -0.5, bz),
    ]
}

/// Sub-samples per side of a boat column's footprint for its mean bottom.
const BOAT_SUBSAMPLES: usize = 8;

/// Most columns of one body: bounds the height-query buffers.
pub const MAX_COLUMNS: usize = 16;

/// One vertical prism of a hull, in the body frame (m, m²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Column {
    /// Centre of the prism's footprint, x.
    pub x: f32,
    /// Centre of the prism's footprint, z.
    pub z: f32,
    /// The hull's bottom at (x, z).
    pub bottom: f32,
    /// The hull's top at (x, z).
    pub top: f32,
    /// Footprint area.
    pub area: f32,
}

impl Column {
    /// Length of the prism (m).
    pub fn length(&self) -> f32 {
        self.top - self.bottom
    }
}

/// The columns of one body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hull {
    columns: [Column; MAX_COLUMNS],
    len: usize,
}

impl Hull {
    /// The columns of `spec`: a 2 × 2 grid for a crate, a 3 × 3 grid over a buoy's circle
    /// (areas scaled to the circle's), 2 across × 4 along a boat (bottoms following its sloped
    /// hull). Two columns per axis are the fewest that give the water a righting moment; these
    /// counts (51 sample points per eight bodies of the default mix, where 3 × 3, 12 and
    /// 3 × 5 took 87) keep a 64-body step inside its budget (BENCHMARKS.md, physics).
    pub fn of(spec: &BodySpec) -> Self {
        let mut hull = Self {
            columns: [Column::default(); MAX_COLUMNS],
            len: 0,
        };
        let s = spec.size();
        match spec.kind() {
            BodyKind::Crate => hull.grid(s, 2, 2, |_, _| Some(-0.5 * s.y)),
            BodyKind::Buoy => {
                let r = 0.5 * s.x;
                hull.grid(s, 3, 3, |x, z| {
                    (x * x + z * z <= r * r).then_some(-0.5 * s.y)
                });
                let area: f32 = hull.columns().iter().map(|c| c.area).sum();
                let scale = std::f32::consts::PI * r * r / area;
                for c in &mut hull.columns[..hull.len] {
                    c.area *= scale;
                }
            }
            BodyKind::Boat => {
                let (a1, b1) = (0.5 * s.x, 0.5 * s.z);
                let (a0, b0) = (a1 * BOAT_BOTTOM_BEAM, b1 * BOAT_BOTTOM_LENGTH);
                // Cross-sections grow linearly from the bottom rectangle to the deck's:
                // (x, z) is inside from the height fraction t on.
                let bottom = |x: f32, z: f32| {
                    let t = ((x.abs() - a0) / (a1 - a0))
                        .max((z.abs() - b0) / (b1 - b0))
                        .max(0.0);
                    s.y * (t - 0.5)
                };
                // A column's bottom is the hull's mean bottom over its footprint (sampled
                // BOAT_SUBSAMPLES² times), so the columns hold the hull's volume; the bottom at
                // the centre alone would miss the slope's kink at the bottom rectangle's edge.
                let (nx, nz) = (2, 4);
                let (dx, dz) = (s.x / nx as f32, s.z / nz as f32);
                hull.grid(s, nx, nz, |x, z| {
                    let n = BOAT_SUBSAMPLES;
                    let mut sum = 0.0;
                    for i in 0..n {
                        for k in 0..n {
                            let u = (i as f32 + 0.5) / n as f32 - 0.5;
                            let v = (k as f32 + 0.5) / n as f32 - 0.5;
                            sum += bottom(x + u * dx, z + v * dz);
                        }
                    }
                    Some(sum / (n * n) as f32)
                })
            }
        }
        hull
    }

    /// Adds the cells of an `nx` × `nz` grid over the footprint whose `bottom` is `Some`.
    fn grid(&mut self, size: Vec3, nx: usize, nz: usize, bottom: impl Fn(f32, f32) -> Option<f32>) {
        let (dx, dz) = (size.x / nx as f32, size.z / nz as f32);
        for i in 0..nx {
            for k in 0..nz {
                let x = (i as f32 + 0.5) * dx - 0.5 * size.x;
                let z = (k as f32 + 0.5) * dz - 0.5 * size.z;
                if let Some(b) = bottom(x, z) {
                    if self.len < MAX_COLUMNS {
                        self.columns[self.len] = Column {
                            x,
                            z,
                            bottom: b,
                            top: 0.5 * size.y,
                            area: dx * dz,
                        };
                        self.len += 1;
                    }
                }
            }
        }
    }

    /// The columns.
    pub fn columns(&self) -> &[Column] {
        &self.columns[..self.len]
    }

    /// Total volume the columns hold (m³): the body's volume as the water sees it.
    pub fn volume(&self) -> f32 {
        self.columns().iter().map(|c| c.area * c.length()).sum()
    }

    /// Total footprint area (m²).
    pub fn area(&self) -> f32 {
        self.columns().iter().map(|c| c.area).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_hold_the_solid_volume() {
        let specs = [
            BodySpec::crate_box(Vec3::new(0.6, 0.4, 0.8), 500.0).unwrap(),
            BodySpec::buoy(0.6, 0.8, 300.0).unwrap(),
            BodySpec::boat(1.4, 0.5, 3.0, 250.0).unwrap(),
        ];
        for spec in specs {
            let hull = Hull::of(&spec);
            let rel = hull.volume() / spec.volume() - 1.0;
            assert!(
                rel.abs() < 0.03,
                "{:?}: columns {} vs solid {} m³",
                spec.kind(),
                hull.volume(),
                spec.volume()
            );
            assert!(hull.columns().len() <= MAX_COLUMNS);
            let solid = spec.collider().build().mass_properties().mass();
            assert!((solid / spec.mass() - 1.0).abs() < 1e-3, "rapier's mass");
        }
    }

    #[test]
    fn bad_sizes_and_densities_are_named() {
        let e = BodySpec::crate_box(Vec3::new(0.5, f32::NAN, 0.5), 500.0).unwrap_err();
        assert!(e.to_string().contains("body size y"), "{e}");
        let e = BodySpec::buoy(0.5, 0.5, 0.0).unwrap_err();
        assert!(e.to_string().contains("density"), "{e}");
        assert!(BodySpec::new(BodyKind::Buoy, Vec3::new(0.5, 1.0, 0.6), 300.0).is_err());
    }
}
