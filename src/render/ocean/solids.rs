//! Solid things drawn in the sea's pass: the floating bodies and the deck. Three unit meshes
//! spanning [-0.5, 0.5]³ (a box, a cylinder along y, the boat's hull), flat-shaded, each drawn
//! instanced in one draw: at most three draws whatever the number of bodies. They share the
//! ocean's depth buffer, so the water hides what lies under its surface: the waterline is
//! where the two meet, exactly, per pixel.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::physics::body::boat_unit_hull;

/// What a solid is; it picks the mesh and the colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidKind {
    /// A buoy: the cylinder, signal red.
    Buoy,
    /// A crate: the box, weathered wood.
    Crate,
    /// A small boat: the hull, white.
    Boat,
    /// The deck the user stands on: the box, grey planks.
    Deck,
    /// A controller's aim ray to the control panel: a thin box, pale and glowing.
    Ray,
}

impl SolidKind {
    /// The unit mesh it is drawn with.
    pub fn shape(self) -> Shape {
        match self {
            SolidKind::Buoy => Shape::Cylinder,
            SolidKind::Crate | SolidKind::Deck | SolidKind::Ray => Shape::Box,
            SolidKind::Boat => Shape::Hull,
        }
    }

    /// Its diffuse albedo (linear RGB).
    pub fn albedo(self) -> [f32; 3] {
        match self {
            SolidKind::Buoy => [0.55, 0.06, 0.03],
            SolidKind::Crate => [0.30, 0.19, 0.10],
            SolidKind::Boat => [0.62, 0.62, 0.58],
            SolidKind::Deck => [0.30, 0.24, 0.18],
            SolidKind::Ray => [0.80, 0.88, 0.95],
        }
    }
}

/// The unit meshes, in draw order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// [-0.5, 0.5]³.
    Box,
    /// Diameter 1 and height 1 along y.
    Cylinder,
    /// The boat's hull: the convex hull of [`boat_unit_hull`].
    Hull,
}

impl Shape {
    /// Every shape, in draw order.
    pub const ALL: [Shape; 3] = [Shape::Box, Shape::Cylinder, Shape::Hull];
}

/// One solid to draw this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solid {
    /// What it is.
    pub kind: SolidKind,
    /// Model matrix of its unit mesh (translation · rotation · scale to its size).
    pub model: Mat4,
    /// Held by a hand: drawn a little brighter.
    pub highlight: bool,
}

/// Most solids one frame draws: every body, the deck and both hands' aim rays.
pub const MAX_SOLIDS: usize = crate::physics::MAX_BODIES + 3;

/// Thickness of an aim ray (m): about 4 pixels at half a metre on a Quest 3.
pub const RAY_THICKNESS: f32 = 0.0015;

impl Solid {
    /// An aim ray from `from` to `to` (world space): a thin glowing box between them.
    pub fn ray(from: Vec3, to: Vec3) -> Option<Self> {
        let along = to - from;
        let length = along.length();
        let dir = along.try_normalize()?;
        let rotation = glam::Quat::from_rotation_arc(Vec3::Z, dir);
        Some(Self {
            kind: SolidKind::Ray,
            model: Mat4::from_scale_rotation_translation(
                Vec3::new(RAY_THICKNESS, RAY_THICKNESS, length),
                rotation,
                (from + to) * 0.5,
            ),
            highlight: true,
        })
    }
}

/// A unit mesh's vertex: position and face normal.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SolidVertex {
    /// Position in the unit box.
    pub position: [f32; 3],
    /// Outward face normal.
    pub normal: [f32; 3],
}

/// Per-instance data of the solids' pipeline (`shaders/solid.vert`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SolidInstance {
    /// Model matrix, column-major.
    pub model: [f32; 16],
    /// Albedo (rgb) and how it is drawn (a: 0 plain, 1 highlighted, 2 deck planks).
    pub colour: [f32; 4],
}

impl SolidInstance {
    /// The instance of `solid`.
    pub fn of(solid: &Solid) -> Self {
        let [r, g, b] = solid.kind.albedo();
        Self {
            model: solid.model.to_cols_array(),
            colour: [
                r,
                g,
                b,
                match (solid.kind, solid.highlight) {
                    (SolidKind::Deck, _) => 2.0,
                    (_, true) => 1.0,
                    (_, false) => 0.0,
                },
            ],
        }
    }
}

/// A unit mesh: vertices and triangles (counter-clockwise seen from outside).
#[derive(Clone, Debug, Default)]
pub struct UnitMesh {
    /// Vertices.
    pub vertices: Vec<SolidVertex>,
    /// Triangle list.
    pub indices: Vec<u16>,
}

impl UnitMesh {
    /// The mesh of `shape`.
    pub fn of(shape: Shape) -> Self {
        let mut m = Self::default();
        match shape {
            Shape::Box => m.convex_hexahedron(&box_corners()),
            Shape::Cylinder => m.cylinder(CYLINDER_SEGMENTS),
            Shape::Hull => m.convex_hexahedron(&boat_unit_hull()),
        }
        m
    }

    /// Adds a flat polygon (corners in order, counter-clockwise seen from outside).
    fn face(&mut self, corners: &[Vec3]) {
        let n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        self.face_with_normals(corners, &vec![n; corners.len()]);
    }

    /// Adds a convex polygon with per-corner normals, fanned from the first corner.
    fn face_with_normals(&mut self, corners: &[Vec3], normals: &[Vec3]) {
        let base = self.vertices.len() as u16;
        for (p, n) in corners.iter().zip(normals) {
            self.vertices.push(SolidVertex {
                position: p.to_array(),
                normal: n.to_array(),
            });
        }
        for i in 1..corners.len() as u16 - 1 {
            self.indices.extend([base, base + i, base + i + 1]);
        }
    }

    /// Six quads between a top rectangle (corners 0-3 at y = 0.5, counter-clockwise seen from
    /// above) and a bottom one (4-7 below them), as [`boat_unit_hull`] and the box give them.
    fn convex_hexahedron(&mut self, c: &[Vec3; 8]) {
        self.face(&[c[3], c[2], c[1], c[0]]);
        self.face(&[c[4], c[5], c[6], c[7]]);
        for i in 0..4 {
            let j = (i + 1) % 4;
            self.face(&[c[i], c[j], c[j + 4], c[i + 4]]);
        }
    }

    /// A cylinder of `segments` sides with smooth side normals and flat caps.
    fn cylinder(&mut self, segments: usize) {
        let ring = |k: usize| {
            let a = std::f32::consts::TAU * k as f32 / segments as f32;
            Vec3::new(0.5 * a.cos(), 0.0, -0.5 * a.sin())
        };
        for k in 0..segments {
            let (p, q) = (ring(k), ring(k + 1));
            let (np, nq) = (p.normalize(), q.normalize());
            let up = Vec3::Y * 0.5;
            self.face_with_normals(&[p - up, q - up, q + up, p + up], &[np, nq, nq, np]);
        }
        let top: Vec<Vec3> = (0..segments).map(|k| ring(k) + Vec3::Y * 0.5).collect();
        self.face(&top);
        let bottom: Vec<Vec3> = (0..segments)
            .rev()
            .map(|k| ring(k) - Vec3::Y * 0.5)
            .collect();
        self.face(&bottom);
    }
}

/// Sides of the buoy's cylinder.
pub const CYLINDER_SEGMENTS: usize = 20;

/// The unit box's corners in [`boat_unit_hull`]'s order.
fn box_corners() -> [Vec3; 8] {
    let mut c = boat_unit_hull();
    for p in &mut c[4..] {
        p.x = p.x.signum() * 0.5;
        p.z = p.z.signum() * 0.5;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's winding agrees with its stored normal and points away from the centre
    /// (the meshes are convex, centred on the origin).
    #[test]
    fn faces_point_outward() {
        for shape in Shape::ALL {
            let m = UnitMesh::of(shape);
            assert!(!m.indices.is_empty());
            for t in m.indices.chunks(3) {
                let p = |i: u16| Vec3::from(m.vertices[i as usize].position);
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                let n = (b - a).cross(c - a);
                let centre = (a + b + c) / 3.0;
                assert!(
                    n.dot(centre) > 0.0,
                    "{shape:?}: inward triangle {a} {b} {c}"
                );
                let stored = Vec3::from(m.vertices[t[0] as usize].normal);
                assert!(n.dot(stored) > 0.0, "{shape:?}: normal against winding");
                for v in [a, b, c] {
                    assert!(
                        v.abs().max_element() <= 0.5 + 1e-6,
                        "{shape:?}: {v} outside"
                    );
                }
            }
        }
    }

    #[test]
    fn the_box_fills_the_unit_cube() {
        let m = UnitMesh::of(Shape::Box);
        assert_eq!(m.vertices.len(), 24);
        assert_eq!(m.indices.len(), 36);
        for v in &m.vertices {
            assert!(v.position.iter().all(|c| c.abs() == 0.5));
        }
    }
}
