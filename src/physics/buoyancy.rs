//! The water's forces on one body, from the heights under its hull columns. Pure: a body's
//! state and the water in, a force and a torque out.
//!
//! Per column ([`Column`], a vertical prism of the hull) with water height η at its centre:
//!
//! - **Archimedes**: the prism's ends are at `lo` and `hi` in the world; the water covers the
//!   fraction f = (η − lo_y) / (hi_y − lo_y) of it (clamped to [0, 1]; a column lying flat
//!   is given the vertical extent of its own width), so its submerged volume is
//!   V = area · length · f, pushed up by ρ·g·V at the centroid of its submerged part.
//! - **Froude-Krylov along the slope**: under a wave the water accelerates horizontally by
//!   a = −g·∇η (linear theory at the surface), and the pressure gradient that moves it pushes
//!   a submerged volume too: (1 + C_a)·ρ·V·a, counting the added mass's share ([Morison]).
//!   ∇η is a least-squares plane through the heights under the body's columns, so waves
//!   shorter than the hull average out as its pressure would. This is what makes bodies surge
//!   with the orbital motion instead of bobbing in place.
//! - **Drag** relative to the water: vertically against the column's footprint,
//!   −ρ·A·(c_lin + ½·C_d·|u|)·u with u = the point's vertical speed minus the water's
//!   ([`crate::physics::water`]); horizontally the same against the wetted side
//!   (√A × submerged length), relative to the water's orbital velocity (below). The linear
//!   term stands in for wave radiation damping (a damping ratio of about 0.15 in heave for
//!   the default bodies), the quadratic one for form drag. Each column's drag is capped so
//!   one step can at most halve its relative speed, counting the turning its lever allows
//!   (the effective mass 1/(1/m + |r⊥|²/I)): explicit drag never overshoots, however light
//!   the body, in translation or rotation. (Capping with the linear mass alone let a small
//!   crate slapping into the water spin up to 31 rad/s.)
//! - **Added mass**: a constant C_a = [`ADDED_MASS_COEFFICIENT`] times the mass of water the
//!   body displaces afloat (its own mass, or its volume of water if it sinks), added to the
//!   rapier body's linear mass with gravity scaled down to match, so it weighs what it
//!   should and accelerates as a body in water does. Out of the water the added mass is not
//!   there: the step pushes the missing weight, C_a·m_w·g·(1 − w), down on the body, with the
//!   wetness w = submerged volume / (footprint × [`WET_LENGTH`]) capped at 1, so a body in
//!   the air falls at g (tests/physics/interact.rs throws one) and a floating body, wet by
//!   more than [`WET_LENGTH`], feels none of it. It matters for
//!   light, wide bodies (a crate of 250 kg/m³ heaves ~20 % slower, as real ones do) and
//!   keeps the explicit coupling stable; rotational added inertia is left out.
//!
//! The water's horizontal velocity at a body is the leaky integral of a = −g·∇η along its
//! path (time constant [`FLOW_MEMORY_S`]): the orbital velocity of waves shorter than a few
//! tens of seconds, with no mean current or Stokes drift: the simulation's drift
//! (`sim::drift`, ~3 % of the wind) carries the foam, not the bodies, which would leave the
//! deck's reach within minutes (a leeway model with the wind's push on the hull above water
//! would come with it).
//!
//! [Morison]: https://en.wikipedia.org/wiki/Morison_equation

use glam::{Vec2, Vec3};

use crate::physics::body::{Column, Hull};
use crate::physics::Pose;

/// Added mass as a fraction of the mass of water a floating body displaces (a half-immersed
/// box or cylinder in heave: 0.4-1).
pub const ADDED_MASS_COEFFICIENT: f32 = 0.5;

/// Linear drag speed c_lin (m/s): the drag per area and water density of slow relative motion.
pub const LINEAR_DRAG_SPEED: f32 = 0.5;

/// Quadratic drag coefficient C_d (a flat face: about 1).
pub const DRAG_COEFFICIENT: f32 = 1.0;

/// Memory of the water's horizontal velocity estimate (s).
pub const FLOW_MEMORY_S: f32 = 8.0;

/// Fastest horizontal water velocity believed (m/s).
pub const MAX_FLOW: f32 = 4.0;

/// Steepest water slope believed (rise over run): breaking crests are steeper only briefly.
pub const MAX_SLOPE: f32 = 1.0;

/// Submerged length (m) at which a column's drag reaches full strength (it grows from 0 as the
/// column enters the water, so contact is not a jump).
pub const WET_LENGTH: f32 = 0.05;

/// Largest fraction of a column's relative speed its drag may remove in one step.
pub const DRAG_CAP: f32 = 0.5;

/// The water and the step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Water {
    /// Density ρ (kg/m³).
    pub density: f32,
    /// Gravity g (m/s², downward).
    pub gravity: f32,
    /// Step (s).
    pub dt: f32,
}

/// A body's motion, in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Pose of the body frame.
    pub pose: Pose,
    /// Centre of mass (m).
    pub com: Vec3,
    /// Velocity of the centre of mass (m/s).
    pub linvel: Vec3,
    /// Angular velocity (rad/s).
    pub angvel: Vec3,
    /// Mass the forces accelerate, added mass included (kg).
    pub mass: f32,
    /// Largest inverse principal moment of inertia (1/(kg·m²)): how easily the body turns
    /// about its most yielding axis, for the drag cap.
    pub inv_inertia: f32,
}

/// What the water does to one body this step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WaterForces {
    /// Total force (N).
    pub force: Vec3,
    /// Total torque about the centre of mass (N·m).
    pub torque: Vec3,
    /// Submerged volume (m³).
    pub submerged: f32,
    /// The water's horizontal velocity for the next step ([`FLOW_MEMORY_S`]) (m/s).
    pub flow: Vec2,
}

/// World positions of a column's bottom and top centres.
#[inline]
pub fn column_ends(pose: &Pose, c: &Column) -> (Vec3, Vec3) {
    let bottom = pose.position + pose.rotation * Vec3::new(c.x, c.bottom, c.z);
    let top = pose.position + pose.rotation * Vec3::new(c.x, c.top, c.z);
    (bottom, top)
}

/// Where a column asks for the water height: the middle of its axis, (x, z).
#[inline]
pub fn sample_point(pose: &Pose, c: &Column) -> [f32; 2] {
    let (b, t) = column_ends(pose, c);
    [0.5 * (b.x + t.x), 0.5 * (b.z + t.z)]
}

/// The water surface's slope (∂η/∂x, ∂η/∂z) under a hull: a plane fitted through the
/// heights at its sample points, weighted by column area (a little ridge regularisation
/// makes a direction the points do not span flat).
pub fn fitted_slope(pose: &Pose, hull: &Hull, heights: &[f32]) -> Vec2 {
    let cols = hull.columns();
    let (mut sw, mut sx, mut sz, mut sh) = (0.0f32, 0.0, 0.0, 0.0);
    for (c, &h) in cols.iter().zip(heights) {
        let [x, z] = sample_point(pose, c);
        sw += c.area;
        sx += c.area * x;
        sz += c.area * z;
        sh += c.area * h;
    }
    if sw <= 0.0 {
        return Vec2::ZERO;
    }
    let (mx, mz, mh) = (sx / sw, sz / sw, sh / sw);
    let (mut xx, mut xz, mut zz, mut xh, mut zh) = (0.0f32, 0.0, 0.0, 0.0, 0.0);
    for (c, &h) in cols.iter().zip(heights) {
        let [x, z] = sample_point(pose, c);
        let (dx, dz, dh) = (x - mx, z - mz, h - mh);
        xx += c.area * dx * dx;
        xz += c.area * dx * dz;
        zz += c.area * dz * dz;
        xh += c.area * dx * dh;
        zh += c.area * dz * dh;
    }
    let ridge = 1e-3 * (xx + zz) + 1e-12;
    let (a, d) = (xx + ridge, zz + ridge);
    let det = a * d - xz * xz;
    let s = Vec2::new(d * xh - xz * zh, a * zh - xz * xh) / det;
    if s.is_finite() {
        s.clamp_length_max(MAX_SLOPE)
    } else {
        Vec2::ZERO
    }
}

/// The water's force and torque on a body with columns `hull` moving as `m`, the heights
/// `heights` and vertical water speeds `rates` under its columns (in column order), and the
/// water's horizontal velocity `flow` from the last step.
pub fn water_forces(
    hull: &Hull,
    m: &Motion,
    heights: &[f32],
    rates: &[f32],
    flow: Vec2,
    water: &Water,
) -> WaterForces {
    let slope = fitted_slope(&m.pose, hull, heights);
    let (rho, g, dt) = (water.density, water.gravity, water.dt);
    let inertia = 1.0 + ADDED_MASS_COEFFICIENT;
    let area_total = hull.area().max(1e-9);
    let mut out = WaterForces::default();
    for ((c, &eta), &rate) in hull.columns().iter().zip(heights).zip(rates) {
        let (b, t) = column_ends(&m.pose, c);
        let (lo, hi) = if b.y <= t.y { (b, t) } else { (t, b) };
        let rise = hi.y - lo.y;
        let extent = rise.max(c.area.sqrt().min(c.length())).max(1e-6);
        let base = 0.5 * (lo.y + hi.y) - 0.5 * extent;
        let f = ((eta - base) / extent).clamp(0.0, 1.0);
        if f <= 0.0 {
            continue;
        }
        let wet_length = c.length() * f;
        let volume = c.area * wet_length;
        out.submerged += volume;
        let centroid = lo + (hi - lo) * (0.5 * f);
        let buoyancy = rho * g * volume;
        let mut force = Vec3::new(
            -inertia * buoyancy * slope.x,
            buoyancy,
            -inertia * buoyancy * slope.y,
        );

        // Drag against the water's motion, capped to half the relative speed per step.
        let r = centroid - m.com;
        let point = m.linvel + m.angvel.cross(r);
        let rel = point - Vec3::new(flow.x, rate, flow.y);
        let wet = (wet_length / WET_LENGTH).min(1.0);
        // The mass a force at this column moves: the body's, less what turning about the
        // centre of mass gives way (1/m_eff = 1/m + |r⊥|²/I, with the most yielding axis's I
        // and, for either direction, the whole lever: conservative).
        let share = (c.area / area_total) / dt;
        let turn = |lever_sq: f32| DRAG_CAP * share / (1.0 / m.mass + lever_sq * m.inv_inertia);
        let cap = turn(r.x * r.x + r.z * r.z);
        let cap_h = turn(r.length_squared());
        let vertical =
            rho * c.area * wet * (LINEAR_DRAG_SPEED + 0.5 * DRAG_COEFFICIENT * rel.y.abs());
        force.y -= vertical.min(cap) * rel.y;
        let rel_h = Vec2::new(rel.x, rel.z);
        let side = c.area.sqrt() * wet_length;
        let horizontal = rho * side * (LINEAR_DRAG_SPEED + 0.5 * DRAG_COEFFICIENT * rel_h.length());
        let drag_h = rel_h * -horizontal.min(cap_h);
        force.x += drag_h.x;
        force.z += drag_h.y;

        out.force += force;
        out.torque += r.cross(force);
    }
    // The water's horizontal velocity: integrate its acceleration where the body is wet,
    // forget it with FLOW_MEMORY_S either way.
    let accel = if out.submerged > 0.0 {
        -g * slope
    } else {
        Vec2::ZERO
    };
    out.flow = ((flow + accel * dt) * (1.0 - dt / FLOW_MEMORY_S)).clamp_length_max(MAX_FLOW);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::body::BodySpec;
    use glam::Quat;

    fn still(pose: Pose, mass: f32) -> Motion {
        Motion {
            pose,
            com: pose.position,
            linvel: Vec3::ZERO,
            angvel: Vec3::ZERO,
            mass,
            inv_inertia: 0.0,
        }
    }

    const WATER: Water = Water {
        density: 1000.0,
        gravity: 10.0,
        dt: 1.0 / 90.0,
    };

    #[test]
    fn a_half_immersed_box_feels_half_its_volume_of_water() {
        let spec = BodySpec::crate_box(Vec3::new(1.0, 0.4, 0.8), 500.0).unwrap();
        let hull = Hull::of(&spec);
        let n = hull.columns().len();
        let zeros = [0.0; 16];
        // Tilted 20° about x, centre on the water: the plane through the centre halves it.
        let pose = Pose {
            position: Vec3::new(3.0, 0.0, -2.0),
            rotation: Quat::from_rotation_x(0.35),
        };
        let f = water_forces(
            &hull,
            &still(pose, 160.0),
            &zeros[..n],
            &zeros[..n],
            Vec2::ZERO,
            &WATER,
        );
        let expect = 0.5 * spec.volume();
        assert!(
            (f.submerged / expect - 1.0).abs() < 1e-3,
            "{} vs {expect}",
            f.submerged
        );
        assert!((f.force.y - 1000.0 * 10.0 * expect).abs() < 1.0);
        assert!(f.force.x.abs() < 1e-3 && f.force.z.abs() < 1e-3);
        // Out of the water: nothing.
        let dry = Pose::at(Vec3::new(0.0, 1.0, 0.0));
        let f = water_forces(
            &hull,
            &still(dry, 160.0),
            &zeros[..n],
            &zeros[..n],
            Vec2::ZERO,
            &WATER,
        );
        assert_eq!(f.force, Vec3::ZERO);
    }

    #[test]
    fn a_sloped_surface_pushes_downhill_and_drag_opposes_motion() {
        let spec = BodySpec::crate_box(Vec3::new(1.0, 0.4, 1.0), 500.0).unwrap();
        let hull = Hull::of(&spec);
        let pose = Pose::at(Vec3::ZERO);
        // η = 0.1·x: uphill towards +x.
        let heights: Vec<f32> = hull
            .columns()
            .iter()
            .map(|c| 0.1 * sample_point(&pose, c)[0])
            .collect();
        let s = fitted_slope(&pose, &hull, &heights);
        // The ridge regularisation biases the fit by 0.2 % (1e-3 on each diagonal).
        assert!((s.x - 0.1).abs() < 5e-4 && s.y.abs() < 1e-5, "{s}");
        let rates = vec![0.0; heights.len()];
        let mut m = still(pose, 200.0);
        let f = water_forces(&hull, &m, &heights, &rates, Vec2::ZERO, &WATER);
        assert!(f.force.x < 0.0, "pushed downhill: {}", f.force);
        m.linvel = Vec3::new(0.0, -1.0, 0.0);
        let flat = vec![0.0; heights.len()];
        let moving = water_forces(&hull, &m, &flat, &rates, Vec2::ZERO, &WATER);
        let resting = water_forces(
            &hull,
            &still(pose, 200.0),
            &flat,
            &rates,
            Vec2::ZERO,
            &WATER,
        );
        let drag = moving.force.y - resting.force.y;
        assert!(drag > 0.0, "sinking is resisted");
        assert!(drag * WATER.dt <= DRAG_CAP * 200.0 * 1.0 + 1e-3, "capped");
    }
}
