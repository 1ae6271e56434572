//! Hydrostatics of the floating bodies in calm water: a box floats with the fraction ρ/ρ_w of
//! its volume under the surface (Archimedes), a body denser than water sinks and is taken out
//! at the documented floor depth.
//!
//! The calm sea is the simulation's own [`Surfaces`] with every field zero (zero amplitude):
//! the heights still go through the physics' batched queries of the surfaces, as in the app.

use glam::{Quat, Vec3};
use vr_ocean::physics::{BodySpec, BodyState, Floaters, PhysicsConfig, Pose, PHYSICS_DT};
use vr_ocean::sim::{OceanConfig, Surfaces};

/// Fresh water, so that "half" is 500 kg/m³ exactly as the issue states it.
const WATER: f32 = 1000.0;

fn calm() -> Surfaces {
    Surfaces::new(&OceanConfig::single(64, 100.0).unwrap())
}

fn open_water() -> Floaters {
    Floaters::new(PhysicsConfig {
        deck: None,
        water_density: WATER,
        ..PhysicsConfig::default()
    })
    .unwrap()
}

/// Tilt of a body's y axis from the vertical (degrees).
fn tilt_deg(pose: &Pose) -> f32 {
    (pose.rotation * Vec3::Y)
        .angle_between(Vec3::Y)
        .to_degrees()
}

/// Drops a box of `density` from 0.2 m above its waterline, lets it settle for 40 s and
/// returns its submerged fraction averaged over the last 5 s, measured from its pose (the
/// depth of its bottom below the calm surface over its height) and, as a cross-check, from
/// the submerged volume the water forces saw.
fn settled_fraction(density: f32) -> (f32, f32) {
    let size = Vec3::new(1.0, 0.4, 0.8);
    let spec = BodySpec::crate_box(size, density).unwrap();
    let surfaces = calm();
    let mut world = open_water();
    // Start off balance: 0.2 m too high and turned a little about two axes.
    let start = Pose {
        position: Vec3::new(2.0, 0.2, -1.0),
        rotation: Quat::from_rotation_x(0.05) * Quat::from_rotation_z(-0.04),
    };
    let id = world.spawn(spec, start).unwrap();
    let settle = (35.0 / PHYSICS_DT) as usize;
    let window = (5.0 / PHYSICS_DT) as usize;
    for _ in 0..settle {
        world.step(&surfaces);
    }
    let (mut geometric, mut forces) = (0.0f64, 0.0f64);
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for _ in 0..window {
        world.step(&surfaces);
        let pose = world.pose(id).unwrap();
        assert!(tilt_deg(&pose) < 0.5, "settled level: {}°", tilt_deg(&pose));
        let y = pose.position.y;
        lo = lo.min(y);
        hi = hi.max(y);
        // The bottom face is level: the water (at 0) covers it to depth 0 − (y − h/2).
        geometric += ((0.5 * size.y - y) / size.y) as f64;
        forces += (world.submerged_volume(id).unwrap() / spec.volume()) as f64;
    }
    assert!(
        hi - lo < 1e-3,
        "still bobbing after 35 s: {} mm peak to peak",
        (hi - lo) * 1e3
    );
    (
        (geometric / window as f64) as f32,
        (forces / window as f64) as f32,
    )
}

#[test]
fn a_box_of_500_floats_half_submerged_and_one_of_250_a_quarter() {
    for (density, expect) in [(500.0, 0.5), (250.0, 0.25)] {
        let (geometric, forces) = settled_fraction(density);
        println!(
            "density {density} kg/m³: submerged fraction {geometric:.4} (pose), {forces:.4} \
             (water forces), expected {expect}"
        );
        let rel = geometric / expect - 1.0;
        assert!(
            rel.abs() < 0.03,
            "density {density}: {geometric} of the volume submerged, expected {expect} ± 3 %"
        );
        assert!(
            (forces / geometric - 1.0).abs() < 0.01,
            "the forces' submerged volume {forces} disagrees with the pose's {geometric}"
        );
    }
}

#[test]
fn a_body_denser_than_water_sinks_and_is_removed_at_the_floor() {
    let surfaces = calm();
    let mut world = open_water();
    let floor = world.config().floor_depth;
    assert_eq!(floor, vr_ocean::physics::DEFAULT_FLOOR_DEPTH);
    let spec = BodySpec::crate_box(Vec3::splat(0.5), 2000.0).unwrap();
    let floater = BodySpec::crate_box(Vec3::splat(0.5), 500.0).unwrap();
    let sinker = world
        .spawn(spec, Pose::at(Vec3::new(0.0, 0.0, 0.0)))
        .unwrap();
    let keeper = world
        .spawn(floater, Pose::at(Vec3::new(5.0, 0.0, 0.0)))
        .unwrap();
    let mut last_y = 0.0f32;
    let mut sunk_at = None;
    let mut max_speed = 0.0f32;
    for step in 0..(60.0 / PHYSICS_DT) as usize {
        world.step(&surfaces);
        match world.state(sinker).unwrap() {
            BodyState::Sunk => {
                sunk_at = Some(step);
                break;
            }
            _ => {
                let y = world.center_of_mass(sinker).unwrap().y;
                assert!(
                    y <= last_y + 1e-4,
                    "sinks monotonically: {y} after {last_y}"
                );
                last_y = y;
                max_speed = max_speed.max(world.velocity(sinker).unwrap().0.length());
            }
        }
    }
    let step = sunk_at.expect("the dense box sinks below the floor within 60 s");
    let t = step as f32 * PHYSICS_DT;
    println!(
        "2000 kg/m³ box: removed after {t:.2} s, last centre at {last_y:.3} m (floor at \
         −{floor} m), fastest sinking {max_speed:.2} m/s"
    );
    // It was removed at the floor: its last live centre was within one step's travel of it.
    assert!(last_y > -floor - 1e-3 && last_y < -floor + max_speed * PHYSICS_DT + 1e-3);
    // Drag holds it to a terminal speed of a few m/s.
    assert!(
        max_speed > 1.0 && max_speed < 5.0,
        "terminal speed {max_speed} m/s"
    );
    // Out of the world: not drawn, not posed, its id refused; the floater stays.
    assert!(world.pose(sinker).is_none());
    assert!(world.instances().all(|i| i.id != sinker));
    assert_eq!(world.live(), 1);
    assert!(world.grab(sinker, Pose::at(Vec3::ZERO)).is_err());
    assert_eq!(world.state(keeper), Some(BodyState::Floating));
    assert!(world.pose(keeper).unwrap().position.y.abs() < 0.1);
}
