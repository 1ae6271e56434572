//! Bodies feel each other's waves through the interaction layer: a buoy 3 m from where a
//! crate plunges in heaves measurably more than without the layer, on a flat sea and on a
//! light breeze's sea; and a body at rest keeps its draft with the layer on (its own hollow is
//! not counted against it).

use glam::{Vec2, Vec3};
use vr_ocean::physics::{BodyId, BodySpec, Floaters, PhysicsConfig, Pose, PHYSICS_DT};
use vr_ocean::sim::interaction::InteractionConfig;
use vr_ocean::sim::{OceanConfig, SimCore, Surfaces};

/// A world without a deck, with a buoy at (3, 0, 0) and, after it settled for `settle` s, a
/// 0.6 m crate dropped from 2 m above the water at the origin. Returns the buoy's heights
/// (m) over the `seconds` after the drop, the sea stepped at `wind` m/s (0: flat).
fn buoy_heave(interaction: bool, wind: f32, settle: f32, seconds: f32) -> (Vec<f32>, Floaters) {
    buoy_run(interaction, wind, settle, seconds, true)
}

/// [`buoy_heave`], with or without the crate.
fn buoy_run(
    interaction: bool,
    wind: f32,
    settle: f32,
    seconds: f32,
    drop: bool,
) -> (Vec<f32>, Floaters) {
    let mut cfg = OceanConfig::default_cascades(64).unwrap();
    if wind > 0.0 {
        cfg.waves.wind_speed = wind;
    }
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut surfaces = Surfaces::new(&cfg);
    let mut world = Floaters::new(PhysicsConfig {
        deck: None,
        ..PhysicsConfig::default()
    })
    .unwrap();
    if interaction {
        let c = InteractionConfig::default_with_dt(PHYSICS_DT).unwrap();
        world.set_interaction(Some(c), Vec2::ZERO);
    }
    let buoy = world
        .spawn(
            BodySpec::buoy(0.6, 0.8, 300.0).unwrap(),
            Pose::at(Vec3::new(3.0, 0.0, 0.0)),
        )
        .unwrap();
    let mut t = 0.0f64;
    let mut step = |world: &mut Floaters, surfaces: &mut Surfaces| {
        t += PHYSICS_DT as f64;
        if wind > 0.0 {
            core.step(t, surfaces);
        }
        world.step(surfaces);
    };
    for _ in 0..(settle / PHYSICS_DT) as usize {
        step(&mut world, &mut surfaces);
    }
    let crate_id = drop.then(|| {
        world
            .spawn(
                BodySpec::crate_box(Vec3::splat(0.6), 600.0).unwrap(),
                Pose::at(Vec3::new(0.0, 2.0, 0.0)),
            )
            .unwrap()
    });
    let mut heights = Vec::new();
    for _ in 0..(seconds / PHYSICS_DT) as usize {
        step(&mut world, &mut surfaces);
        heights.push(y(&world, buoy));
    }
    if let Some(id) = crate_id {
        assert!(y(&world, id) > -1.0, "the crate floats");
    }
    (heights, world)
}

fn y(world: &Floaters, id: BodyId) -> f32 {
    world.pose(id).unwrap().position.y
}

/// Peak-to-peak of a series (m).
fn range(v: &[f32]) -> f32 {
    v.iter().cloned().fold(f32::MIN, f32::max) - v.iter().cloned().fold(f32::MAX, f32::min)
}

/// On a flat sea the buoy's heave is the rings' alone; on a 4 m/s sea (the same sea, the same
/// bits, with and without the layer) the rings' part is the difference of the two runs.
#[test]
fn a_buoy_heaves_in_a_splash_s_rings() {
    let (without, _) = buoy_heave(false, 0.0, 5.0, 8.0);
    let (with, world) = buoy_heave(true, 0.0, 5.0, 8.0);
    let (a, b) = (range(&without), range(&with));
    let energy = world.interaction().unwrap().stats().energy_j;
    println!(
        "flat sea: buoy heave {a:.4} m without the layer, {b:.4} m with it ({energy:.2e} J left)"
    );
    assert!(b > a + 0.03 && b > 3.0 * a, "{b} vs {a}");

    let (without, _) = buoy_heave(false, 4.0, 5.0, 8.0);
    let (with, _) = buoy_heave(true, 4.0, 5.0, 8.0);
    let extra = without
        .iter()
        .zip(&with)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f32>()
        / with.len() as f32;
    let sea = range(&without);
    println!(
        "4 m/s sea: buoy heave {sea:.3} m; the rings add {:.4} m rms",
        extra.sqrt()
    );
    assert!(extra.sqrt() > 0.01, "{}", extra.sqrt());
}

/// A body at rest keeps its draft with the layer on: its own hollow is taken out of the
/// heights it reads (its mean height over a second after 20 s within 2 cm of the one without
/// the layer; measured 1.2 cm deeper: the correction never lifts, and at the hollow's rim the
/// layer is lowered a little more than the pressure's head).
#[test]
fn a_body_at_rest_keeps_its_draft() {
    let mean = |v: Vec<f32>| v.iter().sum::<f32>() / v.len() as f32;
    let a = mean(buoy_run(false, 0.0, 20.0, 1.0, false).0);
    let b = mean(buoy_run(true, 0.0, 20.0, 1.0, false).0);
    println!("buoy at rest: y {a:.4} m without the layer, {b:.4} m with it");
    assert!((a - b).abs() < 0.02, "{a} vs {b}");
}

/// A flat sea (surfaces never stepped) and a world without a deck or a layer.
fn flat_sea_without_deck() -> (Surfaces, Floaters) {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let world = Floaters::new(PhysicsConfig {
        deck: None,
        ..PhysicsConfig::default()
    })
    .unwrap();
    (Surfaces::new(&cfg), world)
}

/// A launched boat motors away at about its speed and leaves a wake in the layer.
#[test]
fn a_launched_boat_motors_and_leaves_a_wake() {
    let (surfaces, mut world) = flat_sea_without_deck();
    let c = InteractionConfig::default_with_dt(PHYSICS_DT).unwrap();
    world.set_interaction(Some(c), Vec2::ZERO);
    let id = world
        .launch_boat(Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, -0.3, -1.0), 2.0)
        .unwrap();
    for _ in 0..(10.0 / PHYSICS_DT) as usize {
        let p = world.pose(id).unwrap().position;
        world.follow(Vec2::new(p.x, p.z));
        world.step(&surfaces);
    }
    let p = world.pose(id).unwrap().position;
    let (v, _) = world.velocity(id).unwrap();
    let energy = world.interaction().unwrap().stats().energy_j;
    println!(
        "boat after 10 s at {p}, speed {:.2} m/s, layer energy {energy:.3e} J",
        v.length()
    );
    assert!(p.z < -6.0 - 15.0 && p.x.abs() < 2.0, "{p}");
    assert!((v.length() - 2.0).abs() < 0.35, "{v}");
    // Waves of a few centimetres over the wake's ~100 m²: hundreds of joules.
    assert!(energy > 100.0, "no wake: {energy} J");
}

/// A hand swept through the water makes ripples (and says it is in the water); above the
/// water, or with the layer off, it does nothing.
#[test]
fn a_hand_in_the_water_ripples_it() {
    use glam::Quat;
    use vr_ocean::physics::HandInput;
    let (surfaces, mut world) = flat_sea_without_deck();
    let hand = |x: f32, y: f32| HandInput {
        grip: 0.0,
        pose: Pose {
            position: Vec3::new(x, y, 0.0),
            rotation: Quat::IDENTITY,
        },
        linvel: Vec3::new(1.0, 0.0, 0.0),
        angvel: Vec3::ZERO,
    };
    assert!(!world.dip(&hand(0.0, -0.1), &surfaces), "no layer, no dip");
    let c = InteractionConfig::default_with_dt(PHYSICS_DT).unwrap();
    world.set_interaction(Some(c), Vec2::ZERO);
    assert!(!world.dip(&hand(0.0, 0.2), &surfaces), "above the water");
    for i in 0..90 {
        let x = -0.5 + i as f32 * PHYSICS_DT;
        assert!(world.dip(&hand(x, -0.1), &surfaces));
        world.step(&surfaces);
    }
    let energy = world.interaction().unwrap().stats().energy_j;
    println!("a hand swept 1 m through the water at 1 m/s: {energy:.3} J of ripples");
    assert!(energy > 0.01, "{energy}");
}

/// Issue 45: a user floating in the water makes waves with the body, and a wake swimming
/// (more than at rest); standing over the water, or with the layer off, nothing.
#[test]
fn a_floating_user_s_body_makes_waves_and_a_wake() {
    let energy_after = |speed: f32| {
        let (surfaces, mut world) = flat_sea_without_deck();
        let c = InteractionConfig::default_with_dt(PHYSICS_DT).unwrap();
        world.set_interaction(Some(c), Vec2::ZERO);
        let v = Vec3::new(0.0, 0.0, -speed);
        for i in 0..(2.0 / PHYSICS_DT) as usize {
            let head = Vec3::new(0.0, 0.15, 0.5 - speed * i as f32 * PHYSICS_DT);
            assert!(
                world.wade(head, v, &surfaces),
                "step {i}: the body is in the water"
            );
            world.step(&surfaces);
        }
        world.interaction().unwrap().stats().energy_j
    };
    let (surfaces, mut world) = flat_sea_without_deck();
    assert!(
        !world.wade(Vec3::new(0.0, 0.15, 0.0), Vec3::ZERO, &surfaces),
        "no layer"
    );
    let c = InteractionConfig::default_with_dt(PHYSICS_DT).unwrap();
    world.set_interaction(Some(c), Vec2::ZERO);
    assert!(
        !world.wade(Vec3::new(0.0, 1.7, 0.0), Vec3::ZERO, &surfaces),
        "standing over it"
    );
    let (rest, swim) = (energy_after(0.0), energy_after(1.2));
    println!(
        "a floating body for 2 s: {rest:.3} J of waves at rest, {swim:.3} J swimming at 1.2 m/s"
    );
    assert!(rest > 0.001, "{rest}");
    assert!(swim > 2.0 * rest, "no wake: {swim} vs {rest} J at rest");
}
